"""vid-bag2asl error handling: each failure is one line on stderr and exit status 1."""
from __future__ import annotations

import pathlib
import subprocess
import sys

import numpy as np
import pytest
from rosbags.rosbag1 import Reader

from vid_eval.bag2asl import sinks
from vid_eval.bag2asl.cli import main
from vid_eval.bag2asl.synthetic import BagWriter

T0 = 1_650_000_000_000_000_000


def small_bag(path: pathlib.Path, compression: str = "none", n: int = 200, extra=None, rotors=True) -> pathlib.Path:
    w = BagWriter(path, compression=compression)
    rng = np.random.default_rng(3)
    for k in range(n):
        t = T0 + k * 10_000_000
        w.write("/djiros/imu", "sensor_msgs/msg/Imu", t, w.imu(t, rng.normal(size=3), (0, 0, 9.81)))
        w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t,
                w.image(t, "mono8", rng.integers(0, 256, (60, 80), dtype=np.uint8)))
        if rotors:
            w.write("/m100withm3508/target_rpm", "uavmotor/msg/motordata", t, w.motordata(t, t, [3000] * 4))
    if extra:
        extra(w)
    w.close()
    return path


def run_error(capsys, argv) -> str:
    assert main(argv + ["--no-progress", "--mass", "1"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("vid-bag2asl: error: ") and "\n" not in err, err
    return err


def test_missing_topic_lists_bag_topics(tmp_path, capsys):
    bag = tmp_path / "b.bag"
    w = BagWriter(bag)
    w.write("/some/other", "sensor_msgs/msg/Imu", T0, w.imu(T0, (0, 0, 0), (0, 0, 0)))
    w.write("/djiros/imu", "sensor_msgs/msg/Imu", T0, w.imu(T0, (0, 0, 0), (0, 0, 0)))
    w.close()
    err = run_error(capsys, [str(bag), str(tmp_path / "out")])
    assert "required topic missing" in err
    assert "cam0 needs /camera/infra1/image_rect_raw" in err and "cam0 needs /synced/infra1" in err
    assert "the bag has: /djiros/imu (sensor_msgs/Imu), /some/other (sensor_msgs/Imu)" in err


def test_unknown_type_without_definition(tmp_path, capsys):
    def add_undefined(w):
        conn = w.w.add_connection("/vicon/m100/m100", "vicon/msg/Mystery", msgdef="", md5sum="0" * 32)
        w.w.write(conn, T0, b"\x00" * 8)

    bag = small_bag(tmp_path / "b.bag", extra=add_undefined)
    err = run_error(capsys, [str(bag), str(tmp_path / "out")])
    assert "topic /vicon/m100/m100: unknown message type vicon/Mystery" in err


def test_wrong_type_on_a_stream_topic(tmp_path, capsys):
    def add_wrong(w):
        w.write("/vicon/m100/m100", "sensor_msgs/msg/Imu", T0, w.imu(T0, (0, 0, 0), (0, 0, 0)))

    bag = small_bag(tmp_path / "b.bag", extra=add_wrong)
    err = run_error(capsys, [str(bag), str(tmp_path / "out")])
    assert "topic /vicon/m100/m100 has type sensor_msgs/Imu" in err and "kind groundtruth" in err


def test_unsupported_image_encoding(tmp_path, capsys):
    bag = tmp_path / "b.bag"
    w = BagWriter(bag)
    w.write("/djiros/imu", "sensor_msgs/msg/Imu", T0, w.imu(T0, (0, 0, 0), (0, 0, 0)))
    w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", T0,
            w.image(T0, "bayer_rggb8", np.zeros((2, 2), np.uint8)))
    w.close()
    err = run_error(capsys, [str(bag), str(tmp_path / "out"), "--allow-no-rotors"])
    assert "image encoding 'bayer_rggb8' not supported" in err and "mono16" in err


def test_truncated_bag(tmp_path, capsys):
    bag = small_bag(tmp_path / "full.bag")
    cut = tmp_path / "cut.bag"
    data = bag.read_bytes()
    cut.write_bytes(data[: len(data) * 2 // 3])
    err = run_error(capsys, [str(cut), str(tmp_path / "out")])
    assert f"{cut}: corrupt or truncated bag" in err


def _message_pos(bag: pathlib.Path, k: int) -> tuple[int, int]:
    with Reader(bag) as r:
        entry = r.indexes[r.connections[0].id][k]
        return r.chunks[entry.chunk_pos].datapos, entry.offset


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_corrupt_chunk(tmp_path, capsys, compression):
    bag = small_bag(tmp_path / "b.bag", compression)
    datapos, offset = _message_pos(bag, 100)
    data = bytearray(bag.read_bytes())
    # uncompressed: break the message record's header; compressed: break the chunk's stream
    start = datapos + offset if compression == "none" else datapos
    data[start:start + 8] = b"\xff" * 8
    bad = tmp_path / "bad.bag"
    bad.write_bytes(bytes(data))
    err = run_error(capsys, [str(bad), str(tmp_path / "out")])
    assert f"{bad}: corrupt or truncated bag" in err


def test_not_a_bag(tmp_path, capsys):
    bad = tmp_path / "x.bag"
    bad.write_bytes(b"hello, not a bag\n" * 10)
    assert "corrupt or truncated bag" in run_error(capsys, [str(bad), str(tmp_path / "out")])
    assert "no such file" in run_error(capsys, [str(tmp_path / "missing.bag"), str(tmp_path / "out")])


@pytest.mark.parametrize("victim", ["imu0/data.csv", ".png", "vehicle.yaml"])
def test_disk_full_names_the_file(tmp_path, capsys, monkeypatch, victim):
    """/dev/full fails every write with ENOSPC, like a full disk."""
    bag = small_bag(tmp_path / "b.bag")
    real_open = sinks._open_out

    def open_out(path, mode):
        if str(path).endswith(victim):
            return open("/dev/full", mode)
        return real_open(path, mode)

    monkeypatch.setattr(sinks, "_open_out", open_out)
    err = run_error(capsys, [str(bag), str(tmp_path / "out")])
    assert "output disk full (ENOSPC) while writing" in err
    assert err.split("while writing ")[1].endswith(victim)


def test_bad_topic_map_names_file_and_line(tmp_path, capsys):
    bag = small_bag(tmp_path / "b.bag", n=2)
    tmap = tmp_path / "map.yaml"
    tmap.write_text("streams:\n  cam0: {kind: image, topics: [/a]\n  imu0: [\n")
    err = run_error(capsys, [str(bag), str(tmp_path / "out"), "--topics", str(tmap)])
    assert f"{tmap}: line" in err and "invalid YAML" in err
    tmap.write_text("streams:\n  cam0: {kind: camera, topics: [/a]}\n")
    err = run_error(capsys, [str(bag), str(tmp_path / "out"), "--topics", str(tmap)])
    assert f"{tmap}: default.streams.cam0.kind: expected one of" in err


def test_bag_without_rotors_needs_the_flag(tmp_path, capsys):
    """No rotor-speed topic: one line naming the topics looked for; --allow-no-rotors converts."""
    bag = small_bag(tmp_path / "b.bag", n=2, rotors=False)
    err = run_error(capsys, [str(bag), str(tmp_path / "out")])
    assert "no rotor speeds in the bag (rotor0 needs /m100withm3508/m3508_m1+" in err
    assert "/m100withm3508/target_rpm" in err and "--allow-no-rotors" in err
    assert main([str(bag), str(tmp_path / "out"), "--no-progress", "--mass", "1", "--allow-no-rotors"]) == 0
    assert not (tmp_path / "out" / "mav0" / "rotor0").exists()


def test_jobs_must_be_positive(capsys):
    for bad in ("0", "-2", "x"):
        with pytest.raises(SystemExit) as e:
            main(["a.bag", "out", "--jobs", bad])
        assert e.value.code == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith("vid-bag2asl: error: argument --jobs: expected a whole number >= 1") and "\n" not in err


def test_existing_output_needs_overwrite(tmp_path, capsys):
    bag = small_bag(tmp_path / "b.bag", n=2)
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--no-progress", "--mass", "1"]) == 0
    capsys.readouterr()
    assert "--overwrite" in run_error(capsys, [str(bag), str(out)])
    assert main([str(bag), str(out), "--no-progress", "--mass", "1", "--overwrite"]) == 0


def test_console_script_exit_status(tmp_path):
    exe = pathlib.Path(sys.executable).parent / "vid-bag2asl"
    res = subprocess.run([str(exe), str(tmp_path / "none.bag"), str(tmp_path / "out")],
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 1
    assert res.stderr.count("\n") == 1 and "no such file" in res.stderr
