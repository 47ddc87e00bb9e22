"""Relative pose error over sub-trajectory lengths, in the style of rpg_trajectory_evaluation.

For each length d and each start pose i, the end pose j is the one whose distance travelled
along the ground truth from i is closest to d (accepted if within ``max_dist_diff * d``;
starts closer than d to the end of the trajectory are skipped).
The error of the pair is ``E = (T_gt,i^-1 T_gt,j)^-1 (T_est,i^-1 T_est,j)`` on the aligned
estimate; reported per length: translation error [m], translation drift [% of d], rotation
error [deg] and [deg/m].
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Optional, Sequence

import numpy as np

from .geometry import matrices_from_wxyz, rotation_angle
from .series import Trajectory
from .stats import error_stats

DEFAULT_PERCENTAGES = (0.1, 0.2, 0.3, 0.4, 0.5)


@dataclass
class RpeSegment:
    """RPE of one sub-trajectory length."""

    distance: float
    start_idx: np.ndarray
    end_idx: np.ndarray
    trans_err: np.ndarray  # [m]
    rot_err_deg: np.ndarray  # [deg]

    def as_dict(self) -> dict:
        """JSON-friendly statistics."""
        d = self.distance
        return {
            "distance_m": d,
            "pairs": int(len(self.trans_err)),
            "trans_m": error_stats(self.trans_err),
            "trans_percent": error_stats(self.trans_err / d * 100.0) if d > 0 else None,
            "rot_deg": error_stats(self.rot_err_deg),
            "rot_deg_per_m": error_stats(self.rot_err_deg / d) if d > 0 else None,
        }


def cumulative_distance(p: np.ndarray) -> np.ndarray:
    """Distance travelled from the first position up to each position [m]."""
    if len(p) == 0:
        return np.zeros(0)
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])


def default_distances(gt: Trajectory, percentages: Sequence[float] = DEFAULT_PERCENTAGES) -> List[float]:
    """Sub-trajectory lengths as fractions of the ground-truth path length (rounded to mm)."""
    length = cumulative_distance(gt.p)[-1] if len(gt) else 0.0
    return [round(float(pct) * length, 3) for pct in percentages]


def _end_indices(accum: np.ndarray, distance: float, max_dist_diff: float):
    """For each start i, the index j >= i whose travelled distance is closest to d."""
    target = accum + distance
    j = np.searchsorted(accum, target, side="left")
    n = len(accum)
    starts = np.arange(n)
    hi = np.clip(j, 0, n - 1)
    lo = np.clip(j - 1, 0, n - 1)
    lo = np.maximum(lo, starts)
    err_hi = np.abs(accum[hi] - target)
    err_lo = np.abs(accum[lo] - target)
    best = np.where(err_lo <= err_hi, lo, hi)
    err = np.minimum(err_lo, err_hi)
    # only segments that fit inside the trajectory (no truncated segments at its end)
    fits = target <= accum[-1] + 1e-9 * max(1.0, distance)
    ok = (err < max_dist_diff * distance) & (best > starts) & fits
    return starts[ok], best[ok]


def compute_rpe(est_aligned: Trajectory, gt: Trajectory, distances: Sequence[float],
                max_dist_diff: float = 0.2) -> List[RpeSegment]:
    """RPE of paired trajectories (sample k of one belongs to sample k of the other).

    Args:
        est_aligned: estimate after the ATE alignment (scale included for sim3).
        gt: paired ground truth.
        distances: sub-trajectory lengths [m].
        max_dist_diff: accepted mismatch of the travelled distance, as a fraction of d.
    """
    accum = cumulative_distance(gt.p)
    R_e, R_g = matrices_from_wxyz(est_aligned.q), matrices_from_wxyz(gt.q)
    out: List[RpeSegment] = []
    for d in distances:
        if d <= 0:
            raise ValueError(f"RPE distance must be positive, got {d}")
        i, j = _end_indices(accum, float(d), max_dist_diff)
        # relative motions expressed in the start frame
        dR_e = np.einsum("nji,njk->nik", R_e[i], R_e[j])
        dR_g = np.einsum("nji,njk->nik", R_g[i], R_g[j])
        dp_e = np.einsum("nji,nj->ni", R_e[i], est_aligned.p[j] - est_aligned.p[i])
        dp_g = np.einsum("nji,nj->ni", R_g[i], gt.p[j] - gt.p[i])
        # E = dT_g^-1 dT_e: rotation dR_g^T dR_e, translation dR_g^T (dp_e - dp_g)
        R_E = np.einsum("nji,njk->nik", dR_g, dR_e)
        t_E = np.einsum("nji,nj->ni", dR_g, dp_e - dp_g)
        trans = np.linalg.norm(t_E, axis=1)
        rot = np.degrees(rotation_angle(R_E)) if len(i) else np.zeros(0)
        out.append(RpeSegment(float(d), i, j, trans, rot))
    return out


def rpe_as_dict(segments: Sequence[RpeSegment], percentages: Optional[Sequence[float]] = None) -> dict:
    """JSON-friendly RPE: one entry per distance (keyed by the distance in m)."""
    out = {"segments": [s.as_dict() for s in segments]}
    if percentages is not None:
        out["percentages"] = list(percentages)
    return out
