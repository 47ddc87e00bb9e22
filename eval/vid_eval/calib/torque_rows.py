"""Rotational-dynamics rows for the per-rotor thrust fit.

The accelerometer sees only the collective thrust ``sum_i k_i n_i^2``: on a hover/step log the
four rotors rise and fall together and the per-rotor k_i are collinear. The gyroscope sees the
differential thrust. For a rigid body with rotors at ``p_i`` in the body plane, spin direction
``d_i`` (+1 counter-clockwise from above) and reaction torque ``c k_i n_i^2`` (c: torque-to-
thrust ratio [m]), Euler's equation is

    J w_dot + w x J w = sum_i k_i n_i^2 g_i,   g_i = p_i x e_z - d_i c e_z = (y_i, -x_i, -d_i c)

which is linear in the k_i. Integrated over a window [a, b] it needs no differentiated gyro:

    J (w_b - w_a) + int_a^b w x J w dt = sum_i k_i g_i int_a^b n_i^2 dt

Each window gives three rows (roll, pitch, yaw). In a steady hover they say that the torques
balance, which with the collective row fixes every k_i. The yaw row assumes one c for all
rotors; rotor inertia (spin-up reaction torque) and aerodynamic torques are not modelled.

The layout mirrors the simulator's (``dynamics::QuadrotorParams::symmetric_layout``): rotor i at
angle ``offset + 2 pi i / count`` (offset ``pi / count`` for ``x``, 0 for ``plus``), body x forward,
z up. The geometry file takes the simulator's ``vehicle:`` keys, so a scenario file is one.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from ..errors import InputFormatError
from ..tools.loaders import load_yaml_mapping

#: Window length of the integrated Euler equation [s]. Long enough that the gyro difference at
#: its ends is small next to the torque integral, short enough that hundreds fit in a log.
WINDOW_S = 0.25
#: Gyro samples averaged at each window end (the average of the rate is the rate at the centre
#: to second order; it divides the white gyro noise by sqrt of this).
END_SAMPLES = 8


@dataclass
class RotorGeometry:
    """What the torque rows need of the vehicle (keys of the simulator's ``vehicle:``)."""

    torque_matrix: np.ndarray   # (3, k): column i = g_i [m]
    inertia: np.ndarray         # (3, 3) [kg m^2]
    source: str = ""


def symmetric_torque_matrix(layout: str, arm_length_m: float, directions: list, torque_to_thrust_m: float,
                            count: int) -> np.ndarray:
    """Columns ``g_i`` of the module docstring for a symmetric ``x`` or ``plus`` layout."""
    offset = {"x": np.pi / count, "plus": 0.0}[layout]
    angle = offset + 2.0 * np.pi * np.arange(count) / count
    x, y = arm_length_m * np.cos(angle), arm_length_m * np.sin(angle)
    d = np.asarray(directions, dtype=float)
    return np.vstack([y, -x, -d * torque_to_thrust_m])


def load_geometry(path: Path, count: int) -> RotorGeometry:
    """A YAML file with ``layout`` (x or plus), ``arm_length_m``, ``rotor_directions``,
    ``torque_to_thrust_m`` and ``inertia_diag`` at the top level or under ``vehicle:`` (a
    simulator scenario file is accepted as it is)."""
    data = load_yaml_mapping(path, "geometry file")
    if isinstance(data.get("vehicle"), dict):
        data = data["vehicle"]

    def number(key: str) -> float:
        value = data.get(key)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
            raise InputFormatError(path, f"key '{key}': expected a positive number, got {value!r}")
        return float(value)

    layout = data.get("layout", "x")
    if layout not in ("x", "plus"):
        raise InputFormatError(path, f"key 'layout': expected x or plus, got {layout!r}")
    dirs = data.get("rotor_directions", [1 if i % 2 == 0 else -1 for i in range(count)])
    if not isinstance(dirs, list) or len(dirs) != count or any(d not in (1, -1) for d in dirs):
        raise InputFormatError(path, f"key 'rotor_directions': expected {count} entries of +1 or -1 "
                                     f"(one per rotor of rotor0), got {dirs!r}")
    inertia = data.get("inertia_diag")
    if (not isinstance(inertia, list) or len(inertia) != 3
            or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0 for v in inertia)):
        raise InputFormatError(path, f"key 'inertia_diag': expected three positive numbers [kg m^2], got {inertia!r}")
    g = symmetric_torque_matrix(layout, number("arm_length_m"), dirs, number("torque_to_thrust_m"), count)
    return RotorGeometry(g, np.diag(np.asarray(inertia, dtype=float)), str(path))


@dataclass
class TorqueRows:
    """Windows of the integrated Euler equation (module docstring)."""

    lhs: np.ndarray            # (W, 3) J (w_b - w_a) + int w x J w dt [N m s]
    speed_sq_int: np.ndarray   # (W, k) int n_i^2 dt [unit^2 s]
    torque_matrix: np.ndarray  # (3, k)

    def design(self) -> np.ndarray:
        """(3W, k): row 3w+a holds the coefficient of k_i in axis a of window w."""
        return np.einsum("ai,wi->wai", self.torque_matrix, self.speed_sq_int).reshape(-1, self.torque_matrix.shape[1])

    def target(self) -> np.ndarray:
        """(3W,) the measured side, in the order of :meth:`design`."""
        return self.lhs.reshape(-1)


def torque_rows(t_ns: np.ndarray, gyro: np.ndarray, speed_sq: np.ndarray, usable: np.ndarray,
                geometry: RotorGeometry, window_s: float = WINDOW_S) -> Optional[TorqueRows]:
    """Windows of ``window_s`` over consecutive IMU samples that are all ``usable`` (inside the
    rotor stream, with thrust); None when no window fits. ``speed_sq`` is n_i^2 at the IMU times
    (:func:`vid_eval.calib.thrust_fit.regressors`); the gyro bias cancels in the difference and
    is negligible in w x J w."""
    t = (t_ns - t_ns[0]) * 1e-9
    if len(t) < 2 * END_SAMPLES + 2:
        return None
    dt = float(np.median(np.diff(t)))
    step = max(int(round(window_s / dt)), 2 * END_SAMPLES)
    J = geometry.inertia
    gyroscopic = np.cross(gyro, gyro @ J.T)
    # Cumulative trapezoids: the integral over [a, b] is a difference of two entries.
    h = np.diff(t)[:, None]
    cum_sq = np.vstack([np.zeros((1, speed_sq.shape[1])), np.cumsum(0.5 * h * (speed_sq[1:] + speed_sq[:-1]), axis=0)])
    cum_gy = np.vstack([np.zeros((1, 3)), np.cumsum(0.5 * h * (gyroscopic[1:] + gyroscopic[:-1]), axis=0)])
    bad = np.concatenate([[0], np.cumsum(~usable)])  # bad[j] - bad[i] = unusable samples in [i, j)
    half = END_SAMPLES // 2
    lhs, sq = [], []
    for a in range(half, len(t) - step - half, step):
        b = a + step
        if bad[b + half + 1] - bad[a - half] > 0:
            continue
        w_a = gyro[a - half:a + half + 1].mean(axis=0)
        w_b = gyro[b - half:b + half + 1].mean(axis=0)
        lhs.append(J @ (w_b - w_a) + (cum_gy[b] - cum_gy[a]))
        sq.append(cum_sq[b] - cum_sq[a])
    if not lhs:
        return None
    return TorqueRows(np.asarray(lhs), np.asarray(sq), geometry.torque_matrix)
