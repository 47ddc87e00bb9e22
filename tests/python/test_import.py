"""vid-import round trips: one known flight written in every axis convention, quaternion order,
time unit and file type, imported, read back with the package's loaders, equal to the flight in
the project's frames; vid_info reads every folder."""
from __future__ import annotations

import itertools
import json
import subprocess

import numpy as np
import pytest

from test_import_synth import (MASS, csv_map, flight, hdf5_map, run_import, write_csv_log, write_hdf5_log)
from vid_eval.tools.loaders import load_imu, load_vehicle
from vid_eval.tools.table_reader import read_table

FLIGHT = flight()


def _read_folder(out):
    mav0 = out / "mav0"
    imu = load_imu(mav0 / "imu0" / "data.csv")
    thrust = read_table(mav0 / "thrust0" / "data.csv", {2})
    gt = read_table(mav0 / "state_groundtruth_estimate0" / "data.csv", {17})
    return imu, thrust, gt


def _assert_equal_to_flight(out, f, t_tol_ns=0, v_tol=1e-12, velocity_tol=1e-12):
    imu, thrust, gt = _read_folder(out)
    assert np.abs(imu.t_ns - f.t_ns).max() <= t_tol_ns
    np.testing.assert_allclose(imu.gyro, f.gyro, atol=v_tol, rtol=0)
    np.testing.assert_allclose(imu.accel, f.accel, atol=v_tol, rtol=0)
    np.testing.assert_allclose(thrust.values[:, 0], MASS * f.thrust, atol=v_tol * MASS, rtol=1e-14)
    assert np.abs(gt.t_ns - f.t_ns).max() <= t_tol_ns
    np.testing.assert_allclose(gt.values[:, 0:3], f.p, atol=v_tol, rtol=0)
    q = gt.values[:, 3:7]
    assert np.all(q[:, 0] >= 0)
    np.testing.assert_allclose(q, f.q_wxyz(), atol=1e-12, rtol=0)
    np.testing.assert_allclose(gt.values[:, 7:10], f.v, atol=velocity_tol, rtol=0)
    np.testing.assert_array_equal(gt.values[:, 10:16], 0.0)


@pytest.mark.parametrize("imu,world,order,unit", [
    (imu, world, order, unit) for (imu, world), (order, unit) in zip(
        itertools.product(("flu", "frd"), ("enu", "nwu", "ned")),
        itertools.cycle([("wxyz", "s"), ("xyzw", "ns"), ("wxyz", "us")]))])
def test_csv_round_trip_in_every_convention(tmp_path, imu, world, order, unit):
    write_csv_log(tmp_path / "log", FLIGHT, imu, world, order, unit)
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "map.yaml", order, unit),
                   "--mass", MASS, "--imu-frame", imu, "--world-frame", world)
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    _assert_equal_to_flight(tmp_path / "out", FLIGHT)
    assert f"IMU {imu} -> flu" in r.stdout and f"mocap world {world} -> enu" in r.stdout
    vehicle = load_vehicle(tmp_path / "out" / "mav0" / "vehicle.yaml")
    assert vehicle.mass_kg == MASS and vehicle.gravity == 9.81


@pytest.mark.parametrize("int_ns", [False, True])
def test_hdf5_round_trip_frd_ned(tmp_path, int_ns):
    """Blackbird-like HDF5 (2-D datasets, thrust 3-vector along -z of an FRD IMU); float seconds
    lose a fraction of a microsecond at 1.7e9 s, integer nanoseconds nothing."""
    write_hdf5_log(tmp_path / "log", FLIGHT, "frd", "ned", "xyzw", int_ns=int_ns)
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", hdf5_map(tmp_path / "m.yaml", "xyzw",
                                                                          "ns" if int_ns else "s"),
                   "--mass", MASS, "--imu-frame", "frd", "--world-frame", "ned")
    assert r.returncode == 0, r.stderr
    # no mocap velocity in this log: differentiated from the position (10 Hz low-pass), so not exact
    _assert_equal_to_flight(tmp_path / "out", FLIGHT, t_tol_ns=0 if int_ns else 500, velocity_tol=0.02)
    assert "velocity differentiated from the position" in r.stdout


def test_velocity_from_position_away_from_the_ends(tmp_path):
    """Without mocap velocity the derivative of the smoothed position is within 1 mm/s of the
    true velocity away from the first and last second (filter edges)."""
    write_csv_log(tmp_path / "log", FLIGHT, with_velocity=False)
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml", with_velocity=False),
                   "--mass", MASS)
    assert r.returncode == 0, r.stderr
    gt = read_table(tmp_path / "out" / "mav0" / "state_groundtruth_estimate0" / "data.csv", {17})
    inner = slice(200, -200)
    assert np.abs(gt.values[inner, 7:10] - FLIGHT.v[inner]).max() < 1e-3


def test_pieces_are_joined_by_time_and_duplicates_counted(tmp_path):
    """Three pieces in folders named against their time order; the second repeats the first's
    last 5 rows (dropped, counted); the folder equals the unsplit flight."""
    n = FLIGHT.t_ns.size
    write_csv_log(tmp_path / "log" / "c_first", FLIGHT, "frd", "nwu", rows=slice(0, 1000))
    write_csv_log(tmp_path / "log" / "a_second", FLIGHT, "frd", "nwu", rows=slice(995, 2500))
    write_csv_log(tmp_path / "log" / "b_third", FLIGHT, "frd", "nwu", rows=slice(2500, n))
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml", pieces="*/"),
                   "--mass", MASS, "--imu-frame", "frd", "--world-frame", "nwu")
    assert r.returncode == 0, r.stderr
    _assert_equal_to_flight(tmp_path / "out", FLIGHT)
    assert "3 piece(s)" in r.stdout
    assert "5 duplicate rows dropped" in r.stdout


def test_the_report_states_rate_span_gaps_and_default_noise(tmp_path):
    keep = np.r_[0:1000, 1010:FLIGHT.t_ns.size]  # a 55 ms gap
    write_csv_log(tmp_path / "log", FLIGHT, rows=keep)
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS,
                   "--gyro-noise", "0.002")
    assert r.returncode == 0, r.stderr
    imu_line = next(line for line in r.stdout.splitlines() if line.startswith("imu0:"))
    span = (FLIGHT.t_ns[-1] - FLIGHT.t_ns[0]) * 1e-9
    assert f"{keep.size} samples" in imu_line and f"span {span:.3f} s" in imu_line
    assert "gaps: 1 longer than 1.5 x 5 ms (largest 55 ms)" in imu_line
    sensor = (tmp_path / "out" / "mav0" / "imu0" / "sensor.yaml").read_text()
    assert "gyroscope_noise_density: 0.002\n" in sensor
    rate = float((keep.size - 1) / span)
    assert f"rate_hz: {round(rate, 6)!r}" in sensor
    assert "defaulted to EuRoC's ADIS16448" in r.stdout and "gyroscope_noise_density," not in r.stdout


def test_vid_info_reads_the_folder(tmp_path, cpp_program):
    write_hdf5_log(tmp_path / "log", FLIGHT, "frd", "enu", "xyzw")
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", hdf5_map(tmp_path / "m.yaml"), "--mass", MASS,
                   "--imu-frame", "frd")
    assert r.returncode == 0, r.stderr
    info = subprocess.run([str(cpp_program("vid_info")), "--json", str(tmp_path / "out")], capture_output=True,
                          text=True)
    assert info.returncode == 0, info.stderr
    doc = json.loads(info.stdout)
    text = json.dumps(doc)
    for stream in ("imu0", "thrust0", "state_groundtruth_estimate0"):
        assert stream in text
    assert str(FLIGHT.t_ns.size) in text


def test_rotor_speeds_write_rotor0(tmp_path, cpp_program):
    """A rotors stream -> rotor0/data.csv + sensor.yaml, coefficients into vehicle.yaml."""
    log = tmp_path / "log"
    log.mkdir()
    n = np.sqrt(MASS * FLIGHT.thrust / (4 * 2.5e-7))
    with open(log / "esc.csv", "w") as fh:
        fh.write("t_us,m1,m2,m3,m4\n")
        for t, x in zip(FLIGHT.t_ns, n):
            x = repr(float(x))
            fh.write(f"{t // 1000},{x},{x},{x},{x}\n")
    write_csv_log(log, FLIGHT)
    (tmp_path / "m.yaml").write_text(
        "imu: {file: imu.csv, time: t, gyro: [wx, wy, wz], accel: [ax, ay, az]}\n"
        "rotors: {file: esc.csv, time: t_us, time_unit: us, speeds: [m1, m2, m3, m4], unit: rpm}\n")
    r = run_import(log, tmp_path / "out", "--map", tmp_path / "m.yaml", "--mass", MASS,
                   "--rotor-coefficients", "2.5e-7,2.5e-7,2.5e-7,2.5e-7")
    assert r.returncode == 0, r.stderr
    rotor = read_table(tmp_path / "out" / "mav0" / "rotor0" / "data.csv", {5})
    np.testing.assert_array_equal(rotor.t_ns, FLIGHT.t_ns)
    np.testing.assert_allclose(rotor.values[:, 0], n, rtol=1e-15)
    assert load_vehicle(tmp_path / "out" / "mav0" / "vehicle.yaml").rotor_thrust_coefficients == [2.5e-7] * 4
    info = subprocess.run([str(cpp_program("vid_info")), str(tmp_path / "out")], capture_output=True, text=True)
    assert info.returncode == 0, info.stderr
    assert "4 thrust coefficients" in info.stdout
