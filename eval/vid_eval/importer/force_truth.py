"""External-force truth from motion capture and thrust (docs/formats.md §1 force0: world frame, N).

The mocap position is low-passed (zero phase, smoothing.py) and differentiated twice, a_W;
the specific force in I is f_I = R_WI^T (a_W - g_W), g_W = [0, 0, -g]; the thrust T_I =
[0, 0, T / m] (thrust0, interpolated to the mocap times); the external force is everything
else, F_W = m R_WI (f_I - T_I) = m (a_W - g_W) - R_WI [0, 0, T]. The thrust term is low-passed
with the same filter as the position, so F_W is the external force seen through that filter
(not the raw thrust's vibration against a smoothed acceleration).

:func:`drag_fit` fits the body force to linear rotor drag, F_I / m = -D v_I per axis (least
squares, no intercept), and tells how much of the force it explains.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.geometry import rot_from_wxyz
from .errors import DataError
from .smoothing import derivatives, smooth

#: Default low-pass cutoff of the force truth [Hz]; docs/own-vehicle.md gives the reasoning.
FORCE_CUTOFF_HZ = 5.0


@dataclass
class ForceTruth:
    t_ns: np.ndarray        # (N,) mocap times inside the thrust stream's span
    F_W: np.ndarray         # (N, 3) external force, world, N
    F_I_per_m: np.ndarray   # (N, 3) the same in the IMU frame per unit mass, m/s^2
    v_I: np.ndarray         # (N, 3) velocity in the IMU frame (smoothed mocap), m/s


def force_truth(t_gt_ns: np.ndarray, p_W: np.ndarray, q_WI_wxyz: np.ndarray, t_thrust_ns: np.ndarray,
                thrust_n: np.ndarray, mass_kg: float, gravity: float, cutoff_hz: float = FORCE_CUTOFF_HZ
                ) -> ForceTruth:
    """F_W at the mocap times that the thrust stream covers (module docstring)."""
    inside = (t_gt_ns >= t_thrust_ns[0]) & (t_gt_ns <= t_thrust_ns[-1])
    if inside.sum() < 5:
        raise DataError("the thrust stream covers fewer than 5 mocap samples: no force truth")
    t = t_gt_ns[inside]
    d = derivatives(t, p_W[inside], cutoff_hz)
    R_WI = rot_from_wxyz(q_WI_wxyz[inside])
    T = np.interp((t - t[0]).astype(float), (t_thrust_ns - t[0]).astype(float), thrust_n)
    thrust_W = smooth(t, R_WI.apply(np.column_stack([np.zeros_like(T), np.zeros_like(T), T])), cutoff_hz)
    g_W = np.array([0.0, 0.0, -gravity])
    F_W = mass_kg * (d.a - g_W) - thrust_W
    # The zero-phase filter's start-up and the padding of the ends bend the second derivative
    # near the ends (the Blackbird flight's first 0.2 s read 3 m/s^2 of force that is not
    # there): no truth within 3 / cutoff seconds of either end.
    edge_ns = int(3.0 / cutoff_hz * 1e9) if cutoff_hz > 0 else 0
    keep = (t - t[0] >= edge_ns) & (t[-1] - t >= edge_ns)
    if keep.sum() < 5:
        raise DataError(f"fewer than 5 mocap samples more than {edge_ns * 1e-9:g} s from the ends: no force truth")
    R_keep = R_WI[keep]
    return ForceTruth(t[keep], F_W[keep], R_keep.inv().apply(F_W[keep]) / mass_kg, R_keep.inv().apply(d.v[keep]))


@dataclass
class DragFit:
    D: np.ndarray            # (3,) 1/s, F_I / m = -D v_I
    rms: np.ndarray          # (3,) RMS of F_I / m, m/s^2
    explained: np.ndarray    # (3,) 1 - residual^2 / F^2 (share of the force's power)
    explained_all: float     # the same over the three axes together


def drag_fit(F_I_per_m: np.ndarray, v_I: np.ndarray) -> DragFit:
    num = np.sum(F_I_per_m * v_I, axis=0)
    den = np.sum(v_I * v_I, axis=0)
    D = -num / np.where(den > 0, den, 1.0)
    r = F_I_per_m + D * v_I
    power = np.sum(F_I_per_m ** 2, axis=0)
    return DragFit(D, np.sqrt(np.mean(F_I_per_m ** 2, axis=0)),
                   1.0 - np.sum(r ** 2, axis=0) / np.where(power > 0, power, 1.0),
                   float(1.0 - np.sum(r ** 2) / max(np.sum(power), 1e-300)))
