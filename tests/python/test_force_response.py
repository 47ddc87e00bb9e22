"""Force response metrics (vid_eval.core.force_response) on synthetic series with known answers."""
from __future__ import annotations

import json

import numpy as np
import pytest

from vid_eval.core.force_response import force_response
from vid_eval.plots.force_response import plot_force_response
from vid_eval.core.series import VectorSeries
from plot_checks import assert_plot

T0_NS = 10**18


def _grid(duration_s: float, rate_hz: int):
    """Integer-ns times (no float rounding at 1e18 ns) and seconds since the start."""
    step_ns = 10**9 // rate_hz
    k = np.arange(int(round(duration_s * rate_hz)), dtype=np.int64)
    return T0_NS + k * step_ns, k * (step_ns * 1e-9)


def _series(t_ns, values):
    return VectorSeries(t_ns, np.asarray(values, dtype=float), "world", "m/s^2")


def _smooth(t):
    """A smooth 3-axis force with incommensurate frequencies (one clear correlation peak)."""
    return np.c_[np.sin(2 * np.pi * 0.7 * t) + 0.5 * np.sin(2 * np.pi * 1.9 * t + 1.0),
                 np.cos(2 * np.pi * 0.31 * t) + 0.3 * np.sin(2 * np.pi * 2.3 * t),
                 0.8 * np.sin(2 * np.pi * 1.13 * t + 0.4) + 0.4 * np.cos(2 * np.pi * 0.53 * t)]


@pytest.mark.parametrize("delay_s", [0.037, -0.037])
def test_lag_of_a_delayed_estimate(delay_s):
    # 100 Hz: 37 ms is 3.7 samples, so the nearest whole sample (40 ms) is off by 3 ms and
    # only the sub-sample refinement gets within 2 ms
    t_ns, t = _grid(20.0, 100)
    res = force_response(_series(t_ns, _smooth(t - delay_s)), _series(t_ns, _smooth(t)))
    assert res.lag * 1e3 == pytest.approx(delay_s * 1e3, abs=2.0)
    for k in range(3):
        assert res.lag_s[k] * 1e3 == pytest.approx(delay_s * 1e3, abs=2.0)
    d = res.as_dict()
    assert d["lag_ms"]["combined"] == pytest.approx(delay_s * 1e3, abs=2.0)
    assert d["lag_peak_corr"]["combined"] > 0.99


def test_lag_respects_the_offset():
    # the estimate's clock is 37 ms behind; --offset 0.037 s puts it right, leaving no lag
    t_ns, t = _grid(20.0, 100)
    est = _series(t_ns - 37_000_000, _smooth(t))
    res = force_response(est, _series(t_ns, _smooth(t)), offset_ns=37_000_000)
    assert res.lag * 1e3 == pytest.approx(0.0, abs=2.0)


def _step_case(size=3.0, t_step=2.0, duration=5.0, rate=200):
    t_ns, t = _grid(duration, rate)
    g = np.zeros((len(t), 3))
    g[t >= t_step - 1e-9, 0] = size
    return t_ns, t, g


def test_first_order_lag_settles_after_tau_ln10():
    tau, size, t_step = 0.1, 3.0, 2.0
    t_ns, t, g = _step_case(size, t_step)
    e = np.zeros_like(g)
    after = t >= t_step - 1e-9
    e[after, 0] = size * (1.0 - np.exp(-(t[after] - t_step) / tau))
    res = force_response(_series(t_ns, e), _series(t_ns, g))
    assert len(res.steps) == 1 and res.pulses == []
    s = res.steps[0]
    assert s.t_s == pytest.approx(t_step, abs=1e-6)
    assert s.size == pytest.approx(size)
    assert s.delta == pytest.approx([size, 0.0, 0.0])
    assert s.peak_error == pytest.approx(size, abs=1e-9)
    assert s.settling_s == pytest.approx(tau * np.log(10.0), abs=2 * 0.005)
    d = res.as_dict()
    assert d["summary"]["settling_median_s"] == pytest.approx(tau * np.log(10.0), abs=0.01)
    assert d["steps"][0]["settled"] is True
    json.dumps(d)  # JSON-serializable as it is


def test_step_below_step_min_is_not_reported():
    t_ns, _, g = _step_case(size=1.5)
    assert force_response(_series(t_ns, g), _series(t_ns, g), step_min=2.0).steps == []
    # the same step is found with a lower threshold: the rule above is the threshold
    assert len(force_response(_series(t_ns, g), _series(t_ns, g), step_min=1.0).steps) == 1


def test_short_pulse_is_a_pulse_not_a_step():
    t_ns, t = _grid(4.0, 200)
    g = np.zeros((len(t), 3))
    on = (t >= 2.0 - 1e-9) & (t < 2.03 - 1e-9)  # 30 ms impact of 4 m/s^2 on z
    g[on, 2] = 4.0
    res = force_response(_series(t_ns, g), _series(t_ns, g))
    assert res.steps == []
    assert len(res.pulses) == 1
    p = res.pulses[0]
    assert p.t_s == pytest.approx(2.0, abs=0.03)
    assert p.peak == pytest.approx([0.0, 0.0, 4.0])
    assert p.duration_s == pytest.approx(0.03, abs=1e-6)
    assert p.captured_fraction == pytest.approx(1.0)
    # an estimate that misses the impact captures none of it
    missed = force_response(_series(t_ns, np.zeros_like(g)), _series(t_ns, g))
    assert missed.pulses[0].captured_fraction == pytest.approx(0.0)


def test_plateau_shorter_than_the_hold_is_not_a_step():
    t_ns, t = _grid(4.0, 200)
    g = np.zeros((len(t), 3))
    g[(t >= 2.0 - 1e-9) & (t < 2.2 - 1e-9), 0] = 3.0  # 0.2 s < hold 0.3 s
    res = force_response(_series(t_ns, g), _series(t_ns, g))
    assert res.steps == []


def test_two_opposite_steps_are_both_found():
    t_ns, t = _grid(6.0, 200)
    g = np.zeros((len(t), 3))
    g[(t >= 2.0 - 1e-9) & (t < 4.0 - 1e-9)] = [2.0, -2.0, 1.0]  # |step| = 3
    res = force_response(_series(t_ns, g), _series(t_ns, g))
    assert [s.t_s for s in res.steps] == pytest.approx([2.0, 4.0], abs=1e-6)
    assert res.steps[0].delta == pytest.approx([2.0, -2.0, 1.0])
    assert res.steps[1].delta == pytest.approx([-2.0, 2.0, -1.0])
    assert all(s.settling_s == 0.0 and s.peak_error == 0.0 for s in res.steps)


def test_noise_on_the_truth_creates_no_steps_and_hides_none():
    rng = np.random.default_rng(17)
    t_ns, t = _grid(30.0, 200)
    # a slowly drifting force (a hover with a small oscillation), plus sigma 0.05 noise
    slow = np.c_[0.5 * np.sin(2 * np.pi * 0.1 * t), 0.3 * np.cos(2 * np.pi * 0.07 * t),
                 np.full_like(t, -0.2)]
    noisy = slow + rng.normal(0.0, 0.05, slow.shape)
    res = force_response(_series(t_ns, slow), _series(t_ns, noisy))
    assert res.steps == [] and res.pulses == []
    assert res.noise_band == pytest.approx(3 * np.sqrt(3) * 0.05, rel=0.25)
    # a real step in the same noise is still found, and a perfect estimate counts as settled
    jump = np.where(t >= 10.0 - 1e-9, 3.0, 0.0)[:, None] * [0.0, 1.0, 0.0]
    res = force_response(_series(t_ns, slow + jump), _series(t_ns, noisy + jump))
    assert [s.t_s for s in res.steps] == pytest.approx([10.0], abs=0.011)
    assert res.steps[0].settling_s is not None and res.steps[0].settling_s < 0.02


def test_estimate_that_never_settles_gives_null():
    t_ns, t, g = _step_case(size=3.0)
    e = g.copy()
    e[t >= 2.0 - 1e-9, 0] -= 0.5  # stays 0.5 short of the new level: outside the 0.3 band
    res = force_response(_series(t_ns, e), _series(t_ns, g))
    assert len(res.steps) == 1
    assert res.steps[0].settling_s is None
    d = res.as_dict()
    assert d["steps"][0]["settling_s"] is None and d["steps"][0]["settled"] is False
    assert d["summary"]["not_settled"] == 1 and d["summary"]["settling_median_s"] is None
    assert "1 not settled" in res.summary_line()


def test_plot_writes_png(tmp_path):
    t_ns, t, g = _step_case(size=3.0)
    e = np.zeros_like(g)
    after = t >= 2.0 - 1e-9
    e[after, 0] = 3.0 * (1.0 - np.exp(-(t[after] - 2.0) / 0.1))
    path = plot_force_response(force_response(_series(t_ns, e), _series(t_ns, g)), tmp_path)
    assert path == tmp_path / "force_response.png"
    # correlations (axis colours, combined black), |truth| black and |estimate| blue, the step marked red
    assert_plot(path, ("black", "tab:blue", "tab:red", "tab:green"))
