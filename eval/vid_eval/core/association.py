"""Timestamp association of an estimate with ground truth, and ground-truth interpolation.

Nearest-neighbour association is evo's rule (``evo.core.sync.associate_trajectories``), so
that the same files give the same pairs, ties included:

* the stream with fewer samples is walked; on equal counts the estimate is walked;
* each walked sample takes the nearest sample of the other stream within the tolerance; on a
  tie the earlier one;
* the time offset (``t_est + offset ~ t_gt``) is applied to the longer stream (with the sign
  that makes it mean the same thing);
* distances are compared in float64 seconds as evo reads them from the file: a TUM stamp is
  the double nearest its decimal text, an ASL stamp is ``double(ns) / 1e9``.

The last point matters only for near ties: at epoch times (~1.7e9 s) a double resolves
~0.24 µs, so two candidates whose exact distances differ by less than that can be ordered
differently than in exact nanoseconds; evo's choice is kept so that the two tools agree
(tests/python/test_eval_association.py). Metrics themselves use the exact int64 ns.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import numpy as np

from ..errors import AssociationError


@dataclass
class Matches:
    """Index pairs: ``est_idx[k]`` is associated with ``gt_idx[k]``."""

    est_idx: np.ndarray
    gt_idx: np.ndarray

    def __len__(self) -> int:
        return len(self.est_idx)


TIME_UNITS = ("ns", "s")


def evo_seconds(t_ns: np.ndarray, time_unit: str = "ns") -> np.ndarray:
    """Timestamps as evo's readers hold them: ``time_unit="s"`` (a TUM file: the double
    nearest ``t_ns / 1e9``, i.e. ``float(text)`` for stamps with <= 9 decimals; Python's int
    division is correctly rounded), ``"ns"`` (an ASL CSV: ``float(ns) / 1e9``)."""
    t_ns = np.asarray(t_ns, dtype=np.int64)
    if time_unit == "s":
        return np.fromiter((x / 1_000_000_000 for x in t_ns.tolist()), np.float64, len(t_ns))
    if time_unit == "ns":
        return t_ns.astype(np.float64) / 1e9
    raise ValueError(f"unknown time unit '{time_unit}' (choose from {', '.join(TIME_UNITS)})")


def _nearest(stamps_a: np.ndarray, stamps_b: np.ndarray, tol: float) -> Tuple[np.ndarray, np.ndarray]:
    """For each of ``stamps_a`` the nearest of sorted ``stamps_b`` within ``tol`` (ties -> earlier)."""
    ia, ib = [], []
    n = len(stamps_b)
    for i, s in enumerate(stamps_a):
        if s < stamps_b[0] - tol or s > stamps_b[-1] + tol:
            continue
        j = int(np.searchsorted(stamps_b, s, side="right"))
        j = min(j, n - 1)
        d_up = stamps_b[j] - s
        d_lo = s - stamps_b[j - 1] if j > 0 else np.inf
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
    est_unit: str = "ns",
    gt_unit: str = "ns",
) -> Matches:
    """Associate two sorted int64-ns time vectors by nearest timestamp within ``max_diff_ns``
    (evo's rule, see the module notes); ``est_unit``/``gt_unit`` say how each file wrote its
    stamps (``"s"`` TUM, ``"ns"`` ASL CSV).

    Raises:
        AssociationError: when fewer than ``min_pairs`` pairs are found.
    """
    t_est = np.asarray(t_est, dtype=np.int64)
    t_gt = np.asarray(t_gt, dtype=np.int64)
    s_est, s_gt = evo_seconds(t_est, est_unit), evo_seconds(t_gt, gt_unit)
    tol, offset_s = max_diff_ns / 1e9, offset_ns / 1e9
    if len(t_est) > len(t_gt):
        ig, ie = _nearest(s_gt, s_est + offset_s, tol)
    else:
        ie, ig = _nearest(s_est, s_gt - offset_s, tol)
    if len(ie) < min_pairs:
        raise AssociationError(_no_overlap_message(t_est + np.int64(offset_ns), t_gt,
                                                   int(max_diff_ns), offset_ns, est_name, gt_name,
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
