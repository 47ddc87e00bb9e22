"""How well a flight can tell the camera-IMU time offset t_d: the rotation path's bound.

A camera that sees its rotation R(t + t_d) and a gyro that measures w(t) + n (white, density
sigma_g) differ by alpha(t) * dt_d to first order, alpha the angular acceleration. The Fisher
information on t_d is then

    I = integral |alpha(t)|^2 dt / sigma_g^2,        sigma(t_d) >= 1 / sqrt(I),

the Cramér-Rao bound of any estimator that gets t_d from the rotation (docs/notes/time-offset.md:
the estimator's sigma on noise-free data is 3-22 % above it; the
position path adds next to nothing on our flights). It says how much rotation a calibration
needs: 0.5 ms at 3 sigma after 10 s takes an RMS angular acceleration of 1.9 rad/s^2 with
sigma_g = 1e-3 rad/s/sqrt(Hz).
"""
from __future__ import annotations

import numpy as np


def angular_acceleration(t_s: np.ndarray, gyro: np.ndarray, half_window_s: float = 0.0) -> np.ndarray:
    """alpha per sample [rad/s^2] (N x 3). half_window_s = 0: central differences (noise-free
    gyro); > 0: slope of a local quadratic over +-half_window_s (a measured gyro; its white
    noise still adds sigma^2 / sum(dt^2) per axis to alpha^2, which rotation_bound does not
    subtract: on a noisy gyro the bound comes out optimistic)."""
    t = np.asarray(t_s, float)
    w = np.asarray(gyro, float)
    if half_window_s <= 0.0:
        return np.gradient(w, t, axis=0)
    alpha = np.empty_like(w)
    for i, ti in enumerate(t):
        m = np.abs(t - ti) <= half_window_s
        x = t[m] - ti
        A = np.stack([np.ones_like(x), x, x * x], axis=1)
        alpha[i] = np.linalg.lstsq(A, w[m], rcond=None)[0][1]
    return alpha


def rotation_bound(t_s, gyro, gyro_noise_density: float, until_s=None, half_window_s: float = 0.0) -> np.ndarray:
    """1-sigma bound on t_d [s] from the data up to each time in ``until_s`` (seconds after the
    first sample; default: the whole record). ``gyro`` as read (bias does not matter)."""
    t = np.asarray(t_s, float)
    alpha = angular_acceleration(t, gyro, half_window_s)
    a2 = np.sum(alpha ** 2, axis=1)
    dt = np.gradient(t)
    info = np.cumsum(a2 * dt) / gyro_noise_density ** 2
    rel = t - t[0]
    until = np.atleast_1d(rel[-1] if until_s is None else np.asarray(until_s, float))
    idx = np.clip(np.searchsorted(rel, until), 0, len(t) - 1)
    with np.errstate(divide="ignore"):
        return 1.0 / np.sqrt(info[idx])
