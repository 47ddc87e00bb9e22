"""Per-phase force metrics (vid_eval.core.phase_metrics): settling after lift-off and touchdown, how
the step is measured, the landed error after 1 s on the ground, pose errors per phase."""
from __future__ import annotations

import json

import numpy as np
import pytest

from vid_eval.core.force_response import force_response
from vid_eval.core.phase_metrics import (event_responses, force_phase_lines, force_phase_report,
                                    landed_after, pose_phase_lines, pose_phase_report)
from vid_eval.core.phases import segment_phases
from vid_eval.core.series import ScalarSeries, VectorSeries

G = 9.81
T0 = 10**18
RATE = 200


def _grid(duration_s: float):
    k = np.arange(int(round(duration_s * RATE)), dtype=np.int64)
    return T0 + k * (10**9 // RATE), k / RATE


def _vec(t_ns, values):
    return VectorSeries(t_ns, np.asarray(values, dtype=float), "world", "m/s^2")


def _flight(t, lift, touch):
    """phase0 and the truth: m g up on the ground, nothing in the air (sharp events)."""
    air = (t >= lift - 1e-9) & (t < touch - 1e-9)
    truth = np.where(air[:, None], 0.0, [0.0, 0.0, G])
    return air, truth


def _lagged(t, truth, events, tau):
    """An estimate following the truth with a first-order lag ``tau`` after each event."""
    est = truth.copy()
    for te, before in events:
        after = t >= te - 1e-9
        nxt = [e for e, _ in events if e > te]
        if nxt:
            after &= t < nxt[0] - 1e-9
        est[after] += (before - truth[after]) * np.exp(-(t[after] - te) / tau)[:, None]
    return est


def test_settling_after_lift_off_and_touchdown_is_tau_ln10():
    t_ns, t = _grid(12.0)
    air, truth = _flight(t, 4.0, 8.0)
    est = _lagged(t, truth, [(4.0, np.array([0, 0, G])), (8.0, np.zeros(3))], tau=0.1)
    seg = segment_phases(ScalarSeries(t_ns, air.astype(np.int64)))
    resp = force_response(_vec(t_ns, est), _vec(t_ns, truth))
    lift, touch = event_responses(seg, resp)
    for r in (lift, touch):
        assert r.level_before is not None and r.step == pytest.approx(G)  # m g: the whole weight
        assert r.band == pytest.approx(0.1 * G, abs=1e-6)
        assert r.peak_error == pytest.approx(G)
        # |e| = g exp(-t/tau) <= 0.1 g from tau ln 10 on; the grid is 5 ms
        assert r.settling_s == pytest.approx(0.1 * np.log(10.0), abs=0.006)
    assert lift.level_before == pytest.approx([0, 0, G]) and lift.level_after == pytest.approx(0.0)
    assert touch.level_before == pytest.approx(0.0) and touch.level_after == pytest.approx([0, 0, G])
    d = lift.as_dict()
    assert d["event"] == "lift-off 1" and d["settled"] is True and d["t_s"] == pytest.approx(4.0)
    json.dumps(d)


def test_an_estimate_that_stays_off_never_settles():
    t_ns, t = _grid(10.0)
    air, truth = _flight(t, 4.0, 99.0)
    est = truth.copy()
    est[air, 2] += 0.2 * G  # stays 20 % of the step above the truth in the air
    seg = segment_phases(ScalarSeries(t_ns, air.astype(np.int64)))
    (r,) = event_responses(seg, force_response(_vec(t_ns, est), _vec(t_ns, truth)))
    assert r.settling_s is None and r.as_dict()["settled"] is False
    assert r.window_s == pytest.approx(2.0)  # followed for the response window of force_response


def test_the_step_is_measured_just_outside_the_transition_window():
    """A ground reaction that ramps down over 2 s of spin-up before lift-off: the level before is
    the truth's median over the 0.3 s before the window (not the full weight)."""
    t_ns, t = _grid(10.0)
    air, truth = _flight(t, 5.0, 99.0)
    ramp = (t >= 3.0 - 1e-9) & ~air
    truth[ramp, 2] = G * (5.0 - t[ramp]) / 2.0
    seg = segment_phases(ScalarSeries(t_ns, air.astype(np.int64)))
    (r,) = event_responses(seg, force_response(_vec(t_ns, truth), _vec(t_ns, truth)))
    # samples 4.200 .. 4.495 s: the median is the ramp at their middle time, 4.3475 s
    assert r.level_before[2] == pytest.approx(G * (5.0 - 4.3475) / 2.0, abs=1e-9)
    assert r.step == pytest.approx(G * 0.6525 / 2.0, abs=1e-9)
    assert r.settling_s == 0.0


def test_an_event_too_close_to_the_start_has_no_step():
    t_ns, t = _grid(6.0)
    air, truth = _flight(t, 0.3, 99.0)  # window clipped to [0, 0.8]: no truth before it
    seg = segment_phases(ScalarSeries(t_ns, air.astype(np.int64)))
    (r,) = event_responses(seg, force_response(_vec(t_ns, truth), _vec(t_ns, truth)))
    assert r.level_before is None and r.step is None and r.settling_s is None
    assert r.as_dict()["step_mps2"] is None


def test_landed_error_after_one_second_on_the_ground():
    t_ns, t = _grid(12.0)
    air, truth = _flight(t, 4.0, 8.0)
    err = np.zeros_like(truth)
    err[:, 0] = np.where(t < 1.0, 0.5, 0.03)  # settling after the start
    err[(t >= 8.0) & (t < 9.0), 1] = 0.4  # settling after touchdown
    err[(t >= 9.0), 1] = -0.06
    seg = segment_phases(ScalarSeries(t_ns, air.astype(np.int64)))
    first, second = landed_after(seg, _vec(t_ns, truth + err), _vec(t_ns, truth), 1.0)
    assert (first["from_s"], first["t1_s"]) == (1.0, 4.0)
    assert first["pairs"] == 2.5 * RATE  # 1.000 .. 3.495 s: the lift-off window starts at 3.5 s
    assert first["error_mps2"]["max"] == pytest.approx(0.03)
    assert second["from_s"] == 9.0
    assert second["error_mps2"]["max"] == pytest.approx(np.hypot(0.03, 0.06))
    assert second["error_mps2"]["count"] == second["pairs"] == 3 * RATE


def test_force_report_json_and_lines():
    t_ns, t = _grid(12.0)
    air, truth = _flight(t, 4.0, 8.0)
    est = truth + [0.0, 0.1, 0.0]
    seg = segment_phases(ScalarSeries(t_ns, air.astype(np.int64)), window_s=1.0)
    pe, pg = _vec(t_ns, est), _vec(t_ns, truth)
    resp = force_response(pe, pg)
    ph = force_phase_report(seg, {"world": (pe, pg, np.full(len(t), 2.0))}, resp,
                            {"body": "no ground-truth poses"})
    assert {"intervals", "events", "frames", "segments", "settling", "landed_after",
            "skipped_frames"} <= set(ph)
    assert [s["name"] for s in ph["segments"]] == ["landed", "airborne", "lift-off 1", "touchdown 1"]
    for s in ph["segments"]:
        assert s["world"]["rmse_mps2"]["norm"] == pytest.approx(0.1)
        assert s["world"]["rmse_N"]["norm"] == pytest.approx(0.2)
    json.dumps(ph)
    lines = force_phase_lines(ph)
    assert lines[0].startswith("phases: 2 landed, 1 airborne intervals; lift-off 1 at 4.000 s")
    assert any(ln.split()[:2] == ["airborne", "3.00"] and "world RMSE 0.1000" in ln for ln in lines)
    assert any("body frame not scored: no ground-truth poses" in ln for ln in lines)


def test_pose_report_never_lifting_off():
    t_ns, _ = _grid(3.0)
    seg = segment_phases(ScalarSeries(t_ns, np.zeros(len(t_ns), dtype=np.int64)))
    pos = np.full(len(t_ns), 0.02)
    ph = pose_phase_report(seg, t_ns, pos, np.full(len(t_ns), 0.7))
    landed, airborne = ph["segments"]
    assert landed["pairs"] == len(t_ns) and landed["pos_m"]["rmse"] == pytest.approx(0.02)
    assert landed["rot_deg"]["max"] == pytest.approx(0.7)
    assert airborne == {"name": "airborne", "kind": "airborne", "duration_s": 0.0, "pairs": 0,
                        "pos_m": None, "rot_deg": None}
    assert pose_phase_lines(ph)[2].split() == ["airborne", "0.00", "s", "pairs", "0", "pos", "RMSE",
                                               "-", "m", "rot", "max", "-", "deg"]
