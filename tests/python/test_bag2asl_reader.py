"""Sequential ROS1 reader (vid_eval.bag2asl.ros1reader): yields exactly what rosbags' indexed
Reader yields, holds back only what overlapping chunks need, and names the byte offset of damage."""
from __future__ import annotations

import pathlib
import struct

import numpy as np
import pytest
import yaml
from rosbags.rosbag1 import Reader

from vid_eval.bag2asl import bagio
from vid_eval.bag2asl.cli import main
from vid_eval.bag2asl.ros1reader import Ros1FormatError, Ros1Reader
from vid_eval.bag2asl.synthetic import BagWriter

T0 = 1_650_000_000_000_000_000
MS = 1_000_000


def jittered_bag(path: pathlib.Path, compression: str, n: int = 300, seed: int = 1) -> pathlib.Path:
    """Many small chunks; IMU record times jitter by +-3 ms so neighbouring chunks overlap in time;
    /late starts half way (its connection record first appears in a middle chunk) and shares
    record times with /ft (ties)."""
    rng = np.random.default_rng(seed)
    w = BagWriter(path, compression=compression)
    w.w.chunk_threshold = 2000
    for k in range(n):
        t = T0 + k * MS + int(rng.integers(-3 * MS, 3 * MS))
        w.write("/imu", "sensor_msgs/msg/Imu", t, w.imu(t, rng.normal(size=3), (0, 0, 9.81)))
        if k % 7 == 0:
            w.write("/ft", "robotiq_ft_sensor/msg/ft_sensor", T0 + k * MS, w.ft_sensor(rng.normal(size=3)))
        if k >= n // 2:
            w.write("/late", "uavmotor/msg/motordata", T0 + k * MS, w.motordata(t, t, [k, 1, 2, 3]))
    w.close()
    return path


def ordered_bag(path: pathlib.Path, n: int) -> pathlib.Path:
    """Written in record-time order (as rosbag record does), 32x24 images at 30 Hz + IMU."""
    w = BagWriter(path)
    w.w.chunk_threshold = 8000
    img = np.arange(32 * 24, dtype=np.uint8).reshape(24, 32)
    for k in range(n):
        t = T0 + k * 2_500_000
        w.write("/djiros/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (0, 0, k), (0, 0, 9.81)))
        if k % 13 == 0:
            w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t, w.image(t, "mono8", img))
    w.close()
    return path


def conn_key(c):
    return (c.id, c.topic, c.msgtype, c.msgdef.data, c.digest, c.msgcount)


def read_all(reader, conns=(), start=None, stop=None):
    return [(c.id, t, bytes(d)) for c, t, d in reader.messages(conns, start, stop)]


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_same_messages_as_rosbags_reader(tmp_path, compression):
    bag = jittered_bag(tmp_path / "b.bag", compression)
    with Reader(bag) as ref, Ros1Reader(bag) as seq:
        assert len(ref.chunk_infos) > 20  # really many chunks
        assert [conn_key(c) for c in seq.connections] == [conn_key(c) for c in ref.connections]
        assert (seq.start_time, seq.end_time, seq.message_count) == (ref.start_time, ref.end_time,
                                                                      ref.message_count)
        expected = read_all(ref)
        assert len(expected) == ref.message_count
        assert read_all(seq) == expected
        assert seq.position == seq.index_pos
        # a subset in a different order (tie-break follows it) and a time window
        pick_ref = [ref.connections[2], ref.connections[0]]
        pick_seq = [seq.connections[2], seq.connections[0]]
        for start, stop in [(T0 + 100 * MS, T0 + 250 * MS), (None, T0 + 40 * MS), (T0 + 280 * MS, None)]:
            expected = read_all(ref, pick_ref, start, stop)
            assert expected and read_all(seq, pick_seq, start, stop) == expected
        # the overlapping chunks were really reordered
        assert seq.peak_held_messages > 0 and seq.max_overlap_bytes > 0


def test_connection_first_seen_mid_file(tmp_path):
    bag = jittered_bag(tmp_path / "b.bag", "none")
    with Ros1Reader(bag) as seq:
        late = next(c for c in seq.connections if c.topic == "/late")
        first = next(t for c, t, _ in seq.messages([late]))
        assert first >= T0 + 150 * MS
        assert late.msgtype == "uavmotor/msg/motordata" and "int16[4] data" in late.msgdef.data
    # the connection record of /late sits inside a chunk after the first one
    data = bag.read_bytes()
    with Reader(bag) as ref:
        first_chunk_end = ref.chunk_infos[1].pos
    assert data.find(b"topic=/late") > first_chunk_end


def test_held_back_messages_do_not_grow_with_the_bag(tmp_path):
    small = ordered_bag(tmp_path / "small.bag", 400)
    big = ordered_bag(tmp_path / "big.bag", 1600)
    peaks = []
    for bag in (small, big):
        with Reader(bag) as ref, Ros1Reader(bag) as seq:
            assert read_all(seq) == read_all(ref)
            assert seq.max_overlap_bytes == 0  # time-ordered chunks never wait for later ones
            peaks.append((seq.peak_held_messages, seq.peak_held_bytes, len(ref.chunk_infos)))
    assert peaks[1][2] > 3 * peaks[0][2]  # 4x the chunks ...
    assert peaks[1][0] <= peaks[0][0] + 2 and peaks[1][1] <= peaks[0][1] + 2000  # ... same peak (one chunk)


def run_error(capsys, argv) -> str:
    assert main(argv + ["--no-progress", "--mass", "1"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("vid-bag2asl: error: ") and "\n" not in err, err
    return err


def patch_u32(data: bytearray, pos: int, value: int) -> None:
    data[pos:pos + 4] = struct.pack("<I", value)


def chunk_layout(bag: pathlib.Path, k: int) -> tuple[int, int, int]:
    """(record position, data length field position, data position) of chunk k."""
    with Reader(bag) as ref:
        pos = ref.chunk_infos[k].pos
        datapos = ref.chunks[pos].datapos
        return pos, datapos - 4, datapos


def test_truncated_file_names_offset(tmp_path, capsys):
    bag = ordered_bag(tmp_path / "full.bag", 400)
    data = bag.read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(data[: len(data) // 2])
    err = run_error(capsys, [str(cut), str(tmp_path / "out")])
    assert f"{cut}: corrupt or truncated bag: bag header record at byte 13: index position" in err
    assert f"lies outside the file (size {len(data) // 2})" in err


def test_truncated_chunk_names_offset(tmp_path, capsys):
    bag = ordered_bag(tmp_path / "b.bag", 400)
    pos, len_pos, _ = chunk_layout(bag, 3)
    data = bytearray(bag.read_bytes())
    patch_u32(data, len_pos, len(data))  # chunk claims more bytes than the file has
    bad = tmp_path / "bad.bag"
    bad.write_bytes(bytes(data))
    err = run_error(capsys, [str(bad), str(tmp_path / "out"), "--allow-no-rotors"])  # a bag without rotors
    assert f"{bad}: corrupt or truncated bag: truncated record at byte {pos}" in err


def test_truncated_message_record_names_chunk_and_offset(tmp_path, capsys):
    bag = ordered_bag(tmp_path / "b.bag", 400)
    pos, _, datapos = chunk_layout(bag, 2)
    data = bytearray(bag.read_bytes())
    # the first record in the (uncompressed) chunk: its data length -> beyond the chunk
    (hlen,) = struct.unpack_from("<I", data, datapos)
    if b"op=\x07" in data[datapos + 4:datapos + 4 + hlen]:  # skip a connection record
        (dlen,) = struct.unpack_from("<I", data, datapos + 4 + hlen)
        inner = 8 + hlen + dlen
        (hlen,) = struct.unpack_from("<I", data, datapos + inner)
    else:
        inner = 0
    patch_u32(data, datapos + inner + 4 + hlen, 10**8)
    bad = tmp_path / "bad.bag"
    bad.write_bytes(bytes(data))
    err = run_error(capsys, [str(bad), str(tmp_path / "out"), "--allow-no-rotors"])
    assert (f"{bad}: corrupt or truncated bag: truncated record in chunk at byte {pos}, "
            f"offset {inner} in the decompressed chunk") in err


def test_unindexed_bag(tmp_path, capsys):
    bag = ordered_bag(tmp_path / "b.bag", 50)
    data = bytearray(bag.read_bytes())
    i = data.index(b"index_pos=") + len(b"index_pos=")
    data[i:i + 8] = bytes(8)
    bad = tmp_path / "active.bag"
    bad.write_bytes(bytes(data))
    err = run_error(capsys, [str(bad), str(tmp_path / "out")])
    assert "not indexed" in err and "rosbag reindex" in err
    with pytest.raises(Ros1FormatError, match="at byte 13"):
        Ros1Reader(bad).open()


def vid_bag_topic_by_topic(path: pathlib.Path) -> pathlib.Path:
    """Each topic written over the whole time span before the next: chunks overlap completely."""
    w = BagWriter(path)
    w.w.chunk_threshold = 3000
    rng = np.random.default_rng(5)
    for k in range(40):
        t = T0 + k * 33 * MS
        w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t,
                w.image(t, "mono8", rng.integers(0, 256, (12, 16), dtype=np.uint8)))
    for k in range(500):
        t = T0 + k * 2_500_000
        w.write("/djiros/imu", "sensor_msgs/msg/Imu", t, w.imu(t, rng.normal(size=3), (0, 0, 9.81)))
    for k in range(130):
        for m in range(4):
            t = T0 + k * 10 * MS + m * MS
            w.write(f"/m100withm3508/m3508_m{m + 1}", "uavmotor/msg/m3508", t, w.m3508(t, t, m + 1, 0, 100 * m + k))
    w.close()
    return path


def test_out_of_order_bag_same_output_with_either_reader(tmp_path, capsys, monkeypatch):
    bag = vid_bag_topic_by_topic(tmp_path / "b.bag")
    with Ros1Reader(bag) as seq:
        bound = seq.max_overlap_bytes
    assert bound > 0
    outs = {}
    for name, limit in [("sequential", bound), ("indexed", bound - 1)]:
        monkeypatch.setattr(bagio, "MAX_OVERLAP_BYTES", limit)
        out = tmp_path / name
        assert main([str(bag), str(out), "--no-progress", "--mass", "1"]) == 0
        summary = yaml.safe_load((out / "bag2asl.yaml").read_text())
        assert summary["bag_reader"]["reader"].startswith(name)
        outs[name] = {p.relative_to(out).as_posix(): p.read_bytes() for p in sorted(out.rglob("*"))
                      if p.is_file() and p.name != "bag2asl.yaml"}
    err = capsys.readouterr().err
    assert "chunks overlap in time" in err and "indexed reader" in err
    assert outs["sequential"] == outs["indexed"]
    assert len([k for k in outs["indexed"] if k.endswith(".png")]) == 40
    rotor = outs["indexed"]["mav0/rotor0/data.csv"].decode().splitlines()
    # one row per complete cycle (130 cycles), at its newest stamp (motor 4, +3 ms)
    assert len(rotor) == 1 + 130 and rotor[1] == f"{T0 + 3 * MS},0,100,200,300"
