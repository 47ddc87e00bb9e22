"""Absolute trajectory error (ATE) after alignment: position RMSE [m], rotation RMSE [deg].

Position error of pose k: ``|| s R p_est,k + t - p_gt,k ||``. Rotation error: the angle of
``R_gt,k^T (R R_est,k)`` — the same quantities as evo's APE ``translation_part`` and
``rotation_angle_deg``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .alignment import Alignment, align
from .geometry import matrices_from_wxyz, rotation_angle, wxyz_from_rot
from scipy.spatial.transform import Rotation
from .pairing import PairingOptions, pair_trajectories
from .series import Trajectory
from .stats import error_stats


@dataclass
class AteResult:
    """ATE of associated, aligned poses (``est_aligned`` and ``gt`` have equal length)."""

    alignment: Alignment
    est_aligned: Trajectory
    gt: Trajectory
    pos_err: np.ndarray  # (N,) [m]
    rot_err_deg: Optional[np.ndarray]  # (N,) [deg] or None without orientations

    @property
    def pos_rmse(self) -> float:
        """Position RMSE [m]."""
        return float(np.sqrt(np.mean(self.pos_err ** 2)))

    @property
    def rot_rmse_deg(self) -> float:
        """Rotation RMSE [deg] (nan without orientations)."""
        if self.rot_err_deg is None:
            return float("nan")
        return float(np.sqrt(np.mean(self.rot_err_deg ** 2)))

    def as_dict(self) -> dict:
        """JSON-friendly summary."""
        out = {"pairs": int(len(self.pos_err)), "alignment": self.alignment.as_dict(),
               "pos_m": error_stats(self.pos_err)}
        if self.rot_err_deg is not None:
            out["rot_deg"] = error_stats(self.rot_err_deg)
        return out


def ate_of_paired(est: Trajectory, gt: Trajectory, mode: str = "posyaw",
                  n_align: Optional[int] = None, with_rotation: bool = True) -> AteResult:
    """ATE of already-paired trajectories (sample k of ``est`` belongs to sample k of ``gt``)."""
    al: Alignment = align(est.p, gt.p, mode, n_align)
    p_al = al.apply_positions(est.p)
    pos_err = np.linalg.norm(p_al - gt.p, axis=1)
    rot_err = None
    R_al = al.apply_rotations(matrices_from_wxyz(est.q))
    if with_rotation:
        R_err = np.einsum("nji,njk->nik", matrices_from_wxyz(gt.q), R_al)
        rot_err = np.degrees(rotation_angle(R_err))
    est_al = Trajectory(est.t_ns, p_al, wxyz_from_rot(Rotation.from_matrix(R_al)), est.source,
                        est.time_unit)
    return AteResult(al, est_al, gt, pos_err, rot_err)


def compute_ate(est: Trajectory, gt: Trajectory, mode: str = "posyaw",
                n_align: Optional[int] = None,
                pairing: Optional[PairingOptions] = None) -> AteResult:
    """Associate (or interpolate) ``gt`` to ``est``, align and compute the ATE."""
    pe, pg = pair_trajectories(est, gt, pairing or PairingOptions())
    return ate_of_paired(pe, pg, mode, n_align)


@dataclass
class PiecewiseAte:
    """ATE of a trajectory whose world frame restarts at re-initializations: each piece aligned on
    its own (as vid_run's summary.json ``ate_segments``), pooled over all pairs."""

    pooled: AteResult  # every piece's aligned poses and errors; .alignment is the first piece's
    pieces: list  # AteResult per piece with pairs
    starts_ns: list  # start of each of those pieces (the first: its first pair)
    empty_pieces: int  # pieces with fewer than 2 pairs (not aligned, not scored)

    def as_dict(self) -> dict:
        """JSON-friendly per-piece summary."""
        return {"pieces": [{"t_start_ns": int(t), "pairs": int(len(a.pos_err)), "pos_rmse_m": a.pos_rmse,
                            "rot_rmse_deg": a.rot_rmse_deg, "alignment": a.alignment.as_dict()}
                           for t, a in zip(self.starts_ns, self.pieces)],
                "pieces_without_pairs": self.empty_pieces}


def compute_ate_pieces(est: Trajectory, gt: Trajectory, starts_ns, mode: str = "posyaw",
                       n_align: Optional[int] = None,
                       pairing: Optional[PairingOptions] = None) -> PiecewiseAte:
    """:func:`compute_ate` per piece between re-initializations (``starts_ns``: the new world
    frames' first times, :func:`vid_eval.tools.loaders.reinit_marks`); anything before the first start
    belongs to the first piece."""
    pe, pg = pair_trajectories(est, gt, pairing or PairingOptions())
    cuts = np.searchsorted(pe.t_ns, np.sort(np.asarray(starts_ns, dtype=np.int64)))
    bounds = [0, *[int(c) for c in cuts if 0 < c < len(pe)], len(pe)]
    pieces, starts, empty = [], [], 0
    for i0, i1 in zip(bounds[:-1], bounds[1:]):
        if i1 - i0 < 2:
            empty += 1
            continue
        idx = np.arange(i0, i1)
        pieces.append(ate_of_paired(pe.subset(idx), pg.subset(idx), mode, n_align))
        starts.append(int(pe.t_ns[i0]))
    if not pieces:
        raise ValueError("no piece of the trajectory has two poses paired with the ground truth")
    cat = lambda f: np.concatenate([f(a) for a in pieces])  # noqa: E731
    est_al = Trajectory(cat(lambda a: a.est_aligned.t_ns), cat(lambda a: a.est_aligned.p),
                        cat(lambda a: a.est_aligned.q), est.source, est.time_unit)
    gt_al = Trajectory(cat(lambda a: a.gt.t_ns), cat(lambda a: a.gt.p), cat(lambda a: a.gt.q), gt.source,
                       gt.time_unit)
    rot = None if pieces[0].rot_err_deg is None else cat(lambda a: a.rot_err_deg)
    pooled = AteResult(pieces[0].alignment, est_al, gt_al, cat(lambda a: a.pos_err), rot)
    return PiecewiseAte(pooled, pieces, starts, empty)


def ate_posyaw(est_t: np.ndarray, est_p: np.ndarray, gt_t: np.ndarray, gt_p: np.ndarray,
               est_q: Optional[np.ndarray] = None, gt_q: Optional[np.ndarray] = None, *,
               max_diff_ns: int = 10_000_000, offset_ns: int = 0,
               n_align: Optional[int] = None, interpolate: bool = False) -> AteResult:
    """ATE with 4-DoF position+yaw alignment from plain arrays (the reference for C++ numbers).

    Args:
        est_t, gt_t: int64 nanosecond timestamps, strictly increasing.
        est_p, gt_p: (N, 3) positions [m].
        est_q, gt_q: optional (N, 4) quaternions (w, x, y, z); without them only the position
            error is computed (``rot_err_deg`` is None).
        max_diff_ns: association tolerance; offset_ns: added to estimate times.
        n_align: align on the first ``n_align`` pairs (None: all).
        interpolate: evaluate the ground truth at estimate times instead of nearest matching.
    """
    def traj(t, p, q):
        t = np.asarray(t, dtype=np.int64)
        p = np.asarray(p, dtype=float).reshape(-1, 3)
        qq = np.tile([1.0, 0.0, 0.0, 0.0], (len(t), 1)) if q is None else np.asarray(q, float)
        return Trajectory(t, p, qq / np.linalg.norm(qq, axis=1, keepdims=True))

    opt = PairingOptions(mode="interpolate" if interpolate else "nearest",
                         max_diff_ns=max_diff_ns, offset_ns=offset_ns)
    pe, pg = pair_trajectories(traj(est_t, est_p, est_q), traj(gt_t, gt_p, gt_q), opt)
    return ate_of_paired(pe, pg, "posyaw", n_align,
                         with_rotation=est_q is not None and gt_q is not None)
