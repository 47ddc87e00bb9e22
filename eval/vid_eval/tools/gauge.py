"""The world-frame gauge of an estimate: bring world-frame vectors into the ground truth's world.

A visual-inertial estimator fixes its own world frame at start-up (gravity up, heading 0, or
whatever its initializer picked); position and yaw are unobservable, so that frame differs
from the ground truth's world (motion capture, simulator) by a rotation about gravity and a
translation. ATE removes the difference by aligning the trajectories; every other
world-frame comparison (external force, velocity) must do the same, or it subtracts vectors
expressed in two different frames. This module finds the trajectories, fits the alignment
with the same code and options as ``vid-eval traj``, and rotates world-frame vectors with it.

Only the rotation of the alignment applies to vectors: a force or a velocity does not move
with the translation, and the estimator's accelerations are metric (from the IMU) whatever
the scale of a ``sim3`` alignment.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np
from scipy.spatial.transform import Rotation

from ..core.alignment import Alignment
from ..core.ate import compute_ate
from ..errors import ConfigurationError, PathLike
from ..core.geometry import rot_from_wxyz, wxyz_from_rot
from .loaders import load_trajectory
from ..core.pairing import PairingOptions
from ..core.series import Trajectory, VectorSeries

#: Files next to an estimate (force.csv) that carry its trajectory, in order of preference.
ESTIMATE_TRAJECTORY_NAMES = ("state.csv", "trajectory_tum.txt")


@dataclass
class WorldGauge:
    """The alignment of an estimate's world frame to the ground truth's, and its sources."""

    alignment: Alignment
    est_source: str
    gt_source: str
    pairs: int

    def as_dict(self) -> dict:
        """JSON-friendly record (mode, yaw, rotation, the files it was fitted on)."""
        out = self.alignment.as_dict()
        out.update({"est_trajectory": self.est_source, "gt_trajectory": self.gt_source,
                    "pairs": self.pairs})
        return out

    def describe(self) -> str:
        """One phrase for printed lines, e.g. ``posyaw-aligned (yaw 165.0 deg)``."""
        if self.alignment.mode == "none":
            return "not aligned (--align none)"
        return f"{self.alignment.mode}-aligned (yaw {self.alignment.yaw_deg:.1f} deg)"


SMOOTHED_FORCE_NAME = "force_smoothed.csv"
SMOOTHED_TRAJECTORY_NAME = "trajectory_smoothed_tum.txt"


def find_estimate_trajectory(est_path: PathLike) -> Optional[Path]:
    """``state.csv`` or ``trajectory_tum.txt`` in the folder of an estimate file, or None;
    for the fixed-lag smoothed ``force_smoothed.csv`` its own ``trajectory_smoothed_tum.txt``
    (``vid_run --smooth``) when present."""
    folder = Path(est_path).resolve().parent
    if Path(est_path).name == SMOOTHED_FORCE_NAME and (folder / SMOOTHED_TRAJECTORY_NAME).is_file():
        return folder / SMOOTHED_TRAJECTORY_NAME
    for name in ESTIMATE_TRAJECTORY_NAMES:
        cand = folder / name
        if cand.is_file() and cand != Path(est_path).resolve():
            return cand
    if Path(est_path).name == "state.csv":
        return Path(est_path)
    return None


def find_gt_trajectory(gt_path: PathLike) -> Optional[Path]:
    """Ground-truth poses of the dataset of ``SEQ/mav0/force0/data.csv``:
    ``mav0/state_groundtruth_estimate0/data.csv``, or None."""
    cand = Path(gt_path).resolve().parent.parent / "state_groundtruth_estimate0" / "data.csv"
    return cand if cand.is_file() else None


def fit_world_gauge(est: Trajectory, gt: Trajectory, mode: str = "posyaw",
                    n_align: Optional[int] = None,
                    pairing: Optional[PairingOptions] = None) -> WorldGauge:
    """Fit the alignment ``mode`` of ``est`` onto ``gt`` exactly as ``vid-eval traj`` does."""
    res = compute_ate(est, gt, mode, n_align, pairing or PairingOptions(min_pairs=3))
    return WorldGauge(res.alignment, est.source, gt.source, int(len(res.pos_err)))


def world_gauge_from_files(est_traj: Optional[PathLike], gt_traj: Optional[PathLike], mode: str,
                           n_align: Optional[int] = None,
                           pairing: Optional[PairingOptions] = None) -> WorldGauge:
    """Load both trajectories and fit the gauge; ``mode == 'none'`` needs no files.

    Raises:
        ConfigurationError: when a trajectory is missing for a mode other than ``none``
            (the world frame of an estimate is not comparable without one: never guessed).
    """
    if mode == "none":
        return WorldGauge(Alignment(mode="none"), str(est_traj or ""), str(gt_traj or ""), 0)
    missing = [what for what, p in (("the estimate's trajectory (--traj or --state; state.csv or "
                                     "trajectory_tum.txt next to EST)", est_traj),
                                    ("the ground-truth poses (--gt-state; mav0/state_groundtruth_"
                                     "estimate0 next to GT)", gt_traj)) if p is None]
    if missing:
        raise ConfigurationError(
            f"a world-frame comparison needs {' and '.join(missing)} to remove the unobservable "
            f"heading of the estimator's world frame; give them, or use --frame body, or "
            f"--align none if both are known to share one world frame")
    pairing = pairing or PairingOptions(min_pairs=3)
    return fit_world_gauge(load_trajectory(est_traj), load_trajectory(gt_traj), mode, n_align,
                           pairing)


def rotate_world(series: VectorSeries, gauge: WorldGauge) -> VectorSeries:
    """Express a world-frame series of the estimate in the ground truth's world frame: values
    ``R v``, a per-axis 1-sigma as the square root of the diagonal of ``R diag(sigma^2) R^T``."""
    if series.frame != "world":
        raise ConfigurationError(f"rotate_world needs a world-frame series, got {series.frame}")
    R = gauge.alignment.R
    sigma = None if series.sigma is None else np.sqrt((series.sigma ** 2) @ (R ** 2).T)
    return VectorSeries(series.t_ns, series.values @ R.T, "world", series.unit, sigma,
                        series.source)



def rotate_orientations(traj: Trajectory, gauge: WorldGauge) -> Trajectory:
    """The estimate's orientations in the ground truth's world, ``q_GI = R q_WI`` (positions
    kept: only frame changes of vectors and their sigma use this). A per-axis sigma must be
    rotated in one step with these: rotating twice, taking the diagonal each time, inflates it."""
    R = gauge.alignment.R
    q = wxyz_from_rot(Rotation.from_matrix(R) * rot_from_wxyz(traj.q))
    return Trajectory(traj.t_ns, traj.p, q, traj.source, traj.time_unit)
