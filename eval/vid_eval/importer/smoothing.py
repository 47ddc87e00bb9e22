"""Smoothed position and its first two derivatives from motion-capture samples.

The samples are resampled to a uniform grid at their median interval (mocap logs drop frames),
low-passed with a zero-phase Butterworth filter (scipy ``butter`` + ``sosfiltfilt``: forward and
backward, so no delay, which a force truth compared sample by sample must not have), and
differentiated with second-order central differences (``numpy.gradient``); the results are
interpolated back to the original times. Differentiating twice multiplies white position
noise by (2 pi f)^2: the cutoff sets how much of that passes (docs/own-vehicle.md,
"Importing a log that is not a bag").
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import butter, sosfiltfilt

from .errors import DataError

FILTER_ORDER = 4  # per pass; sosfiltfilt's two passes give a -6 dB point at the cutoff


@dataclass
class Derivatives:
    p: np.ndarray  # (N, 3) smoothed position
    v: np.ndarray  # (N, 3) velocity
    a: np.ndarray  # (N, 3) acceleration


def lowpass(x: np.ndarray, rate_hz: float, cutoff_hz: float) -> np.ndarray:
    """Zero-phase Butterworth low-pass of the columns of ``x`` (uniformly sampled at
    ``rate_hz``); ``cutoff_hz <= 0`` or at (within 0.2 %) or above Nyquist returns ``x`` unchanged."""
    if cutoff_hz <= 0 or cutoff_hz >= 0.499 * rate_hz:
        return np.asarray(x, dtype=float)
    sos = butter(FILTER_ORDER, cutoff_hz, fs=rate_hz, output="sos")
    padlen = min(x.shape[0] - 1, 3 * (2 * len(sos) + 1) * 4)
    return sosfiltfilt(sos, x, axis=0, padlen=padlen)


class _Grid:
    """A uniform grid over sample times (their median interval) and the way back."""

    def __init__(self, t_ns: np.ndarray):
        if t_ns.size < 5:
            raise DataError(f"{t_ns.size} samples: too few to filter or differentiate")
        self.t = (t_ns - t_ns[0]).astype(np.float64) * 1e-9
        self.dt = float(np.median(np.diff(self.t)))
        self.grid = np.arange(int(round(self.t[-1] / self.dt)) + 1) * self.dt

    def to_grid(self, x: np.ndarray) -> np.ndarray:
        return np.stack([np.interp(self.grid, self.t, x[:, j]) for j in range(x.shape[1])], axis=1)

    def back(self, x: np.ndarray) -> np.ndarray:
        return np.stack([np.interp(self.t, self.grid, x[:, j]) for j in range(x.shape[1])], axis=1)


def smooth(t_ns: np.ndarray, x: np.ndarray, cutoff_hz: float) -> np.ndarray:
    """The columns of ``x`` (sampled at ``t_ns``) low-passed as the position is in
    :func:`derivatives`, so that both sides of a difference see the same filter."""
    g = _Grid(t_ns)
    return g.back(lowpass(g.to_grid(x), 1.0 / g.dt, cutoff_hz))


def derivatives(t_ns: np.ndarray, p: np.ndarray, cutoff_hz: float) -> Derivatives:
    """Smoothed p, v = dp/dt, a = d2p/dt2 at the times ``t_ns`` (see the module docstring)."""
    g = _Grid(t_ns)
    ps = lowpass(g.to_grid(p), 1.0 / g.dt, cutoff_hz)
    v = np.gradient(ps, g.dt, axis=0, edge_order=2)
    a = np.gradient(v, g.dt, axis=0, edge_order=2)
    return Derivatives(g.back(ps), g.back(v), g.back(a))
