"""Camera-IMU time offset (issue #23, docs/notes/time-offset.md): the simulator stamps
images t_imu - t_d (cameras.time_offset_s), the estimator places frames at t_cam + t_d, with t_d
from the calibration (timeshift_cam_imu) or estimated online (init_sigma_time_offset > 0)."""
import os
import re
import shutil

import numpy as np
import pytest
from scipy.stats import chi2
from vid_eval.core.time_offset_bound import rotation_bound

from ratchets import ratchet, target, target_not_met
from test_vid_run_helpers import REPO, simulate, summary, vid_run


def scenario(tmp_path, preset: str, camera_keys: str, timeshift: float = None) -> str:
    """config/sim/<preset>.yaml with keys added under `cameras:` (and every camera's calibrated
    timeshift_cam_imu set), as an absolute path."""
    text = (REPO / "config" / "sim" / f"{preset}.yaml").read_text()
    text = text.replace("cameras:\n", "cameras:\n" + camera_keys, 1)
    if timeshift is not None:
        text = re.sub(r"(?m)^(\s*)(T_imu_cam: .*)$", rf"\1\2\n\1timeshift_cam_imu: {timeshift}", text)
    path = tmp_path / f"{preset}_clock.yaml"
    path.write_text(text)
    return str(path)


def offset_series(out):
    v = np.loadtxt(out / "time_offset.csv", delimiter=",", comments="#")
    return (v[:, 0] - v[0, 0]) * 1e-9, v[:, 1], v[:, 2]


@pytest.mark.parametrize("offset", [0.010, -0.010])
def test_calibrated_offset_is_applied(tmp_path, offset):
    """A sequence whose camera runs t_d behind/ahead of the IMU, with t_d in its calibration,
    is estimated as well as the same flight without an offset (a negative t_d means frames
    arrive after the IMU samples they precede: the estimator holds the IMU for them)."""
    clean = simulate(tmp_path / "clean", "vid17_like.yaml", 20.0, 1, True)
    seq = simulate(tmp_path / "seq", scenario(tmp_path, "vid17_like", f"  time_offset_s: {offset}\n", offset),
                   20.0, 1, True)
    for s, out in ((clean, tmp_path / "o_clean"), (seq, tmp_path / "o_seq")):
        r = vid_run(s, out, "--config", str(REPO / "config" / "sim"))
        assert r.returncode == 0, r.stderr
    a, b = summary(tmp_path / "o_clean"), summary(tmp_path / "o_seq")
    assert b["ate_posyaw_m"] <= 1.1 * a["ate_posyaw_m"], (a["ate_posyaw_m"], b["ate_posyaw_m"])
    assert b["force_rmse_world_mps2"] <= 1.1 * a["force_rmse_world_mps2"]


def config(tmp_path, sigma: float, jitter: float = 0.0):
    cfg = tmp_path / "cfg"
    shutil.copytree(REPO / "config" / "sim", cfg)
    with open(cfg / "estimator.yaml", "a") as f:
        f.write(f"\ninit_sigma_time_offset: {sigma}\ncamera_time_jitter: {jitter}\n")
    return cfg


def at_seconds(t, values, seconds):
    return np.array([values[min(np.searchsorted(t, s), len(t) - 1)] for s in seconds])


@pytest.mark.parametrize("preset", ["vid18_like", "fast_yaw"])
def test_offset_estimated_online_noise_free(tmp_path, preset):
    """From t_d = 0 with sigma 20 ms, a true 10 ms offset (noise-free sensors): within 0.5 ms from
    10 s on, the estimate's sigma covers its error, and the sigma is the rotation path's
    information bound (vid_eval.core.time_offset_bound) within 30 %: the filter uses what the flight
    offers. On fast_yaw (3 rad/s) the fresh clone's exact copy of the IMU pose once made the
    covariance check call P non-PD at 1.4 s."""
    seq = simulate(tmp_path / "seq", scenario(tmp_path, preset, "  time_offset_s: 0.010\n"), 20.0, 1, True,
                   noise_free=True)
    out = tmp_path / "out"
    r = vid_run(seq, out, "--config", str(config(tmp_path, 0.02)))
    assert r.returncode == 0, r.stderr
    t, td, sigma = offset_series(out)
    late = t >= 10.0
    assert np.abs(td[late] - 0.010).max() <= 0.0005, f"max error {np.abs(td[late] - 0.010).max() * 1e3:.2f} ms"
    assert np.all(np.abs(td[late] - 0.010) <= 3 * sigma[late])
    imu = np.loadtxt(seq / "mav0" / "imu0" / "data.csv", delimiter=",", comments="#")
    t_imu = (imu[:, 0] - imu[0, 0]) * 1e-9
    t0 = (np.loadtxt(out / "time_offset.csv", delimiter=",", comments="#")[0, 0] - imu[0, 0]) * 1e-9
    bound = rotation_bound(t_imu, imu[:, 1:4], 1.0e-3, [t0 + 10.0, t0 + 19.5])  # config/sim gyro_noise_density
    ratio = at_seconds(t, sigma, [10.0, 19.5]) / bound
    assert np.all((ratio >= 0.95) & (ratio <= 1.3)), f"sigma / bound {ratio}"


def mc_runs(tmp_path, presets, seeds, keys, jitter, *args):
    """t_d error and sigma at 10, 15 and 19.5 s of every (preset, seed) run, estimated from 0."""
    cfg = config(tmp_path, 0.02, jitter)
    errors, sigmas = [], []
    for preset in presets:
        for seed in seeds:
            seq = simulate(tmp_path / f"{preset}_{seed}", scenario(tmp_path, preset, keys), 20.5, seed, True)
            out = tmp_path / f"out_{preset}_{seed}"
            r = vid_run(seq, out, "--config", str(cfg), *args)
            assert r.returncode == 0, r.stderr
            t, td, sigma = offset_series(out)
            truth = float(re.search(r"time_offset_s: ([-\d.e]+)", keys).group(1))
            errors.append(at_seconds(t, td, [10.0, 15.0, 19.5]) - truth)
            sigmas.append(at_seconds(t, sigma, [10.0, 15.0, 19.5]))
    return np.array(errors), np.array(sigmas)


MC_SEEDS = [1, 2, 3] if os.environ.get("CI") else [1, 2, 3, 4, 5]


@pytest.mark.parametrize("preset", ["rope_snap", "force_steps", "impacts"])
def test_offset_not_pulled_by_abrupt_forces(tmp_path, preset):
    """Noise-free abrupt-force flights with the real-data preset (t_d estimated, sigma 5 ms, no
    true offset): t_d stays within 2 sigma of 0 all the way. Two earlier faults each put it out:
    the +-0.4 s gyro fit near an impact (impacts: 5 ms off at sigma 1.6 in one frame; now
    fit_rate_adaptive) and the force-jump undo of the IMU pose without the clones (rope_snap:
    6.7 sigma at the slack rope, force_steps 3.9 sigma; now the pose is not undone)."""
    seq = simulate(tmp_path / "seq", f"{preset}.yaml", 15.0, 1, True, noise_free=True)
    r = vid_run(seq, tmp_path / "out", "--config", str(REPO / "config" / "vid_dataset"))
    assert r.returncode == 0, r.stderr
    assert summary(tmp_path / "out")["accel"]["force_jumps"] > 0  # the jump path ran
    t, td, sigma = offset_series(tmp_path / "out")
    worst = np.argmax(np.abs(td) / sigma)
    assert abs(td[worst]) < 2.0 * sigma[worst], (t[worst], td[worst], sigma[worst])


@pytest.mark.parametrize("preset", ["impacts", "rope_snap", "force_steps"])
def test_offset_within_half_ms_where_the_flight_turns_hard(tmp_path, preset):
    """Issue #23's criterion where the flight carries the information: from a true +10 ms, the
    real-data preset (estimated from 0, sigma 5 ms) is within 0.5 ms from 10 s on and within
    3 sigma at the end (measured, seeds 1-3: within 0.18 ms, sigma 0.03-0.09 ms)."""
    seq = simulate(tmp_path / "seq", scenario(tmp_path, preset, "  time_offset_s: 0.010\n"), 20.0, 1, True)
    r = vid_run(seq, tmp_path / "out", "--config", str(REPO / "config" / "vid_dataset"))
    assert r.returncode == 0, r.stderr
    t, td, sigma = offset_series(tmp_path / "out")
    late = t >= 10.0
    assert np.max(np.abs(td[late] - 0.010)) < 0.0005, np.max(np.abs(td[late] - 0.010))
    assert abs(td[-1] - 0.010) < 3.0 * sigma[-1], (td[-1], sigma[-1])


@pytest.mark.parametrize("offset,mode", [(0.010, "dynamics"), (-0.010, "dynamics"), (0.010, "imu")])
def test_offset_consistent_with_sensor_noise(tmp_path, offset, mode):
    """Sensor noise, a true +-10 ms offset with 0.5 ms frame jitter (camera_time_jitter told),
    vid17_like / vid18_like / fast_yaw: the mean NEES of t_d over the runs at 10, 15 and 19.5 s
    is inside the two-sided 95 % chi^2 band (docs/notes/time-offset.md table: 0.2-0.3 ms sigma with 20 mrad/s of gyro
    noise per sample in the clone Jacobian was 2-27 ms off)."""
    args = ("--mode", "imu") if mode == "imu" else ()
    e, s = mc_runs(tmp_path, ["vid17_like", "vid18_like", "fast_yaw"], MC_SEEDS,
                   f"  time_offset_s: {offset}\n  time_offset_jitter_s: 0.0005\n", 0.0005, *args)
    n = e.shape[0]
    nees = np.mean((e / s) ** 2, axis=0)
    lo, hi = chi2.ppf(0.025, n) / n, chi2.ppf(0.975, n) / n
    assert np.all((nees >= lo) & (nees <= hi)), f"mean NEES {nees} over {n} runs, band [{lo:.2f}, {hi:.2f}]"


# Measured (vid18_like, 20 s, +10 ms with 0.5 ms jitter, estimated from 0 with sigma 20 ms), 182d56e:
# largest |t_d error| after 10 s 1.14 / 4.20 / 2.92 ms for seeds 1 / 2 / 3. The seed spread is
# wide (mean + 3 sd = 7.4 ms), so each seed is held at 1.2 x its own value.
ONLINE_ERROR_S = {1: 1.14e-3, 2: 4.20e-3, 3: 2.92e-3}


@pytest.fixture(scope="module", params=[1, 2, 3])
def online_offset(request, tmp_path_factory):
    """(seed, largest |t_d error| after 10 s): a true 10 ms offset (0.5 ms jitter), estimated
    from 0 on vid18_like; the run's own checks are here, outside the xfail."""
    seed, tmp = request.param, tmp_path_factory.mktemp(f"online_{request.param}")
    seq = simulate(tmp / "seq", scenario(tmp, "vid18_like", "  time_offset_s: 0.010\n  time_offset_jitter_s: 0.0005\n"),
                   20.0, seed, True)
    out = tmp / "out"
    r = vid_run(seq, out, "--config", str(config(tmp, 0.02, 0.0005)))
    assert r.returncode == 0, r.stderr
    t, td, _ = offset_series(out)
    assert t[-1] > 19.0
    return seed, float(np.abs(td[t >= 10.0] - 0.010).max())


def test_offset_estimated_online_ratchet(online_offset):
    seed, err = online_offset
    ratchet(f"vid18_like seed {seed} t_d error after 10 s [s]", err, 1.2 * ONLINE_ERROR_S[seed],
            ONLINE_ERROR_S[seed])


@target_not_met("issue #23: 0.5 ms after 10 s is below what vid18_like's rotation can tell: "
                "the information bound is 1.9-3.1 ms at 10 s (README)")
def test_offset_estimated_online(online_offset):
    """The issue's criterion: from a true 10 ms offset (0.5 ms jitter), within 0.5 ms after 10 s."""
    seed, err = online_offset
    target(f"vid18_like seed {seed} t_d error after 10 s [s]", err, 0.0005)


def test_rotation_bound_matches_the_closed_form():
    """w = A sin(2 pi f t) on one axis: integral alpha^2 over T = A^2 (2 pi f)^2 T / 2, so
    sigma = sigma_g / (A 2 pi f sqrt(T / 2)); the local-quadratic slope (for a measured gyro)
    gives the same on the clean signal."""
    t = np.arange(0, 20.0, 0.0025)
    A, f, sg = 0.5, 0.5, 1e-3
    w = np.zeros((t.size, 3))
    w[:, 2] = A * np.sin(2 * np.pi * f * t)
    expected = sg / (A * 2 * np.pi * f * np.sqrt(np.array([10.0, 19.0]) / 2))
    got = rotation_bound(t, w, sg, [10.0, 19.0])
    np.testing.assert_allclose(got, expected, rtol=0.01)
    np.testing.assert_allclose(rotation_bound(t, w, sg, [10.0, 19.0], half_window_s=0.1), expected, rtol=0.02)
