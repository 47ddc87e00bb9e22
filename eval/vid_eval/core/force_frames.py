"""Bring force series to a common frame and unit before comparing them.

Ground truth ``force0`` is world-frame Newton; the estimator reports mass-normalized
[m/s^2] force in the body frame (and world). These helpers divide by the mass and rotate
between W and I with an orientation trajectory ``q_WI`` (SLERP at the force times).
"""
from __future__ import annotations

from typing import Optional, Union

import numpy as np

from ..errors import AssociationError, ConfigurationError
from .geometry import lerp, matrices_from_wxyz, slerp_wxyz
from .series import ScalarSeries, Trajectory, VectorSeries

Mass = Union[float, ScalarSeries]


def mass_at(mass: Mass, t_ns: np.ndarray) -> np.ndarray:
    """Mass [kg] at each time: a constant, or a mass series interpolated linearly (held
    constant before its first and after its last sample)."""
    if isinstance(mass, ScalarSeries):
        t = np.clip(np.asarray(t_ns, dtype=np.int64), mass.t_ns[0], mass.t_ns[-1])
        return lerp(mass.t_ns, mass.values, t)
    m = float(mass)
    if not m > 0.0:
        raise ConfigurationError(f"mass must be positive, got {m}")
    return np.full(len(t_ns), m)


def newton_to_accel(series: VectorSeries, mass: Mass) -> VectorSeries:
    """Divide a force in N by the mass: result in m/s^2 (sigma too)."""
    if series.unit == "m/s^2":
        return series
    m = mass_at(mass, series.t_ns)[:, None]
    sig = None if series.sigma is None else series.sigma / m
    return VectorSeries(series.t_ns, series.values / m, series.frame, "m/s^2", sig, series.source)


def accel_to_newton(values: np.ndarray, t_ns: np.ndarray, mass: Mass) -> np.ndarray:
    """Multiply an (N, …) array in m/s^2 by the mass at ``t_ns``: result in N."""
    m = mass_at(mass, t_ns)
    return values * m.reshape((-1,) + (1,) * (np.ndim(values) - 1))


def rotate_series(series: VectorSeries, orient: Trajectory, to_frame: str) -> VectorSeries:
    """Express ``series`` in ``to_frame`` ('world' or 'body') with orientations ``q_WI``
    SLERP-interpolated at the series times; samples outside the orientation span are dropped.

    A 1-sigma given per axis is propagated as the square root of the diagonal of
    ``R diag(sigma^2) R^T``.
    """
    if series.frame == to_frame:
        return series
    if to_frame not in ("world", "body"):
        raise ConfigurationError(f"unknown frame '{to_frame}'")
    keep = np.flatnonzero((series.t_ns >= orient.t_ns[0]) & (series.t_ns <= orient.t_ns[-1]))
    if keep.size == 0:
        raise AssociationError(
            f"force times of {series.source or 'the force series'} do not overlap the "
            f"orientation times of {orient.source or 'the orientation source'}")
    s = series.subset(keep)
    R = matrices_from_wxyz(slerp_wxyz(orient.t_ns, orient.q, s.t_ns))
    if to_frame == "body":
        R = np.transpose(R, (0, 2, 1))  # R_IW
    values = np.einsum("nij,nj->ni", R, s.values)
    sigma = None
    if s.sigma is not None:
        sigma = np.sqrt(np.einsum("nij,nj->ni", R ** 2, s.sigma ** 2))
    return VectorSeries(s.t_ns, values, to_frame, s.unit, sigma, s.source)


def require_orientation(orient: Optional[Trajectory], what: str) -> Trajectory:
    """Raise a clear error when a frame change needs an orientation that was not given."""
    if orient is None:
        raise ConfigurationError(
            f"{what} needs orientations q_WI: give --gt-state (ground-truth poses) or "
            f"--state (our state.csv)")
    return orient
