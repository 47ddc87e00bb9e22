"""Mass-identification metrics: RMSPE (docs/model.md eq. (56)) and RMSE.

``RMSPE = sqrt( (1/N) * sum_k ((m_hat_k - m_k) / m_k)^2 ) * 100 %``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .series import ScalarSeries
from .stats import error_stats


def rmspe(m_hat: np.ndarray, m: np.ndarray) -> float:
    """Root-mean-square percentage error [%] of estimates ``m_hat`` against truth ``m`` (eq. 48)."""
    m_hat = np.asarray(m_hat, dtype=float)
    m = np.asarray(m, dtype=float)
    if m_hat.shape != m.shape or m.size == 0:
        raise ValueError("rmspe needs two non-empty arrays of equal shape")
    if np.any(m == 0.0):
        raise ValueError("rmspe: true mass must be non-zero")
    return float(np.sqrt(np.mean(((m_hat - m) / m) ** 2)) * 100.0)


def settle_times(t_s: np.ndarray, m_hat: np.ndarray, m: np.ndarray, band_pct: float = 5.0,
                 gap_s: float = 0.5, t0_s: float = None) -> list:
    """Settling after each change of the true mass: for every change (truth samples that differ
    from their predecessor, grouped while less than ``gap_s`` apart), the time from the change's
    end until the estimate enters the band ``|m_hat - m| / m < band_pct %`` for good (until the
    next change or the end). Returns ``[{"t_s": change end (s after t0_s, default the first
    sample), "settle_s": ...}]``; ``settle_s`` is None when the estimate never settles."""
    t_s, m_hat, m = (np.asarray(a, dtype=float) for a in (t_s, m_hat, m))
    changing = np.flatnonzero(np.abs(np.diff(m)) > 1e-12 * np.abs(m[1:])) + 1
    if changing.size == 0:
        return []
    groups = np.split(changing, np.flatnonzero(np.diff(t_s[changing]) > gap_s) + 1)
    out = []
    for k, g in enumerate(groups):
        end = g[-1]
        stop = groups[k + 1][0] if k + 1 < len(groups) else len(t_s)
        bad = np.flatnonzero(np.abs(m_hat[end:stop] - m[end:stop]) >= band_pct / 100.0 * m[end:stop])
        if bad.size == 0:
            settle = 0.0
        elif end + bad[-1] + 1 < stop:
            settle = float(t_s[end + bad[-1] + 1] - t_s[end])
        else:
            settle = None
        out.append({"t_s": float(t_s[end] - (t_s[0] if t0_s is None else t0_s)), "settle_s": settle})
    return out


@dataclass
class MassResult:
    """Paired mass estimate and truth with their errors."""

    est: ScalarSeries
    gt: ScalarSeries
    t0_ns: Optional[int] = None  #: times in the summary are seconds after this (default: first pair)

    @property
    def err(self) -> np.ndarray:
        """m_hat - m [kg]."""
        return self.est.values - self.gt.values

    @property
    def rmspe(self) -> float:
        """RMSPE [%] (eq. 48)."""
        return rmspe(self.est.values, self.gt.values)

    @property
    def rmse(self) -> float:
        """RMSE [kg]."""
        return float(np.sqrt(np.mean(self.err ** 2)))

    def as_dict(self) -> dict:
        """JSON-friendly summary."""
        out = {"pairs": int(len(self.err)), "rmspe_percent": self.rmspe, "rmse_kg": self.rmse,
               "abs_err_kg": error_stats(np.abs(self.err)),
               "settle_5pct": settle_times((self.est.t_ns - self.est.t_ns[0]) * 1e-9, self.est.values,
                                           self.gt.values,
                                           t0_s=None if self.t0_ns is None else (self.t0_ns - self.est.t_ns[0]) * 1e-9)}
        if self.est.sigma is not None and np.all(self.est.sigma > 0):
            # NEES of a 1-dof state: in the 95 % band [0.00098, 5.02] 95 % of the time if consistent.
            nees = (self.err / self.est.sigma) ** 2
            out["nees_mean"] = float(np.mean(nees))
            out["nees_in_95pct_band"] = float(np.mean((nees > 0.000982) & (nees < 5.024)))
        return out
