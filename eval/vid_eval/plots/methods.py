"""Estimates of several methods against one truth, every curve visible (issue #25).

Overlaid on one axes, methods that agree (ELM, RELM and OSELM give the same mass to 1e-6 kg;
the filters agree within the line width after their transients) hide each other completely.
Here each method gets its own panel in a grid (rows: cases, columns: methods) with the truth
under it and shared y axes per row, and each panel names how far the method is from the
first one, so equal curves are seen to be equal rather than missing.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .style import GT_COLOR, new_figure

METHOD_COLORS = {"ekf": "tab:blue", "ukf": "tab:orange", "msckf": "tab:green", "swls": "tab:red",
                 "vio": "tab:pink", "elm": "tab:brown", "relm": "tab:purple", "oselm": "tab:olive"}


@dataclass
class CaseSeries:
    """One case (row): its name, time [s], true mass [kg] and each method's estimate."""

    name: str
    t: np.ndarray
    truth: np.ndarray
    estimates: Dict[str, np.ndarray] = field(default_factory=dict)


def rmspe(est: np.ndarray, truth: np.ndarray) -> float:
    """Seed eq. 48: root-mean-square percentage error [%]."""
    return float(100.0 * np.sqrt(np.mean(((est - truth) / truth) ** 2)))


def methods_grid(cases: Sequence[CaseSeries], methods: Sequence[str], title: str = "",
                 ylim: Optional[Callable[[CaseSeries], Tuple[float, float]]] = None):
    """The grid figure: ``len(cases)`` rows x ``len(methods)`` columns."""
    fig, axes = new_figure(len(cases), len(methods), width=3.6 * len(methods) + 1.0,
                           height=2.3 * len(cases) + 0.6, sharex=True, sharey="row", squeeze=False)
    ref = methods[0]
    for row, case in zip(axes, cases):
        for ax, m in zip(row, methods):
            est = case.estimates[m]
            # the estimate wide, the truth dashed on top: where they agree both still show
            ax.plot(case.t, est, color=METHOD_COLORS.get(m, "tab:gray"), lw=1.4, zorder=2,
                    label=f"{m} ({rmspe(est, case.truth):.2f} %)")
            ax.plot(case.t, case.truth, color=GT_COLOR, lw=1.0, ls=(0, (4, 3)), zorder=3, label="truth")
            head = f"{m}: RMSPE {rmspe(est, case.truth):.2f} %"
            if m != ref:
                head += f", max |{m} − {ref}| {np.max(np.abs(est - case.estimates[ref])):.1e} kg"
            ax.set_title(head, fontsize=8)
            if ylim is not None:
                ax.set_ylim(*ylim(case))
        row[0].set_ylabel(f"{case.name}\nmass [kg]", fontsize=9)
        row[0].legend(loc="upper right", fontsize=7, handles=row[0].get_lines()[1:])
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    if title:
        fig.suptitle(title)
    return fig


def method_names(header: List[str], skip: Sequence[str]) -> List[str]:
    """Method columns of an estimates CSV header: everything but ``skip``."""
    return [h for h in header if h not in skip]


def ordered(names, order: Sequence[str]) -> List[str]:
    """The names in the given order first, then the rest sorted (profiles, trajectories, methods)."""
    return [n for n in order if n in names] + sorted(n for n in names if n not in order)
