"""Issue 49 step 3: init_mode auto initializes in flight from a 1 s stereo window
(docs/notes/initialization.md). fast_yaw started mid-yaw (which the still test refuses) and vid17_like started
mid-flight initialize within 1.5 s of data, and their ATE stays near a run initialized from
ground truth at the same time; a hovering start still takes the still window."""
import numpy as np
import pytest

from test_vid_run_helpers import REPO, first_timestamp_ns, simulate_cached, summary, vid_run

CONFIG = REPO / "config" / "sim"


def auto_vs_groundtruth(seq, tmp_path, start, seconds):
    r = vid_run(seq, tmp_path / "auto", "--config", str(CONFIG), "--init", "auto", "--start", str(start),
                "--end", str(start + seconds))
    assert r.returncode == 0, r.stderr
    s = summary(tmp_path / "auto")
    ev = s["initializations"]["events"]
    assert s["initializations"]["count"] == 1 and ev[0]["how"] == "in_flight", s["initializations"]
    t_init = (ev[0]["t_ns"] - first_timestamp_ns(seq)) * 1e-9
    g = vid_run(seq, tmp_path / "gt", "--config", str(CONFIG), "--init", "groundtruth", "--start", f"{t_init:.6f}",
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


def test_hovering_start_takes_the_still_window(tmp_path):
    seq = simulate_cached("vid17_real_sensors_short.yaml", 4.0, 1, True)
    r = vid_run(seq, tmp_path / "run", "--config", str(CONFIG), "--init", "auto")
    assert r.returncode == 0, r.stderr
    ev = summary(tmp_path / "run")["initializations"]["events"]
    assert ev and ev[0]["how"] == "still"
    assert (ev[0]["t_ns"] - first_timestamp_ns(seq)) * 1e-9 <= 1.0
