"""Write the converted log as the dataset folder of docs/formats.md §1: imu0 (data.csv,
sensor.yaml), thrust0 or rotor0, vehicle.yaml, state_groundtruth_estimate0. Values are written
with the shortest text that reads back to the same float (exact round trips); headers are the
ones vid-bag2asl writes (one definition)."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional

import numpy as np
import yaml

from ..bag2asl.extract import GT_HEADER, IMU_HEADER, THRUST_HEADER
from ..bag2asl.sinks import fmt
from .errors import DataError

#: IMU noise written when no flag gives it: the EuRoC ADIS16448 values (sensor.yaml of EuRoC MAV).
DEFAULT_IMU_NOISE = {
    "gyroscope_noise_density": 1.6968e-4,      # rad/s/sqrt(Hz)
    "gyroscope_random_walk": 1.9393e-5,        # rad/s^2/sqrt(Hz)
    "accelerometer_noise_density": 2.0e-3,     # m/s^2/sqrt(Hz)
    "accelerometer_random_walk": 3.0e-3,       # m/s^3/sqrt(Hz)
}
DEFAULT_ROTOR_NOISE = 1.0  # rotor unit / sqrt(Hz)


@dataclass
class Imported:
    """A log in the project's frames, ready to write."""

    t_imu: np.ndarray              # (N,) int64 ns
    gyro: np.ndarray               # (N, 3) rad/s, I (FLU)
    accel: np.ndarray              # (N, 3) m/s^2, I
    mass_kg: float
    gravity: float
    imu_noise: Dict[str, float]
    t_thrust: Optional[np.ndarray] = None
    thrust_n: Optional[np.ndarray] = None        # (M,) collective thrust [N] along body z
    t_rotor: Optional[np.ndarray] = None
    rotor_speeds: Optional[np.ndarray] = None    # (M, k)
    rotor_unit: str = "rpm"
    rotor_noise: float = DEFAULT_ROTOR_NOISE
    rotor_coefficients: List[float] = field(default_factory=list)
    t_gt: Optional[np.ndarray] = None
    p_WI: Optional[np.ndarray] = None            # (K, 3) m, W (ENU)
    q_WI_wxyz: Optional[np.ndarray] = None       # (K, 4) Hamilton, w >= 0
    v_WI: Optional[np.ndarray] = None            # (K, 3) m/s, W


def rate_hz(t_ns: np.ndarray) -> float:
    """Rate measured from the stamps: (N - 1) / span."""
    if t_ns.size < 2 or t_ns[-1] == t_ns[0]:
        raise DataError(f"{t_ns.size} samples: cannot measure a rate")
    return (t_ns.size - 1) * 1e9 / float(t_ns[-1] - t_ns[0])


def write_csv(path: Path, header: str, t_ns: np.ndarray, values: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        values = values[:, None]
    with open(path, "w", encoding="utf-8") as f:
        f.write(header + "\n")
        for t, row in zip(t_ns.tolist(), values.tolist()):
            f.write(str(t) + "".join("," + fmt(v) for v in row) + "\n")


def _flow(value) -> str:
    """A YAML value in flow style; numbers as the shortest exact text."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_flow(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_flow(v) for v in value) + "]"
    if isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
        return fmt(value)
    return yaml.safe_dump(str(value), default_style=None).splitlines()[0]


def _yaml(path: Path, comment: str, doc: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    text = "".join(f"# {line}\n" for line in comment.splitlines())
    for key, value in doc.items():  # block style at the top, flow style inside (as EuRoC's files)
        text += f"{key}: {_flow(value)}\n"
    path.write_text(text, encoding="utf-8")


def write_dataset(out: Path, log: Imported, source: str) -> Dict[str, float]:
    """Write everything under ``out/mav0``; returns the measured rates by stream."""
    mav0 = out / "mav0"
    rates = {"imu0": rate_hz(log.t_imu)}
    write_csv(mav0 / "imu0" / "data.csv", IMU_HEADER, log.t_imu, np.hstack([log.gyro, log.accel]))
    imu_doc = {"sensor_type": "imu", "comment": f"written by vid-import from {source}",
               "T_BS": {"cols": 4, "rows": 4, "data": [float(x) for x in np.eye(4).reshape(-1)]},
               "rate_hz": round(rates["imu0"], 6), **{k: float(v) for k, v in log.imu_noise.items()}}
    _yaml(mav0 / "imu0" / "sensor.yaml", "imu0: rate measured from the stamps (vid-import)", imu_doc)
    if log.t_thrust is not None:
        rates["thrust0"] = rate_hz(log.t_thrust)
        write_csv(mav0 / "thrust0" / "data.csv", THRUST_HEADER, log.t_thrust, log.thrust_n)
    if log.t_rotor is not None:
        rates["rotor0"] = rate_hz(log.t_rotor)
        k = log.rotor_speeds.shape[1]
        write_csv(mav0 / "rotor0" / "data.csv", "#timestamp [ns]," + ",".join(f"n_{i + 1}" for i in range(k)),
                  log.t_rotor, log.rotor_speeds)
        _yaml(mav0 / "rotor0" / "sensor.yaml", "rotor speeds: count and rate measured (vid-import)",
              {"sensor_type": "rotor_speed", "unit": log.rotor_unit, "count": k,
               "rate_hz": round(rates["rotor0"], 6), "noise_density": float(log.rotor_noise)})
    vehicle = {"mass_kg": float(log.mass_kg), "gravity": float(log.gravity)}
    if log.rotor_coefficients:
        vehicle["rotor_thrust_coefficients"] = [float(c) for c in log.rotor_coefficients]
    _yaml(mav0 / "vehicle.yaml", "vehicle: written by vid-import (mass from --mass)", vehicle)
    if log.t_gt is not None:
        rates["state_groundtruth_estimate0"] = rate_hz(log.t_gt)
        write_gt(mav0, log.t_gt, log.p_WI, log.q_WI_wxyz, log.v_WI)
    return rates


def write_gt(mav0: Path, t_ns: np.ndarray, p: np.ndarray, q_wxyz: np.ndarray, v: np.ndarray) -> None:
    """state_groundtruth_estimate0/data.csv: pose, velocity; biases 0 (mocap cannot know them)."""
    rows = np.hstack([p, q_wxyz, v, np.zeros((t_ns.size, 6))])
    write_csv(mav0 / "state_groundtruth_estimate0" / "data.csv", GT_HEADER, t_ns, rows)
