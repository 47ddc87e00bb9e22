"""Trajectory alignment: Umeyama (SE(3) / Sim(3)) and 4-DoF position+yaw, in closed form.

An alignment is ``p_gt ~ s * R @ p_est + t`` (and ``R_gt ~ R @ R_est``). It is estimated from
the first ``n`` associated positions (all when ``n`` is None or <= 0).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..errors import VidEvalError

ALIGN_MODES = ("posyaw", "se3", "sim3", "none")


class AlignmentError(VidEvalError):
    """Too few or degenerate points for the requested alignment."""


@dataclass
class Alignment:
    """Similarity transform ``x -> s R x + t`` applied to the estimate."""

    R: np.ndarray = field(default_factory=lambda: np.eye(3))
    t: np.ndarray = field(default_factory=lambda: np.zeros(3))
    s: float = 1.0
    mode: str = "none"

    def apply_positions(self, p: np.ndarray) -> np.ndarray:
        """Transform (N, 3) positions."""
        return self.s * p @ self.R.T + self.t

    def apply_rotations(self, R: np.ndarray) -> np.ndarray:
        """Left-multiply (N, 3, 3) orientations R_WI by the alignment rotation."""
        return np.einsum("ij,njk->nik", self.R, R)

    @property
    def yaw_deg(self) -> float:
        """Yaw of R about z [deg] (exact for posyaw, informative otherwise)."""
        return float(np.degrees(np.arctan2(self.R[1, 0], self.R[0, 0])))

    def as_dict(self) -> dict:
        """JSON-friendly representation."""
        return {"mode": self.mode, "R": self.R.tolist(), "t": self.t.tolist(), "s": self.s,
                "yaw_deg": self.yaw_deg}


def _first(p: np.ndarray, n: Optional[int]) -> np.ndarray:
    return p if n is None or n <= 0 else p[: min(n, len(p))]


def umeyama(src: np.ndarray, dst: np.ndarray, with_scale: bool) -> Alignment:
    """Least-squares ``dst ~ s R src + t`` (Umeyama 1991) for (N, 3) point sets.

    Raises:
        AlignmentError: for fewer than 3 points or a rank-deficient cross-covariance.
    """
    n = len(src)
    if n < 3:
        raise AlignmentError(f"Umeyama alignment needs >= 3 associated poses, got {n}")
    mu_s, mu_d = src.mean(axis=0), dst.mean(axis=0)
    xs, xd = src - mu_s, dst - mu_d
    cov = xd.T @ xs / n
    U, d, Vt = np.linalg.svd(cov)
    if np.count_nonzero(d > np.finfo(float).eps) < 2:
        raise AlignmentError("degenerate point set (all poses on a line or a point): "
                             "Umeyama alignment is not possible")
    S = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0.0:
        S[2, 2] = -1.0
    R = U @ S @ Vt
    var_s = np.sum(xs * xs) / n
    s = float(np.trace(np.diag(d) @ S) / var_s) if with_scale else 1.0
    t = mu_d - s * R @ mu_s
    return Alignment(R, t, s, "sim3" if with_scale else "se3")


def posyaw(src: np.ndarray, dst: np.ndarray) -> Alignment:
    """4-DoF alignment ``dst ~ Rz(yaw) src + t`` (rotation about gravity only), closed form.

    With centred points a = src - mean, b = dst - mean, the cost is minimised by
    ``yaw = atan2(sum(a_x b_y - a_y b_x), sum(a_x b_x + a_y b_y))`` and
    ``t = mean(dst) - Rz(yaw) mean(src)``.

    Raises:
        AlignmentError: for no points. With one point (or no horizontal spread) the yaw
        is unobservable and set to 0 (translation only).
    """
    if len(src) == 0:
        raise AlignmentError("posyaw alignment needs >= 1 associated pose")
    mu_s, mu_d = src.mean(axis=0), dst.mean(axis=0)
    a, b = src - mu_s, dst - mu_d
    num = float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))
    den = float(np.sum(a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]))
    yaw = float(np.arctan2(num, den)) if (num != 0.0 or den != 0.0) else 0.0
    c, s_ = np.cos(yaw), np.sin(yaw)
    R = np.array([[c, -s_, 0.0], [s_, c, 0.0], [0.0, 0.0, 1.0]])
    return Alignment(R, mu_d - R @ mu_s, 1.0, "posyaw")


def align(p_est: np.ndarray, p_gt: np.ndarray, mode: str, n: Optional[int] = None) -> Alignment:
    """Estimate the alignment ``mode`` from the first ``n`` associated position pairs."""
    if mode == "none":
        return Alignment(mode="none")
    src, dst = _first(p_est, n), _first(p_gt, n)
    if mode == "posyaw":
        return posyaw(src, dst)
    if mode in ("se3", "sim3"):
        return umeyama(src, dst, with_scale=(mode == "sim3"))
    raise ValueError(f"unknown alignment '{mode}' (choose from {', '.join(ALIGN_MODES)})")
