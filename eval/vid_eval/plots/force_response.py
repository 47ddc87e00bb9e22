"""Force response plot: cross-correlation with the lag, the force norm with steps and pulses,
and for each step the per-axis estimate vs truth and the error against the settling band."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

import numpy as np

from ..core.force_response import ForceResponse
from .style import AXIS_COLORS, ERR_COLOR, EST_COLOR, GT_COLOR, new_figure, save

_BEFORE_S = 0.3  # shown before each step, to see the level it leaves


def plot_force_response(res: ForceResponse, out_dir: os.PathLike,
                        name: str = "force_response.png", max_steps: int = 6,
                        stamp: Optional[str] = None) -> Path:
    """Top row: correlation curves (lag marked) and |force| over time (steps, pulses marked).
    Then one row per step (the first ``max_steps``): axes around the step, and |error| with
    the settling band and the settling time."""
    steps = res.steps[:max_steps]
    fig, axes = new_figure(1 + len(steps), 2, width=13, height=3.2 * (1 + len(steps)), squeeze=False)
    ax = axes[0, 0]
    for k, (lbl, col) in enumerate(zip(("x", "y", "z"), AXIS_COLORS)):
        ax.plot(res.lags_s * 1e3, res.corr[k], color=col, lw=0.8, alpha=0.7, label=lbl)
    ax.plot(res.lags_s * 1e3, res.corr[3], color=GT_COLOR, lw=1.5, label="combined")
    if res.lag is not None:
        ax.axvline(res.lag * 1e3, color=ERR_COLOR, ls="--", lw=1.0, label=f"lag {res.lag * 1e3:.1f} ms")
    ax.set_xlabel("lag of the estimate [ms]")
    ax.set_ylabel("correlation")
    ax.legend(loc="lower right", fontsize=8)

    t = res.t_s
    ax = axes[0, 1]
    ax.plot(t, np.linalg.norm(res.gt, axis=1), color=GT_COLOR, lw=1.0, label="‖truth‖")
    ax.plot(t, np.linalg.norm(res.est, axis=1), color=EST_COLOR, lw=0.8, label="‖estimate‖")
    for s in res.steps:
        ax.axvline(s.t_s, color=ERR_COLOR, lw=0.8, alpha=0.6)
    for p in res.pulses:
        ax.axvline(p.t_s, color="tab:orange", lw=0.8, ls=":", alpha=0.8)
    ax.set_xlabel("time [s]  (red: steps, orange: pulses)")
    ax.set_ylabel("‖F‖ [m/s²]")
    ax.legend(loc="upper right", fontsize=8)

    err = np.linalg.norm(res.est - res.gt, axis=1)
    for row, s in enumerate(steps, start=1):
        sel = (t >= s.t_s - _BEFORE_S) & (t <= s.t_s + s.window_s)
        ax = axes[row, 0]
        for k, col in enumerate(AXIS_COLORS):
            ax.plot(t[sel], res.gt[sel, k], color=col, lw=1.2, label=f"truth {'xyz'[k]}")
            ax.plot(t[sel], res.est[sel, k], color=col, lw=0.9, ls="--", label=f"estimate {'xyz'[k]}")
        ax.axvline(s.t_s, color="gray", lw=0.8)
        ax.set_ylabel("F [m/s²]")
        ax.set_title(f"step at {s.t_s:.2f} s, |Δ| {s.size:.2f} m/s²", fontsize=9)
        ax.legend(loc="upper right", fontsize=7, ncol=3)
        ax = axes[row, 1]
        ax.plot(t[sel], err[sel], color=ERR_COLOR, lw=0.9, label="‖error‖")
        ax.axhspan(0.0, s.band, color="tab:green", alpha=0.15, lw=0, label=f"band {s.band:.2f} m/s²")
        ax.axvline(s.t_s, color="gray", lw=0.8)
        if s.settling_s is None:
            ax.set_title("not settled within the window", fontsize=9)
        else:
            ax.axvline(s.t_s + s.settling_s, color="tab:green", ls="--", lw=1.0,
                       label=f"settled {s.settling_s:.3f} s")
            ax.set_title(f"settling {s.settling_s:.3f} s, peak error {s.peak_error:.2f} m/s²", fontsize=9)
        ax.set_ylabel("‖error‖ [m/s²]")
        ax.legend(loc="upper right", fontsize=7)
    axes[-1, 0].set_xlabel("time [s]")
    axes[-1, 1].set_xlabel("time [s]")
    fig.suptitle(f"force response ({len(res.steps)} steps, {len(res.pulses)} pulses)")
    return save(fig, out_dir, name, stamp)
