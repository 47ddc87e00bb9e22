"""Rotation helpers on Hamilton quaternions stored as (w, x, y, z) arrays.

Thin wrappers over scipy's Rotation so that the rest of the package never has to remember
scipy's (x, y, z, w) order.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation, Slerp


def rot_from_wxyz(q_wxyz: np.ndarray) -> Rotation:
    """Rotation(s) from Hamilton quaternions (w, x, y, z); normalizes."""
    q = np.atleast_2d(np.asarray(q_wxyz, dtype=float))
    return Rotation.from_quat(q[:, [1, 2, 3, 0]])


def wxyz_from_rot(rot: Rotation) -> np.ndarray:
    """Hamilton quaternions (w, x, y, z), sign chosen with w >= 0."""
    q = np.atleast_2d(rot.as_quat())[:, [3, 0, 1, 2]]
    q[q[:, 0] < 0] *= -1.0
    return q


def matrices_from_wxyz(q_wxyz: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotation matrices of (N, 4) quaternions (w, x, y, z)."""
    return rot_from_wxyz(q_wxyz).as_matrix().reshape(-1, 3, 3)


def rotation_angle(R: np.ndarray) -> np.ndarray:
    """Rotation angle [rad] of each (…, 3, 3) rotation matrix, robust near 0 and pi."""
    R = np.asarray(R, dtype=float).reshape(-1, 3, 3)
    return Rotation.from_matrix(R).magnitude()


def rot_z(yaw: float) -> np.ndarray:
    """Rotation matrix about the world z axis (gravity) by ``yaw`` [rad]."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def slerp_wxyz(t_src: np.ndarray, q_src: np.ndarray, t_query: np.ndarray) -> np.ndarray:
    """Spherical linear interpolation of quaternions (w, x, y, z) at ``t_query``.

    ``t_query`` must lie within ``[t_src[0], t_src[-1]]``. Times may be int64 ns; they are
    shifted to the first source time before conversion to float to keep precision.
    """
    t0 = t_src[0]
    src = (np.asarray(t_src) - t0).astype(float)
    qry = (np.asarray(t_query) - t0).astype(float)
    if len(src) == 1:
        return np.repeat(np.atleast_2d(q_src), len(qry), axis=0)
    slerp = Slerp(src, rot_from_wxyz(q_src))
    return wxyz_from_rot(slerp(qry))


def lerp(t_src: np.ndarray, x_src: np.ndarray, t_query: np.ndarray) -> np.ndarray:
    """Per-column linear interpolation of ``x_src`` (N, …) at ``t_query`` (int64 ns ok)."""
    t0 = t_src[0]
    src = (np.asarray(t_src) - t0).astype(float)
    qry = (np.asarray(t_query) - t0).astype(float)
    x = np.asarray(x_src, dtype=float)
    if x.ndim == 1:
        return np.interp(qry, src, x)
    return np.stack([np.interp(qry, src, x[:, j]) for j in range(x.shape[1])], axis=1)
