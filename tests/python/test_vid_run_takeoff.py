"""Issue 29: a flight that starts and ends on the ground, rotors stopped (takeoff_landing_short:
rest, spin-up, lift-off, figure-8, touchdown, spin-down, rest), under the one set of defaults
(config/sim), feature level for three seeds and rendered images for one, random initial heading.

The estimator initializes on the ground from the data (no excitation), follows the ground
reaction while landed, lift-off and touchdown without rejecting the accelerometer, and reports
landed / airborne in summary.json (docs/notes/flight-phase.md). Per-phase errors come from
`vid-eval force` with the simulator's phase0 stream (eval/README.md).
"""

import numpy as np
import pytest

from ratchets import ratchet, target, target_not_met
from test_vid_run_helpers import REPO, first_timestamp_ns, run_and_score, simulate_cached, tum_rows
from vid_eval.tools.loaders import load_phases

PRESET = "takeoff_landing_short.yaml"
DURATION = 22.0
_RUNS = {}


def run(tmp_path_factory, seed: int, images: bool = False) -> dict:
    key = (seed, images)
    if key not in _RUNS:
        seq = simulate_cached(PRESET, DURATION, seed, not images)
        out = tmp_path_factory.mktemp(f"takeoff_s{seed}{'_img' if images else ''}")
        _RUNS[key] = {"seq": seq, "out": out, **run_and_score(seq, out, REPO / "config" / "sim")}
    return _RUNS[key]


def truth_events(seq) -> list:
    """(t_ns, 'lift_off' | 'touchdown') from the simulator's phase0 (0 on the ground, 1 airborne)."""
    ph = load_phases(seq / "mav0" / "phase0" / "data.csv")
    t, p = np.asarray(ph.t_ns), np.asarray(ph.values).astype(int)
    idx = np.flatnonzero(np.diff(p) != 0) + 1
    return [(int(t[i]), "lift_off" if p[i] == 1 else "touchdown") for i in idx]


CASES = [(1, False), (2, False), (3, False), (1, True)]


@pytest.mark.parametrize("seed,images", CASES)
def test_initializes_on_the_ground_within_a_second(tmp_path_factory, seed, images):
    r = run(tmp_path_factory, seed, images)
    assert r["summary"]["status"] == "ok"
    t_first = float(tum_rows(r["out"] / "trajectory_tum.txt")[0][0])
    t_imu = first_timestamp_ns(r["seq"]) * 1e-9
    assert t_first - t_imu <= 1.0, f"first estimate {t_first - t_imu:.2f} s after the first IMU sample"


@pytest.mark.parametrize("seed,images", CASES)
def test_landed_and_airborne_are_reported_at_the_true_events(tmp_path_factory, seed, images):
    r = run(tmp_path_factory, seed, images)
    fp = r["summary"]["flight_phase"]
    truth = truth_events(r["seq"])
    assert [e for _, e in truth] == ["lift_off", "touchdown"]
    assert fp["lift_offs"] == 1 and fp["touchdowns"] == 1, fp["events"]
    assert fp["final"] == "landed"
    for (t_true, kind), ev in zip(truth, fp["events"]):
        assert ev["event"] == kind
        # The classifier speaks of support: the ground carries < 25 % of the weight shortly
        # before the feet leave it (spin-up) and >= 50 % only once the rotors spin down.
        assert abs(ev["t_ns"] - t_true) * 1e-9 <= 1.0, f"{kind} at {(ev['t_ns'] - t_true) * 1e-9:+.2f} s"
    assert fp["landed_s"] > 4.0 and fp["airborne_s"] > 8.0
    # Standing on the ground, the stereo filter applies the zero-velocity update (no parallax
    # in the window), and only then: stereo never needs it in the air.
    counts = r["summary"]["counts"]
    assert counts["zero_velocity_updates_landed"] > 0.25 * fp["landed_s"] * 30, counts  # 30 Hz camera
    assert counts["zero_velocity_updates"] == counts["zero_velocity_updates_landed"], counts


@pytest.mark.parametrize("seed,images", CASES)
def test_pose_and_airborne_force_are_followed_without_rejections(tmp_path_factory, seed, images):
    r = run(tmp_path_factory, seed, images)
    s = r["summary"]
    assert s["accel"]["rejected"] == 0, "no accelerometer sample dropped, landed or airborne"
    assert s["ate_posyaw_m"] <= 0.02, f"ATE {s['ate_posyaw_m']:.4f} m"
    air = [g for g in r["force"]["phases"]["segments"] if g["kind"] == "airborne"][0]
    assert air["world"]["rmse_mps2"]["norm"] <= 0.25, air["world"]


# Issue 29 acceptance not met: the landed force error after 1 s on the ground is above 0.1 m/s^2
# RMSE (the 2 s rests leave ~1 s of it, next to the idle / spin-up and spin-down ramps the rate
# model trails), and the attitude error reaches 2.2 deg on one run (the tilt of the static
# initialization on the ground, from the accelerometer bias). docs/notes/flight-phase.md.
# Measured at 182d56e, per run (seeds 1 / 2 / 3 feature level, seed 1 images, and seeds 4 / 5
# feature level for the spread): landed force RMSE 0.103 / 0.108 / 0.106 / 0.105 / 0.101 /
# 0.111 m/s^2 (worst of the test's runs 0.108; mean + 3 sd = 0.117 is tighter than 1.2 x);
# attitude error max 1.32 / 2.22 / 0.82 / 1.23 / 1.28 / 1.51 deg (worst 2.22; 1.2 x = 2.67 is
# tighter than mean + 3 sd = 2.79).
LANDED_WORST, LANDED_RATCHET = 0.108, 0.117
ATT_WORST, ATT_RATCHET = 2.22, 2.67


@pytest.fixture(scope="module")
def worst_over_cases(tmp_path_factory):
    """(worst landed force RMSE after 1 s on the ground, worst attitude error) over CASES."""
    worst_landed, worst_att = 0.0, 0.0
    for seed, images in CASES:
        r = run(tmp_path_factory, seed, images)
        intervals = r["force"]["phases"]["landed_after"]["intervals"]
        assert len(intervals) == 2, intervals  # before lift-off and after touchdown
        for iv in intervals:
            worst_landed = max(worst_landed, iv["error_mps2"]["rmse"])
        worst_att = max(worst_att, r["att_err_max_deg"])
    return worst_landed, worst_att


def test_landed_force_and_attitude_ratchet(worst_over_cases):
    landed, att = worst_over_cases
    ratchet("landed force RMSE after 1 s, worst run [m/s^2]", landed, LANDED_RATCHET, LANDED_WORST)
    ratchet("attitude error max, worst run [deg]", att, ATT_RATCHET, ATT_WORST)


@target_not_met("issue 29: landed force error 0.10-0.11 m/s^2 > 0.1, attitude up to 2.2 deg > 1.5")
def test_landed_force_and_attitude_meet_the_issue(worst_over_cases):
    landed, att = worst_over_cases
    target("landed force RMSE after 1 s, worst run [m/s^2]", landed, 0.1)
    target("attitude error max, worst run [deg]", att, 1.5)


def test_live_path_keeps_the_whole_recording(tmp_path_factory):
    """The live path (vid_replay -> LCM event log -> vid_live) on the rendered run, rest to rest:
    nothing is trimmed, the same estimates and flight-phase events as vid_run on the folder."""
    from test_live import program, run as run_cmd

    r = run(tmp_path_factory, 1, True)
    work = tmp_path_factory.mktemp("takeoff_live")
    log = work / "replay.log"
    res = run_cmd([program("vid_replay"), "--dataset", r["seq"], "--lcm-url", "memq://", "--fast",
                   "--log", log, "--quiet"])
    assert res.returncode == 0, res.stderr
    try:
        res = run_cmd([program("vid_live"), "--lcm-url", f"file://{log}?speed=0", "--sensors", r["seq"],
                       "--config", REPO / "config" / "sim", "--out", work / "live", "--quiet"])
        assert res.returncode == 0, res.stderr
    finally:
        log.unlink()  # ~1 GB of raw images
    import json
    live = json.loads((work / "live" / "summary.json").read_text())
    assert live["status"] == "ok" and live["input_end"] == "eof"
    assert live["counts"]["imu_samples"] == r["summary"]["counts"]["imu_samples"]
    assert live["flight_phase"]["events"] == r["summary"]["flight_phase"]["events"]
    rows_live = tum_rows(work / "live" / "trajectory_tum.txt")
    rows_run = tum_rows(r["out"] / "trajectory_tum.txt")
    assert [x[0] for x in rows_live] == [x[0] for x in rows_run]
    p_live = np.array([[float(v) for v in x[1:4]] for x in rows_live])
    p_run = np.array([[float(v) for v in x[1:4]] for x in rows_run])
    assert np.max(np.linalg.norm(p_live - p_run, axis=1)) < 1e-3
