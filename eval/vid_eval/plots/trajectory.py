"""Trajectory plots: top and side views against ground truth; position/rotation error over time."""
from __future__ import annotations

import os
from pathlib import Path
from typing import List, Optional, Sequence

import numpy as np

from ..core.ate import AteResult
from ..core.phases import PhaseSegmentation
from ..core.rpe import RpeSegment
from .phases import shade_phases
from .style import ERR_COLOR, EST_COLOR, GT_COLOR, new_figure, save


def plot_views(res: AteResult, out_dir: os.PathLike, full_gt=None, title: str = "",
               name: str = "traj_views.png", stamp: Optional[str] = None) -> Path:
    """Top (x-y) and side (x-z) views of the aligned estimate over the ground truth."""
    fig, axes = new_figure(1, 2, width=12, height=5.5)
    gt = full_gt if full_gt is not None else res.gt
    est = res.est_aligned.p
    for ax, (i, j), view in zip(axes, [(0, 1), (0, 2)], ["top view", "side view"]):
        ax.plot(gt.p[:, i], gt.p[:, j], color=GT_COLOR, lw=1.2, label="ground truth")
        ax.plot(est[:, i], est[:, j], color=EST_COLOR, lw=1.0, label=f"estimate ({res.alignment.mode})")
        ax.plot(est[0, i], est[0, j], "o", color="tab:green", label="start")
        ax.set_xlabel(f"{'xyz'[i]} [m]")
        ax.set_ylabel(f"{'xyz'[j]} [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(view)
        ax.legend(loc="best", fontsize=8)
    fig.suptitle(title or f"ATE {res.pos_rmse:.3f} m RMSE, alignment {res.alignment.mode}")
    return save(fig, out_dir, name, stamp)


def plot_errors(res: AteResult, out_dir: os.PathLike,
                phases: Optional[PhaseSegmentation] = None, name: str = "traj_errors.png",
                stamp: Optional[str] = None) -> Path:
    """Position error [m] (and rotation error [deg]) over time; with ``phases``, landed
    intervals shaded and lift-off / touchdown marked."""
    rows = 2 if res.rot_err_deg is not None else 1
    fig, axes = new_figure(rows, 1, width=10, height=3.2 * rows, sharex=True, squeeze=False)
    t = res.est_aligned.t_s
    ax = axes[0, 0]
    ax.plot(t, res.pos_err, color=ERR_COLOR, lw=1.0, label="position error")
    ax.axhline(res.pos_rmse, color="gray", ls="--", lw=1.0, label=f"RMSE {res.pos_rmse:.3f} m")
    ax.set_ylabel("position error [m]")
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(f"absolute trajectory error ({res.alignment.mode} alignment)")
    if res.rot_err_deg is not None:
        ax = axes[1, 0]
        ax.plot(t, res.rot_err_deg, color="tab:purple", lw=1.0, label="rotation error")
        ax.axhline(res.rot_rmse_deg, color="gray", ls="--", lw=1.0,
                   label=f"RMSE {res.rot_rmse_deg:.2f} deg")
        ax.set_ylabel("rotation error [deg]")
        ax.legend(loc="upper left", fontsize=8)
    for k, a in enumerate(axes[:, 0]):
        a.set_ylim(bottom=0.0)
        a.ticklabel_format(axis="y", useOffset=False, style="plain")
        if phases is not None:  # the x axis counts from the first pair (ground-truth clock)
            shade_phases(a, phases, int(res.gt.t_ns[0]), label=True)
            a.legend(loc="upper left", fontsize=8)
    axes[-1, 0].set_xlabel("time since first pose [s]")
    return save(fig, out_dir, name, stamp)


def plot_rpe(segments: Sequence[RpeSegment], out_dir: os.PathLike, name: str = "traj_rpe.png",
             stamp: Optional[str] = None) -> Optional[Path]:
    """Box plots of the relative translation [m] and rotation [deg] error per length."""
    segs: List[RpeSegment] = [s for s in segments if len(s.trans_err)]
    if not segs:
        return None
    fig, axes = new_figure(1, 2, width=11, height=4)
    labels = [f"{s.distance:.3g}" for s in segs]
    axes[0].boxplot([s.trans_err for s in segs], showfliers=False)
    axes[0].set_xticks(range(1, len(segs) + 1), labels)
    axes[0].set_ylabel("translation error [m]")
    axes[1].boxplot([s.rot_err_deg for s in segs], showfliers=False)
    axes[1].set_xticks(range(1, len(segs) + 1), labels)
    axes[1].set_ylabel("rotation error [deg]")
    for ax in axes:
        ax.set_xlabel("distance travelled [m]")
    fig.suptitle("relative pose error per sub-trajectory length")
    return save(fig, out_dir, name, stamp)
