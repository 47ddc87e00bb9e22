"""The streams of one dataset folder (docs/formats.md §1) that the calibration tools read,
through the package's one set of loaders (:mod:`vid_eval.tools.loaders`)."""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import numpy as np

from ..core import formats
from ..errors import ConfigurationError, InputFormatError
from ..core.geometry import matrices_from_wxyz
from ..tools.loaders import ImuSeries, Vehicle, load_force_gt, load_imu, load_rotor_speeds, load_vehicle, load_yaml_mapping
from ..tools.table_reader import Table, read_table


def find_mav0(dataset: os.PathLike) -> Path:
    """``DATASET/mav0`` (or DATASET itself when it is the mav0 folder); an error otherwise."""
    root = Path(dataset)
    for cand in (root / "mav0", root):
        if (cand / "imu0" / "data.csv").is_file():
            return cand
    if not root.exists():
        raise InputFormatError(root, "no such dataset folder")
    raise InputFormatError(root, "not a dataset folder (no mav0/imu0/data.csv)")


def imu(mav0: Path) -> ImuSeries:
    """``imu0/data.csv``."""
    return load_imu(mav0 / "imu0" / "data.csv")


def rotor_unit_and_count(mav0: Path) -> tuple[str, Optional[int]]:
    """``unit`` and ``count`` of ``rotor0/sensor.yaml`` (``"unit"`` / None without the file)."""
    path = mav0 / "rotor0" / "sensor.yaml"
    if not path.is_file():
        return "unit", None
    data = load_yaml_mapping(path, "rotor0/sensor.yaml")
    unit = data.get("unit", "unit")
    if unit not in ("rpm", "rad/s"):
        raise InputFormatError(path, f"key 'unit': expected rpm or rad/s, got '{unit}'")
    count = data.get("count")
    if count is not None and (isinstance(count, bool) or not isinstance(count, int) or count < 1):
        raise InputFormatError(path, f"key 'count': expected a positive integer, got '{count}'")
    return unit, count


def rotor_speeds(mav0: Path) -> tuple[Table, str]:
    """``rotor0/data.csv`` and the speed unit."""
    path = mav0 / "rotor0" / "data.csv"
    unit, count = rotor_unit_and_count(mav0)
    return load_rotor_speeds(path, count), unit


@dataclass
class ThrustStream:
    """What the thrust fit regresses on: rotor speeds (``rotor0``, squared in the fit) or a
    measured collective thrust (``thrust0``, N, one column)."""

    t_ns: np.ndarray
    values: np.ndarray   # (N, k) rotor speeds, or (N, 1) thrust [N]
    unit: str            # rpm | rad/s | unit (rotor0), N (thrust0)
    kind: str            # rotor0 | thrust0
    path: str

    @property
    def squared(self) -> bool:
        """The fit's regressors are the squared values (rotor speeds), not the values."""
        return self.kind == "rotor0"


SOURCES = ("auto", "rotor0", "thrust0")


def thrust_stream(mav0: Path, source: str = "auto") -> ThrustStream:
    """``rotor0`` (``auto``: when present) or ``thrust0``; an error naming the folder without either."""
    has_rotor, has_thrust = (mav0 / "rotor0" / "data.csv").is_file(), (mav0 / "thrust0" / "data.csv").is_file()
    if source == "thrust0" or (source == "auto" and has_thrust and not has_rotor):
        path = mav0 / "thrust0" / "data.csv"
        if not has_thrust:
            raise InputFormatError(path, "no measured thrust in this dataset")
        tab = read_table(path, {2}, what="thrust0 CSV")
        return ThrustStream(tab.t_ns, tab.values[:, :1], "N", "thrust0", tab.path)
    if not has_rotor:
        raise InputFormatError(mav0 / "rotor0" / "data.csv", "no rotor speeds" + (
            "" if source == "rotor0" else " and no thrust0/data.csv in this dataset: nothing to fit"))
    tab, unit = rotor_speeds(mav0)
    return ThrustStream(tab.t_ns, tab.values, unit, "rotor0", tab.path)


def vehicle(mav0: Path, mass_flag: Optional[float]) -> tuple[Optional[Vehicle], float, str]:
    """(vehicle.yaml or None, the mass to use, where the mass came from). ``mav0/vehicle.yaml``
    or the folder above it; ``--mass`` overrides."""
    path = next((p for p in (mav0 / "vehicle.yaml", mav0.parent / "vehicle.yaml") if p.is_file()), None)
    veh = load_vehicle(path) if path is not None else None
    if mass_flag is not None:
        return veh, mass_flag, "--mass"
    if veh is None:
        raise ConfigurationError(f"{mav0}: no vehicle.yaml for the mass (pass --mass KG)")
    return veh, veh.mass_kg, str(path)


def groundtruth(mav0: Path) -> Optional[Table]:
    """``state_groundtruth_estimate0/data.csv`` with all 17 EuRoC columns, or None."""
    path = mav0 / "state_groundtruth_estimate0" / "data.csv"
    if not path.is_file():
        return None
    return read_table(path, range(formats.EUROC_GT_MIN_COLUMNS, 200), what="EuRoC ground truth CSV")


def groundtruth_accel_bias_z(gt: Table, t_ns: np.ndarray) -> np.ndarray:
    """Ground-truth accelerometer bias along body z at ``t_ns`` (EuRoC column b_a_RS_S_z)."""
    if gt.values.shape[1] + 1 < formats.EUROC_GT_COLUMNS:
        raise InputFormatError(gt.path, f"ground truth has {gt.values.shape[1] + 1} columns: no accelerometer "
                                        f"bias (needs {formats.EUROC_GT_COLUMNS}); use --bias fit")
    return np.interp((t_ns - gt.t_ns[0]).astype(float), (gt.t_ns - gt.t_ns[0]).astype(float),
                     gt.values[:, formats.EUROC_GT_COLUMNS - 2])


def external_force_I(mav0: Path, gt: Optional[Table], t_ns: np.ndarray, mass_kg: float) -> Optional[np.ndarray]:
    """(N, 3) external force per mass in the IMU frame [m/s^2] from ``force0`` (world, N) rotated
    with the ground-truth attitude, at ``t_ns``; None without force0 or ground truth."""
    path = mav0 / "force0" / "data.csv"
    if not path.is_file() or gt is None:
        return None
    force = load_force_gt(path)
    t0 = force.t_ns[0]
    f_w = np.stack([np.interp((t_ns - t0).astype(float), (force.t_ns - t0).astype(float), force.values[:, j])
                    for j in range(3)], axis=1)
    tg = (gt.t_ns - t0).astype(float)
    ti = (t_ns - t0).astype(float)
    # The attitude of the nearest ground-truth sample (200 Hz): enough for a force in N.
    idx = np.clip(np.searchsorted(tg, ti), 0, len(tg) - 1)
    R_WI = matrices_from_wxyz(gt.values[idx, 3:7])
    return np.einsum("nij,ni->nj", R_WI, f_w) / mass_kg
