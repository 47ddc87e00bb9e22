"""bench/peers/real_data.py window(): a time window of a dataset folder for the real-flight peer
table (compare_real.py). Needs no peer build and no real data:

    .venv/bin/python -m pytest bench/peers/test_real_data.py -q
"""
from __future__ import annotations

import pathlib
import sys

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from real_data import window  # noqa: E402

T0 = 1_525_745_865_001_655_296  # a real epoch stamp: the cut must be exact in int64 ns


def make_seq(root: pathlib.Path) -> pathlib.Path:
    m = root / "seq" / "mav0"
    for s, dt in (("imu0", 10_000_000), ("cam0", 33_333_333), ("cam1", 33_333_333), ("thrust0", 10_000_000),
                  ("state_groundtruth_estimate0", 10_000_000), ("force0", 10_000_000)):
        (m / s).mkdir(parents=True)
        rows = [f"{T0 + k * dt},{k}" for k in range(int(3e9 // dt) + 1)]
        (m / s / "data.csv").write_text("#timestamp [ns],v\n" + "\n".join(rows) + "\n")
        (m / s / "sensor.yaml").write_text(f"name: {s}\n")
    (m / "cam0" / "data").mkdir()
    (m / "cam0" / "data" / "x.png").write_bytes(b"png")
    (m / "vehicle.yaml").write_text("mass_kg: 0.915\n")
    return root / "seq"


def stamps(csv: pathlib.Path):
    return [int(ln.split(",")[0]) for ln in csv.read_text().splitlines() if ln and not ln.startswith("#")]


def test_window_cuts_every_stream_by_time(tmp_path):
    seq = make_seq(tmp_path)
    w = window(seq, tmp_path / "w", 1.0, 1.5)
    for s in ("imu0", "cam0", "thrust0", "state_groundtruth_estimate0", "force0"):
        t = stamps(w / "mav0" / s / "data.csv")
        assert t[0] >= T0 + 1_000_000_000 and t[-1] <= T0 + 2_500_000_000, s
        assert t[0] - (T0 + 1_000_000_000) < 34_000_000 and (T0 + 2_500_000_000) - t[-1] < 34_000_000, s
        assert (w / "mav0" / s / "data.csv").read_text().startswith("#timestamp [ns],v\n")
        assert (w / "mav0" / s / "sensor.yaml").read_text() == f"name: {s}\n"
    assert len(stamps(w / "mav0" / "imu0" / "data.csv")) == 151  # 1.0 .. 2.5 s at 100 Hz, both ends
    assert (w / "mav0" / "cam0" / "data").is_symlink()
    assert (w / "mav0" / "cam0" / "data" / "x.png").read_bytes() == b"png"
    assert (w / "mav0" / "vehicle.yaml").read_text() == "mass_kg: 0.915\n"


def test_window_is_remade_only_when_asked_for_another(tmp_path):
    seq = make_seq(tmp_path)
    w = window(seq, tmp_path / "w", 0.0, 1.0)
    (w / "mav0" / "marker").write_text("kept")
    window(seq, tmp_path / "w", 0.0, 1.0)
    assert (w / "mav0" / "marker").exists()
    window(seq, tmp_path / "w", 0.5, 1.0)
    assert not (w / "mav0" / "marker").exists()
    assert stamps(w / "mav0" / "imu0" / "data.csv")[0] == T0 + 500_000_000


def test_window_outside_the_data_is_refused(tmp_path):
    seq = make_seq(tmp_path)
    with pytest.raises(SystemExit, match="no rows in the window"):
        window(seq, tmp_path / "w", 10.0, 5.0)
