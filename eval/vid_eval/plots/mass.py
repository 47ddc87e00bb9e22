"""Mass plot: estimate (with ±3σ when given) vs ground truth, and the percentage error."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

from ..core.mass_metrics import MassResult
from .style import ERR_COLOR, EST_COLOR, GT_COLOR, new_figure, save


def plot_mass(res: MassResult, out_dir: os.PathLike, name: str = "mass.png",
              stamp: Optional[str] = None) -> Path:
    """Two panels: mass [kg] over time, percentage error [%] over time."""
    fig, axes = new_figure(2, 1, width=10, height=6.5, sharex=True)
    t0 = min(res.est.t_ns[0], res.gt.t_ns[0])
    te = (res.est.t_ns - t0) * 1e-9
    tg = (res.gt.t_ns - t0) * 1e-9
    ax = axes[0]
    if res.est.sigma is not None:
        ax.fill_between(te, res.est.values - 3 * res.est.sigma, res.est.values + 3 * res.est.sigma,
                        color=EST_COLOR, alpha=0.2, lw=0, label="estimate ±3σ")
    ax.plot(tg, res.gt.values, color=GT_COLOR, lw=1.4, label="ground truth")
    ax.plot(te, res.est.values, color=EST_COLOR, lw=1.0, label="estimate")
    ax.set_ylabel("mass [kg]")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"mass identification: RMSPE {res.rmspe:.2f} %, RMSE {res.rmse:.4f} kg")
    ax = axes[1]
    ax.plot(te, 100.0 * res.err / res.gt.values, color=ERR_COLOR, lw=1.0, label="(m̂ − m)/m")
    ax.axhline(0.0, color="gray", lw=0.8)
    ax.set_ylabel("error [%]")
    ax.set_xlabel("time [s]")
    ax.legend(loc="best", fontsize=8)
    return save(fig, out_dir, name, stamp)
