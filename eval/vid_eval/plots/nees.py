"""NEES plot: run-averaged NEES of orientation, position and F_ext over time against the
two-sided 95 % band of the mean of N chi2(3) values (shaded), with the share of time inside."""
from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

from ..core.formats import NEES_DOF
from ..core.series import NeesCurves
from .style import new_figure, save

BAND_COLOR = "tab:green"
CURVE_COLORS = ("tab:blue", "tab:orange", "tab:purple")  # none close to the band's colour


def nees_figure(nees: NeesCurves, skip_s: float, title: str = ""):
    """One panel: each curve with its share inside the band (after ``skip_s``) in the legend,
    the band shaded and its bounds labelled, the skipped start greyed out."""
    fig, ax = new_figure(1, 1, width=10, height=4.5)
    t = nees.t_ns * 1e-9
    ax.axhspan(nees.band_lo, nees.band_hi, color=BAND_COLOR, alpha=0.15, lw=0, zorder=0,
               label=f"95 % band of the mean of {nees.runs} χ²({NEES_DOF}): "
                     f"[{nees.band_lo:.2f}, {nees.band_hi:.2f}]")
    ax.axhline(NEES_DOF, color=BAND_COLOR, ls=":", lw=1.2, zorder=1, label=f"expected value {NEES_DOF}")
    if skip_s > 0:
        ax.axvspan(t[0], skip_s, facecolor="none", edgecolor="0.7", hatch="//", lw=0, zorder=0,
                   label=f"first {skip_s:g} s: not scored")
    for (name, values), color in zip(nees.curves().items(), CURVE_COLORS):
        inside = 100.0 * nees.fraction_inside(values, skip_s)
        ax.plot(t, values, color=color, lw=1.0, zorder=2, label=f"{name} ({inside:.0f} % inside)")
    ax.set_xlabel("time since the filter started [s]")
    ax.set_ylabel(f"NEES averaged over {nees.runs} runs ({NEES_DOF} dof)")
    ax.set_title(title or _title(Path(nees.source).stem, nees.runs))
    ax.set_ylim(bottom=0.0)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), fontsize=8, ncol=3)  # below: no curve hidden
    return fig


def _title(stem: str, runs: int) -> str:
    """'nees_vid17_like_dynamics' -> 'NEES consistency: vid17_like, dynamics mode (20 runs)'."""
    parts = stem.removeprefix("nees_").rsplit("_", 1)
    what = f"{parts[0]}, {parts[1]} mode" if len(parts) == 2 and parts[1] in ("dynamics", "imu") else stem
    return f"NEES consistency: {what} ({runs} Monte-Carlo runs)"


def plot_nees(nees: NeesCurves, out_dir: os.PathLike, name: str, skip_s: float = 5.0,
              stamp: Optional[str] = None) -> Path:
    """Write :func:`nees_figure` as ``out_dir/name``."""
    return save(nees_figure(nees, skip_s), out_dir, name, stamp)
