"""Idealized accuracy bound of external-force estimation on a recorded force signal.

Question answered: how well could *any* linear filter estimate the world-frame force of a
sequence if everything except the force were known exactly (attitude, thrust, accelerometer
bias, gravity) and the camera delivered the *absolute* position with white noise sigma_p?
The real estimator has strictly less information (the MSCKF only sees relative motion, and
tilt, b_a and F_ext trade off), so its error can not be below these numbers.

Per world axis the model is the estimator's force model (force-rate state, integrated random
walk; docs/notes/force-accuracy.md):

    p' = v,  v' = F,  F' = F_dot,  F_dot' = w,   w white, density q  [m/s^4/sqrt(Hz)]

measured by the accelerometer at every IMU sample (y = F + n_a, density sigma_a) and by the
camera at its rate (y = p + n_p, sigma_p per frame). The truth is the sequence's force0
divided by the mass; the position is its double integral (thrust and gravity cancel). The
covariance recursion does not depend on the data, so it runs once for the three axes.
The causal Kalman filter is what an estimator can output at time t; the Rauch-Tung-Striebel
smoother (all data, both directions) is shown beside it for comparison.

Abrupt forces (rope snaps, impacts, steps) break the random-walk model of any linear filter.
``jump_min`` > 0 gives the filter a *jump oracle*: at every IMU sample where the true force
changes by more than ``jump_min`` [m/s^2] from the previous one (a rate no smooth force has),
the filter is told a jump happens and forgets the force and its rate (variance 1e4). It still
has to estimate the new level from the noisy readings; this is the bound for an estimator with
a perfect jump detector.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, List, Optional, Sequence

import numpy as np


@dataclass(frozen=True)
class BoundSetup:
    """Sensor model of the bound."""
    imu_rate_hz: float = 400.0
    camera_rate_hz: float = 30.0
    accel_noise_density: float = 0.1  # [m/s^2/sqrt(Hz)]
    skip_s: float = 5.0               # RMSE after the first skip_s seconds, as the estimator's
    seed: int = 1


@dataclass(frozen=True)
class BoundResult:
    """RMSE of the norm of the force error [m/s^2] for one sigma_p (best q of the grid)."""
    sigma_p_m: float
    q: float
    filter_rmse: float
    smoother_rmse: float
    filter_rmse_axes: tuple


def _model(dt: float, q: float):
    A = np.array([[1.0, dt, dt ** 2 / 2, dt ** 3 / 6],
                  [0.0, 1.0, dt, dt ** 2 / 2],
                  [0.0, 0.0, 1.0, dt],
                  [0.0, 0.0, 0.0, 1.0]])
    # Exact discretization of white noise of density q on F_dot's derivative.
    Q = q ** 2 * np.array([
        [dt ** 7 / 252, dt ** 6 / 72, dt ** 5 / 30, dt ** 4 / 24],
        [dt ** 6 / 72, dt ** 5 / 20, dt ** 4 / 8, dt ** 3 / 6],
        [dt ** 5 / 30, dt ** 4 / 8, dt ** 3 / 3, dt ** 2 / 2],
        [dt ** 4 / 24, dt ** 3 / 6, dt ** 2 / 2, dt]])
    return A, Q


def resample_force(t_s: np.ndarray, force: np.ndarray, rate_hz: float):
    """Force [N/kg = m/s^2] (n x 3) on a uniform grid at rate_hz, and its double integral."""
    if t_s.ndim != 1 or force.shape != (t_s.size, 3) or t_s.size < 2:
        raise ValueError("force must be n x 3 with n >= 2 timestamps")
    dt = 1.0 / rate_hz
    t = np.arange(0.0, t_s[-1] - t_s[0], dt)
    F = np.stack([np.interp(t, t_s - t_s[0], force[:, k]) for k in range(3)], axis=1)
    v = np.cumsum(F, axis=0) * dt
    p = np.cumsum(v, axis=0) * dt
    return t, F, p


def simulate_measurements(F: np.ndarray, p: np.ndarray, sigma_p: float, setup: BoundSetup,
                          rng: np.random.Generator):
    """Accelerometer readings of F (every sample) and noisy positions (n x 3 each; only the
    camera samples, every imu_rate / camera_rate, are used by the filter)."""
    r_a = setup.accel_noise_density ** 2 * setup.imu_rate_hz  # variance of one IMU sample
    y_a = F + np.sqrt(r_a) * rng.standard_normal(F.shape)
    y_p = p + sigma_p * rng.standard_normal(p.shape)
    return y_a, y_p


def kalman_force(y_a: np.ndarray, y_p: np.ndarray, x0: np.ndarray, P0: np.ndarray, q: float,
                 sigma_p: float, setup: BoundSetup, smooth: bool,
                 jumps: Optional[np.ndarray] = None) -> np.ndarray:
    """State [p, v, F, F_dot] per axis (4 x 3) from the readings: the causal filter's
    estimates (smooth=False) or the RTS smoother's (n x 4 x 3). ``jumps`` (bool per sample):
    forget F and F_dot before that sample's update (jump oracle)."""
    n = y_a.shape[0]
    dt = 1.0 / setup.imu_rate_hz
    A, Q = _model(dt, q)
    r_a = setup.accel_noise_density ** 2 / dt
    cam_every = max(1, int(round(setup.imu_rate_hz / setup.camera_rate_hz)))
    x = np.array(x0, dtype=float)
    P = np.array(P0, dtype=float)
    xs = np.empty((n, 4, 3))
    if smooth:
        Ps = np.empty((n, 4, 4))
        Pp = np.empty((n, 4, 4))
    for i in range(n):
        if i > 0:
            x = A @ x
            P = A @ P @ A.T + Q
        if jumps is not None and jumps[i]:
            P[2:, :] = 0.0
            P[:, 2:] = 0.0
            P[2, 2] = P[3, 3] = 1e4
        if smooth:
            Pp[i] = P
        meas = [(2, y_a[i], r_a)]
        if i % cam_every == 0:
            meas.append((0, y_p[i], sigma_p ** 2))
        for h, y, r in meas:
            K = P[:, h] / (P[h, h] + r)
            x = x + np.outer(K, y - x[h])
            P = P - np.outer(K, P[h, :])
        xs[i] = x
        if smooth:
            Ps[i] = P
    if not smooth:
        return xs
    xsm = xs.copy()
    for i in range(n - 2, -1, -1):
        C = np.linalg.solve(Pp[i + 1].T, (Ps[i] @ A.T).T).T  # Ps A^T Pp^-1
        xsm[i] = xs[i] + C @ (xsm[i + 1] - A @ xs[i])
    return xsm


def run_bound(F: np.ndarray, p: np.ndarray, q: float, sigma_p: float, setup: BoundSetup,
              smooth: bool, rng: np.random.Generator, jump_min: float = 0.0) -> np.ndarray:
    """Force estimate (n x 3) of the filter or smoother on noisy readings of the truth,
    started at the truth (the bound is about tracking, not initialization); with a jump
    oracle when jump_min > 0 (see the module text)."""
    y_a, y_p = simulate_measurements(F, p, sigma_p, setup, rng)
    x0 = np.zeros((4, 3))
    x0[0], x0[2] = p[0], F[0]
    P0 = np.diag([1e-6, 1e-4, 1.0, 1.0])
    jumps = None
    if jump_min > 0.0:
        jumps = np.zeros(F.shape[0], dtype=bool)
        jumps[1:] = np.linalg.norm(np.diff(F, axis=0), axis=1) > jump_min
    return kalman_force(y_a, y_p, x0, P0, q, sigma_p, setup, smooth, jumps)[:, 2, :]


def _rmse_norm(err: np.ndarray):
    per_axis = np.sqrt(np.mean(err ** 2, axis=0))
    return float(np.sqrt(np.sum(per_axis ** 2))), tuple(float(a) for a in per_axis)


def force_bound(t_s: np.ndarray, force: np.ndarray, sigmas_p_m: Sequence[float],
                q_grid: Iterable[float] = (0.1, 0.2, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0),
                setup: Optional[BoundSetup] = None, jump_min: float = 0.0) -> List[BoundResult]:
    """Best-q filter RMSE and the smoother RMSE at that q, for every sigma_p (with a jump
    oracle when jump_min > 0)."""
    setup = setup or BoundSetup()
    _, F, p = resample_force(np.asarray(t_s, float), np.asarray(force, float), setup.imu_rate_hz)
    k0 = int(round(setup.skip_s * setup.imu_rate_hz))
    if F.shape[0] <= k0 + 1:
        raise ValueError(f"the force signal is shorter than skip_s = {setup.skip_s} s")
    q_list = list(q_grid)
    out = []
    for sp in sigmas_p_m:
        if not sp > 0:
            raise ValueError(f"sigma_p must be > 0, got {sp}")
        best = None
        for q in q_list:
            rng = np.random.default_rng(setup.seed)
            est = run_bound(F, p, q, sp, setup, smooth=False, rng=rng, jump_min=jump_min)
            total, axes = _rmse_norm(est[k0:] - F[k0:])
            if best is None or total < best[1]:
                best = (q, total, axes)
        rng = np.random.default_rng(setup.seed)
        sm = run_bound(F, p, best[0], sp, setup, smooth=True, rng=rng, jump_min=jump_min)
        out.append(BoundResult(sigma_p_m=sp, q=best[0], filter_rmse=best[1],
                               smoother_rmse=_rmse_norm(sm[k0:] - F[k0:])[0],
                               filter_rmse_axes=best[2]))
    return out


def split_by_time_scale(t_s: np.ndarray, err: np.ndarray, window_s: float):
    """RMSE of |err| split into its slow part (centred moving average over window_s) and the
    rest: (total, slow, fast). Samples within window_s / 2 of either end are left out of all
    three so that they cover the same samples. A slow part that dominates says the error is
    a bias-like offset (tilt / accelerometer bias), a fast one that it is tracking lag / noise.
    """
    t_s = np.asarray(t_s, float)
    err = np.asarray(err, float)
    if err.ndim != 2 or err.shape != (t_s.size, 3):
        raise ValueError("err must be n x 3 matching t_s")
    dt = float(np.median(np.diff(t_s)))
    n = max(1, int(round(window_s / dt)))
    if err.shape[0] <= 2 * n:
        raise ValueError(f"series shorter than two windows of {window_s} s")
    kernel = np.ones(n) / n
    slow = np.stack([np.convolve(err[:, k], kernel, mode="same") for k in range(3)], axis=1)
    keep = slice(n, err.shape[0] - n)
    fast = err - slow

    def rmse(e):
        return float(np.sqrt(np.mean(np.sum(e[keep] ** 2, axis=1))))
    return rmse(err), rmse(slow), rmse(fast)
