"""Issue 49: recovery from divergence without a restart (apps/vid_run/README.md "Exit codes",
docs/notes/recovery.md).

vid17_like (30 s, features, seed 1, config/sim) with 2 s of garbage IMU samples (gyro and
accelerometer N(0, 30) per axis) from 15 s: the estimator diverges (velocity beyond max_velocity)
a few seconds later. By default vid_run re-initializes from the data, in flight, and goes on;
`--on-divergence stop` ends the run with exit 3 as before. A fault that outlives the
re-initialization (diverging again within 10 s) stops the run too (the persistent cases are in
test_vid_run_robustness.py and test_vid_run_health.py).
"""
import numpy as np
import pytest

from test_vid_run_helpers import REPO, link_copy, replace_file, simulate_cached, summary, tum_rows, vid_run

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


def test_each_piece_is_scored_in_its_own_world_frame(recovered, undisturbed):
    _, _, s = recovered
    pieces = s["ate_segments"]
    assert len(pieces) == 2
    assert pieces[1]["t_start_ns"] == s["initializations"]["events"][1]["t_ns"]
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
