"""Force plots: estimate vs ground truth per axis with the 3-sigma band, and the error norm."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

import numpy as np

from ..force_metrics import ForceResult
from ..phases import PhaseSegmentation
from .phases import shade_phases
from .style import ERR_COLOR, EST_COLOR, GT_COLOR, new_figure, save


def plot_force(res: ForceResult, out_dir: os.PathLike, name: str = "force.png",
               phases: Optional[PhaseSegmentation] = None) -> Path:
    """Three axis panels (estimate, ground truth, +-3 sigma) and one error-norm panel; with
    ``phases``, landed intervals shaded and lift-off / touchdown marked on every panel."""
    fig, axes = new_figure(4, 1, width=11, height=10, sharex=True)
    t0 = min(res.est.t_ns[0], res.gt.t_ns[0])
    te = (res.est.t_ns - t0) * 1e-9
    tg = (res.gt.t_ns - t0) * 1e-9
    frame = res.est.frame
    for k, ax in enumerate(axes[:3]):
        if res.est.sigma is not None:
            lo = res.est.values[:, k] - 3 * res.est.sigma[:, k]
            hi = res.est.values[:, k] + 3 * res.est.sigma[:, k]
            ax.fill_between(te, lo, hi, color=EST_COLOR, alpha=0.2, lw=0, label="estimate ±3σ")
        ax.plot(tg, res.gt.values[:, k], color=GT_COLOR, lw=1.2, label="ground truth")
        ax.plot(te, res.est.values[:, k], color=EST_COLOR, lw=0.9,
                label=f"estimate (RMSE {res.rmse_axis[k]:.3f} m/s²)")
        ax.set_ylabel(f"F_{'xyz'[k]} ({frame}) [m/s²]")
        ax.legend(loc="upper right", fontsize=8, ncol=3)
    axes[3].plot(te, np.linalg.norm(res.err, axis=1), color=ERR_COLOR, lw=0.9, label="‖error‖")
    axes[3].axhline(res.rmse_norm, color="gray", ls="--", lw=1.0,
                    label=f"RMSE {res.rmse_norm:.3f} m/s²")
    axes[3].set_ylim(bottom=0.0, top=max(1e-6, 1.15 * float(np.max(np.linalg.norm(res.err, axis=1)))))
    axes[3].set_ylabel("‖error‖ [m/s²]")
    for k, ax in enumerate(axes):
        ax.ticklabel_format(axis="y", useOffset=False, style="plain")
        if phases is not None:
            shade_phases(ax, phases, t0, label=(k == 3))
    axes[3].set_xlabel("time [s]")
    axes[3].legend(loc="upper right", fontsize=8)
    fig.suptitle(f"external force (mass-normalized, {frame} frame)")
    return save(fig, out_dir, name)
