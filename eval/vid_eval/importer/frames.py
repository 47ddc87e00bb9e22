"""Axis maps from the log's frames to the project's (docs/design.md §3): world W z up (written
as ENU), IMU frame I = body frame, FLU (x forward, y left, z up).

* ``--imu-frame frd``: an FRD (z-down) IMU is turned into FLU by R_FLU_FRD = diag(1, -1, -1),
  applied to gyro, accelerometer and a thrust vector, and to the motion-capture body
  orientation: R_W_FLU = R_W_FRD diag(1, -1, -1) (the matrix is its own inverse).
* ``--world-frame``: positions, velocities and orientations of the mocap world are rotated into
  ENU: p_W = R_ENU_SRC p_SRC, R_WI = R_ENU_SRC R_SRC_I. NWU is z up already (a yaw of 90 deg);
  NED is turned over.

Then the checks: the median collective thrust and the median accelerometer z must point +z in
the IMU frame (a multirotor pushes itself up); a failure is one line saying what was found and
which flag fixes it.
"""
from __future__ import annotations

from typing import Optional

import numpy as np
from scipy.spatial.transform import Rotation

from .errors import DataError

R_FLU_FRD = np.diag([1.0, -1.0, -1.0])

#: R_ENU_SRC for each world frame the mocap may use (columns: the source axes in ENU).
WORLD_TO_ENU = {
    "enu": np.eye(3),
    "nwu": np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
    "ned": np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]),
}
IMU_TO_FLU = {"flu": np.eye(3), "frd": R_FLU_FRD}


def quat_to_xyzw(q: np.ndarray, order: str) -> np.ndarray:
    """(N, 4) quaternions in the map's order -> scipy's (x, y, z, w); zero norm is an error."""
    q = np.asarray(q, dtype=float)
    q = q[:, [1, 2, 3, 0]] if order == "wxyz" else q
    n = np.linalg.norm(q, axis=1)
    if (n < 1e-6).any():
        raise DataError(f"mocap quaternion row {int(np.flatnonzero(n < 1e-6)[0]) + 1} has zero norm")
    return q / n[:, None]


def imu_vectors(v_imu: np.ndarray, imu_frame: str) -> np.ndarray:
    """Body-frame vectors (gyro, accelerometer, thrust) of the log's IMU frame -> FLU."""
    return v_imu @ IMU_TO_FLU[imu_frame].T


def world_vectors(v_src: np.ndarray, world_frame: str) -> np.ndarray:
    """Mocap-world vectors (position, velocity) -> W (ENU)."""
    return v_src @ WORLD_TO_ENU[world_frame].T


def mocap_orientation(q_xyzw: np.ndarray, imu_frame: str, world_frame: str) -> Rotation:
    """R_WI in the project's frames from the mocap's R_SRC_BODY (BODY = the IMU's own frame)."""
    R_src = Rotation.from_quat(q_xyzw)
    return (Rotation.from_matrix(WORLD_TO_ENU[world_frame]) * R_src
            * Rotation.from_matrix(IMU_TO_FLU[imu_frame].T))


def other_imu_frame(imu_frame: str) -> str:
    return "frd" if imu_frame == "flu" else "flu"


def check_up(accel_flu: np.ndarray, thrust_z: Optional[np.ndarray], imu_frame: str,
             thrust_unit: str) -> None:
    """The median accelerometer z and (when given) the median collective thrust must be positive
    in the converted IMU frame; otherwise one line naming what was found and the fixing flag."""
    a_z = float(np.median(accel_flu[:, 2]))
    fix = f"--imu-frame {other_imu_frame(imu_frame)}"
    if thrust_z is not None:
        t_z = float(np.median(thrust_z))
        if not t_z > 0.0:
            if a_z < 0.0:
                raise DataError(f"thrust points down: median collective thrust {t_z:.3g} {thrust_unit} and median "
                                f"accelerometer z {a_z:.3g} m/s^2 along body z after --imu-frame {imu_frame}: "
                                f"the IMU is not {imu_frame.upper()} (pass {fix})")
            raise DataError(f"thrust points down: median collective thrust {t_z:.3g} {thrust_unit} along body z "
                            f"after --imu-frame {imu_frame}, while the accelerometer's median z is "
                            f"{a_z:.3g} m/s^2 (up): the thrust column has the opposite sign convention "
                            "(pass --negate-thrust)")
    if a_z < 0.0:
        raise DataError(f"the accelerometer points down: median z {a_z:.3g} m/s^2 after --imu-frame {imu_frame} "
                        f"(a vehicle at rest or flying measures about +9.8): pass {fix}")


def check_world(t_imu_ns: np.ndarray, accel_flu: np.ndarray, t_gt_ns: np.ndarray, R_WI: Rotation,
                world_frame: str) -> float:
    """The IMU's specific force rotated into W by the mocap orientation must average to about
    +g z (over a flight the mean acceleration is ~0). Returns the angle [deg] between that mean
    and +z; a mean pointing down is one line naming the flags that fix it."""
    idx = np.clip(np.searchsorted(t_imu_ns, t_gt_ns), 0, t_imu_ns.size - 1)
    inside = (t_gt_ns >= t_imu_ns[0]) & (t_gt_ns <= t_imu_ns[-1])
    mean = R_WI[inside].apply(accel_flu[idx[inside]]).mean(axis=0)
    angle = float(np.degrees(np.arccos(np.clip(mean[2] / np.linalg.norm(mean), -1.0, 1.0))))
    if mean[2] < 0.0:
        other = "enu" if world_frame == "ned" else "ned"
        raise DataError(f"gravity points up in the mocap world: the accelerometer rotated by the mocap orientation "
                        f"averages [{mean[0]:.3g}, {mean[1]:.3g}, {mean[2]:.3g}] m/s^2 after --world-frame "
                        f"{world_frame} (expected about +9.8 along z): the mocap world is not {world_frame.upper()} "
                        f"(pass --world-frame {other}), or the mocap body is not the IMU's frame")
    return angle
