"""Clock offsets and the IMU-to-mocap-body rotation, measured from the data.

* :func:`lag`: the offset d between two sampled signals of the same motion: what the reference
  shows at its time t, the other stream shows stamped t + d (d > 0: the other stream's stamps
  are late). Coarse: the normalized cross-correlation at whole reference samples; fine: the
  maximum of the same correlation over continuous d (scipy's bounded Brent search, golden
  section with parabolic steps) with the other signal interpolated by a cubic spline.
* :func:`mocap_body_rate`: the mocap body angular rate, w_M = Log(R_k^T R_k+1) / dt at the
  midpoint of two poses.
* :func:`gyro_mocap_sync`: d from |w_I| vs |w_M| (rotation-invariant), then R_IM from the rate
  vectors (Wahba's problem: scipy ``Rotation.align_vectors`` on the centred vectors, w_I = b +
  R_IM w_M with a gyro bias b), then d again on the vectors rotated into I, and R_IM again.
* :func:`thrust_offset`: the thrust stream's offset against the accelerometer, from the fit
  a_z = s T/m(t + d) + b - D_z v_z: the body drag term is a regressor of the fit, because the
  drag correlates with the velocity and fakes a lag at low frequency in a plain correlation.
* Each number comes with a standard error from its spread over 5 consecutive parts of the log:
  a flight that hardly rotates cannot pin them down, and says so.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Tuple

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import minimize_scalar
from scipy.spatial.transform import Rotation

from ..core.geometry import rot_from_wxyz
from .errors import DataError

DEFAULT_MAX_LAG_S = 0.5
SEGMENTS = 5


@dataclass
class Lag:
    offset_s: float      # other stamps - reference stamps of the same event
    coarse_s: float      # best whole-sample lag
    correlation: float   # normalized correlation (or R^2 with regressors) at offset_s
    samples: int         # reference samples used
    stderr_s: float = float("nan")   # standard error: spread of the offset over SEGMENTS parts / sqrt(parts)
    at_limit: bool = False           # the best whole-sample lag is the largest searched: not determined

    def text(self) -> str:
        """``+1.234 +- 0.056 ms`` (and a warning at the search limit)."""
        limit = " (at the --max-lag limit: not determined)" if self.at_limit else ""
        return f"{self.offset_s * 1e3:+.3f} +- {self.stderr_s * 1e3:.3f} ms{limit}"


def _corr(a: np.ndarray, b: np.ndarray) -> float:
    a = a - a.mean(axis=0)
    b = b - b.mean(axis=0)
    den = np.sqrt((a * a).sum() * (b * b).sum())
    return float((a * b).sum() / den) if den > 0 else 0.0


def _r2(y: np.ndarray, X: np.ndarray) -> float:
    """R^2 of the least-squares fit of y on the columns of X (which include a constant): the
    explained share b^T G^-1 b / |y_c|^2 of the centred, unit-scaled columns (G = X_c^T X_c,
    b = X_c^T y_c; a few columns, so the small normal equations are well conditioned and ~3x
    cheaper than an SVD of the whole design, which the lag search solves hundreds of times)."""
    Xc = X - X.mean(axis=0)
    norm = np.sqrt(np.einsum("ij,ij->j", Xc, Xc))
    Xn = Xc[:, norm > 0] / norm[norm > 0]
    yc = y - y.mean()
    b = Xn.T @ yc
    coef, *_ = np.linalg.lstsq(Xn.T @ Xn, b, rcond=None)
    return float((b @ coef) / (yc @ yc))


def lag(t_ref_ns: np.ndarray, x_ref: np.ndarray, t_other_ns: np.ndarray, x_other: np.ndarray,
        max_lag_s: float = DEFAULT_MAX_LAG_S, regressors: Optional[np.ndarray] = None,
        segments: int = SEGMENTS) -> Lag:
    """Offset of ``x_other`` against ``x_ref`` (1-D or (N, k)); see the module docstring.

    With ``regressors`` ((N, r) at the reference times; 1-D ``x_ref`` only) the score is the
    R^2 of x_ref ~ a x_other(t + d) + b + c . regressors instead of the correlation (a known
    second cause of x_ref, such as body drag in the accelerometer, would otherwise bias d).
    The standard error comes from the spread of d over ``segments`` consecutive parts."""
    t0 = int(t_ref_ns[0])
    tr = (t_ref_ns - t0) * 1e-9
    to = (t_other_ns - t0) * 1e-9
    xr = np.asarray(x_ref, dtype=float).reshape(len(tr), -1)
    spline = CubicSpline(to, np.asarray(x_other, dtype=float).reshape(len(to), -1), axis=0, extrapolate=False)
    margin = max_lag_s + 2.0 * max(float(np.median(np.diff(tr))), float(np.median(np.diff(to))))
    keep = (tr >= to[0] + margin) & (tr <= to[-1] - margin)
    if keep.sum() < 20:
        raise DataError(f"{int(keep.sum())} samples where the streams overlap (with +-{max_lag_s:g} s of lag): "
                        "too few to measure a clock offset")
    fixed = None
    if regressors is not None:
        fixed = np.hstack([np.asarray(regressors, dtype=float).reshape(len(tr), -1), np.ones((len(tr), 1))])
    dt = float(np.median(np.diff(tr)))
    idx = np.flatnonzero(keep)
    offset, coarse, value = _best(tr[idx], xr[idx], None if fixed is None else fixed[idx], spline, dt, max_lag_s)
    parts = [p for p in np.array_split(idx, segments) if p.size >= 20] if segments > 1 else []
    each = [_best(tr[p], xr[p], None if fixed is None else fixed[p], spline, dt, max_lag_s)[0] for p in parts]
    stderr = float(np.std(each, ddof=1) / np.sqrt(len(each))) if len(each) > 1 else float("nan")
    return Lag(offset, coarse, value, int(keep.sum()), stderr, abs(coarse) >= int(max_lag_s / dt) * dt - 1e-12)


def _best(tk, xk, fixed, spline, dt, max_lag_s):
    """(refined offset, whole-sample offset, score) of one set of reference samples."""
    if fixed is None:
        score = lambda d: _corr(xk, spline(tk + d))  # noqa: E731
    else:
        score = lambda d: _r2(xk[:, 0], np.hstack([spline(tk + d), fixed]))  # noqa: E731
    steps = np.arange(-int(max_lag_s / dt), int(max_lag_s / dt) + 1)
    scores = np.array([score(k * dt) for k in steps])
    coarse = float(steps[int(np.argmax(scores))] * dt)
    res = minimize_scalar(lambda d: -score(d), bounds=(coarse - dt, coarse + dt),
                          method="bounded", options={"xatol": 1e-7})
    return float(res.x), coarse, -float(res.fun)


@dataclass
class ThrustOffset:
    fitted: Lag      # thrust stamps - IMU stamps from a_z ~ s T/m + b (- D_z v_z with the velocity)
    plain: Lag       # the same from the plain correlation of a_z and T/m (no drag regressor)
    scale: float     # s of the fit at the fitted offset
    drag_z: float    # D_z [1/s] of the fit (NaN without the velocity)


def thrust_offset(t_imu_ns: np.ndarray, accel_z: np.ndarray, t_thrust_ns: np.ndarray, thrust_per_m: np.ndarray,
                  v_z: Optional[np.ndarray] = None, max_lag_s: float = DEFAULT_MAX_LAG_S) -> ThrustOffset:
    """Thrust stamps - IMU stamps (module docstring): ``thrust_per_m`` [m/s^2] at the thrust
    stamps, ``v_z`` the body-z velocity at the IMU stamps (None: no drag term, plain correlation)."""
    plain = lag(t_imu_ns, accel_z, t_thrust_ns, thrust_per_m, max_lag_s)
    fitted = plain if v_z is None else lag(t_imu_ns, accel_z, t_thrust_ns, thrust_per_m, max_lag_s,
                                           regressors=np.asarray(v_z)[:, None])
    shifted = np.interp((t_imu_ns - t_thrust_ns[0]).astype(float) + fitted.offset_s * 1e9,
                        (t_thrust_ns - t_thrust_ns[0]).astype(float), thrust_per_m)
    X = np.column_stack([shifted, np.ones_like(shifted)] + ([] if v_z is None else [v_z]))
    coef, *_ = np.linalg.lstsq(X, accel_z, rcond=None)
    return ThrustOffset(fitted, plain, float(coef[0]), float("nan") if v_z is None else float(-coef[2]))


def mocap_body_rate(t_ns: np.ndarray, q_WM_wxyz: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(midpoint times [ns], body rates w_M (N-1, 3) [rad/s]) of a mocap orientation series."""
    R = rot_from_wxyz(q_WM_wxyz)
    dt = np.diff(t_ns) * 1e-9
    w = (R[:-1].inv() * R[1:]).as_rotvec() / dt[:, None]
    t_mid = t_ns[:-1] + np.diff(t_ns) // 2
    return t_mid, w


@dataclass
class GyroSync:
    lag: Lag
    R_IM: Rotation         # mocap body axes -> IMU axes (w_I = R_IM w_M)
    rms_rad_s: float       # |w_I - b - R_IM w_M(t + d)| RMS after the corrections
    bias: np.ndarray = field(default_factory=lambda: np.zeros(3))   # gyro bias b fitted alongside R_IM
    angle_stderr_deg: float = float("nan")   # spread of R_IM over SEGMENTS parts / sqrt(parts - 1)


def gyro_mocap_sync(t_imu_ns: np.ndarray, gyro: np.ndarray, t_gt_ns: np.ndarray, q_WM_wxyz: np.ndarray,
                    max_lag_s: float = DEFAULT_MAX_LAG_S) -> GyroSync:
    """Clock offset of the mocap against the IMU and the rotation R_IM (module docstring)."""
    t_mid, w_M = mocap_body_rate(t_gt_ns, q_WM_wxyz)
    first = lag(t_imu_ns, np.linalg.norm(gyro, axis=1), t_mid, np.linalg.norm(w_M, axis=1), max_lag_s, segments=1)
    offset = first.offset_s
    R_IM = Rotation.identity()
    result = first
    for _ in range(2):
        w_M_at = _at(t_mid, w_M, t_imu_ns, offset)
        ok = np.isfinite(w_M_at).all(axis=1)
        R_IM = _wahba(gyro[ok], w_M_at[ok])
        result = lag(t_imu_ns, gyro, t_mid, R_IM.apply(w_M), max_lag_s)
        offset = result.offset_s
    w_M_at = _at(t_mid, w_M, t_imu_ns, offset)
    ok = np.isfinite(w_M_at).all(axis=1)
    R_IM = _wahba(gyro[ok], w_M_at[ok])
    bias = gyro[ok].mean(axis=0) - R_IM.apply(w_M_at[ok].mean(axis=0))
    rms = float(np.sqrt(np.mean(np.sum((gyro[ok] - bias - R_IM.apply(w_M_at[ok])) ** 2, axis=1))))
    parts = [p for p in np.array_split(np.flatnonzero(ok), SEGMENTS) if p.size >= 20]
    each = [_wahba(gyro[p], w_M_at[p]) for p in parts]
    spread = np.array([np.degrees((R * R_IM.inv()).magnitude()) for R in each])
    stderr = float(np.sqrt(np.mean(spread ** 2) / max(len(each) - 1, 1))) if len(each) > 1 else float("nan")
    return GyroSync(result, R_IM, rms, bias, stderr)


def _wahba(w_I: np.ndarray, w_M: np.ndarray) -> Rotation:
    """R_IM minimizing |w_I - b - R_IM w_M|^2 over R_IM and a constant gyro bias b (both sides
    centred, then scipy's align_vectors)."""
    R, _ = Rotation.align_vectors(w_I - w_I.mean(axis=0), w_M - w_M.mean(axis=0))
    return R


def _at(t_ns: np.ndarray, x: np.ndarray, t_query_ns: np.ndarray, offset_s: float) -> np.ndarray:
    """x (cubic spline) at t_query + offset; NaN outside its span."""
    t0 = int(t_ns[0])
    spline = CubicSpline((t_ns - t0) * 1e-9, x, axis=0, extrapolate=False)
    return spline((t_query_ns - t0) * 1e-9 + offset_s)
