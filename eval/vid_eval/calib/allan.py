"""IMU noise from a static log: overlapping Allan deviation (``allantools``) and a fit of the
noise model to it, in Kalibr's continuous-time parameters.

An IMU axis at rest reads white noise of density N (Kalibr ``*_noise_density``) plus a bias
that random-walks with density K (``*_random_walk``), and real sensors add a flicker floor
("bias instability" B). Their Allan variances add:

    sigma^2(tau) = N^2 / tau + K^2 tau / 3 + (2 ln 2 / pi) B^2

so N is the -1/2 slope line read at tau = 1 s and K the +1/2 slope line read at tau = 3 s
(IEEE Std 952; Kalibr's IMU noise model page). Reading two points off the curve uses two
noisy values; fitting all three terms to every tau (weighted by each point's uncertainty,
~1/sqrt(2 (T/tau - 1)) relative for a log of length T) uses the whole curve.

The Allan deviation itself is allantools' ``oadev`` (a maintained library; this module only
fits the model).
"""
from __future__ import annotations

from dataclasses import dataclass

import allantools
import numpy as np
from scipy.optimize import nnls

_FLICKER = 2.0 * np.log(2.0) / np.pi  # Allan variance of bias instability B: (2 ln2 / pi) B^2


@dataclass
class AllanFit:
    """One axis: the Allan deviation and the fitted noise model."""

    taus: np.ndarray         # averaging times [s]
    adev: np.ndarray         # overlapping Allan deviation [unit]
    noise_density: float     # N [unit * sqrt(s)] = [unit / sqrt(Hz)]
    random_walk: float       # K [unit / sqrt(s)]
    bias_instability: float  # B [unit]

    def model(self, taus: np.ndarray) -> np.ndarray:
        """The fitted Allan deviation at ``taus``."""
        return np.sqrt(model_variance(taus, self.noise_density, self.random_walk, self.bias_instability))


def model_variance(taus: np.ndarray, n: float, k: float, b: float) -> np.ndarray:
    """Allan variance of white noise N, random walk K and bias instability B."""
    taus = np.asarray(taus, dtype=float)
    return n * n / taus + k * k * taus / 3.0 + _FLICKER * b * b


def allan_deviation(samples: np.ndarray, rate_hz: float, points: int = 60) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(taus, overlapping ADEV, number of clusters per tau) at ``points`` log-spaced averaging
    times from one sample to a ninth of the log (longer taus have too few clusters)."""
    n = len(samples)
    m = np.unique(np.round(np.logspace(0, np.log10(max(n / 9.0, 2.0)), points)).astype(int))
    taus, adev, _, _ = allantools.oadev(np.asarray(samples, dtype=float), rate=rate_hz, data_type="freq",
                                        taus=m / rate_hz)
    taus = np.asarray(taus)
    clusters = np.floor(n / np.round(taus * rate_hz))
    return taus, np.asarray(adev), clusters


def fit_allan(taus: np.ndarray, adev: np.ndarray, clusters: np.ndarray) -> tuple[float, float, float]:
    """(N, K, B) fitted to the Allan variance. The variance is linear in (N^2, K^2, B^2), so
    this is a non-negative linear least squares (scipy's ``nnls``), each point weighted by its
    uncertainty relative to the model (reweighted twice: weights from the data itself would
    favour the points that came out low). Fitting log ADEV instead would be biased low where
    few clusters make the estimate skewed (the long taus that carry K)."""
    ok = (adev > 0) & (clusters > 1)
    t, avar, c = taus[ok], adev[ok] ** 2, clusters[ok]
    rel = np.sqrt(2.0 / (c - 1.0))  # relative 1-sigma of an Allan variance point (chi^2 with c - 1 dof)
    A = np.stack([1.0 / t, t / 3.0, np.full_like(t, _FLICKER)], axis=1)
    model = avar.copy()
    for _ in range(3):
        w = 1.0 / (rel * model)
        x, _ = nnls(A * w[:, None], avar * w)
        model = np.maximum(A @ x, 1e-300)
    n2, k2, b2 = x
    return float(np.sqrt(n2)), float(np.sqrt(k2)), float(np.sqrt(b2))


def analyse(samples: np.ndarray, rate_hz: float) -> AllanFit:
    """Allan deviation and noise model of one axis of a static log."""
    taus, adev, clusters = allan_deviation(samples, rate_hz)
    n, k, b = fit_allan(taus, adev, clusters)
    return AllanFit(taus, adev, n, k, b)
