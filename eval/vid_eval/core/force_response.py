"""Dynamic response of a force estimate to abrupt forces: lag, steps (settling), pulses.

All quantities are mass-normalized forces in m/s^2. Both series are first resampled by linear
interpolation (:func:`vid_eval.core.geometry.lerp`) onto one uniform grid over their common time
span, spacing ``dt`` (default: the median sample spacing of the ground truth). Nothing else is
smoothed. The rules below are applied to that grid.

**Lag** (cross-correlation). Per axis, both series are mean-removed and cross-correlated,
``c(k) = mean_i gt[i] * est[i + k]`` over the overlapping samples, normalized to a correlation
coefficient. The combined curve sums the three axes' cross-correlations (so the axes with the
most force variation weigh most). The peak is searched over ``|lag| <= max_lag_s`` and refined
to a fraction of a sample by a parabola through the peak and its two neighbours. A positive lag
means the estimate lags (``est(t) ~ gt(t - lag)``). The lag is ``None`` when the peak lies on
the edge of the search range (the true peak is outside) or a series is constant. A periodic
force (one sine on an axis) correlates equally well one period away, so that axis's lag is
ambiguous; the combined lag is the one to read.

**Noise band.** A noisy ground truth must neither create steps nor hide them, so every band
below is widened by ``noise_band = noise_k * ||sigma||``. ``sigma`` is the truth's per-axis
noise, estimated robustly from its second differences, ``1.4826 * median|d2 g| / sqrt(6)``
(white noise of std s has second differences of std ``sqrt(6) s``; smooth motion and the few
steps barely change the median). For a noise-free truth it is 0. ``noise_band`` may be given.

**Steps.** With ``R = rise_s`` and ``H = hold_s``, a step is a change between two held levels:
  * a *rise window* of length R contains the whole change;
  * the *level before*, ``L0``, is the per-axis median of the truth over the H before the rise
    window, the *level after*, ``L1``, the median over the H after it, ``delta = L1 - L0``;
  * ``|delta| >= step_min``;
  * *held*: every truth sample of each of the two H windows is within
    ``tol * |delta| + noise_band`` (vector norm) of that window's level.
  All rise-window positions that pass belong to the same step when they are consecutive (gaps of
  up to R are bridged). The step time is the first sample where the truth is at least half-way,
  ``|g - L0| >= |delta| / 2``. Two steps must therefore be at least H + R apart, and a change
  from a level that was not held for H (e.g. a snap while the force still oscillates) is not a
  step.

**Pulses** (impacts) are excursions shorter than H that return to the level they left: a middle
window of length H holds an excursion with peak ``p = max |g - L0| >= step_min``; the H before
and the H after are held within ``tol * p + noise_band`` of their levels; and the two levels
agree within the same bound. A pulse is therefore never a step (a step's levels differ by
``|delta|``), and an excursion that lasts between H and 2 H, or does not come back, is neither
(it is not reported).

**Step response.** The response window runs from the step time while the truth stays within
``tol * |delta| + noise_band`` of ``L1`` (starting at the end of the rise window), at most
``window_s``. In it: ``peak_error`` is ``max |f_est - f_gt|`` (norm), and the *settling time* is
the time from the step to the first sample after which ``|f_est - f_gt| <= tol * |delta| +
noise_band`` holds to the end of the window. When the error is outside the band at the end of
the window the estimate never settled: ``settling_s`` is ``None``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from .geometry import lerp
from .series import VectorSeries

AXES = "xyz"
_CURVES = ("x", "y", "z", "combined")  # rows of the correlation curves
_CHUNK = 4096  # rows per block for windowed medians: bounds memory on long, fast series


@dataclass
class Step:
    """One step of the ground truth and the estimate's response to it."""

    t_ns: int  # step time (truth half-way), ground-truth clock
    t_s: float  # the same, seconds since the start of the common grid
    level_before: np.ndarray  # (3,) L0 [m/s^2]
    level_after: np.ndarray  # (3,) L1 [m/s^2]
    band: float  # settling band tol*|delta| + noise_band [m/s^2]
    window_s: float  # length of the response window [s]
    peak_error: float  # max |f_est - f_gt| in the window [m/s^2]
    settling_s: Optional[float]  # None: not settled within the window

    @property
    def delta(self) -> np.ndarray:
        """Change of the force, L1 - L0 (3,) [m/s^2]."""
        return self.level_after - self.level_before

    @property
    def size(self) -> float:
        """|L1 - L0| [m/s^2]."""
        return float(np.linalg.norm(self.delta))

    def as_dict(self) -> dict:
        return {"t_ns": int(self.t_ns), "t_s": self.t_s, "size_mps2": self.size,
                "delta_mps2": _xyz(self.delta), "level_before_mps2": _xyz(self.level_before),
                "level_after_mps2": _xyz(self.level_after), "band_mps2": self.band,
                "window_s": self.window_s, "peak_error_mps2": self.peak_error,
                "settling_s": self.settling_s, "settled": self.settling_s is not None}


@dataclass
class Pulse:
    """One short excursion (impact) of the ground truth and how much of it the estimate shows."""

    t_ns: int  # time of the truth's peak, ground-truth clock
    t_s: float  # the same, seconds since the start of the common grid
    peak: np.ndarray  # (3,) truth at the peak minus the level around the pulse [m/s^2]
    duration_s: float  # time the truth is at least half of the peak away from the level [s]
    captured_fraction: float  # estimate's largest excursion along the peak direction / |peak|

    def as_dict(self) -> dict:
        return {"t_ns": int(self.t_ns), "t_s": self.t_s,
                "peak_mps2": float(np.linalg.norm(self.peak)), "peak_axis_mps2": _xyz(self.peak),
                "duration_s": self.duration_s, "captured_fraction": self.captured_fraction}


@dataclass
class ForceResponse:
    """Lag, steps and pulses of a force estimate; also the resampled series for plotting."""

    t0_ns: int  # first grid time (ground-truth clock)
    dt: float  # grid spacing [s]
    est: np.ndarray  # (n, 3) estimate on the grid [m/s^2]
    gt: np.ndarray  # (n, 3) truth on the grid [m/s^2]
    lags_s: np.ndarray  # (2K+1,) searched lags [s]
    corr: np.ndarray  # (4, 2K+1) correlation coefficient: x, y, z, combined
    lag_s: List[Optional[float]]  # x, y, z, combined (None: peak at the search edge)
    noise_band: float  # added to every band [m/s^2]
    params: dict
    steps: List[Step] = field(default_factory=list)
    pulses: List[Pulse] = field(default_factory=list)

    @property
    def t_s(self) -> np.ndarray:
        """Grid times, seconds since the first grid time."""
        return np.arange(len(self.gt)) * self.dt

    @property
    def t_ns(self) -> np.ndarray:
        """Grid times on the ground-truth clock [ns] (as :func:`resample_common` builds them)."""
        return self.t0_ns + np.round(np.arange(len(self.gt)) * self.dt * 1e9).astype(np.int64)

    @property
    def lag(self) -> Optional[float]:
        """Combined lag [s] (positive: the estimate lags)."""
        return self.lag_s[3]

    def settling_times(self) -> np.ndarray:
        """Settling times [s] of the steps that settled."""
        return np.array([s.settling_s for s in self.steps if s.settling_s is not None])

    def summary(self) -> dict:
        """Step statistics: counts, median/max settling time and peak error."""
        st = self.settling_times()
        pe = np.array([s.peak_error for s in self.steps])
        return {"steps": len(self.steps), "not_settled": len(self.steps) - len(st),
                "settling_median_s": float(np.median(st)) if len(st) else None,
                "settling_max_s": float(np.max(st)) if len(st) else None,
                "peak_error_median_mps2": float(np.median(pe)) if len(pe) else None,
                "peak_error_max_mps2": float(np.max(pe)) if len(pe) else None,
                "pulses": len(self.pulses)}

    def summary_line(self) -> str:
        """One line for the console: lag, steps (settling, peak error), pulses."""
        lag = "lag n/a" if self.lag is None else f"lag {self.lag * 1e3:.1f} ms"
        s = self.summary()
        line = f"{lag}, {s['steps']} steps"
        if s["settling_median_s"] is not None:
            line += f": settling median {s['settling_median_s']:.3f} s max {s['settling_max_s']:.3f} s"
        if s["not_settled"]:
            line += f", {s['not_settled']} not settled"
        if s["steps"]:
            line += (f", peak error median {s['peak_error_median_mps2']:.3f} max "
                     f"{s['peak_error_max_mps2']:.3f} m/s^2")
        return line + f", {s['pulses']} pulses"

    def as_dict(self) -> dict:
        """JSON-friendly result (the 'response' object of ``vid-eval force``)."""
        peak = [float(np.max(c)) if np.isfinite(c).any() else None for c in self.corr]
        return {
            "dt_s": self.dt,
            "lag_ms": {k: (None if v is None else v * 1e3) for k, v in zip(_CURVES, self.lag_s)},
            "lag_peak_corr": dict(zip(_CURVES, peak)),
            "noise_band_mps2": self.noise_band,
            "params": self.params,
            "summary": self.summary(),
            "steps": [s.as_dict() for s in self.steps],
            "pulses": [p.as_dict() for p in self.pulses],
        }


def _xyz(v) -> dict:
    return {a: float(x) for a, x in zip(AXES, v)}


def resample_common(est: VectorSeries, gt: VectorSeries, dt: Optional[float] = None,
                    offset_ns: int = 0):
    """Both series on one uniform grid over their common span: (t0_ns, dt, est, gt).

    ``offset_ns`` is added to the estimate's times (``t_est + offset = t_gt``, as --offset).
    """
    t_est = np.asarray(est.t_ns, dtype=np.int64) + int(offset_ns)
    t_gt = np.asarray(gt.t_ns, dtype=np.int64)
    if dt is None:
        dt = float(np.median(np.diff(t_gt))) * 1e-9
    if not dt > 0:
        raise ValueError(f"grid spacing must be positive, got {dt}")
    t0, t1 = max(t_est[0], t_gt[0]), min(t_est[-1], t_gt[-1])
    if t1 <= t0:
        raise ValueError("estimate and ground truth do not overlap in time")
    n = int(np.floor((t1 - t0) * 1e-9 / dt + 1e-9)) + 1
    q = t0 + np.round(np.arange(n) * dt * 1e9).astype(np.int64)
    return int(t0), dt, lerp(t_est, est.values, q), lerp(t_gt, gt.values, q)


def cross_correlation(est: np.ndarray, gt: np.ndarray, max_lag: int):
    """Correlation coefficients of (n, 3) series for lags -K..K samples: (lags, (4, 2K+1)).

    Rows x, y, z and combined (sum of the axes). ``c(k) = mean_i gt[i] est[i+k]`` over the
    overlapping samples (not tapered by the overlap length, so the peak is not pulled toward
    0), divided by the product of the standard deviations.
    """
    n = len(gt)
    x = gt - gt.mean(axis=0)
    y = est - est.mean(axis=0)
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    raw = np.fft.irfft(np.conj(np.fft.rfft(x, nfft, axis=0)) * np.fft.rfft(y, nfft, axis=0),
                       nfft, axis=0)  # raw[k] = sum_i x[i] y[i+k]; negative k wrap around
    lags = np.arange(-max_lag, max_lag + 1)
    c = raw[lags % nfft] / (n - np.abs(lags))[:, None]  # (2K+1, 3) mean products
    vx, vy = np.mean(x ** 2, axis=0), np.mean(y ** 2, axis=0)
    out = np.full((4, len(lags)), np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        out[:3] = (c / np.sqrt(vx * vy)).T
        out[3] = c.sum(axis=1) / np.sqrt(vx.sum() * vy.sum())
    return lags, out


def peak_lag(corr: np.ndarray) -> Optional[float]:
    """Lag of the maximum [samples, fractional] by parabolic interpolation; None at the edge."""
    if not np.isfinite(corr).all():
        return None
    k = int(np.argmax(corr))
    if k == 0 or k == len(corr) - 1:
        return None
    a, b, c = corr[k - 1], corr[k], corr[k + 1]
    den = a - 2 * b + c
    frac = 0.5 * (a - c) / den if den < 0 else 0.0
    return k - (len(corr) - 1) // 2 + frac


def noise_sigma(g: np.ndarray) -> np.ndarray:
    """Per-axis noise std of a series from the MAD of its second differences (see module)."""
    if len(g) < 3:
        return np.zeros(g.shape[1])
    d2 = g[2:] - 2 * g[1:-1] + g[:-2]
    return 1.4826 * np.median(np.abs(d2), axis=0) / np.sqrt(6.0)


def _window_median(x: np.ndarray, w: int) -> np.ndarray:
    """Per-axis median of x[j:j+w] for every j: (n-w+1, 3)."""
    v = sliding_window_view(x, w, axis=0)
    return np.concatenate([np.median(v[a:a + _CHUNK], axis=-1) for a in range(0, len(v), _CHUNK)])


def _window_spread(x: np.ndarray, ref: np.ndarray, w: int) -> np.ndarray:
    """max_m |x[j+m] - ref[j]| over m < w, for j < len(ref): (len(ref),)."""
    v = sliding_window_view(x, w, axis=0)[:len(ref)]
    out = np.empty(len(v))
    for a in range(0, len(v), _CHUNK):
        d = v[a:a + _CHUNK] - ref[a:a + _CHUNK, :, None]
        out[a:a + _CHUNK] = np.sqrt(np.sum(d ** 2, axis=1)).max(axis=1)
    return out


def _runs(mask: np.ndarray, bridge: int) -> List[np.ndarray]:
    """Indices of True in ``mask`` grouped into runs; gaps of up to ``bridge`` are bridged."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return []
    return np.split(idx, np.flatnonzero(np.diff(idx) > bridge + 1) + 1)


def _dist(x: np.ndarray, ref: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x - ref, axis=-1)


def settling_index(err: np.ndarray, band: float) -> Optional[int]:
    """Index of the first sample from which ``err <= band`` holds to the end of ``err`` (0 when
    it always does); None when the last sample is outside the band (not settled)."""
    out = np.flatnonzero(np.asarray(err) > band)
    if out.size == 0:
        return 0
    if out[-1] == len(err) - 1:
        return None
    return int(out[-1]) + 1


def _find_steps(g, e, dt, step_min, nr, nh, nwin, tol, band) -> List[Step]:
    n = len(g)
    m_len = n - 2 * nh - nr + 1  # pre-window starts j with a full post window
    if m_len <= 0:
        return []
    med = _window_median(g, nh)  # med[j]: level of window [j, j+nh)
    spread = _window_spread(g, med, nh)
    l0, l1 = med[:m_len], med[nh + nr:nh + nr + m_len]
    size = _dist(l1, l0)
    lim = tol * size + band
    ok = (size >= step_min) & (spread[:m_len] <= lim) & (spread[nh + nr:nh + nr + m_len] <= lim)
    err = _dist(e, g)
    steps = []
    for run in _runs(ok, nr):
        j = int(run[len(run) // 2])
        L0, L1, d = l0[j], l1[j], size[j]
        lo = int(run[0]) + nh  # first rise window start of the run
        k_s = lo + int(np.argmax(_dist(g[lo:], L0) >= 0.5 * d))
        b = float(lim[j])
        # the response window lasts while the truth holds L1, from the end of the rise window
        k_end = min(n - 1, k_s + nwin)
        q = j + nh + nr
        left = np.flatnonzero(_dist(g[q:k_end + 1], L1) > b)
        if left.size:
            k_end = q + int(left[0]) - 1
        w = err[k_s:k_end + 1]
        k_settle = settling_index(w, b)
        settle = None if k_settle is None else k_settle * dt
        steps.append(Step(0, k_s * dt, L0.copy(), L1.copy(), b, (k_end - k_s) * dt,
                          float(np.max(w)), settle))
    return steps


def _find_pulses(g, e, dt, step_min, nr, nh, tol, band) -> List[Pulse]:
    n = len(g)
    m_len = n - 3 * nh + 1  # pre, middle and post windows of length nh each
    if m_len <= 0:
        return []
    med = _window_median(g, nh)
    spread = _window_spread(g, med, nh)
    l0, l1 = med[:m_len], med[2 * nh:2 * nh + m_len]
    peak = _window_spread(g[nh:], l0, nh)  # farthest middle sample from the level before
    lim = tol * peak + band
    ok = ((peak >= step_min) & (spread[:m_len] <= lim) & (spread[2 * nh:2 * nh + m_len] <= lim)
          & (_dist(l1, l0) <= lim))
    pulses = []
    for run in _runs(ok, nr):
        j = int(run[len(run) // 2])
        L0 = l0[j]
        lo, hi = int(run[0]) + nh, int(run[-1]) + 2 * nh  # union of the middle windows
        dev = _dist(g[lo:hi], L0)
        k = int(np.argmax(dev))
        p_vec = g[lo + k] - L0
        p = float(np.linalg.norm(p_vec))
        above = dev >= 0.5 * p
        a = k - int(np.argmin(above[k::-1])) + 1 if not above[:k + 1].all() else 0
        z = k + int(np.argmin(above[k:])) if not above[k:].all() else len(dev)
        e0 = np.median(e[j:j + nh], axis=0)  # the estimate's level before, same window as L0
        captured = float(np.max((e[lo:hi] - e0) @ (p_vec / p)) / p)
        pulses.append(Pulse(0, (lo + k) * dt, p_vec, (z - a) * dt, captured))
    return pulses


def force_response(est: VectorSeries, gt: VectorSeries, step_min: float = 2.0, *,
                   rise_s: float = 0.1, hold_s: float = 0.3, tol: float = 0.1,
                   window_s: float = 2.0, max_lag_s: float = 1.0, dt: Optional[float] = None,
                   offset_ns: int = 0, noise_k: float = 3.0,
                   noise_band: Optional[float] = None) -> ForceResponse:
    """Lag, steps and pulses of ``est`` against ``gt`` (same frame, m/s^2); rules: see module.

    The series need not be paired (each is interpolated onto the grid); pairing first restricts
    them to matched samples. ``step_min`` [m/s^2] is the smallest step and pulse; ``rise_s``,
    ``hold_s`` the rise window and the hold; ``tol`` the band as a fraction of the step;
    ``window_s`` the longest response window; ``max_lag_s`` the lag search range; ``dt`` the grid
    spacing (default: the truth's median spacing); ``offset_ns`` is added to the estimate's
    times; ``noise_band`` overrides ``noise_k`` times the estimated truth noise.
    """
    if est.frame != gt.frame or est.unit != "m/s^2" or gt.unit != "m/s^2":
        raise ValueError(f"compare like with like: est {est.frame} {est.unit}, gt {gt.frame} {gt.unit}")
    if not hold_s > rise_s > 0:
        raise ValueError(f"need hold_s > rise_s > 0, got hold {hold_s} rise {rise_s}")
    t0, dt, e, g = resample_common(est, gt, dt, offset_ns)
    n = len(g)
    nr = max(1, int(round(rise_s / dt)))
    nh = max(nr + 1, int(round(hold_s / dt)))
    k_max = max(1, min(int(round(max_lag_s / dt)), (n - 1) // 2))
    lags, corr = cross_correlation(e, g, k_max)
    lag_s = [None if (k := peak_lag(c)) is None else k * dt for c in corr]
    if noise_band is None:
        noise_band = float(noise_k * np.linalg.norm(noise_sigma(g)))
    steps = _find_steps(g, e, dt, step_min, nr, nh, int(round(window_s / dt)), tol, noise_band)
    pulses = _find_pulses(g, e, dt, step_min, nr, nh, tol, noise_band)
    for ev in (*steps, *pulses):
        ev.t_ns = t0 + int(round(ev.t_s * 1e9))
    params = {"step_min_mps2": step_min, "rise_s": rise_s, "hold_s": hold_s, "tol": tol,
              "window_s": window_s, "max_lag_s": lags[-1] * dt, "offset_ns": int(offset_ns)}
    return ForceResponse(t0, dt, e, g, lags * dt, corr, lag_s, float(noise_band), params,
                         steps, pulses)
