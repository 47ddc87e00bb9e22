"""Force plots: estimate vs ground truth per axis with the 3-sigma band, and the error norm."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

import numpy as np

from ..core.force_metrics import ForceResult
from ..core.phases import PhaseSegmentation
from .phases import shade_phases
from .style import ERR_COLOR, EST_COLOR, GT_COLOR, new_figure, save


def plot_force(res: ForceResult, out_dir: os.PathLike, name: str = "force.png",
               phases: Optional[PhaseSegmentation] = None, stamp: Optional[str] = None) -> Path:
    """Write :func:`force_figure` as ``out_dir/name``."""
    return save(force_figure(res, phases), out_dir, name, stamp)


def _robust_ylim(ax, keep: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                 floor: Optional[float] = None) -> None:
    """Y range: all of ``keep`` (the truth) and of ``lo`` / ``hi`` (band or estimate), 8 %
    margin; but when that is over twice the span of their 0.5-99.5 % range, only the latter: a
    brief spike (a touchdown impact) would squeeze the whole flight into a line. What is cut is
    named in the panel."""
    a = min(float(np.min(keep)), float(np.percentile(lo, 0.5)))
    b = max(float(np.max(keep)), float(np.percentile(hi, 99.5)))
    cut_lo, cut_hi = float(np.min(lo)), float(np.max(hi))
    if cut_hi - cut_lo <= 2.0 * (b - a):  # no spike, just tails: show everything
        a, b = min(a, cut_lo), max(b, cut_hi)
    pad = max(0.08 * (b - a), 0.05)
    a, b = (a - pad if floor is None else floor), b + pad
    ax.set_ylim(a, b)
    if cut_lo < a or cut_hi > b:
        ax.text(0.005, 0.95, f"range {cut_lo:.2f} … {cut_hi:.2f} m/s², clipped", transform=ax.transAxes,
                fontsize=7, color="0.3", va="top", bbox={"fc": "white", "ec": "none", "alpha": 0.8})


def force_figure(res: ForceResult, phases: Optional[PhaseSegmentation] = None):
    """Three axis panels (estimate, ground truth, +-3 sigma) and one error-norm panel; with
    ``phases``, landed intervals shaded and lift-off / touchdown marked on every panel."""
    fig, axes = new_figure(4, 1, width=11, height=10, sharex=True)
    t0 = min(res.est.t_ns[0], res.gt.t_ns[0])
    te = (res.est.t_ns - t0) * 1e-9
    tg = (res.gt.t_ns - t0) * 1e-9
    frame = res.est.frame
    for k, ax in enumerate(axes[:3]):
        est = res.est.values[:, k]
        lo = hi = est
        if res.est.sigma is not None:
            lo, hi = est - 3 * res.est.sigma[:, k], est + 3 * res.est.sigma[:, k]
            ax.fill_between(te, lo, hi, color=EST_COLOR, alpha=0.2, lw=0, label="estimate ±3σ")
        ax.plot(tg, res.gt.values[:, k], color=GT_COLOR, lw=1.2, label="ground truth")
        ax.plot(te, est, color=EST_COLOR, lw=0.9, label=f"estimate (RMSE {res.rmse_axis[k]:.3f} m/s²)")
        _robust_ylim(ax, res.gt.values[:, k], lo, hi)
        ax.set_ylabel(f"F_{'xyz'[k]} ({frame}) [m/s²]")
        ax.legend(loc="upper right", fontsize=8, ncol=3)
    err = np.linalg.norm(res.err, axis=1)
    axes[3].plot(te, err, color=ERR_COLOR, lw=0.9, label="‖error‖")
    axes[3].axhline(res.rmse_norm, color="gray", ls="--", lw=1.0,
                    label=f"RMSE {res.rmse_norm:.3f} m/s²")
    _robust_ylim(axes[3], np.array([0.0, 1.5 * res.rmse_norm]), err, err, floor=0.0)
    axes[3].set_ylabel("‖error‖ [m/s²]")
    for k, ax in enumerate(axes):
        ax.ticklabel_format(axis="y", useOffset=False, style="plain")
        if phases is not None:
            shade_phases(ax, phases, t0, label=(k == 3))
    axes[3].set_xlabel("time [s]")
    axes[3].legend(loc="upper right", fontsize=8)
    fig.suptitle(f"external force (mass-normalized, {frame} frame)")
    return fig
