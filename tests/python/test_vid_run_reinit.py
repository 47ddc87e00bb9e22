"""Issue 49: recovery from divergence without a restart (apps/vid_run/README.md "Exit codes",
docs/notes/recovery.md).

vid17_like (30 s, features, seed 1, config/sim) with 2 s of garbage IMU samples (gyro and
accelerometer N(0, 30) per axis) from 15 s: the estimator diverges (velocity beyond max_velocity)
a few seconds later. By default vid_run re-initializes from the data, in flight, and goes on;
`--on-divergence stop` ends the run with exit 3 as before. A fault that outlives the
re-initialization (diverging again within 10 s) stops the run too (the persistent cases are in
test_vid_run_robustness.py and test_vid_run_health.py).
"""
import json
from decimal import Decimal
import subprocess

import numpy as np
import pytest

from test_vid_run_helpers import (REPO, VENV_BIN, link_copy, replace_file, simulate_cached, summary, tum_rows,
                                  vid_run)

CONFIG = REPO / "config" / "sim"
BURST_S = (15.0, 17.0)


@pytest.fixture(scope="module")
def clean():
    return simulate_cached("vid17_like.yaml", 30.0, 1, True)


@pytest.fixture(scope="module")
def burst(clean, tmp_path_factory):
    bad = link_copy(clean, tmp_path_factory.mktemp("burst") / "seq")
    imu = bad / "mav0" / "imu0" / "data.csv"
    lines = imu.read_text().splitlines()
    rows = [ln for ln in lines if ln and not ln.startswith("#")]
    t0 = int(rows[0].split(",")[0])
    rng = np.random.default_rng(0)
    out = []
    for ln in lines:
        if ln and not ln.startswith("#"):
            f = ln.split(",")
            if BURST_S[0] * 1e9 <= int(f[0]) - t0 < BURST_S[1] * 1e9:
                ln = ",".join([f[0]] + [f"{x:.6f}" for x in rng.normal(0.0, 30.0, 6)])
        out.append(ln)
    replace_file(imu, ("\n".join(out) + "\n").encode())
    return bad, t0


@pytest.fixture(scope="module")
def undisturbed(clean, tmp_path_factory):
    out = tmp_path_factory.mktemp("clean_run")
    r = vid_run(clean, out, "--config", str(CONFIG))
    assert r.returncode == 0, r.stderr
    return summary(out)


@pytest.fixture(scope="module")
def recovered(burst, tmp_path_factory):
    out = tmp_path_factory.mktemp("reinit_run")
    r = vid_run(burst[0], out, "--config", str(CONFIG))
    return r, out, summary(out)


def test_divergence_is_followed_by_an_in_flight_reinitialization(burst, recovered):
    r, out, s = recovered
    assert r.returncode == 0, r.stderr
    assert s["status"] == "ok"
    assert len(s["divergences"]) == 1, s["divergences"]
    t_div = s["divergences"][0]["t_ns"]
    assert t_div > burst[1] + BURST_S[0] * 1e9
    warn = [ln for ln in r.stderr.splitlines() if "re-initializing" in ln]
    assert len(warn) == 1 and "diverged at t = " in warn[0], r.stderr
    events = s["initializations"]["events"]
    assert [e["how"] for e in events] == ["still", "in_flight"], events
    assert s["counts"]["estimator_restarts"] == 1
    # Back to tracking within 2 s of the divergence, and the trajectory goes on from there.
    assert (events[1]["t_ns"] - t_div) * 1e-9 <= 2.0
    t = np.array([float(row[0]) for row in tum_rows(out / "trajectory_tum.txt")])
    after = t[t * 1e9 >= events[1]["t_ns"] - 1e6]
    assert after[0] * 1e9 - events[1]["t_ns"] < 0.05e9 and after[-1] - after[0] > 9.0
    assert np.max(np.diff(after)) < 0.05
    # Gap-free: the in-flight initializer's window fills the time between the divergence and
    # the new state (its frame poses; before, a ~1 s hole), in time order.
    assert np.all(np.diff(t) > 0)
    gaps = np.diff(t)
    print(f"largest gap {gaps.max():.3f} s at {t[np.argmax(gaps)] - t[0]:.2f} s")
    assert gaps.max() < 0.15, gaps.max()


def test_the_trajectory_marks_the_new_world_frame(recovered):
    _, out, s = recovered
    lines = (out / "trajectory_tum.txt").read_text().splitlines()
    marks = [i for i, ln in enumerate(lines) if ln.startswith("# re-initialized at ")]
    assert len(marks) == 1, marks
    # the marker's time is the first pose of the second piece (the window's oldest frame) ...
    t_mark = lines[marks[0]].split()[3].rstrip(":")
    assert t_mark == lines[marks[0] + 1].split()[0]
    piece = s["ate_segments"][1]
    assert int(Decimal(t_mark) * 10**9) == piece["t_start_ns"]  # exact: 9 decimals
    assert piece["t_start_ns"] < s["initializations"]["events"][1]["t_ns"]
    # ... and the marker is the only comment after the header: no other file changes
    assert sum(ln.startswith("#") for ln in lines) == 2
    assert not any(ln.startswith("# re-init") for ln in (out / "state.csv").read_text().splitlines())


def test_vid_eval_scores_each_piece_as_vid_run(clean, recovered, tmp_path):
    _, out, s = recovered
    gt = clean / "mav0" / "state_groundtruth_estimate0" / "data.csv"

    def traj(*extra):
        r = subprocess.run([str(VENV_BIN / "vid-eval"), "traj", str(out / "trajectory_tum.txt"), str(gt),
                            "--json", str(tmp_path / "ate.json"), *extra], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        return r.stdout, json.loads((tmp_path / "ate.json").read_text())

    text, j = traj()
    pieces = j["ate_pieces"]["pieces"]
    assert [p["t_start_ns"] for p in pieces][1] == s["ate_segments"][1]["t_start_ns"]
    # Near vid_run's own per-piece ATE, not equal: vid_run pairs each 400 Hz estimate with its
    # nearest truth, vid-eval (evo's rule) each 200 Hz truth with its nearest estimate, so the
    # pairs differ (2095 vs 4082 pairs after the re-initialization, 2.3 % apart since the
    # initializer's reprojection refinement, within 2 % before). The pooled number below is
    # checked exactly against the pieces.
    for mine, theirs in zip(pieces, s["ate_segments"]):
        assert mine["pos_rmse_m"] == pytest.approx(theirs["ate_posyaw_m"], rel=0.05), (mine, theirs)
    # Pooled over every pair of every piece (vid-eval pairs one-to-one with the ground truth,
    # vid_run each estimate with its nearest truth: the pair counts, so the weights, differ).
    pooled = np.sqrt(sum(p["pos_rmse_m"] ** 2 * p["pairs"] for p in pieces) / sum(p["pairs"] for p in pieces))
    assert j["ate_pos_rmse_m"] == pytest.approx(pooled, rel=1e-9)
    assert text.count("aligned on its own") == 2
    # One alignment over both frames scores the frame change, not the estimator.
    _, one = traj("--one-alignment")
    assert "ate_pieces" not in one and one["ate_pos_rmse_m"] > j["ate_pos_rmse_m"]


def test_each_piece_is_scored_in_its_own_world_frame(recovered, undisturbed):
    _, _, s = recovered
    pieces = s["ate_segments"]
    assert len(pieces) == 2
    # the second piece starts with the in-flight initializer's window, after the divergence
    assert s["divergences"][0]["t_ns"] < pieces[1]["t_start_ns"] <= s["initializations"]["events"][1]["t_ns"]
    assert sum(p["pairs"] for p in pieces) == s["ate_pairs"]
    pooled = np.sqrt(sum(p["ate_posyaw_m"] ** 2 * p["pairs"] for p in pieces) / s["ate_pairs"])
    assert s["ate_posyaw_m"] == pytest.approx(pooled, rel=1e-12)
    # The criterion, on what follows the re-initialization: within +30 % of the
    # undisturbed run's ATE (measured 0.0060 against 0.0070 m). The first piece holds the
    # diverged estimates between the burst and its detection (metres off) and says so.
    print(f"after re-initialization {pieces[1]['ate_posyaw_m']:.4f} m, undisturbed {undisturbed['ate_posyaw_m']:.4f} m")
    assert pieces[1]["ate_posyaw_m"] <= 1.3 * undisturbed["ate_posyaw_m"]
    assert pieces[0]["ate_posyaw_m"] > 1.0


def test_stop_keeps_the_old_behaviour(burst, tmp_path):
    r = vid_run(burst[0], tmp_path / "run", "--config", str(CONFIG), "--on-divergence", "stop")
    assert r.returncode == 3, r.stderr
    s = summary(tmp_path / "run")
    assert s["status"] == "diverged" and len(s["divergences"]) == 1
    assert s["initializations"]["count"] == 1


def test_unknown_policy_is_a_usage_error(burst, tmp_path):
    r = vid_run(burst[0], tmp_path / "run", "--on-divergence", "retry")
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "--on-divergence" in r.stderr
