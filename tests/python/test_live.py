"""vid_live / vid_replay end to end over real LCM between processes (issue 9).

vid_replay writes an LCM event log (file:// transport, no network); vid_live consumes it with
LCM's file provider (`file://LOG?speed=0`: as fast as it takes messages) and writes vid_run's
outputs. Acceptance values of the issue: same trajectory as vid_run (< 1 mm) when nothing is
dropped; with injected faults every fault is counted and the ATE is at most twice the clean
run's; the log reads back with LCM's own EventLog API.
"""
import json
import subprocess
import sys

import numpy as np
import pytest

from test_vid_run_helpers import REPO, build_dir, simulate_cached, summary, tum_rows, vid_run
from vid_eval.live.fault_counts import fault_mismatches

SEQ_S = 12.0   # rendered sequence shared with test_vid_run.py (cached per session)
END_S = 6.0    # replayed / estimated seconds (keeps the image log ~110 MB)
FAULTS = ["--drop-images", "0.1", "--duplicate-imu", "0.01", "--reorder", "0.05", "--reorder-max-ms", "20",
          "--malformed", "10", "--fault-seed", "3"]


def lcm_types():
    """Import path of the Python LCM types generated at build time (<build>/python/vid)."""
    path = build_dir() / "python"
    if not (path / "vid" / "state_t.py").exists():
        pytest.fail(f"{path}/vid not generated: build the vid_lcm_types target")
    if str(path) not in sys.path:
        sys.path.insert(0, str(path))


def program(name):
    path = build_dir() / "bin" / name
    if not path.exists():
        pytest.fail(f"{path} not built")
    return str(path)


def run(cmd, timeout=300):
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=timeout)


def replay(seq, log, report, *extra):
    r = run([program("vid_replay"), "--dataset", seq, "--lcm-url", "memq://", "--fast", "--end", END_S,
             "--log", log, "--report", report, "--quiet", *extra])
    assert r.returncode == 0, r.stderr
    return json.loads(report.read_text())


def live(seq, log, out, *extra):
    r = run([program("vid_live"), "--lcm-url", f"file://{log}?speed=0", "--sensors", seq,
             "--config", REPO / "config" / "sim", "--out", out, "--quiet", *extra])
    assert r.returncode == 0, r.stderr
    return summary(out)


def ate(out, seq):
    from vid_eval.core.ate import compute_ate
    from vid_eval.tools.loaders import load_euroc_pose_csv, load_tum
    gt = load_euroc_pose_csv(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv")
    return compute_ate(load_tum(out / "trajectory_tum.txt"), gt, "posyaw").pos_rmse


@pytest.fixture(scope="module")
def seq():
    return simulate_cached("vid17_like_short.yaml", SEQ_S, 1, features_only=False)


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    path = tmp_path_factory.mktemp("live")
    yield path
    for log in path.glob("*.log"):  # ~100 MB each (raw images)
        log.unlink()


@pytest.fixture(scope="module")
def clean(seq, work):
    """Clean log, vid_live on it, and vid_run on the same span of the folder."""
    log = work / "clean.log"
    report = replay(seq, log, work / "clean_report.json")
    live_s = live(seq, log, work / "live_clean")
    r = vid_run(seq, work / "run", "--config", str(REPO / "config" / "sim"), "--end", str(END_S))
    assert r.returncode == 0, r.stderr
    return log, report, live_s


def test_live_on_replayed_log_matches_vid_run(seq, work, clean):
    _, report, s = clean
    assert s["status"] == "ok" and s["health"] == "tracking" and s["input_end"] == "eof"
    run_rows = tum_rows(work / "run" / "trajectory_tum.txt")
    live_rows = tum_rows(work / "live_clean" / "trajectory_tum.txt")
    assert len(run_rows) > 0.9 * 400 * (END_S - 1.5)  # initialized early, estimates at IMU rate
    assert len(live_rows) == len(run_rows)
    t_run = np.array([float(r[0]) for r in run_rows])
    t_live = np.array([float(r[0]) for r in live_rows])
    assert np.array_equal(t_run, t_live)
    p_run = np.array([[float(x) for x in r[1:4]] for r in run_rows])
    p_live = np.array([[float(x) for x in r[1:4]] for r in live_rows])
    assert np.max(np.linalg.norm(p_run - p_live, axis=1)) < 1e-3
    # Nothing dropped or flagged on a clean log, every published message used.
    faults = s["faults"]
    for stream, channel in [("imu", "IMU"), ("cam0", "CAM0"), ("cam1", "CAM1"), ("rotors", "ROTORS")]:
        assert faults[f"{stream}.received"] == report["published"][channel]
        for kind in ["malformed", "duplicate", "reordered", "late", "missing"]:
            assert faults[f"{stream}.{kind}"] == 0, f"{stream}.{kind}"
    assert faults["frames_dropped_overload"] == 0
    assert faults["camera_stalls"] == 0
    ref = summary(work / "run")
    assert s["counts"]["camera_frames"] == ref["counts"]["camera_frames"]
    assert s["counts"]["imu_samples"] == ref["counts"]["imu_samples"]
    assert s["latency_image_to_state_ms"]["count"] == s["counts"]["frames_processed"]


def test_log_reads_back_with_lcm_eventlog(seq, clean):
    """The vid_replay log is an LCM event log: LCM's own reader decodes every event."""
    import lcm
    lcm_types()
    from vid import image_t, imu_t, rotor_speeds_t
    log, report, _ = clean
    counts, first = {}, {}
    last_ts = -1
    for ev in lcm.EventLog(str(log), "r"):
        counts[ev.channel] = counts.get(ev.channel, 0) + 1
        assert ev.timestamp >= last_ts  # time-ordered, microseconds of data time
        last_ts = ev.timestamp
        first.setdefault(ev.channel, ev.data)
    assert counts == report["published"]
    imu_rows = [l for l in (seq / "mav0" / "imu0" / "data.csv").read_text().splitlines() if l and l[0] != "#"]
    f = [float(x) for x in imu_rows[0].split(",")]
    m = imu_t.decode(first["IMU"])
    assert m.timestamp == int(imu_rows[0].split(",")[0])
    assert list(m.gyro) == pytest.approx(f[1:4], abs=0) and list(m.accel) == pytest.approx(f[4:7], abs=0)
    img = image_t.decode(first["CAM1"])
    assert (img.camera_id, img.width, img.height, img.encoding) == (1, 640, 480, "mono8")
    assert len(img.data) == img.size == 640 * 480
    assert len(set(img.data[:10000])) > 10  # a rendered texture, not a blank buffer
    rs = rotor_speeds_t.decode(first["ROTORS"])
    assert rs.count == 4 and rs.unit == "rpm"


def test_lcm_logplayer_plays_the_log(seq, work):
    """lcm-logplayer (liblcm-bin) plays a vid_replay log; replayed into a file:// log, every
    event comes out with the same channel and payload, in the same order."""
    import shutil
    import lcm
    player = shutil.which("lcm-logplayer")
    assert player, "lcm-logplayer not installed (liblcm-bin)"
    log, played = work / "one_second.log", work / "played.log"
    r = run([program("vid_replay"), "--dataset", seq, "--lcm-url", "memq://", "--fast", "--end", "1", "--log", log,
             "--quiet"])
    assert r.returncode == 0, r.stderr
    r = run([player, "--speed", "50", "--lcm-url", f"file://{played}?mode=w", log], timeout=60)
    assert r.returncode == 0, r.stderr
    original = [(e.channel, e.data) for e in lcm.EventLog(str(log), "r")]
    replayed = [(e.channel, e.data) for e in lcm.EventLog(str(played), "r")]
    assert len(original) > 500
    assert replayed == original


def test_faults_are_counted_and_cost_at_most_twice_the_ate(seq, work, clean):
    log = work / "faults.log"
    report = replay(seq, log, work / "faults_report.json", *FAULTS)
    s = live(seq, log, work / "live_faults")
    inj, got = report["faults"], s["faults"]
    assert sum(inj["images_dropped"].values()) >= 10 and inj["imu_duplicated"] >= 5
    assert sum(inj["reordered_arrivals"].values()) >= 50 and sum(inj["malformed"].values()) == 10
    assert fault_mismatches(report, s) == []  # every fault counted exactly as injected
    for stream in ["imu", "rotors", "cam0", "cam1"]:
        assert got[f"{stream}.late"] == 0  # 20 ms of reordering fits the 30 ms window
    assert s["status"] == "ok"
    assert s["counts"]["imu_samples"] == summary(work / "live_clean")["counts"]["imu_samples"]
    clean_ate = ate(work / "live_clean", seq)
    faults_ate = ate(work / "live_faults", seq)
    assert clean_ate < 0.05
    assert faults_ate <= 2.0 * clean_ate, f"ATE {faults_ate:.4f} m with faults vs {clean_ate:.4f} m clean"


def test_live_publishes_state_force_and_status(seq, work, clean):
    """--publish-url file://...?mode=w records what vid_live publishes: VID_STATE at IMU rate,
    VID_FORCE (dynamics mode), VID_STATUS with health and counters."""
    import lcm
    lcm_types()
    from vid import force_t, state_t, status_t
    log, _, _ = clean
    out_log = work / "published.log"
    s = live(seq, log, work / "live_pub", "--publish-url", f"file://{out_log}?mode=w")
    states, forces, status = [], [], []
    for ev in lcm.EventLog(str(out_log), "r"):
        if ev.channel == "VID_STATE":
            states.append(state_t.decode(ev.data))
        elif ev.channel == "VID_FORCE":
            forces.append(force_t.decode(ev.data))
        elif ev.channel == "VID_STATUS":
            status.append(status_t.decode(ev.data))
    assert len(states) == len(forces) == s["counts"]["estimates"]
    rows = tum_rows(work / "live_pub" / "trajectory_tum.txt")
    assert len(rows) == len(states)
    last = states[-1]
    assert abs(last.timestamp * 1e-9 - float(rows[-1][0])) < 1e-9
    assert np.allclose(last.p, [float(x) for x in rows[-1][1:4]], atol=1e-8)
    assert abs(np.linalg.norm(last.q) - 1.0) < 1e-9
    assert last.status == state_t.STATUS_TRACKING
    assert all(v >= 0 for v in last.cov_diag) and last.cov_diag[15] > 0  # force variance (body)
    f = forces[-1]
    assert f.mass_kg == pytest.approx(3.1015)
    assert np.allclose(np.array(f.f_world) * f.mass_kg, f.f_world_newton)
    assert status and status[-1].status_text == "tracking"
    named = dict(zip(status[-1].counter_names, status[-1].counter_values))
    assert named["imu.received"] == s["faults"]["imu.received"] and named["states_published"] == len(states)


def _force_csv(path):
    rows = [line.split(",") for line in path.read_text().splitlines() if line and not line.startswith("#")]
    return np.array([int(r[0]) for r in rows]), np.array([[float(x) for x in r[1:]] for r in rows])


def test_live_lag_publishes_the_smoothed_estimate(seq, work, clean):
    """vid_live --lag 0.3 (issue #22): every estimate comes again, smoothed, on VID_STATE_LAGGED /
    VID_FORCE_LAGGED; the causal channels are those of the run without --lag; the lagged force
    is force_smoothed.csv's and that of vid_run --smooth 0.3 over the same data; --lag in IMU
    mode is a usage error."""
    import lcm
    lcm_types()
    from vid import force_t, state_t
    log, _, clean_s = clean
    out_log = work / "lagged.log"
    s = live(seq, log, work / "live_lag", "--lag", "0.3", "--publish-url", f"file://{out_log}?mode=w")
    counts = {"VID_STATE": 0, "VID_FORCE": 0, "VID_STATE_LAGGED": 0}
    lagged_force = []
    for ev in lcm.EventLog(str(out_log), "r"):
        if ev.channel in counts:
            counts[ev.channel] += 1
        if ev.channel == "VID_STATE_LAGGED":
            state_t.decode(ev.data)
        elif ev.channel == "VID_FORCE_LAGGED":
            lagged_force.append(force_t.decode(ev.data))
    n = s["counts"]["estimates"]
    assert counts["VID_STATE"] == counts["VID_FORCE"] == n == clean_s["counts"]["estimates"]
    assert counts["VID_STATE_LAGGED"] == len(lagged_force) == n  # the last clones are released at the end
    assert s["faults"]["lagged_states_published"] == n
    # The causal outputs do not change with --lag (to rounding: the clones enlarge the matrices).
    lag_rows, clean_rows = (np.array([[float(x) for x in r] for r in tum_rows(work / d / "trajectory_tum.txt")])
                            for d in ("live_lag", "live_clean"))
    assert lag_rows.shape == clean_rows.shape and np.array_equal(lag_rows[:, 0], clean_rows[:, 0])
    assert np.max(np.abs(lag_rows[:, 1:] - clean_rows[:, 1:])) < 1e-7
    t_lag, f_lag = _force_csv(work / "live_lag" / "force.csv")
    t_clean, f_clean = _force_csv(work / "live_clean" / "force.csv")
    assert np.array_equal(t_lag, t_clean) and np.max(np.abs(f_lag - f_clean)) < 1e-6
    # The lagged messages are force_smoothed.csv's rows (printed to 6 significant digits there).
    t_sm, f_sm = _force_csv(work / "live_lag" / "force_smoothed.csv")
    assert np.array_equal(t_sm, [m.timestamp for m in lagged_force])
    assert np.allclose(f_sm[:, 3:6], [m.f_world for m in lagged_force], rtol=1e-5, atol=1e-6)
    assert np.allclose(f_sm[:, 6:9], [m.sigma_body for m in lagged_force], rtol=1e-5, atol=1e-9)
    # Smoothing moved the estimate (else this test says nothing) and vid_run --smooth agrees.
    _, f_causal = _force_csv(work / "live_lag" / "force.csv")
    assert np.sqrt(np.mean((f_sm[:, 3:6] - f_causal[:, 3:6]) ** 2)) > 1e-3
    assert np.all(f_sm[:, 6:9] <= f_causal[:, 6:9] * (1 + 1e-5))  # smoothed sigma never larger
    r = vid_run(seq, work / "run_smooth", "--config", str(REPO / "config" / "sim"), "--end", str(END_S), "--smooth", "0.3")
    assert r.returncode == 0, r.stderr
    t_run, f_run = _force_csv(work / "run_smooth" / "force_smoothed.csv")
    assert np.array_equal(t_run, t_sm)
    assert np.sqrt(np.mean((f_run[:, 3:6] - f_sm[:, 3:6]) ** 2)) < 0.01  # live vs offline: < 1 % of the force error
    bad = run([program("vid_live"), "--lcm-url", f"file://{log}?speed=0", "--sensors", seq, "--config",
               REPO / "config" / "sim", "--mode", "imu", "--lag", "0.3"], timeout=60)
    assert bad.returncode == 2 and len(bad.stderr.splitlines()) == 1 and "--lag" in bad.stderr, bad.stderr
    bad = vid_run(seq, work / "run_smooth_imu", "--mode", "imu", "--end", str(END_S), "--smooth", "0.3")
    assert bad.returncode == 2 and len(bad.stderr.splitlines()) == 1 and "--smooth" in bad.stderr, bad.stderr


def test_cli_errors_are_one_line(tmp_path):
    cases = [
        [program("vid_replay"), "--dataset", tmp_path / "missing", "--lcm-url", "memq://", "--fast"],
        [program("vid_live"), "--lcm-url", f"file://{tmp_path}/missing.log?speed=0", "--sensors", tmp_path],
        [program("vid_live"), "--lcm-url", "nosuchprovider://x", "--sensors", tmp_path],
    ]
    bad_channels = tmp_path / "channels.yaml"
    bad_channels.write_text("imu: A\ncamera0: B\n")
    cases.append([program("vid_live"), "--lcm-url", "memq://", "--channels", bad_channels])
    for cmd in cases:
        r = run(cmd, timeout=60)
        assert r.returncode != 0, cmd
        lines = r.stderr.splitlines()  # nothing filtered: LCM's own "Error: ..." lines must not appear
        assert len(lines) == 1 and "error" in lines[0], r.stderr


def test_late_messages_and_camera_stall_are_counted(seq, work, clean):
    """Messages 100 ms late (beyond the 30 ms window) are dropped and counted; a 0.8 s camera
    stall is counted once, publishes `degraded` while it lasts and tracking resumes after."""
    import lcm
    lcm_types()
    from vid import state_t
    log = work / "late.log"
    report = replay(seq, log, work / "late_report.json", "--late", "0.003", "--camera-stall", "3.0", "0.8",
                    "--fault-seed", "5")
    out_log = work / "late_published.log"
    s = live(seq, log, work / "live_late", "--publish-url", f"file://{out_log}?mode=w")
    inj, got = report["faults"], s["faults"]
    assert sum(inj["late"].values()) >= 3
    # A late message never enters the estimator: its stream has a gap there (counted missing).
    assert fault_mismatches(report, s) == []
    assert inj["camera_stalls"] == 1 and got["camera_stalls"] == 1
    assert s["counts"]["imu_samples"] == report["published"]["IMU"] - inj["late"].get("imu", 0)
    health = [state_t.decode(ev.data).status for ev in lcm.EventLog(str(out_log), "r") if ev.channel == "VID_STATE"]
    assert state_t.STATUS_DEGRADED in health
    assert health[-1] == state_t.STATUS_TRACKING and s["health"] == "tracking" and s["status"] == "ok"
