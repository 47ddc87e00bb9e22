"""Force and pose errors per flight phase (issue #29: real flights start and end on the ground).

The phases come from :mod:`vid_eval.core.phases`. Every number here reuses the whole-run pairing
and alignment: a phase's errors are the whole run's paired errors whose ground-truth time lies
in that phase, so no phase is aligned on its own.

* **Per segment** (``landed``, ``airborne``, each transition window): the force RMSE as
  :func:`vid_eval.core.force_metrics.force_errors` (per frame given), the position error and the
  attitude error statistics of the ATE.
* **Settling after each event** (force). It follows the step response of
  :mod:`vid_eval.core.force_response` on the same resampled grid, with the same ``tol``, ``hold_s``,
  ``window_s`` and noise band. The transition window plays the role of the rise window:
  the *level before* is the per-axis median of the truth over the ``hold_s`` just before the
  window, the *level after* the median over the ``hold_s`` just after it. Neither reaches into
  a neighbouring event's window or outside the sequence. The *step* is ``|after - before|``,
  and the band is ``tol * step + noise_band``. The settling time counts from the event to the
  first grid sample after which ``|f_est - f_gt|`` stays inside the band. The error is followed
  up to ``window_s`` after the event, but not past the next event's window or the sequence
  end. It is None when the error is outside the band at the end, or when a level has no truth
  sample (an event within ``hold_s`` of the sequence end).
* **Landed after a while** (force): per landed interval, the error norm over the times at
  least ``skip_s`` after the interval began (touchdown, or the sequence start), outside the
  transition windows.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

import numpy as np

from .force_metrics import force_errors
from .force_response import ForceResponse, settling_index
from .phases import AIRBORNE, LANDED, Event, PhaseSegmentation
from .series import VectorSeries
from .stats import error_stats

DEFAULT_LANDED_SKIP_S = 1.0
#: A frame's paired force series (estimate, truth) and the mass at each pair (None: unknown).
FramePairs = Tuple[VectorSeries, VectorSeries, Optional[np.ndarray]]


def _kind(seg: PhaseSegmentation, name: str) -> str:
    return name if name in (LANDED, AIRBORNE) else seg.event(name).kind


def _xyz(v: Optional[np.ndarray]) -> Optional[dict]:
    return None if v is None else {a: float(x) for a, x in zip("xyz", v)}


def force_segments(seg: PhaseSegmentation, frames: Dict[str, FramePairs]) -> List[dict]:
    """Per segment, :meth:`ForceResult.as_dict` of the pairs inside it, for every frame
    (``{"frame", "pairs": 0}`` for a segment without pairs)."""
    out = []
    for name in seg.segment_names():
        rec = {"name": name, "kind": _kind(seg, name), "duration_s": seg.duration_s(name)}
        for frame, (pe, pg, m) in frames.items():
            idx = np.flatnonzero(seg.mask(pg.t_ns, name))
            rec[frame] = ({"frame": frame, "pairs": 0} if idx.size == 0 else
                          force_errors(pe.subset(idx), pg.subset(idx),
                                       None if m is None else m[idx]).as_dict())
        out.append(rec)
    return out


@dataclass
class EventResponse:
    """The force estimate's response to one lift-off or touchdown (rules: module docstring)."""

    event: Event
    t_s: float  # event time since the sequence start
    level_before: Optional[np.ndarray]  # (3,) [m/s^2], None without truth there
    level_after: Optional[np.ndarray]
    band: Optional[float]  # tol * step + noise band [m/s^2]
    window_s: float  # how long the error was followed
    peak_error: Optional[float]  # max |f_est - f_gt| over it [m/s^2]
    settling_s: Optional[float]

    @property
    def step(self) -> Optional[float]:
        """|level after - level before| [m/s^2]."""
        if self.level_before is None or self.level_after is None:
            return None
        return float(np.linalg.norm(self.level_after - self.level_before))

    def as_dict(self) -> dict:
        """JSON-friendly record."""
        return {"event": self.event.name, "kind": self.event.kind, "t_ns": int(self.event.t_ns),
                "t_s": self.t_s, "level_before_mps2": _xyz(self.level_before),
                "level_after_mps2": _xyz(self.level_after), "step_mps2": self.step,
                "band_mps2": self.band, "window_s": self.window_s,
                "peak_error_mps2": self.peak_error, "settling_s": self.settling_s,
                "settled": self.settling_s is not None}


def event_responses(seg: PhaseSegmentation, resp: ForceResponse) -> List[EventResponse]:
    """Step, band and settling time after every event, on ``resp``'s grid and parameters."""
    t = resp.t_ns
    err = np.linalg.norm(resp.est - resp.gt, axis=1)
    hold = int(round(resp.params["hold_s"] * 1e9))
    follow = int(round(resp.params["window_s"] * 1e9))
    out = []
    for i, ev in enumerate(seg.events):
        lo = seg.events[i - 1].w1_ns if i > 0 else seg.t0_ns
        hi = seg.events[i + 1].w0_ns if i + 1 < len(seg.events) else seg.t1_ns
        before = resp.gt[(t >= max(ev.w0_ns - hold, lo)) & (t < ev.w0_ns)]
        after = resp.gt[(t > ev.w1_ns) & (t <= min(ev.w1_ns + hold, hi))]
        l0 = np.median(before, axis=0) if len(before) else None
        l1 = np.median(after, axis=0) if len(after) else None
        end = min(ev.t_ns + follow, hi)
        k = np.flatnonzero((t >= ev.t_ns) & (t <= end))
        rec = EventResponse(ev, seg.t_s(ev.t_ns), l0, l1, None, max(0, end - ev.t_ns) / 1e9,
                            float(np.max(err[k])) if k.size else None, None)
        if rec.step is not None and k.size:
            rec.band = resp.params["tol"] * rec.step + resp.noise_band
            j = settling_index(err[k], rec.band)
            rec.settling_s = None if j is None else (0.0 if j == 0 else (t[k[j]] - ev.t_ns) / 1e9)
        out.append(rec)
    return out


def landed_after(seg: PhaseSegmentation, pe: VectorSeries, pg: VectorSeries,
                 skip_s: float = DEFAULT_LANDED_SKIP_S) -> List[dict]:
    """Per landed interval, statistics of ``|f_est - f_gt|`` [m/s^2] from ``skip_s`` on."""
    err = np.linalg.norm(pe.values - pg.values, axis=1)
    out = []
    for iv, m in seg.landed_after(pg.t_ns, skip_s):
        out.append({"t0_s": seg.t_s(iv.t0_ns), "t1_s": seg.t_s(iv.t1_ns),
                    "from_s": seg.t_s(iv.t0_ns) + skip_s, "pairs": int(np.count_nonzero(m)),
                    "error_mps2": error_stats(err[m]) if m.any() else None})
    return out


def force_phase_report(seg: PhaseSegmentation, frames: Dict[str, FramePairs],
                       resp: ForceResponse, skipped: Optional[Dict[str, str]] = None,
                       skip_s: float = DEFAULT_LANDED_SKIP_S) -> dict:
    """The ``phases`` object of ``vid-eval force --json``. The first frame of ``frames`` is
    the command's; settling and the landed error are given in it (``resp`` must be too)."""
    main = next(iter(frames))
    pe, pg, _ = frames[main]
    p = resp.params
    out = seg.as_dict()
    out["frames"] = list(frames)
    if skipped:
        out["skipped_frames"] = dict(skipped)
    out["segments"] = force_segments(seg, frames)
    out["settling"] = {"frame": main, "tol": p["tol"], "hold_s": p["hold_s"],
                       "window_s": p["window_s"], "noise_band_mps2": resp.noise_band,
                       "events": [r.as_dict() for r in event_responses(seg, resp)]}
    out["landed_after"] = {"frame": main, "skip_s": skip_s,
                           "intervals": landed_after(seg, pe, pg, skip_s)}
    return out


def pose_phase_report(seg: PhaseSegmentation, t_ns: np.ndarray, pos_err: np.ndarray,
                      rot_err_deg: Optional[np.ndarray]) -> dict:
    """The ``phases`` object of ``vid-eval traj --json``: per segment, statistics of the
    whole-run ATE's position [m] and attitude [deg] errors at ground-truth times ``t_ns``."""
    out = seg.as_dict()
    out["segments"] = []
    for name in seg.segment_names():
        m = seg.mask(t_ns, name)
        rec = {"name": name, "kind": _kind(seg, name), "duration_s": seg.duration_s(name),
               "pairs": int(np.count_nonzero(m)),
               "pos_m": error_stats(pos_err[m]) if m.any() else None}
        if rot_err_deg is not None:
            rec["rot_deg"] = error_stats(rot_err_deg[m]) if m.any() else None
        out["segments"].append(rec)
    return out


def _head(ph: dict) -> str:
    n = {k: sum(iv["phase"] == k for iv in ph["intervals"]) for k in (LANDED, AIRBORNE)}
    events = ", ".join(f"{e['name']} at {e['t_s']:.3f} s" for e in ph["events"]) or "no events"
    return (f"phases: {n[LANDED]} landed, {n[AIRBORNE]} airborne intervals; {events}; "
            f"window {ph['window_s']:g} s")


def _fmt(x: Optional[float], spec: str) -> str:
    return "-" if x is None else format(x, spec)


def force_phase_lines(ph: dict) -> List[str]:
    """Printed block of :func:`force_phase_report`."""
    lines = [_head(ph)]
    for s in ph["segments"]:
        cols = "  ".join(f"{f} RMSE {_fmt(s[f].get('rmse_mps2', {}).get('norm'), '.4f')}"
                         for f in ph["frames"])
        pairs = s[ph["frames"][0]]["pairs"]
        lines.append(f"  {s['name']:<13} {s['duration_s']:7.2f} s  pairs {pairs:6d}  {cols} m/s^2")
    for f, why in ph.get("skipped_frames", {}).items():
        lines.append(f"  ({f} frame not scored: {why})")
    st = ph["settling"]
    for r in st["events"]:
        if r["step_mps2"] is None:
            lines.append(f"  {r['event']:<13} step unknown (no truth within {st['hold_s']:g} s "
                         f"of the window)")
            continue
        head = f"  {r['event']:<13} step {r['step_mps2']:.3f} m/s^2, band {r['band_mps2']:.3f}: "
        if r["settling_s"] is None:
            head += f"not settled within {r['window_s']:.3f} s"
        else:
            head += f"settling {r['settling_s']:.3f} s"
        lines.append(head + f", peak error {_fmt(r['peak_error_mps2'], '.3f')} m/s^2")
    la = ph["landed_after"]
    for iv in la["intervals"]:
        e = iv["error_mps2"]
        what = ("no pairs" if e is None else
                f"error max {e['max']:.4f} RMSE {e['rmse']:.4f} m/s^2 ({iv['pairs']} pairs)")
        lines.append(f"  landed {iv['t0_s']:.2f}-{iv['t1_s']:.2f} s after {la['skip_s']:g} s "
                     f"on the ground: {what}")
    return lines


def pose_phase_lines(ph: dict) -> List[str]:
    """Printed block of :func:`pose_phase_report`."""
    lines = [_head(ph)]
    for s in ph["segments"]:
        pos = None if s["pos_m"] is None else s["pos_m"]["rmse"]
        rot = s.get("rot_deg")
        line = (f"  {s['name']:<13} {s['duration_s']:7.2f} s  pairs {s['pairs']:6d}"
                f"  pos RMSE {_fmt(pos, '.4f')} m")
        if "rot_deg" in s:
            line += f"  rot max {_fmt(None if rot is None else rot['max'], '.3f')} deg"
        lines.append(line)
    return lines
