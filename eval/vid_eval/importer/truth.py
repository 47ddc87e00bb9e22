"""What ``vid-eval mocap-truth FOLDER`` does on a dataset folder with IMU, thrust (or rotor
speeds and their coefficients) and mocap ground truth: measure the mocap clock offset and the
IMU-to-mocap-body rotation (sync.py), the thrust stream's offset against the accelerometer, and
derive the external-force truth force0 (force_truth.py); optionally write the corrections back.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np
from scipy.spatial.transform import Rotation

from ..bag2asl.extract import FORCE_HEADER, THRUST_HEADER
from ..errors import InputFormatError
from ..core.geometry import rot_from_wxyz, wxyz_from_rot
from ..tools.loaders import load_imu, load_rotor_speeds, load_vehicle, load_yaml_mapping
from ..tools.table_reader import read_table
from .force_truth import FORCE_CUTOFF_HZ, DragFit, ForceTruth, drag_fit, force_truth
from .sync import DEFAULT_MAX_LAG_S, GyroSync, Lag, gyro_mocap_sync, thrust_offset
from .writer import write_csv, write_gt

GT = "state_groundtruth_estimate0"


@dataclass
class Folder:
    """The streams of a dataset folder that the truth needs."""

    mav0: Path
    t_imu: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    t_thrust: np.ndarray
    thrust_n: np.ndarray
    thrust_from: str          # thrust0 | rotor0
    mass_kg: float
    gravity: float
    t_gt: np.ndarray
    p_W: np.ndarray
    q_WI: np.ndarray          # (N, 4) w, x, y, z
    v_W: np.ndarray


def _mav0(folder: Path) -> Path:
    mav0 = folder / "mav0" if (folder / "mav0").is_dir() else folder
    if not (mav0 / "imu0").is_dir():
        raise InputFormatError(folder, "not a dataset folder (no mav0/imu0)")
    return mav0


def load_folder(folder: Path) -> Folder:
    mav0 = _mav0(folder)
    imu = load_imu(mav0 / "imu0" / "data.csv")
    vehicle = load_vehicle(mav0 / "vehicle.yaml")
    if (mav0 / "thrust0" / "data.csv").is_file():
        tab = read_table(mav0 / "thrust0" / "data.csv", {2}, what="thrust0 CSV")
        t_thrust, thrust_n, source = tab.t_ns, tab.values[:, 0], "thrust0"
    elif (mav0 / "rotor0" / "data.csv").is_file():
        k = np.asarray(vehicle.rotor_thrust_coefficients)
        count = int(load_yaml_mapping(mav0 / "rotor0" / "sensor.yaml", "rotor0 sensor.yaml").get("count", 0)) or None
        tab = load_rotor_speeds(mav0 / "rotor0" / "data.csv", count)
        if k.size != tab.values.shape[1]:
            raise InputFormatError(vehicle.source, f"key 'rotor_thrust_coefficients': {k.size} values for "
                                                   f"{tab.values.shape[1]} rotors (the thrust needs them)")
        t_thrust, thrust_n, source = tab.t_ns, (tab.values ** 2) @ k, "rotor0"
    else:
        raise InputFormatError(mav0, "no thrust0/ or rotor0/: the force truth needs the thrust")
    gt = read_table(mav0 / GT / "data.csv", {17}, what="ground-truth CSV")
    v = gt.values
    return Folder(mav0, imu.t_ns, imu.gyro, imu.accel, t_thrust, thrust_n, source, vehicle.mass_kg,
                  vehicle.gravity, gt.t_ns, v[:, 0:3], v[:, 3:7], v[:, 7:10])


@dataclass
class TruthReport:
    gyro: GyroSync
    thrust: Lag
    thrust_plain: Lag
    thrust_scale: float
    drag_z: float
    force: ForceTruth
    drag: DragFit
    applied: List[str] = field(default_factory=list)

    def as_dict(self) -> Dict:
        rv = self.gyro.R_IM.as_rotvec(degrees=True)
        return {
            "mocap_minus_imu_s": self.gyro.lag.offset_s, "mocap_minus_imu_stderr_s": self.gyro.lag.stderr_s,
            "R_IM_angle_stderr_deg": self.gyro.angle_stderr_deg, "gyro_bias_rad_s": self.gyro.bias.tolist(),
            "thrust_minus_imu_stderr_s": self.thrust.stderr_s, "mocap_lag_coarse_s": self.gyro.lag.coarse_s,
            "gyro_mocap_correlation": self.gyro.lag.correlation,
            "R_IM_rotvec_deg": rv.tolist(), "R_IM_angle_deg": float(np.linalg.norm(rv)),
            "rate_residual_rms_rad_s": self.gyro.rms_rad_s,
            "thrust_minus_imu_s": self.thrust.offset_s, "thrust_fit_r2": self.thrust.correlation,
            "thrust_scale": self.thrust_scale, "thrust_fit_drag_z": self.drag_z,
            "thrust_minus_imu_plain_correlation_s": self.thrust_plain.offset_s,
            "force_samples": int(self.force.t_ns.size),
            "body_force_rms_m_s2": self.drag.rms.tolist(), "linear_drag_D": self.drag.D.tolist(),
            "linear_drag_explained": self.drag.explained.tolist(),
            "linear_drag_explained_all": self.drag.explained_all, "applied": self.applied,
        }


def _thrust_lag(f: Folder, gt_offset_s: float, R_IM: Rotation, max_lag_s: float):
    """Thrust stamps - IMU stamps from a_z ~ s T/m + b - D_z v_z (sync.thrust_offset; v_I from the
    mocap velocity, rotated into the IMU frame with R_IM unless already applied)."""
    R = rot_from_wxyz(f.q_WI)
    v_I = R_IM.apply(R.inv().apply(f.v_W))
    t_q = (f.t_imu - f.t_gt[0]).astype(float) + gt_offset_s * 1e9
    v_z = np.interp(t_q, (f.t_gt - f.t_gt[0]).astype(float), v_I[:, 2])
    off = thrust_offset(f.t_imu, f.accel[:, 2], f.t_thrust, f.thrust_n / f.mass_kg, v_z, max_lag_s)
    return off.fitted, off.plain, off.scale, off.drag_z


def synced_groundtruth(t_gt_ns: np.ndarray, q_WM_wxyz: np.ndarray, sync: GyroSync) -> Tuple[np.ndarray, np.ndarray]:
    """The ground truth in the IMU's clock and frame: stamps minus the mocap offset, orientation
    R_WI = R_WM R_IM^T (what ``--apply-sync`` writes and ``vid-import --sync`` uses)."""
    t_ns = t_gt_ns - int(round(sync.lag.offset_s * 1e9))
    return t_ns, wxyz_from_rot(rot_from_wxyz(q_WM_wxyz) * sync.R_IM.inv())


def applied_sync_line(sync: GyroSync) -> str:
    """The report line of an applied sync."""
    return f"{GT}: stamps {-sync.lag.offset_s * 1e3:+.3f} ms, orientation R_WI = R_WM R_IM^T"


def mocap_truth(folder: Path, cutoff_hz: float = FORCE_CUTOFF_HZ, max_lag_s: float = DEFAULT_MAX_LAG_S,
                apply_sync: bool = False, apply_thrust_lag: bool = False,
                force_out: Optional[Path] = None) -> TruthReport:
    """Measure, optionally correct, and write force0 (module docstring)."""
    f = load_folder(folder)
    if apply_thrust_lag and f.thrust_from != "thrust0":
        raise InputFormatError(f.mav0 / "rotor0", "--apply-thrust-lag rewrites thrust0 only (this folder has rotor0)")
    gyro = gyro_mocap_sync(f.t_imu, f.gyro, f.t_gt, f.q_WI, max_lag_s)
    applied = []
    gt_offset, R_IM = gyro.lag.offset_s, gyro.R_IM
    if apply_sync:
        f.t_gt, f.q_WI = synced_groundtruth(f.t_gt, f.q_WI, gyro)
        write_gt(f.mav0, f.t_gt, f.p_W, f.q_WI, f.v_W)
        applied.append(applied_sync_line(gyro))
        gt_offset, R_IM = 0.0, Rotation.identity()
    thrust, plain, scale, drag_z = _thrust_lag(f, gt_offset, R_IM, max_lag_s)
    if apply_thrust_lag:
        f.t_thrust = f.t_thrust - int(round(thrust.offset_s * 1e9))
        write_csv(f.mav0 / "thrust0" / "data.csv", THRUST_HEADER, f.t_thrust, f.thrust_n)
        applied.append(f"thrust0: stamps {-thrust.offset_s * 1e3:+.3f} ms")
    ft = force_truth(f.t_gt, f.p_W, f.q_WI, f.t_thrust, f.thrust_n, f.mass_kg, f.gravity, cutoff_hz)
    out = force_out or (f.mav0 / "force0" / "data.csv")
    write_csv(out, FORCE_HEADER, ft.t_ns, ft.F_W)
    return TruthReport(gyro, thrust, plain, scale, drag_z, ft, drag_fit(ft.F_I_per_m, ft.v_I), applied)


def gyro_sync_lines(g: GyroSync) -> List[str]:
    """The two lines of the mocap clock offset and the IMU-mocap rotation."""
    rv = g.R_IM.as_rotvec(degrees=True)
    return [
        f"mocap vs gyro: mocap stamps - IMU stamps = {g.lag.text()} "
        f"(best whole sample "
        f"{g.lag.coarse_s * 1e3:+.1f} ms; rate correlation {g.lag.correlation:.4f} over {g.lag.samples} samples)",
        f"IMU vs mocap body: rotation R_IM {np.linalg.norm(rv):.3f} +- {g.angle_stderr_deg:.3f} deg (rotation vector "
        f"[{rv[0]:+.3f}, {rv[1]:+.3f}, {rv[2]:+.3f}] deg; gyro bias fitted alongside [{g.bias[0]:+.4f}, "
        f"{g.bias[1]:+.4f}, {g.bias[2]:+.4f}] rad/s); rate residual RMS {g.rms_rad_s:.4f} rad/s",
    ]


def report_lines(r: TruthReport, cutoff_hz: float) -> List[str]:
    return [
        *gyro_sync_lines(r.gyro),
        f"thrust vs accelerometer z: thrust stamps - IMU stamps = {r.thrust.text()} "
        f"(fit a_z = s T/m + b - D_z v_z: s {r.thrust_scale:.4f}, D_z {r.drag_z:.3f} 1/s, R^2 {r.thrust.correlation:.4f}); "
        f"without the drag term {r.thrust_plain.offset_s * 1e3:+.3f} ms",
        *[f"applied: {a}" for a in r.applied],
        f"force0: {r.force.t_ns.size} samples, position low-pass {cutoff_hz:g} Hz; body force per unit mass RMS "
        f"x/y/z {r.drag.rms[0]:.3f} / {r.drag.rms[1]:.3f} / {r.drag.rms[2]:.3f} m/s^2",
        f"linear drag F_I/m = -D v_I: D x/y/z {r.drag.D[0]:.3f} / {r.drag.D[1]:.3f} / {r.drag.D[2]:.3f} 1/s, "
        f"explaining {100 * r.drag.explained[0]:.0f} / {100 * r.drag.explained[1]:.0f} / "
        f"{100 * r.drag.explained[2]:.0f} % of the force's power ({100 * r.drag.explained_all:.0f} % of all axes together)",
    ]
