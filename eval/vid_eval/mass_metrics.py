"""Mass-identification metrics: RMSPE (seed eq. 48) and RMSE.

``RMSPE = sqrt( (1/N) * sum_k ((m_hat_k - m_k) / m_k)^2 ) * 100 %``.
"""
from __future__ import annotations

from dataclasses import dataclass

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


@dataclass
class MassResult:
    """Paired mass estimate and truth with their errors."""

    est: ScalarSeries
    gt: ScalarSeries

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
        return {"pairs": int(len(self.err)), "rmspe_percent": self.rmspe, "rmse_kg": self.rmse,
                "abs_err_kg": error_stats(np.abs(self.err))}
