"""Flight phases on a time axis: landed intervals shaded, lift-off and touchdown marked."""
from __future__ import annotations

from ..core.phases import LANDED, LIFT_OFF, PhaseSegmentation

LANDED_COLOR = "tab:brown"
EVENT_COLORS = {LIFT_OFF: "tab:green", "touchdown": "tab:orange"}


def shade_phases(ax, phases: PhaseSegmentation, t0_ns: int, label: bool = False) -> None:
    """Shade the landed intervals and draw a line at each event on ``ax``, whose x axis is
    seconds since ``t0_ns`` (ground-truth clock). The data's x range is kept, so intervals
    beyond the plotted samples do not widen the axis. ``label`` names them for a legend."""
    xlim = ax.get_xlim()
    first = {LANDED: label, LIFT_OFF: label, "touchdown": label}
    for iv in phases.intervals:
        if iv.phase == LANDED:
            ax.axvspan((iv.t0_ns - t0_ns) * 1e-9, (iv.t1_ns - t0_ns) * 1e-9, color=LANDED_COLOR,
                       alpha=0.12, lw=0, label="landed" if first[LANDED] else None)
            first[LANDED] = False
    for e in phases.events:
        ax.axvline((e.t_ns - t0_ns) * 1e-9, color=EVENT_COLORS[e.kind], ls="--", lw=1.0,
                   label=e.kind if first[e.kind] else None)
        first[e.kind] = False
    ax.set_xlim(xlim)
