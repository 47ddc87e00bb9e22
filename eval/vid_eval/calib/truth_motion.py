"""The ground truth's (or the motion capture's) motion at the IMU times, for the fits that need
it: the body velocity v_I = R_WI^T v_W (the drag regressor) and the body rate w_I (the gyro's
truth, for its in-flight noise). Samples outside the ground truth's span are NaN."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from ..core.geometry import lerp, rot_from_wxyz, slerp_wxyz
from ..importer.sync import mocap_body_rate
from ..tools.table_reader import Table


@dataclass
class TruthMotion:
    v_I: np.ndarray   # (N, 3) body velocity [m/s]
    w_I: np.ndarray   # (N, 3) body rate [rad/s]
    source: str


def truth_motion(gt: Table, t_ns: np.ndarray) -> TruthMotion:
    """v_I and w_I of a EuRoC ground truth (p, q_wxyz, v_W columns) at ``t_ns``."""
    t_gt = gt.t_ns
    inside = (t_ns >= t_gt[0]) & (t_ns <= t_gt[-1])
    v_I = np.full((len(t_ns), 3), np.nan)
    w_I = np.full((len(t_ns), 3), np.nan)
    q = gt.values[:, 3:7]
    q_at = slerp_wxyz(t_gt, q, t_ns[inside])
    v_I[inside] = rot_from_wxyz(q_at).inv().apply(lerp(t_gt, gt.values[:, 7:10], t_ns[inside]))
    # Body rate of each pose pair at its midpoint (sync.mocap_body_rate), cubic spline to the IMU
    # times: smooth where the motion is, so the gyro's own noise is what remains.
    t_mid, w_M = mocap_body_rate(t_gt, q)
    t0 = int(t_mid[0])
    spline = CubicSpline((t_mid - t0) * 1e-9, w_M, axis=0, extrapolate=False)
    w_I[inside] = spline((t_ns[inside] - t0) * 1e-9)
    return TruthMotion(v_I, w_I, str(gt.path))
