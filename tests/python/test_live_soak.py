"""vid-soak (#26): the looped replay with injected faults into vid_live, short and through an
event log (deterministic; the hour at real time over udpm is a measurement, apps/vid_live/README.md).
Three passes of the rendered take-off / landing hop: three lift-offs, every injected fault
counted exactly, memory flat after the first pass, the hop still tracked on the last pass; with
fixed-lag smoothing on (vid_live --lag 0.3, #22) through the landings and re-initializations."""
from __future__ import annotations

import json
import subprocess
import sys

from test_vid_run_helpers import REPO, build_dir, simulate_cached
from vid_eval.live.fault_counts import fault_mismatches
from vid_eval.live.soak import _estimated_until_ns


def soak(tmp_path, *extra):
    seq = simulate_cached("takeoff_landing_short.yaml", 22.0, 1, features_only=False)
    out = tmp_path / "soak"
    cmd = [sys.executable, "-m", "vid_eval.live.soak", "--dataset", str(seq), "--out", str(out),
           "--build-dir", str(build_dir()), "--transport", "log", "--sample-s", "0.1", *extra]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, cwd=REPO)
    return r, out


def test_looped_replay_with_faults_is_counted_exactly_and_memory_stays_flat(tmp_path):
    r, out = soak(tmp_path, "--loops", "3", "--warmup-s", "22", "--lag", "0.3")
    res = json.loads((out / "soak.json").read_text())
    assert r.returncode == 0, r.stdout + r.stderr
    assert res["ok"] and res["vid_live_rc"] == 0 and res["vid_replay_rc"] == 0
    inj = res["injected"]
    # every kind of fault was injected, in every pass
    assert inj["camera_stalls"] == 3 and sum(inj["malformed"].values()) == 12
    assert inj["imu_duplicated"] > 0 and sum(inj["images_dropped"].values()) > 0
    assert sum(inj["late"].values()) > 0 and sum(inj["reordered_arrivals"].values()) > 0
    assert res["mismatches"] == []
    report = json.loads((out / "replay_report.json").read_text())
    summary = json.loads((out / "live" / "summary.json").read_text())
    assert fault_mismatches(report, summary) == []
    assert report["loops"] == 3 and report["published"]["CAM0"] < 3 * 661
    assert res["lift_offs"] == 3 and res["health"] == "tracking"
    # growth over the last two passes (data time, not wall time: the log is read as fast as it can)
    assert res["rss"]["samples"] >= 5 and res["rss"]["growth"] <= 0.05
    assert res["ate_posyaw"]["last_pass_m"] < 0.05
    assert res["lag_s"] == 0.3 and summary["faults"]["lagged_states_published"] > 0.9 * summary["counts"]["estimates"]
    assert (out / "live" / "force_smoothed.csv").stat().st_size > 0


def test_a_miscounted_fault_fails_the_soak(tmp_path):
    """The comparison can fail: a summary missing one dropped image is reported."""
    report = {"faults": {"images_dropped": {"cam0": 2}, "imu_duplicated": 1, "late": {},
                         "reordered_arrivals": {}, "malformed": {"IMU": 1}, "stall_images": {},
                         "camera_stalls": 0}}
    got = {f"{s}.{k}": 0 for s in ("imu", "cam0", "cam1", "rotors", "thrust")
           for k in ("late", "reordered", "missing", "malformed", "duplicate")}
    got.update({"cam0.missing": 1, "imu.duplicate": 1, "imu.malformed": 1, "camera_stalls": 0,
                "frames_dropped_overload": 0})
    assert fault_mismatches(report, {"faults": got}) == ["cam0.missing: counted 1, injected 2"]


def test_usage_errors_are_one_line(tmp_path):
    for args in (["--loops", "0"], ["--minutes", "-1"]):
        r, _ = soak(tmp_path, *args)
        assert r.returncode == 2 and len(r.stderr.splitlines()) == 1, r.stderr
    r = subprocess.run([sys.executable, "-m", "vid_eval.live.soak", "--dataset", str(tmp_path),
                        "--out", str(tmp_path / "o")], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "imu0/data.csv" in r.stderr and len(r.stderr.splitlines()) == 1


def test_progress_is_the_last_whole_trajectory_line(tmp_path):
    """Warm-up counts data time from vid_live's growing trajectory: the last whole line, never
    a half-written one; nothing before the first estimate."""
    traj = tmp_path / "trajectory_tum.txt"
    assert _estimated_until_ns(traj) is None
    traj.write_text("# timestamp tx ty tz qx qy qz qw\n")
    assert _estimated_until_ns(traj) is None
    traj.write_text("# timestamp\n12.000000005 0 0 0 0 0 0 1\n13.250000000 0 0 0 0 0 0 1\n14.5")
    assert _estimated_until_ns(traj) == 13_250_000_000
