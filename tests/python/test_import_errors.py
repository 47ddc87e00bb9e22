"""vid-import on bad input: one line on stderr naming what is wrong (file, field, the fixing
flag), exit 2 for usage errors (flags, map, names that are not there), 1 for data errors."""
from __future__ import annotations

import numpy as np
import pytest

from test_import_synth import MASS, csv_map, flight, run_import, write_csv_log

FLIGHT = flight(seconds=3.0)


@pytest.fixture
def log(tmp_path):
    write_csv_log(tmp_path / "log", FLIGHT, "frd", "enu")
    return tmp_path / "log"


def _one_line(r, code):
    assert r.returncode == code, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("vid-import: error: ")
    return lines[0]


def test_wrong_imu_frame_names_the_fixing_flag(tmp_path, log):
    r = run_import(log, tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS)
    line = _one_line(r, 1)
    assert "thrust points down" in line and "pass --imu-frame frd" in line
    assert f"{-np.median(FLIGHT.thrust):.3g}" in line
    assert not (tmp_path / "out" / "mav0").exists()


def test_flipped_thrust_sign_names_negate_thrust(tmp_path):
    write_csv_log(tmp_path / "log", FLIGHT, "flu", "enu")
    text = (tmp_path / "log" / "imu.csv").read_text().splitlines()
    rows = [text[0]] + [",".join(r.split(",")[:-1] + [repr(-float(r.split(",")[-1]))]) for r in text[1:]]
    (tmp_path / "log" / "imu.csv").write_text("\n".join(rows) + "\n")
    m = csv_map(tmp_path / "m.yaml")
    line = _one_line(run_import(tmp_path / "log", tmp_path / "out", "--map", m, "--mass", MASS), 1)
    assert "thrust column has the opposite sign" in line and "--negate-thrust" in line
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", m, "--mass", MASS, "--negate-thrust")
    assert r.returncode == 0, r.stderr


def test_bad_column_name_names_file_and_field(tmp_path, log):
    m = csv_map(tmp_path / "m.yaml")
    m.write_text(m.read_text().replace("gyro: [wx, wy, wz]", "gyro: [wx, wy, w_z]"))
    line = _one_line(run_import(log, tmp_path / "out", "--map", m, "--mass", MASS, "--imu-frame", "frd"), 2)
    assert str(log / "imu.csv") in line and "'imu.gyro'" in line and "no column 'w_z'" in line


def test_bad_hdf5_dataset_names_file_and_field(tmp_path):
    from test_import_synth import hdf5_map, write_hdf5_log

    write_hdf5_log(tmp_path / "log", FLIGHT)
    m = hdf5_map(tmp_path / "m.yaml")
    m.write_text(m.read_text().replace("position: mocap/p", "position: mocap/pos"))
    line = _one_line(run_import(tmp_path / "log", tmp_path / "out", "--map", m, "--mass", MASS,
                                "--imu-frame", "frd"), 2)
    assert "data.h5" in line and "'mocap.position'" in line and "no dataset 'mocap/pos'" in line


@pytest.mark.parametrize("edit,expect", [
    (lambda s: s.replace("time_unit: s,", "time_unit: minutes,", 1), "key 'imu.time_unit': 'minutes'"),
    (lambda s: s.replace("accel: [ax, ay, az]", "acel: [ax, ay, az]"), "key 'imu.acel': unknown"),
    (lambda s: s.replace("accel: [ax, ay, az]", "accel: [ax, ay]"), "'imu.accel'"),
    (lambda s: s + "camera: {file: x}\n", "key 'camera': unknown"),
    (lambda s: s.replace(", quaternion_order: wxyz", ", quaternion_order: zyxw"), "'mocap.quaternion_order'"),
])
def test_map_errors_are_usage_errors(tmp_path, log, edit, expect):
    m = csv_map(tmp_path / "m.yaml")
    m.write_text(edit(m.read_text()))
    line = _one_line(run_import(log, tmp_path / "out", "--map", m, "--mass", MASS, "--imu-frame", "frd"), 2)
    assert expect in line


def test_not_a_number_names_file_and_line(tmp_path, log):
    text = (log / "imu.csv").read_text().splitlines()
    text[7] = text[7].replace(text[7].split(",")[4], "abc", 1)
    (log / "imu.csv").write_text("\n".join(text) + "\n")
    line = _one_line(run_import(log, tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS,
                                "--imu-frame", "frd"), 1)
    assert f"{log / 'imu.csv'}:8:" in line and "value 'abc' is not a number" in line


def test_time_going_backwards_names_file_and_line(tmp_path, log):
    text = (log / "mocap.csv").read_text().splitlines()
    text[10], text[11] = text[11], text[10]
    (log / "mocap.csv").write_text("\n".join(text) + "\n")
    line = _one_line(run_import(log, tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS,
                                "--imu-frame", "frd"), 1)
    assert f"{log / 'mocap.csv'}:12:" in line and "decreasing timestamp" in line


def test_overlapping_pieces_with_other_values_are_refused(tmp_path):
    write_csv_log(tmp_path / "log" / "p1", FLIGHT, rows=slice(0, 300))
    other = flight(seconds=3.0)
    other.gyro = other.gyro + 0.01
    write_csv_log(tmp_path / "log" / "p2", other, rows=slice(290, 600))
    line = _one_line(run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml", pieces="*/"),
                                "--mass", MASS), 1)
    assert "p2/imu.csv" in line and "repeats a timestamp of" in line and "p1/imu.csv" in line


def test_wrong_time_unit_is_caught_by_the_overlap_check(tmp_path, log):
    m = csv_map(tmp_path / "m.yaml")
    m.write_text(m.read_text().replace("time: time, time_unit: s", "time: time, time_unit: ms"))
    line = _one_line(run_import(log, tmp_path / "out", "--map", m, "--mass", MASS, "--imu-frame", "frd"), 1)
    assert "do not overlap in time" in line and "time_unit" in line


@pytest.mark.parametrize("args,expect", [
    (["--mass", "-1"], "--mass"),
    (["--imu-frame", "fru"], "--imu-frame"),
    (["--map", "no_such_preset"], "no such preset"),
    ([], "--mass"),
])
def test_bad_flags_exit_2(tmp_path, log, args, expect):
    base = ["--map", str(csv_map(tmp_path / "m.yaml")), "--mass", str(MASS)]
    if args and args[0] in base:
        i = base.index(args[0])
        base[i + 1] = args[1]
        args = []
    elif not args:
        base = base[:2]
    r = run_import(log, tmp_path / "out", *base, *args)
    assert r.returncode == 2, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and expect in r.stderr


def test_existing_output_needs_overwrite(tmp_path, log):
    args = [log, tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS, "--imu-frame", "frd"]
    assert run_import(*args).returncode == 0
    line = _one_line(run_import(*args), 2)
    assert "--overwrite" in line
    assert run_import(*args, "--overwrite").returncode == 0


@pytest.mark.parametrize("given", ["ned", "enu"])
def test_wrong_world_frame_names_the_fixing_flag(tmp_path, given):
    """An ENU log imported as NED (and the reverse) turns gravity over: one line, exit 1."""
    write_csv_log(tmp_path / "log", FLIGHT, "flu", "ned" if given == "enu" else "enu")
    line = _one_line(run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"),
                                "--mass", MASS, "--world-frame", given), 1)
    assert "gravity points up in the mocap world" in line
    assert f"pass --world-frame {'enu' if given == 'ned' else 'ned'}" in line
