"""The body x and y rows of the dynamics model, and the thrust axis they give.

With the thrust along a unit axis t_I (vehicle.yaml ``thrust_axis``) and linear rotor drag
(``linear_drag``), the estimator predicts the accelerometer (docs/design.md §3)

    a_j = t_j T/m - D_j v_j + b_j          j = x, y, z (body axes, v_I the body velocity)

The z row is the thrust fit (:mod:`vid_eval.calib.thrust_fit`; it fits k' = k t_z, t_z = cos
of the tilt). Given its T'/m = k' n^2 / m, each lateral row is linear in c_j = t_j / t_z, D_j and
b_j: a_j = c_j T'/m - D_j v_j + b_j, least squares (numpy ``lstsq``). The thrust axis is then
[c_x, c_y, 1] normalized and the coefficient k = k' |[c_x, c_y, 1]|. In hover T'/m is a constant
and c_j T'/m cannot be told from the bias b_j: only a thrust that varies (vertical steps)
separates the two, and the 1-sigma of c_j says how well.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
from scipy.signal import butter, sosfiltfilt

#: Largest 1-sigma of a tilt component [deg] for which the thrust axis is written: beyond it
#: the log does not separate the tilt from the accelerometer bias (too little thrust variation).
AXIS_SIGMA_MAX_DEG = 0.25
#: Largest 1-sigma of a drag coefficient [1/s] for which it is written: beyond it the log hardly
#: moves along that axis (real rotor drag is 0.2-0.5 1/s).
DRAG_SIGMA_MAX = 0.05
#: Low-pass [Hz] for the force comparisons (drag share, lateral force): below it lies the
#: aerodynamic force, above it the rotor vibration.
FORCE_BAND_HZ = 5.0


@dataclass
class LateralFit:
    """One body axis: a_j = c T'/m - D v_j + b."""

    c: float
    c_sigma: float
    drag: float           # D_j [1/s] (NaN without the velocity)
    drag_sigma: float
    bias: float           # b_j [m/s^2]
    residual: np.ndarray  # (N,) a_j - model


def fit_lateral(a_j: np.ndarray, thrust_per_m: np.ndarray, v_j: Optional[np.ndarray] = None) -> LateralFit:
    """Least squares of one lateral row (module docstring); 1-sigma from the residual scatter.
    The drag column stays in even where the log hardly moves along the axis: on vertical steps
    the body leans by the thrust tilt, so v_j ~ -tilt_j v_z follows the thrust steps, and
    leaving the drag out biased the tilt 6 % low on the simulated steps log. A velocity that is
    zero to 1 mm/s (a simulated level body) carries nothing: no column, the drag is NaN."""
    if v_j is not None and not np.sqrt(np.mean(np.square(v_j))) > 1e-3:
        fit = fit_lateral(a_j, thrust_per_m)
        fit.drag_sigma = float("inf")
        return fit
    cols = [thrust_per_m] + ([] if v_j is None else [-v_j]) + [np.ones_like(thrust_per_m)]
    A = np.column_stack(cols)
    scale = np.sqrt(np.mean(A ** 2, axis=0))
    sol, *_ = np.linalg.lstsq(A / scale, a_j, rcond=None)
    p = sol / scale
    res = a_j - A @ p
    cov = float(res @ res) / max(len(a_j) - len(p), 1) * np.linalg.pinv((A / scale).T @ (A / scale))
    sig = np.sqrt(np.clip(np.diag(cov), 0.0, None)) / scale
    drag, drag_sig = (float(p[1]), float(sig[1])) if v_j is not None else (float("nan"), float("nan"))
    return LateralFit(float(p[0]), float(sig[0]), drag, drag_sig, float(p[-1]), res)


@dataclass
class ThrustAxis:
    axis: np.ndarray         # (3,) unit vector in I
    sigma: np.ndarray        # (3,) 1-sigma of each component
    tilt_deg: float          # angle from z_I
    tilt_sigma_deg: float
    azimuth_deg: float       # direction of the tilt from x_I towards y_I
    component_sigma_deg: float  # the larger 1-sigma of the two tilt components

    @property
    def determined(self) -> bool:
        """The log separates the tilt from the bias (AXIS_SIGMA_MAX_DEG)."""
        return self.component_sigma_deg <= AXIS_SIGMA_MAX_DEG

    @property
    def norm_factor(self) -> float:
        """|[c_x, c_y, 1]| = 1 / t_z: the z fit's coefficient times this is the thrust's."""
        return float(1.0 / self.axis[2])


def thrust_axis(x: LateralFit, y: LateralFit) -> ThrustAxis:
    """The axis [c_x, c_y, 1] / norm and its 1-sigma (first-order propagation; x and y rows are
    separate fits, so independent)."""
    u = np.array([x.c, y.c, 1.0])
    n = float(np.linalg.norm(u))
    a = u / n
    J = (np.eye(3) - np.outer(a, a)) / n            # d(u/|u|)/du; u_z is fixed
    cov_u = np.diag([x.c_sigma ** 2, y.c_sigma ** 2, 0.0])
    sigma = np.sqrt(np.clip(np.diag(J @ cov_u @ J.T), 0.0, None))
    r = float(np.hypot(x.c, y.c))
    tilt = float(np.degrees(np.arctan(r)))
    if r > 0:
        g = np.array([x.c, y.c]) / (r * (1.0 + r * r))   # d atan(r) / dc
        tilt_sig = float(np.degrees(np.sqrt((g[0] * x.c_sigma) ** 2 + (g[1] * y.c_sigma) ** 2)))
    else:
        tilt_sig = float(np.degrees(max(x.c_sigma, y.c_sigma)))
    comp = float(np.degrees(np.arctan(max(x.c_sigma, y.c_sigma))))
    return ThrustAxis(a, sigma, tilt, tilt_sig, float(np.degrees(np.arctan2(y.c, x.c))), comp)


def low_pass(x: np.ndarray, rate_hz: float, cutoff_hz: float = FORCE_BAND_HZ) -> np.ndarray:
    """Zero-phase 4th-order Butterworth low-pass along axis 0 (scipy ``sosfiltfilt``)."""
    sos = butter(4, cutoff_hz, "lowpass", fs=rate_hz, output="sos")
    return sosfiltfilt(sos, x, axis=0)


def drag_share(body_force: np.ndarray, drag_term: np.ndarray, rate_hz: float) -> float:
    """Share of the low-passed body force's power (everything but thrust and bias, (N, 3)) that
    the drag term -D v_I explains, over the three axes together."""
    f = low_pass(body_force - body_force.mean(axis=0), rate_hz)
    r = low_pass(body_force - drag_term - (body_force - drag_term).mean(axis=0), rate_hz)
    return float(1.0 - np.sum(r ** 2) / max(np.sum(f ** 2), 1e-300))
