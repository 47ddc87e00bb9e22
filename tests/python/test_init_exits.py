"""Issue 49 step 1, honest exits: a run that never initializes or uses no camera frame exits
non-zero with one line saying why (apps/vid_run/README.md "Exit codes"); a constant turn is not
a still window (fast_yaw started mid-yaw used to initialize at once with its 3 rad/s yaw taken
as gyro bias, end metres off and report ok); --init groundtruth with the camera-IMU time offset
estimated uses the camera frames (it used to skip every one and show a perfect-looking ATE)."""
import shutil

import numpy as np

from test_vid_run_helpers import REPO, link_copy, simulate_cached, summary, vid_run

CONFIG = REPO / "config" / "sim"


def error_lines(stderr: str) -> list:
    return [line for line in stderr.splitlines() if "error" in line]


def test_fast_yaw_mid_turn_is_not_still(tmp_path):
    """Started 8 s in (3 rad/s yaw), the still/hover test must refuse every window: exit 4,
    one line naming the turn, status waiting_for_init."""
    seq = simulate_cached("fast_yaw.yaml", 12.0, 1, True)
    r = vid_run(seq, tmp_path / "run", "--config", str(CONFIG), "--init", "static", "--start", "8")
    assert r.returncode == 4, r.stderr
    lines = error_lines(r.stderr)
    assert len(lines) == 1 and "never initialized" in lines[0] and "turning" in lines[0], r.stderr
    assert summary(tmp_path / "run")["status"] == "waiting_for_init"


def test_fast_yaw_from_its_hover_has_a_small_gyro_bias(tmp_path):
    """From the start the vehicle hovers 1 s before the yaw ramps up: it initializes there, and
    the initial gyro bias is the bias, not a turn rate."""
    seq = simulate_cached("fast_yaw.yaml", 12.0, 1, True)
    r = vid_run(seq, tmp_path / "run", "--config", str(CONFIG), "--init", "static", "--end", "4")
    assert r.returncode == 0, r.stderr
    rows = np.loadtxt(tmp_path / "run" / "state.csv", delimiter=",", comments="#", ndmin=2)[0]
    b_g = rows[11:14]
    assert np.all(np.abs(b_g) < 0.03), b_g  # 3 init_sigma_gyro_bias; the simulated bias is 0.002


def test_groundtruth_init_with_estimated_time_offset_uses_the_frames(tmp_path):
    seq = simulate_cached("vid17_like_short.yaml", 12.0, 1, True)
    cfg = tmp_path / "config"
    shutil.copytree(CONFIG, cfg)
    with open(cfg / "estimator.yaml", "a") as f:
        f.write("\ninit_sigma_time_offset: 0.005\n")
    r = vid_run(seq, tmp_path / "run", "--config", str(cfg), "--init", "groundtruth")
    assert r.returncode == 0, r.stderr
    s = summary(tmp_path / "run")
    c = s["counts"]
    assert s["status"] == "ok"
    # Measured: 359 of 361 processed, 2 skipped (the frames before the first IMU sample).
    assert c["frames_skipped_by_filter"] <= 3, c
    assert c["frames_processed"] >= c["feature_frames"] - 3, c
    assert c["visual_updates"] >= 0.95 * c["frames_processed"], c


def test_no_camera_frame_used_exits_5(tmp_path):
    """Every frame stamped 30 s before the IMU (cam0 timeshift_cam_imu -30 s): the filter skips
    them all; the run says so in one line and exits 5."""
    seq = simulate_cached("vid17_like_short.yaml", 12.0, 1, True)
    bad = link_copy(seq, tmp_path / "seq")
    yaml = bad / "mav0" / "cam0" / "sensor.yaml"
    text = yaml.read_text()
    yaml.unlink()
    yaml.write_text(text + "\ntimeshift_cam_imu: -30.0\n")
    r = vid_run(bad, tmp_path / "run", "--config", str(CONFIG))
    assert r.returncode == 5, r.stderr
    lines = error_lines(r.stderr)
    assert len(lines) == 1 and "used none of the" in lines[0], r.stderr
    assert summary(tmp_path / "run")["counts"]["frames_processed"] == 0
