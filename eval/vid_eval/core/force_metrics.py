"""External-force error metrics: RMSE per axis and of the error norm, in m/s^2 (and N).

``rmse_norm = sqrt(mean ||f_est - f_gt||^2)`` is the headline "force RMSE" (the seed's
tables). ``rmse_magnitude`` is the RMSE of ``||f_est|| - ||f_gt||``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .series import VectorSeries


@dataclass
class ForceResult:
    """Errors of paired force series in one frame, m/s^2 (and N when ``mass_kg`` given)."""

    est: VectorSeries
    gt: VectorSeries
    err: np.ndarray  # (N, 3) est - gt [m/s^2]
    mass_kg: Optional[np.ndarray] = None  # (N,) mass used for the N conversion

    @property
    def rmse_axis(self) -> np.ndarray:
        """RMSE per axis [m/s^2]."""
        return np.sqrt(np.mean(self.err ** 2, axis=0))

    @property
    def rmse_norm(self) -> float:
        """sqrt(mean ||e||^2) [m/s^2]."""
        return float(np.sqrt(np.mean(np.sum(self.err ** 2, axis=1))))

    @property
    def rmse_magnitude(self) -> float:
        """RMSE of the difference of the force magnitudes [m/s^2]."""
        d = np.linalg.norm(self.est.values, axis=1) - np.linalg.norm(self.gt.values, axis=1)
        return float(np.sqrt(np.mean(d ** 2)))

    def within_3sigma(self) -> Optional[float]:
        """Fraction of axis samples whose error is inside +-3 sigma (None without sigma)."""
        if self.est.sigma is None:
            return None
        return float(np.mean(np.abs(self.err) <= 3.0 * self.est.sigma))

    def as_dict(self) -> dict:
        """JSON-friendly summary."""
        out = {
            "frame": self.est.frame,
            "pairs": int(len(self.err)),
            "rmse_mps2": {"x": float(self.rmse_axis[0]), "y": float(self.rmse_axis[1]),
                          "z": float(self.rmse_axis[2]), "norm": self.rmse_norm,
                          "magnitude": self.rmse_magnitude},
        }
        if self.mass_kg is not None:
            e_n = self.err * self.mass_kg[:, None]
            ax = np.sqrt(np.mean(e_n ** 2, axis=0))
            out["rmse_N"] = {"x": float(ax[0]), "y": float(ax[1]), "z": float(ax[2]),
                             "norm": float(np.sqrt(np.mean(np.sum(e_n ** 2, axis=1))))}
            out["mass_kg_mean"] = float(np.mean(self.mass_kg))
        frac = self.within_3sigma()
        if frac is not None:
            out["fraction_within_3sigma"] = frac
        return out


def force_errors(est: VectorSeries, gt: VectorSeries,
                 mass_kg: Optional[np.ndarray] = None) -> ForceResult:
    """Errors of paired series (same length, same frame, both m/s^2)."""
    if len(est) != len(gt):
        raise ValueError("force series must be paired (equal length)")
    if est.frame != gt.frame or est.unit != "m/s^2" or gt.unit != "m/s^2":
        raise ValueError(f"compare like with like: est {est.frame} {est.unit}, gt {gt.frame} {gt.unit}")
    return ForceResult(est, gt, est.values - gt.values, mass_kg)
