"""In-memory time series used by the metrics: trajectories, vector series, scalar series.

All times are int64 nanoseconds; quaternions are Hamilton (w, x, y, z), ``q_WI``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np


@dataclass
class Trajectory:
    """Poses ``p_WI`` (N, 3) [m] and ``q_WI`` (N, 4) (w, x, y, z) at times ``t_ns`` (N,).

    ``time_unit`` says how the file wrote the stamps (``"s"``: TUM seconds, ``"ns"``: ASL);
    only the evo-compatible association looks at it (:mod:`vid_eval.core.association`).
    """

    t_ns: np.ndarray
    p: np.ndarray
    q: np.ndarray
    source: str = ""
    time_unit: str = "ns"

    def __len__(self) -> int:
        return len(self.t_ns)

    def subset(self, idx: np.ndarray) -> "Trajectory":
        """The poses at the given indices."""
        return Trajectory(self.t_ns[idx], self.p[idx], self.q[idx], self.source, self.time_unit)

    @property
    def t_s(self) -> np.ndarray:
        """Seconds since the first pose."""
        return (self.t_ns - self.t_ns[0]) * 1e-9

    def path_length(self) -> float:
        """Length of the position path [m]."""
        if len(self) < 2:
            return 0.0
        return float(np.sum(np.linalg.norm(np.diff(self.p, axis=0), axis=1)))


@dataclass
class VectorSeries:
    """A 3-vector time series (force), with optional 1-sigma per axis.

    ``frame`` is ``"world"`` or ``"body"``; ``unit`` is ``"N"`` or ``"m/s^2"``.
    """

    t_ns: np.ndarray
    values: np.ndarray
    frame: str
    unit: str
    sigma: Optional[np.ndarray] = None
    source: str = ""

    def __len__(self) -> int:
        return len(self.t_ns)

    def subset(self, idx: np.ndarray) -> "VectorSeries":
        """The samples at the given indices."""
        sig = None if self.sigma is None else self.sigma[idx]
        return VectorSeries(self.t_ns[idx], self.values[idx], self.frame, self.unit, sig, self.source)


@dataclass
class ScalarSeries:
    """A scalar time series (mass [kg]) with an optional 1-sigma."""

    t_ns: np.ndarray
    values: np.ndarray
    sigma: Optional[np.ndarray] = None
    source: str = ""

    def __len__(self) -> int:
        return len(self.t_ns)

    def subset(self, idx: np.ndarray) -> "ScalarSeries":
        """The samples at the given indices."""
        sig = None if self.sigma is None else self.sigma[idx]
        return ScalarSeries(self.t_ns[idx], self.values[idx], sig, self.source)


@dataclass
class StateSeries:
    """Rows of our ``state.csv`` (see :mod:`vid_eval.core.formats`)."""

    t_ns: np.ndarray
    p: np.ndarray
    q: np.ndarray
    v: np.ndarray
    b_g: np.ndarray
    b_a: np.ndarray
    f_body: np.ndarray
    sigma: dict = field(default_factory=dict)  # 'theta','p','v','bg','ba','f' -> (N, 3)
    source: str = ""

    def __len__(self) -> int:
        return len(self.t_ns)

    def trajectory(self) -> Trajectory:
        """The pose part as a :class:`Trajectory`."""
        return Trajectory(self.t_ns, self.p, self.q, self.source)

    def force_body(self) -> VectorSeries:
        """F_ext in the body frame [m/s^2] with its 1-sigma."""
        return VectorSeries(self.t_ns, self.f_body, "body", "m/s^2", self.sigma.get("f"), self.source)


@dataclass
class NeesCurves:
    """Run-averaged NEES (3 dof each) of orientation, position and F_ext at times ``t_ns``
    (from the filter's start), over ``runs`` Monte-Carlo runs, and the 95 % band of that
    average for a consistent filter: ``[band_lo, band_hi]``."""

    t_ns: np.ndarray
    theta: np.ndarray
    p: np.ndarray
    F: np.ndarray
    runs: int
    band_lo: float
    band_hi: float
    source: str = ""

    def curves(self) -> dict:
        """name -> values of the curves that carry data (F_ext is all zero in imu mode)."""
        named = {"orientation θ": self.theta, "position p": self.p, "force F_ext": self.F}
        return {k: v for k, v in named.items() if np.any(v != 0)}

    def fraction_inside(self, values: np.ndarray, skip_s: float) -> float:
        """Fraction of the times t >= ``skip_s`` at which ``values`` is inside the band (the
        rule of tests/vio_core/test_nees_sim.cpp)."""
        keep = self.t_ns >= int(round(skip_s * 1e9))
        v = values[keep]
        return float(np.mean((v >= self.band_lo) & (v <= self.band_hi))) if v.size else float("nan")
