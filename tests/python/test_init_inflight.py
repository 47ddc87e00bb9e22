"""Issue 49 step 3: init_mode auto initializes in flight from a 1 s stereo window
(docs/notes/initialization.md). fast_yaw started mid-yaw (which the still test refuses) and vid17_like started
mid-flight initialize within 1.5 s of data, and their ATE stays near a run initialized from
ground truth at the same time; a hovering start still takes the still window."""
import shutil

import numpy as np
import pytest

from test_vid_run_helpers import REPO, first_timestamp_ns, simulate_cached, summary, vid_run

CONFIG = REPO / "config" / "sim"


def auto_vs_groundtruth(seq, tmp_path, start, seconds, config=CONFIG):
    r = vid_run(seq, tmp_path / "auto", "--config", str(config), "--init", "auto", "--start", str(start),
                "--end", str(start + seconds))
    assert r.returncode == 0, r.stderr
    s = summary(tmp_path / "auto")
    ev = s["initializations"]["events"]
    assert s["initializations"]["count"] == 1 and ev[0]["how"] == "in_flight", s["initializations"]
    t_init = (ev[0]["t_ns"] - first_timestamp_ns(seq)) * 1e-9
    g = vid_run(seq, tmp_path / "gt", "--config", str(config), "--init", "groundtruth", "--start", f"{t_init:.6f}",
                "--end", str(start + seconds))
    assert g.returncode == 0, g.stderr
    return t_init - start, s["ate_posyaw_m"], summary(tmp_path / "gt")["ate_posyaw_m"]


@pytest.mark.parametrize("scenario,duration,start", [("fast_yaw.yaml", 16.0, 8.0), ("vid17_like.yaml", 24.0, 10.0)])
def test_mid_flight_start_initializes_in_flight(scenario, duration, start, tmp_path):
    seq = simulate_cached(scenario, duration, 1, True)
    delay, ate, ate_gt = auto_vs_groundtruth(seq, tmp_path, start, 6.0)
    assert delay <= 1.5
    # Ratchet (docs/testing.md): measured ATE ratios 1.08-1.23 on fast_yaw, 1.11-1.33 on vid17_like
    # over 12 s (scripts/init_sweep.py); the target is 1.2 over all presets.
    assert ate <= 1.5 * ate_gt, (ate, ate_gt)


def mono_config(tmp_path):
    """config/sim with one camera (use_stereo: false): the scale from the accelerometer over 2 s."""
    config = tmp_path / "config"
    shutil.copytree(CONFIG, config)
    est = config / "estimator.yaml"
    est.write_text(est.read_text().replace("use_stereo: true", "use_stereo: false"))
    assert "use_stereo: false" in est.read_text()
    return config


def test_mono_mid_flight_start_initializes_in_flight(tmp_path):
    seq = simulate_cached("vid17_like.yaml", 24.0, 1, True)
    delay, ate, ate_gt = auto_vs_groundtruth(seq, tmp_path, 10.0, 6.0, mono_config(tmp_path))
    assert delay <= 3.0  # the mono limit
    # Ratchet as above; the mono sweep's ratios are in docs/notes/initialization.md.
    assert ate <= 1.5 * ate_gt, (ate, ate_gt)


def test_mono_fast_yaw_start_waits_and_says_why(tmp_path):
    # Ratchet: at 3 rad/s of yaw the 2 s mono window is too thin (few tracks span three of its
    # frames); it used to initialize with tilts 5-9 degrees off at a 1.4 degree sigma. Today it
    # waits, and the run exits 4 with one line naming the thin window.
    seq = simulate_cached("fast_yaw.yaml", 16.0, 1, True)
    r = vid_run(seq, tmp_path / "run", "--config", str(mono_config(tmp_path)), "--init", "auto", "--start", "8",
                "--end", "15")
    assert r.returncode == 4, r.stderr
    lines = [line for line in r.stderr.splitlines() if "error" in line]
    assert len(lines) == 1 and "never initialized" in lines[0] and "sparsest frame" in lines[0], r.stderr


@pytest.mark.xfail(strict=True, reason="issue #49 target not met: mono fast_yaw does not initialize in flight")
def test_mono_fast_yaw_start_target(tmp_path):
    seq = simulate_cached("fast_yaw.yaml", 16.0, 1, True)
    delay, ate, ate_gt = auto_vs_groundtruth(seq, tmp_path, 8.0, 6.0, mono_config(tmp_path))
    assert delay <= 3.0 and ate <= 1.2 * ate_gt, (delay, ate, ate_gt)


def test_hovering_start_takes_the_still_window(tmp_path):
    seq = simulate_cached("vid17_real_sensors_short.yaml", 4.0, 1, True)
    r = vid_run(seq, tmp_path / "run", "--config", str(CONFIG), "--init", "auto")
    assert r.returncode == 0, r.stderr
    ev = summary(tmp_path / "run")["initializations"]["events"]
    assert ev and ev[0]["how"] == "still"
    assert (ev[0]["t_ns"] - first_timestamp_ns(seq)) * 1e-9 <= 1.0
