"""Timestamp association of an estimate with ground truth, and ground-truth interpolation.

Nearest-neighbour association follows evo's rule (``evo.core.sync.associate_trajectories``)
so that the same files give the same pairs: the stream with fewer samples is walked, each of
its samples takes the nearest sample of the other stream if it is within the tolerance. A
time offset is added to the estimate's timestamps before matching (``t_est + offset ~ t_gt``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from .errors import AssociationError


@dataclass
class Matches:
    """Index pairs: ``est_idx[k]`` is associated with ``gt_idx[k]``."""

    est_idx: np.ndarray
    gt_idx: np.ndarray

    def __len__(self) -> int:
        return len(self.est_idx)


def _nearest(stamps_a: np.ndarray, stamps_b: np.ndarray, tol: int) -> Tuple[np.ndarray, np.ndarray]:
    """For each of ``stamps_a`` the nearest of sorted ``stamps_b`` within ``tol`` (ties -> earlier)."""
    ia, ib = [], []
    n = len(stamps_b)
    for i, s in enumerate(stamps_a):
        if s < stamps_b[0] - tol or s > stamps_b[-1] + tol:
            continue
        j = int(np.searchsorted(stamps_b, s, side="right"))
        j = min(j, n - 1)
        d_up = stamps_b[j] - s
        d_lo = s - stamps_b[j - 1] if j > 0 else np.iinfo(np.int64).max
        if d_up <= tol and d_up < d_lo:
            best = j
        elif d_lo <= tol and d_lo <= d_up:
            best = j - 1
        else:
            continue
        ia.append(i)
        ib.append(best)
    return np.asarray(ia, dtype=np.int64), np.asarray(ib, dtype=np.int64)


def associate(
    t_est: np.ndarray,
    t_gt: np.ndarray,
    max_diff_ns: int = 10_000_000,
    offset_ns: int = 0,
    *,
    est_name: str = "estimate",
    gt_name: str = "ground truth",
    min_pairs: int = 1,
) -> Matches:
    """Associate two sorted int64-ns time vectors by nearest timestamp within ``max_diff_ns``.

    Raises:
        AssociationError: when fewer than ``min_pairs`` pairs are found.
    """
    t_est = np.asarray(t_est, dtype=np.int64) + np.int64(offset_ns)
    t_gt = np.asarray(t_gt, dtype=np.int64)
    tol = int(max_diff_ns)
    if len(t_gt) > len(t_est):
        ie, ig = _nearest(t_est, t_gt, tol)
    else:
        ig, ie = _nearest(t_gt, t_est, tol)
    if len(ie) < min_pairs:
        raise AssociationError(_no_overlap_message(t_est, t_gt, tol, offset_ns, est_name, gt_name,
                                                   len(ie), min_pairs))
    return Matches(ie, ig)


def interpolation_support(
    t_est: np.ndarray,
    t_gt: np.ndarray,
    offset_ns: int = 0,
    max_gap_ns: int | None = None,
    *,
    est_name: str = "estimate",
    gt_name: str = "ground truth",
    min_pairs: int = 1,
) -> Tuple[np.ndarray, np.ndarray]:
    """Estimate indices whose (offset) time lies inside the ground-truth span, and those
    query times. With ``max_gap_ns`` a query is dropped when its bracketing ground-truth
    samples are further apart than that (a hole in the ground truth).

    Raises:
        AssociationError: when fewer than ``min_pairs`` samples can be interpolated.
    """
    q = np.asarray(t_est, dtype=np.int64) + np.int64(offset_ns)
    t_gt = np.asarray(t_gt, dtype=np.int64)
    keep = (q >= t_gt[0]) & (q <= t_gt[-1])
    if max_gap_ns is not None and len(t_gt) > 1:
        j = np.clip(np.searchsorted(t_gt, q, side="right"), 1, len(t_gt) - 1)
        keep &= (t_gt[j] - t_gt[j - 1]) <= max_gap_ns
    idx = np.flatnonzero(keep)
    if len(idx) < min_pairs:
        raise AssociationError(_no_overlap_message(q, t_gt, 0, offset_ns, est_name, gt_name,
                                                   len(idx), min_pairs))
    return idx, q[idx]


def _no_overlap_message(t_est, t_gt, tol, offset_ns, est_name, gt_name, found, need) -> str:
    span = lambda t: f"[{t[0] * 1e-9:.3f}, {t[-1] * 1e-9:.3f}] s"  # noqa: E731
    return (f"{est_name} {span(t_est)} and {gt_name} {span(t_gt)} give {found} matching "
            f"timestamps (need {need}) with tolerance {tol * 1e-9:g} s and offset "
            f"{offset_ns * 1e-9:g} s")
