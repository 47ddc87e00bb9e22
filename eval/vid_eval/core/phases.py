"""Flight phases of a sequence (ground-truth ``phase0``, issue #29): landed and airborne
intervals, lift-off and touchdown events, and the transition window around each event.

Rules:
  * phase0 gives the phase at each of its times; a phase holds from its sample up to the next
    sample with the other phase. An *event* (lift-off 0 -> 1, touchdown 1 -> 0) is at the first
    sample of the new phase. Events are numbered per kind from 1 (``lift-off 1``, ...).
  * The *sequence* is the span of phase0, ``[first, last sample]``; times outside it have no
    phase and belong to no segment.
  * The *transition window* of an event is the closed interval of ``window_s`` centred on it,
    clipped to the sequence. Windows of events closer than ``window_s`` overlap; a time in both
    belongs to both.
  * The segments ``landed`` and ``airborne`` are the times of that phase outside every
    transition window.
``t_s`` in records counts seconds from the first phase0 sample.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Tuple

import numpy as np

from .formats import PHASE_AIRBORNE
from .series import ScalarSeries

LANDED, AIRBORNE = "landed", "airborne"
LIFT_OFF, TOUCHDOWN = "lift-off", "touchdown"
DEFAULT_WINDOW_S = 1.0


@dataclass(frozen=True)
class Interval:
    """A maximal run of one phase: ``[t0_ns, t1_ns)``; the last interval includes ``t1_ns``."""

    phase: str  # LANDED or AIRBORNE
    t0_ns: int
    t1_ns: int


@dataclass(frozen=True)
class Event:
    """A lift-off or touchdown at ``t_ns`` with its transition window ``[w0_ns, w1_ns]``."""

    kind: str  # LIFT_OFF or TOUCHDOWN
    number: int  # 1-based, per kind
    t_ns: int
    w0_ns: int
    w1_ns: int

    @property
    def name(self) -> str:
        """``lift-off 1``, ``touchdown 2``, ..."""
        return f"{self.kind} {self.number}"


@dataclass
class PhaseSegmentation:
    """Intervals and events of one sequence, and the masks of its segments at any times."""

    t0_ns: int
    t1_ns: int
    window_s: float
    intervals: List[Interval]
    events: List[Event]
    source: str = ""

    def segment_names(self) -> List[str]:
        """``landed``, ``airborne``, then every event's window in time order."""
        return [LANDED, AIRBORNE] + [e.name for e in self.events]

    def event(self, name: str) -> Event:
        """The event called ``name`` (KeyError when absent)."""
        for e in self.events:
            if e.name == name:
                return e
        raise KeyError(name)

    def interval_index(self, t_ns: np.ndarray) -> np.ndarray:
        """Index into :attr:`intervals` of each time; -1 outside the sequence."""
        t = np.asarray(t_ns, dtype=np.int64)
        starts = np.array([iv.t0_ns for iv in self.intervals], dtype=np.int64)
        idx = np.searchsorted(starts, t, side="right") - 1
        return np.where((t >= self.t0_ns) & (t <= self.t1_ns), idx, -1)

    def in_window(self, t_ns: np.ndarray) -> np.ndarray:
        """True for times inside any transition window."""
        t = np.asarray(t_ns, dtype=np.int64)
        out = np.zeros(t.shape, dtype=bool)
        for e in self.events:
            out |= (t >= e.w0_ns) & (t <= e.w1_ns)
        return out

    def mask(self, t_ns: np.ndarray, name: str) -> np.ndarray:
        """Times in segment ``name``: ``landed``, ``airborne`` (windows excluded) or an event's
        window (``lift-off 1``)."""
        t = np.asarray(t_ns, dtype=np.int64)
        if name in (LANDED, AIRBORNE):
            # the trailing False is picked by index -1: outside the sequence
            phase = np.array([iv.phase == name for iv in self.intervals] + [False])
            return phase[self.interval_index(t)] & ~self.in_window(t)
        e = self.event(name)
        return (t >= e.w0_ns) & (t <= e.w1_ns)

    def landed_after(self, t_ns: np.ndarray, skip_s: float) -> List[Tuple[Interval, np.ndarray]]:
        """Per landed interval, the times ``skip_s`` or more after it began (on the ground since
        then, or since the sequence start), outside every transition window."""
        t = np.asarray(t_ns, dtype=np.int64)
        idx, win = self.interval_index(t), self.in_window(t)
        skip = int(round(skip_s * 1e9))
        return [(iv, (idx == i) & ~win & (t >= iv.t0_ns + skip))
                for i, iv in enumerate(self.intervals) if iv.phase == LANDED]

    def duration_s(self, name: str) -> float:
        """Length of segment ``name`` [s] (for landed/airborne, without the windows)."""
        if name not in (LANDED, AIRBORNE):
            e = self.event(name)
            return (e.w1_ns - e.w0_ns) / 1e9
        total = 0
        for iv in self.intervals:
            if iv.phase == name:
                total += iv.t1_ns - iv.t0_ns - sum(max(0, min(iv.t1_ns, b) - max(iv.t0_ns, a))
                                                   for a, b in self._merged_windows())
        return total / 1e9

    def _merged_windows(self) -> List[Tuple[int, int]]:
        out: List[Tuple[int, int]] = []
        for a, b in sorted((e.w0_ns, e.w1_ns) for e in self.events):
            if out and a <= out[-1][1]:
                out[-1] = (out[-1][0], max(out[-1][1], b))
            else:
                out.append((a, b))
        return out

    def t_s(self, t_ns: int) -> float:
        """Seconds since the first phase0 sample."""
        return (int(t_ns) - self.t0_ns) / 1e9  # division: 15.0, not 15.000000000000002

    def as_dict(self) -> dict:
        """JSON-friendly record: source, window, intervals and events."""
        return {
            "source": self.source, "window_s": self.window_s,
            "t0_ns": int(self.t0_ns), "t1_ns": int(self.t1_ns),
            "intervals": [{"phase": iv.phase, "t0_ns": int(iv.t0_ns), "t1_ns": int(iv.t1_ns),
                           "t0_s": self.t_s(iv.t0_ns), "t1_s": self.t_s(iv.t1_ns)}
                          for iv in self.intervals],
            "events": [{"name": e.name, "kind": e.kind, "t_ns": int(e.t_ns), "t_s": self.t_s(e.t_ns),
                        "window_t0_s": self.t_s(e.w0_ns), "window_t1_s": self.t_s(e.w1_ns)}
                       for e in self.events],
        }


def segment_phases(phases: ScalarSeries, window_s: float = DEFAULT_WINDOW_S) -> PhaseSegmentation:
    """Intervals, events and transition windows of a phase0 series (rules: see the module)."""
    if not window_s > 0:
        raise ValueError(f"the phase window must be positive, got {window_s} s")
    t = np.asarray(phases.t_ns, dtype=np.int64)
    air = np.asarray(phases.values) == PHASE_AIRBORNE
    t0, t1 = int(t[0]), int(t[-1])
    starts = np.r_[0, np.flatnonzero(air[1:] != air[:-1]) + 1]
    ends = [int(t[k]) for k in starts[1:]] + [t1]
    intervals = [Interval(AIRBORNE if air[k] else LANDED, int(t[k]), end)
                 for k, end in zip(starts, ends)]
    half = int(round(window_s * 0.5e9))
    events, count = [], {LIFT_OFF: 0, TOUCHDOWN: 0}
    for k in starts[1:]:
        kind = LIFT_OFF if air[k] else TOUCHDOWN
        count[kind] += 1
        te = int(t[k])
        events.append(Event(kind, count[kind], te, max(t0, te - half), min(t1, te + half)))
    return PhaseSegmentation(t0, t1, float(window_s), intervals, events, phases.source)
