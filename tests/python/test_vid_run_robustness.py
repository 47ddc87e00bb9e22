"""vid_run robustness (issue 6 item 5): bad images skip their frame (warned, counted),
dynamics mode without thrust data is a one-line error suggesting --mode imu, SIGINT keeps the
flushed outputs and writes an "interrupted" summary (exit 130), and a diverging estimator
(provoked by corrupting the data, not by mocking) is reported in summary.json and exit 3.
"""
import io

import numpy as np
import pytest
from PIL import Image

from test_vid_run_helpers import (REPO, interrupt_vid_run, link_copy, replace_file, simulate_cached, summary, tum_rows,
                                  vid_run)


@pytest.fixture(scope="module")
def rendered():
    """12 s of config/sim/vid17_like_short.yaml with images (seed 1; shared with test_vid_run.py)."""
    return simulate_cached("vid17_like_short.yaml", 12.0, 1, features_only=False)


@pytest.fixture(scope="module")
def long_feat():
    """60 s of config/sim/vid17_like.yaml, features only (a run long enough to interrupt)."""
    return simulate_cached("vid17_like.yaml", 60.0, 4, features_only=True)


@pytest.fixture(scope="module")
def euroc_feat():
    return simulate_cached("euroc_like_short.yaml", 10.0, 2, features_only=True)


def image_rows(dataset, cam):
    lines = (dataset / "mav0" / cam / "data.csv").read_text().splitlines()
    return [line.split(",") for line in lines if line and not line.startswith("#")]


def png_bytes(width, height):
    buf = io.BytesIO()
    Image.fromarray(np.full((height, width), 128, np.uint8)).save(buf, format="PNG")
    return buf.getvalue()


def test_bad_images_skip_their_frame(rendered, tmp_path):
    bad = link_copy(rendered, tmp_path / "bad")
    cam0, cam1 = image_rows(bad, "cam0"), image_rows(bad, "cam1")
    # frame 20: left image is not a PNG; frame 40: right image has the wrong size.
    replace_file(bad / "mav0" / "cam0" / "data" / cam0[20][1].strip(), b"this is not a png")
    replace_file(bad / "mav0" / "cam1" / "data" / cam1[40][1].strip(), png_bytes(320, 240))
    out = tmp_path / "run"
    r = vid_run(bad, out, "--config", str(REPO / "config" / "sim"))
    assert r.returncode == 0, r.stderr
    s = summary(out)
    assert s["status"] == "ok"
    assert s["counts"]["images_unreadable"] == 1
    assert s["counts"]["images_wrong_size"] == 1
    assert s["counts"]["frames_skipped_bad_image"] == 2
    assert "unreadable image (not a decodable image" in r.stderr and "libpng" not in r.stderr
    assert "image is 320x240, calibration says 640x480; frame skipped" in r.stderr
    # The skipped frames are not tracked: two fewer timing rows than camera frames.
    assert s["timing"]["tracking"]["count"] <= s["counts"]["camera_frames"] - 2
    assert len(tum_rows(out / "trajectory_tum.txt")) > 1000


def test_missing_image_file_is_counted(rendered, tmp_path):
    bad = link_copy(rendered, tmp_path / "missing")
    cam0 = image_rows(bad, "cam0")
    missing = bad / "mav0" / "cam0" / "data" / cam0[10][1].strip()
    missing.unlink()
    out = tmp_path / "run"
    r = vid_run(bad, out, "--config", str(REPO / "config" / "sim"), "--end", "3")
    assert r.returncode == 0, r.stderr
    assert summary(out)["counts"]["images_missing"] == 1
    assert r.stderr.splitlines() == [f"vid_run: warning: {missing}: missing image file; frame skipped"]


def test_many_bad_frames_sum_up_in_one_line(rendered, tmp_path):
    """Past 5 skipped frames the rest are one line at the end, with the counts."""
    bad = link_copy(rendered, tmp_path / "bad")
    cam0 = image_rows(bad, "cam0")
    for k in range(10, 30, 2):
        (bad / "mav0" / "cam0" / "data" / cam0[k][1].strip()).unlink()
    out = tmp_path / "run"
    r = vid_run(bad, out, "--config", str(REPO / "config" / "sim"), "--end", "3")
    assert r.returncode == 0, r.stderr
    lines = r.stderr.splitlines()
    assert len(lines) == 6 and all("missing image file; frame skipped" in line for line in lines[:5]), r.stderr
    assert "10 camera frames skipped in all, 5 more than warned above (10 missing, 0 unreadable" in lines[5]
    assert summary(out)["counts"]["images_missing"] == 10


def test_strict_makes_a_bad_frame_an_error_and_keeps_outputs(rendered, tmp_path):
    bad = link_copy(rendered, tmp_path / "bad")
    cam0 = image_rows(bad, "cam0")
    victim = bad / "mav0" / "cam0" / "data" / cam0[60][1].strip()
    replace_file(victim, png_bytes(320, 240))
    out = tmp_path / "run"
    r = vid_run(bad, out, "--config", str(REPO / "config" / "sim"), "--strict")
    assert r.returncode == 1
    assert r.stderr.splitlines() == [f"vid_run: error: {victim}: image is 320x240, calibration says 640x480 "
                                     "(--strict: a bad camera frame is an error)"]
    s = summary(out)
    assert s["status"] == "error" and str(victim) in s["status_message"]
    assert len(tum_rows(out / "trajectory_tum.txt")) > 100  # estimates before frame 60 are kept


@pytest.mark.parametrize("how", [["--mode", "dynamics"], ["--config", "vid_dataset"]])
def test_dynamics_without_thrust_data_is_one_line_error(how, euroc_feat, tmp_path):
    args = [how[0], str(REPO / "config" / how[1]) if how[0] == "--config" else how[1]]
    r = vid_run(euroc_feat, tmp_path / "run", *args)
    assert r.returncode == 1
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, r.stderr
    assert "--mode imu" in lines[0]
    assert "rotor" in lines[0]


def test_sigint_keeps_outputs_and_writes_summary(long_feat, tmp_path):
    out = tmp_path / "run"
    traj = out / "trajectory_tum.txt"
    returncode, err = interrupt_vid_run(long_feat, out, 2000)  # 5 s of 400 Hz estimates
    assert returncode == 130, err
    s = summary(out)
    assert s["status"] == "interrupted"
    rows = tum_rows(traj)
    assert len(rows) >= 2000
    assert s["counts"]["estimates"] == len(rows)  # every estimate reached the file
    # Stopped early: well short of the 60 s of data.
    assert s["data_duration_s"] < 55.0
    assert len((out / "state.csv").read_text().splitlines()) == len(rows) + 1
    assert "interrupted" in err


def corrupt_csv_rows(path, t_from_ns, t_to_ns, columns, value):
    """Rewrite a real copy of a data.csv with `value` in `columns` for rows in [t_from, t_to]."""
    lines = path.read_text().splitlines()
    out = []
    for line in lines:
        if line and not line.startswith("#"):
            f = line.split(",")
            if t_from_ns <= int(f[0]) <= t_to_ns:
                for c in columns:
                    f[c] = repr(value)
                line = ",".join(f)
        out.append(line)
    replace_file(path, ("\n".join(out) + "\n").encode())


def t_first(path):
    for line in path.read_text().splitlines():
        if line and not line.startswith("#"):
            return int(line.split(",")[0])


def test_divergence_from_absurd_imu_data(euroc_feat, tmp_path):
    """imu mode: 1 s of 5000 m/s^2 accelerometer readings mid-run drives the velocity far
    beyond any bound; with --on-divergence stop the run stops, says so in summary.json and exits
    3 (the default re-initializes: test_vid_run_reinit.py)."""
    bad = link_copy(euroc_feat, tmp_path / "bad")
    imu = bad / "mav0" / "imu0" / "data.csv"
    t0 = t_first(imu)
    corrupt_csv_rows(imu, t0 + 4_000_000_000, t0 + 5_000_000_000, [4, 5, 6], 5000.0)
    out = tmp_path / "run"
    r = vid_run(bad, out, "--mode", "imu", "--on-divergence", "stop")
    assert r.returncode == 3, r.stderr
    s = summary(out)
    assert s["status"] == "diverged"
    assert s["status_message"]
    assert "diverged" in r.stderr
    rows = tum_rows(out / "trajectory_tum.txt")
    assert len(rows) > 0
    assert float(rows[-1][0]) - t0 * 1e-9 < 6.0  # stopped soon after the corruption


def test_divergence_from_absurd_rotor_speeds(rendered, tmp_path):
    """dynamics mode: rotor speeds of 1e6 rpm (thrust ~ 1e6 N) for 0.5 s mid-run."""
    bad = link_copy(rendered, tmp_path / "bad")
    rotor = bad / "mav0" / "rotor0" / "data.csv"
    t0 = t_first(rotor)
    corrupt_csv_rows(rotor, t0 + 3_000_000_000, t0 + 3_500_000_000, [1, 2, 3, 4], 1.0e6)
    out = tmp_path / "run"
    r = vid_run(bad, out, "--config", str(REPO / "config" / "sim"), "--features", "feat0")
    assert r.returncode == 3, r.stderr
    s = summary(out)
    assert s["status"] == "diverged"
    assert s["mode"] == "dynamics"
