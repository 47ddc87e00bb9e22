"""Thrust-coefficient fit: the estimator's own thrust model fitted to a flight log.

The estimator (vio_core/thrust.h, docs/design.md §3) predicts the accelerometer as
``a_m = [0, 0, T/m] + F_ext + b_a + n_a`` with ``T = sum_i k_i n_i^2`` (n in the rotor sensor's
unit) and the thrust linearly interpolated from the rotor samples to the IMU times
(vio_core/thrust_buffer.h). With no external force (hover and vertical steps in still air,
away from the ground) the body-z accelerometer is therefore linear in the unknowns:

    a_z(t) = sum_i (k_i / m) n_i(t)^2 + b_z + noise

``per-rotor`` fits one k_i per rotor, ``collective`` one k shared by all rotors
(``T = k sum_i n_i^2``). A measured collective thrust (thrust0, N) is the same fit with one
"rotor" whose squared speed is the thrust: its k is the thrust scale s (a factor on the
measured thrust). Known regressors with unknown coefficients (``FitInput.extra``: the body
velocity -v_z, whose coefficient is the linear drag D_z) join the accelerometer rows. The mass is not fitted: the estimator divides by the mass of
vehicle.yaml, so k is fitted for that mass (k/m is what the data determine).

Per-rotor coefficients need differential thrust, which the accelerometer does not see; with the
vehicle's geometry and inertia the gyroscope does (:mod:`vid_eval.calib.torque_rows`: the
integrated Euler equation, linear in the k_i). The fit then stacks both kinds of rows, each
block weighted by the inverse of its own residual RMS (feasible generalised least squares:
start from the collective fit, re-estimate each block's noise, refit; three rounds). The
torque rows then give the **ratios** between the k_i, the accelerometer alone their **scale**
(with the bias, as in the collective fit): the torque windows carry some scale information too
(where the body accelerates), but their regressors (integrated noisy rotor speeds) attenuate
it, and with the bias free that was enough to pull every k_i 0.4-0.8 % low on the simulated
logs; the hover torque balance, whose measured side is zero, fixes the ratios without that
attenuation.

The least squares is numpy's ``lstsq`` (LAPACK gelsd, SVD based): it is stable on the
near-collinear designs a vertical-only log gives for per-rotor coefficients, and the same
SVD gives the parameter covariance; a hand-written normal-equations solver would square the
condition number and need its own rank handling.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np

from .torque_rows import TorqueRows

MODELS = ("collective", "per-rotor")
BIAS_MODES = ("fit", "groundtruth", "none")

#: Rotor samples further apart than this many median periods are a gap: IMU samples inside
#: it are not used (the estimator holds the last thrust there; a fit must not).
GAP_PERIODS = 5.0


@dataclass
class FitInput:
    """Samples of one log, already at the IMU times (see :func:`regressors`)."""

    t_ns: np.ndarray            # (N,) IMU times used
    accel_z: np.ndarray         # (N,) body-z specific force [m/s^2], external force removed
    speed_sq: np.ndarray        # (N, k) n_i^2 interpolated to the IMU times [unit^2]
    bias_z: Optional[np.ndarray] = None  # (N,) known accelerometer bias (ground truth)
    extra: Optional[np.ndarray] = None   # (N, e) further regressors of a_z (e.g. -v_z: coefficient D_z)


@dataclass
class ThrustFit:
    """Result of :func:`fit_thrust`."""

    model: str
    coefficients: np.ndarray    # (k,) k_i [N/unit^2] (all equal for collective)
    sigma: np.ndarray           # (k,) 1-sigma of each k_i from the residual scatter
    bias_z: float               # fitted (or mean known) accelerometer bias [m/s^2]
    residuals: np.ndarray       # (N,) a_z - prediction [m/s^2]
    predicted: np.ndarray       # (N,) predicted T/m + b_z [m/s^2]
    condition: float            # condition number of the (column-scaled) design
    warnings: List[str] = field(default_factory=list)
    torque_rms: Optional[np.ndarray] = None  # (3,) roll/pitch/yaw window residual RMS [N m s]
    torque_windows: int = 0     # windows of the Euler equation used (0: accelerometer only)
    extra: np.ndarray = field(default_factory=lambda: np.zeros(0))        # coefficients of FitInput.extra
    extra_sigma: np.ndarray = field(default_factory=lambda: np.zeros(0))  # their 1-sigma
    thrust_per_m: Optional[np.ndarray] = None  # (N,) the fitted T/m alone [m/s^2]

    @property
    def rms(self) -> float:
        """Residual RMS [m/s^2]."""
        return float(np.sqrt(np.mean(self.residuals ** 2)))

    @property
    def relative_sigma(self) -> np.ndarray:
        """1-sigma of each k_i relative to k_i."""
        return self.sigma / np.abs(self.coefficients)


def regressors(t_imu: np.ndarray, accel_z: np.ndarray, t_rotor: np.ndarray, speeds: np.ndarray,
               min_thrust_fraction: float, square: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """``(keep, speed_sq)``: n_i^2 linearly interpolated to the IMU times (as the estimator
    interpolates T, which is linear in n_i^2) and the mask of IMU samples usable for the fit:
    inside the rotor stream, not inside a rotor gap, and with sum n_i^2 at least
    ``min_thrust_fraction`` of its median (drops the ground, idle and spin-up parts, where the
    ground carries the weight). ``square=False``: the values are a thrust already (thrust0)."""
    t0 = t_rotor[0]
    tr = (t_rotor - t0).astype(float)
    ti = (t_imu - t0).astype(float)
    sq = speeds.astype(float) ** 2 if square else speeds.astype(float)
    speed_sq = np.stack([np.interp(ti, tr, sq[:, j]) for j in range(sq.shape[1])], axis=1)
    keep = (ti >= tr[0]) & (ti <= tr[-1])
    if len(tr) > 1:
        period = float(np.median(np.diff(tr)))
        right = np.clip(np.searchsorted(tr, ti, side="left"), 1, len(tr) - 1)
        keep &= (tr[right] - tr[right - 1]) <= GAP_PERIODS * period
    total = speed_sq.sum(axis=1)
    if keep.any():
        keep &= total >= min_thrust_fraction * float(np.median(total[keep]))
    keep &= np.isfinite(accel_z)
    return keep, speed_sq


def fit_thrust(data: FitInput, mass_kg: float, model: str, bias: str,
               torque: Optional[TorqueRows] = None) -> ThrustFit:
    """Least-squares fit of the thrust coefficients (module docstring: model and solver).

    Args:
        data: the samples (at least 10 and more than the unknowns).
        mass_kg: the mass the estimator will divide by (vehicle.yaml).
        model: ``collective`` or ``per-rotor``.
        bias: ``fit`` (a constant b_z is an unknown), ``groundtruth`` (``data.bias_z`` is
            subtracted) or ``none`` (b_z = 0).
        torque: rows of the rotational dynamics (per-rotor only; None: accelerometer only).
    """
    if model not in MODELS:
        raise ValueError(f"unknown model '{model}' (choose from {', '.join(MODELS)})")
    if bias not in BIAS_MODES:
        raise ValueError(f"unknown bias mode '{bias}' (choose from {', '.join(BIAS_MODES)})")
    y = np.asarray(data.accel_z, dtype=float).copy()
    known_bias = 0.0
    if bias == "groundtruth":
        if data.bias_z is None:
            raise ValueError("bias 'groundtruth' needs the ground-truth accelerometer bias")
        y -= data.bias_z
        known_bias = float(np.mean(data.bias_z))
    n_rotors = data.speed_sq.shape[1]
    cols = data.speed_sq / mass_kg if model == "per-rotor" else data.speed_sq.sum(axis=1, keepdims=True) / mass_kg
    k_count = cols.shape[1]
    extra = np.zeros((len(y), 0)) if data.extra is None else np.asarray(data.extra, dtype=float).reshape(len(y), -1)
    cols = np.hstack([cols, extra])
    if bias == "fit":
        cols = np.hstack([cols, np.ones((len(y), 1))])
    n_params = cols.shape[1]
    if len(y) < max(10, n_params + 1):
        raise ValueError(f"too few samples for the fit ({len(y)}; need at least {max(10, n_params + 1)})")
    use_torque = model == "per-rotor" and torque is not None
    if use_torque:
        t_cols = torque.design()
        t_cols = np.hstack([t_cols, np.zeros((len(t_cols), n_params - n_rotors))])
        t_y = torque.target()
        # Start from the collective solution (the accelerometer's scale, equal k_i) to get the
        # first noise estimates of each block.
        first = fit_thrust(data, mass_kg, "collective", bias)
        sigmas = _block_rms(first.residuals, t_y - t_cols[:, :n_rotors] @ first.coefficients)
        for _ in range(3):
            w = _row_weights(len(y), len(t_y), sigmas)
            A_all, y_all = np.vstack([cols, t_cols]) * w[:, None], np.concatenate([y, t_y]) * w
            sol_all, _, _, _ = np.linalg.lstsq(A_all / np.sqrt(np.mean(A_all ** 2, axis=0)), y_all, rcond=None)
            p_all = sol_all / np.sqrt(np.mean(A_all ** 2, axis=0))
            sigmas = _block_rms(y - cols @ p_all, t_y - t_cols @ p_all)
        w = _row_weights(len(y), len(t_y), sigmas)
        A_raw, y_fit = np.vstack([cols, t_cols]) * w[:, None], np.concatenate([y, t_y]) * w
    else:
        A_raw, y_fit = cols, y
    # Scale the columns to unit RMS so that the condition number speaks of the data (collinear
    # rotors), not of the units (rpm^2 ~ 1e7 next to the bias column of ones).
    scale = np.sqrt(np.mean(A_raw ** 2, axis=0))
    if np.any(scale == 0.0):
        raise ValueError("a rotor's speed is zero over the whole window: nothing to fit")
    A = A_raw / scale
    sol, _, rank, sv = np.linalg.lstsq(A, y_fit, rcond=None)
    if rank < n_params:  # no unique solution: any numbers printed would be arbitrary
        raise ValueError(f"the log cannot separate the {n_params} unknowns (design rank {rank}): the thrust "
                         "must vary (hover and vertical steps), or the bias be given (--bias groundtruth or none)")
    params = sol / scale
    pred = cols @ params
    res = y - pred
    if use_torque:  # rows already whitened by their block's noise: (A^T A)^-1 is the covariance
        cov_scaled = np.linalg.pinv(A.T @ A)
    else:  # covariance s^2 (A^T A)^-1 through the SVD (pinv), in the scaled parameters
        s2 = float(res @ res) / max(len(y) - n_params, 1)
        cov_scaled = s2 * np.linalg.pinv(A.T @ A)
    sig = np.sqrt(np.clip(np.diag(cov_scaled), 0.0, None)) / scale
    if use_torque:
        params, sig, pred = _rescale_by_accelerometer(params, cov_scaled / np.outer(scale, scale), data, y,
                                                      mass_kg, bias, n_rotors, extra)
        res = y - pred
    condition = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    thrust_per_m = cols[:, :k_count] @ params[:k_count]
    e_count = extra.shape[1]
    k, k_sig = params[:k_count], sig[:k_count]
    if model == "collective":
        k, k_sig = np.repeat(k, n_rotors), np.repeat(k_sig, n_rotors)
    b = float(params[-1]) if bias == "fit" else known_bias
    warnings = []
    worst = float(np.max(k_sig / np.abs(k)))
    if model == "per-rotor" and worst > 0.01:
        hint = ("the log lacks differential thrust (yaw, roll and pitch accelerations): give the vehicle's "
                "geometry (--geometry) so that the gyroscope's torque balance separates the rotors, or fit "
                "--model collective" if not use_torque else
                "the geometry or inertia may not match the vehicle, or the log is too short")
        warnings.append(f"per-rotor coefficients are poorly determined (1-sigma up to {100 * worst:.1f} %): {hint}")
    torque_rms = None
    if use_torque:
        t_res = (torque.target() - torque.design() @ params[:n_rotors]).reshape(-1, 3)
        torque_rms = np.sqrt(np.mean(t_res ** 2, axis=0))
    return ThrustFit(model, k, k_sig, b, res, pred + (known_bias if bias == "groundtruth" else 0.0),
                     condition, warnings, torque_rms, len(torque.lhs) if use_torque else 0,
                     params[k_count:k_count + e_count], sig[k_count:k_count + e_count], thrust_per_m)


def _rescale_by_accelerometer(params: np.ndarray, cov: np.ndarray, data: FitInput, y: np.ndarray, mass_kg: float,
                              bias: str, n_rotors: int, extra: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Keep the ratios k_i / mean(k) of the joint fit, refit their common scale (and the extra
    regressors and the bias) on the accelerometer rows alone. Returns (params, 1-sigma, predicted
    a_z); the 1-sigma of k_i combines the ratio's (from the joint covariance) and the scale's in
    quadrature."""
    k = params[:n_rotors]
    ratio = k / k.mean()
    # d ratio / d k = (I - ratio 1^T / n) / mean(k)
    jac = (np.eye(n_rotors) - np.outer(ratio, np.ones(n_rotors)) / n_rotors) / k.mean()
    ratio_sig = np.sqrt(np.clip(np.diag(jac @ cov[:n_rotors, :n_rotors] @ jac.T), 0.0, None))
    cols = np.hstack([(data.speed_sq @ ratio / mass_kg)[:, None], extra])
    if bias == "fit":
        cols = np.hstack([cols, np.ones((len(y), 1))])
    scale = np.sqrt(np.mean(cols ** 2, axis=0))  # unit columns: pinv must not drop the bias direction
    sol, _, _, _ = np.linalg.lstsq(cols / scale, y, rcond=None)
    pred = cols / scale @ sol
    res = y - pred
    cov_s = float(res @ res) / max(len(y) - cols.shape[1], 1) * np.linalg.pinv((cols / scale).T @ (cols / scale))
    sol, cov_s = sol / scale, cov_s / np.outer(scale, scale)
    alpha, alpha_sig = float(sol[0]), float(np.sqrt(max(cov_s[0, 0], 0.0)))
    out = params.copy()
    out[:n_rotors] = alpha * ratio
    out[n_rotors:] = sol[1:]
    sig = np.sqrt(np.concatenate([(alpha * ratio_sig) ** 2 + (ratio * alpha_sig) ** 2,
                                  np.clip(np.diag(cov_s)[1:], 0.0, None)]))
    return out, sig, pred


def _block_rms(accel_res: np.ndarray, torque_res: np.ndarray) -> np.ndarray:
    """(4,) residual RMS of the accelerometer rows and of each torque axis (floored: a block that
    fits perfectly must not get an infinite weight)."""
    axes = torque_res.reshape(-1, 3)
    rms = np.concatenate([[np.sqrt(np.mean(accel_res ** 2))], np.sqrt(np.mean(axes ** 2, axis=0))])
    return np.maximum(rms, 1e-12)


def _row_weights(n_accel: int, n_torque: int, sigmas: np.ndarray) -> np.ndarray:
    """Row weights 1/sigma: accelerometer rows first, then torque rows in roll/pitch/yaw order."""
    return np.concatenate([np.full(n_accel, 1.0 / sigmas[0]), np.tile(1.0 / sigmas[1:], n_torque // 3)])


def residuals_with(data: FitInput, mass_kg: float, coefficients: np.ndarray, bias: str) -> np.ndarray:
    """Residuals of given coefficients (e.g. the vehicle.yaml in use) on the same samples,
    with the bias handled as in the fit (``fit``: a fitted constant) and the extra regressors
    (drag) refitted."""
    pred = data.speed_sq @ np.asarray(coefficients, dtype=float) / mass_kg
    res = np.asarray(data.accel_z, dtype=float) - pred
    if bias == "groundtruth" and data.bias_z is not None:
        res = res - data.bias_z
    cols = [np.asarray(data.extra, dtype=float).reshape(len(res), -1)] if data.extra is not None else []
    if bias == "fit":
        cols.append(np.ones((len(res), 1)))
    if cols:
        A = np.hstack(cols)
        res = res - A @ np.linalg.lstsq(A, res, rcond=None)[0]
    return res
