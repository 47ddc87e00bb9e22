"""Pair an estimate with ground truth sample by sample: nearest association or interpolation.

``mode="nearest"`` uses :func:`vid_eval.core.association.associate` (evo's rule);
``mode="interpolate"`` evaluates the ground truth at every estimate time inside its span —
SLERP for rotations, linear for positions, forces and masses.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .association import associate, interpolation_support
from .geometry import lerp, slerp_wxyz
from .series import ScalarSeries, Trajectory, VectorSeries

PAIRING_MODES = ("nearest", "interpolate")


@dataclass
class PairingOptions:
    """How to pair: mode, tolerance [ns] (nearest), offset added to estimate times [ns],
    largest ground-truth gap to interpolate across [ns] (None: any), minimum pair count."""

    mode: str = "nearest"
    max_diff_ns: int = 10_000_000
    offset_ns: int = 0
    max_gap_ns: Optional[int] = None
    min_pairs: int = 2


def _indices(t_est, t_gt, opt: PairingOptions, est_name: str, gt_name: str,
             units: tuple[str, str] = ("ns", "ns")):
    if opt.mode == "nearest":
        m = associate(t_est, t_gt, opt.max_diff_ns, opt.offset_ns, est_name=est_name,
                      gt_name=gt_name, min_pairs=opt.min_pairs, est_unit=units[0],
                      gt_unit=units[1])
        return m.est_idx, m.gt_idx, None
    if opt.mode == "interpolate":
        idx, q = interpolation_support(t_est, t_gt, opt.offset_ns, opt.max_gap_ns,
                                       est_name=est_name, gt_name=gt_name, min_pairs=opt.min_pairs)
        return idx, None, q
    raise ValueError(f"unknown pairing mode '{opt.mode}'")


def pair_trajectories(est: Trajectory, gt: Trajectory, opt: PairingOptions):
    """Return (est, gt) trajectories of equal length, sample k of one paired with k of the
    other. The ground truth keeps its own clock; the estimate keeps its own timestamps."""
    ie, ig, q = _indices(est.t_ns, gt.t_ns, opt, est.source or "estimate", gt.source or "ground truth",
                         (est.time_unit, gt.time_unit))
    if q is None:
        return est.subset(ie), gt.subset(ig)
    gt_i = Trajectory(q, lerp(gt.t_ns, gt.p, q), slerp_wxyz(gt.t_ns, gt.q, q), gt.source)
    return est.subset(ie), gt_i


def pair_vectors(est: VectorSeries, gt: VectorSeries, opt: PairingOptions):
    """Return (est, gt) vector series of equal length."""
    ie, ig, q = _indices(est.t_ns, gt.t_ns, opt, est.source or "estimate", gt.source or "ground truth")
    if q is None:
        return est.subset(ie), gt.subset(ig)
    sig = None if gt.sigma is None else lerp(gt.t_ns, gt.sigma, q)
    return est.subset(ie), VectorSeries(q, lerp(gt.t_ns, gt.values, q), gt.frame, gt.unit, sig, gt.source)


def pair_scalars(est: ScalarSeries, gt: ScalarSeries, opt: PairingOptions):
    """Return (est, gt) scalar series of equal length."""
    ie, ig, q = _indices(est.t_ns, gt.t_ns, opt, est.source or "estimate", gt.source or "ground truth")
    if q is None:
        return est.subset(ie), gt.subset(ig)
    return est.subset(ie), ScalarSeries(q, lerp(gt.t_ns, gt.values, q), None, gt.source)
