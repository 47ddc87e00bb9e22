"""Loaders of every file format the evaluation reads (docs/formats.md §1 and §5, TUM, EuRoC).

Each loader returns a typed series from :mod:`vid_eval.core.series` or raises
:class:`~vid_eval.errors.InputFormatError` naming file and line.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import List, Optional

import numpy as np
import yaml

from ..core import formats
from ..errors import InputFormatError, PathLike
from ..core.series import NeesCurves, ScalarSeries, StateSeries, Trajectory, VectorSeries
from .table_reader import Table, not_utf8, parse_time, read_table

TRAJ_FORMATS = ("tum", "euroc", "state")


def _quaternions(table: Table, q_wxyz: np.ndarray) -> np.ndarray:
    """Normalize quaternions; a (near) zero quaternion is an input error."""
    norms = np.linalg.norm(q_wxyz, axis=1)
    bad = np.flatnonzero(norms < 1e-6)
    if bad.size:
        raise InputFormatError(table.path, "quaternion has zero norm", int(table.lines[bad[0]]))
    return q_wxyz / norms[:, None]


def load_tum(path: PathLike) -> Trajectory:
    """TUM file ``timestamp[s] tx ty tz qx qy qz qw`` (whitespace separated)."""
    tab = read_table(path, {formats.TUM_COLUMNS}, delimiter=None, time_in_seconds=True,
                     what="TUM trajectory")
    v = tab.values
    q = _quaternions(tab, v[:, [6, 3, 4, 5]])
    return Trajectory(tab.t_ns, v[:, 0:3].copy(), q, tab.path, time_unit="s")


#: vid_run's marker of a re-initialization in a TUM trajectory (system/include/vid_system/outputs.h,
#: kTumReinitMarker): "# re-initialized at <t [s]>: a new world frame from here on".
REINIT_MARKER = "# re-initialized at"


def reinit_marks(path: PathLike) -> np.ndarray:
    """Times [ns] of the re-initialization markers in a trajectory file (docs/notes/recovery.md):
    from each on, the estimate is in a new world frame. Empty for other files."""
    spath = os.fspath(path)
    marks: List[int] = []
    with open(spath, "r", encoding="utf-8", errors="replace") as handle:
        for lineno, raw in enumerate(handle, start=1):
            if raw.startswith(REINIT_MARKER):
                token = raw[len(REINIT_MARKER):].split(":")[0].strip()
                marks.append(parse_time(token, True, spath, lineno, "re-initialization marker"))
    return np.asarray(marks, dtype=np.int64)


def load_euroc_pose_csv(path: PathLike) -> Trajectory:
    """EuRoC ``state_groundtruth_estimate0/data.csv`` (17 columns) or a plain ASL pose CSV
    (``timestamp [ns], p_x, p_y, p_z, q_w, q_x, q_y, q_z``); extra columns are ignored."""
    tab = read_table(path, range(formats.EUROC_GT_MIN_COLUMNS, 200), what="EuRoC pose CSV")
    v = tab.values
    q = _quaternions(tab, v[:, 3:7])
    return Trajectory(tab.t_ns, v[:, 0:3].copy(), q, tab.path)


def load_state(path: PathLike) -> StateSeries:
    """Our ``state.csv`` (docs/formats.md §2, columns in :data:`vid_eval.core.formats.STATE_COLUMNS`)."""
    names = [n for n, _ in formats.STATE_COLUMNS]
    tab = read_table(path, {len(names)}, expected_names=names, what="state.csv")
    v = tab.values
    idx = {n: formats.column_index(formats.STATE_COLUMNS, n) - 1 for n in names[1:]}

    def cols(prefix: str) -> np.ndarray:
        return v[:, [idx[f"{prefix}_{a}"] for a in "xyz"]].copy()

    q = _quaternions(tab, v[:, [idx["q_w"], idx["q_x"], idx["q_y"], idx["q_z"]]])
    sigma = {k: cols(f"sigma_{k}") for k in ("theta", "p", "v", "bg", "ba", "f")}
    return StateSeries(tab.t_ns, cols("p"), q, cols("v"), cols("bg"), cols("ba"), cols("f"),
                       sigma, tab.path)


def dataset_first_time_ns(folder: PathLike) -> int:
    """The earliest first stamp over a dataset folder's ``mav0/*/data.csv`` streams: the origin
    of ``vid_run --start`` / ``--end`` (docs/formats.md section 1)."""
    t = None
    for csv in sorted((Path(folder) / "mav0").glob("*/data.csv")):
        with open(csv, encoding="utf-8") as f:
            for line in f:
                if line.strip() and not line.startswith("#"):
                    v = int(line.split(",")[0])
                    t = v if t is None else min(t, v)
                    break
    if t is None:
        raise InputFormatError(folder, "no mav0/*/data.csv with a data row")
    return t


def load_trajectory(path: PathLike, fmt: Optional[str] = None) -> Trajectory:
    """Load a trajectory in ``tum``, ``euroc`` (EuRoC/ASL CSV) or ``state`` format;
    ``fmt=None`` detects it (see :func:`detect_trajectory_format`)."""
    fmt = fmt or detect_trajectory_format(path)
    if fmt == "tum":
        return load_tum(path)
    if fmt == "euroc":
        return load_euroc_pose_csv(path)
    if fmt == "state":
        return load_state(path).trajectory()
    raise ValueError(f"unknown trajectory format '{fmt}' (choose from {', '.join(TRAJ_FORMATS)})")


def detect_trajectory_format(path: PathLike) -> str:
    """Guess the format from the first data line: whitespace -> tum; a header naming the
    state.csv columns -> state; otherwise comma separated -> euroc."""
    spath = os.fspath(path)
    if not os.path.isfile(spath):
        raise InputFormatError(spath, "no such trajectory file")
    header = None
    try:
        with open(spath, "r", encoding="utf-8") as handle:
            for raw in handle:
                text = raw.strip()
                if not text:
                    continue
                if text.startswith("#"):
                    header = header or text
                    continue
                if "," not in text:
                    return "tum"
                break
    except UnicodeDecodeError:
        raise not_utf8(spath, "trajectory") from None
    if header is not None and formats.header_names(header)[:2] == ["timestamp", "p_x"] and \
            "sigma_f_x" in formats.header_names(header):
        return "state"
    if header is None and spath.endswith(".txt"):
        return "tum"
    return "euroc"


def load_force_estimate(path: PathLike) -> tuple[VectorSeries, VectorSeries]:
    """Our ``force.csv``: returns (body series with sigma, world series without sigma),
    both in m/s^2."""
    names = [n for n, _ in formats.FORCE_COLUMNS]
    tab = read_table(path, {len(names)}, expected_names=names, what="force.csv")
    v = tab.values
    body = VectorSeries(tab.t_ns, v[:, 0:3].copy(), "body", "m/s^2", v[:, 6:9].copy(), tab.path)
    world = VectorSeries(tab.t_ns, v[:, 3:6].copy(), "world", "m/s^2", None, tab.path)
    return body, world


def load_force_gt(path: PathLike) -> VectorSeries:
    """Ground-truth ``force0/data.csv``: world frame, Newton. Files with the three force-rate
    columns (7 columns) load too; the rate is not part of the returned series."""
    n = len(formats.FORCE0_COLUMNS)
    tab = read_table(path, {n, n + len(formats.FORCE0_RATE_COLUMNS)}, what="force0 CSV")
    return VectorSeries(tab.t_ns, tab.values[:, : n - 1].copy(), "world", "N", None, tab.path)


def load_mass(path: PathLike) -> ScalarSeries:
    """``mass0/data.csv`` (``timestamp [ns], mass [kg]``) or a mass estimate with an optional
    third column ``sigma [kg]``."""
    tab = read_table(path, {2, 3}, what="mass CSV")
    v = tab.values
    bad = np.flatnonzero(v[:, 0] <= 0.0)
    if bad.size:
        raise InputFormatError(tab.path, "mass must be positive", int(tab.lines[bad[0]]))
    sigma = v[:, 1].copy() if v.shape[1] == 2 else None
    return ScalarSeries(tab.t_ns, v[:, 0].copy(), sigma, tab.path)


def load_phases(path: PathLike) -> ScalarSeries:
    """Ground-truth ``phase0/data.csv`` (``#timestamp [ns],phase``): 0 on the ground,
    1 airborne, at strictly increasing times; any other value names file, line and column."""
    names = [n for n, _ in formats.PHASE0_COLUMNS]
    tab = read_table(path, {len(names)}, expected_names=names, what="phase0 CSV")
    v = tab.values[:, 0]
    bad = np.flatnonzero((v != formats.PHASE_ON_GROUND) & (v != formats.PHASE_AIRBORNE))
    if bad.size:
        raise InputFormatError(tab.path, f"phase0 CSV: column 2 'phase': expected "
                                         f"{formats.PHASE_ON_GROUND} (on the ground) or "
                                         f"{formats.PHASE_AIRBORNE} (airborne), got {v[bad[0]]:g}",
                               int(tab.lines[bad[0]]))
    return ScalarSeries(tab.t_ns, v.astype(np.int64), None, tab.path)


def find_phases(gt_path: PathLike) -> Optional[Path]:
    """``mav0/phase0/data.csv`` of the dataset whose ground-truth file (``mav0/<stream>/data.csv``)
    is ``gt_path``, or None."""
    cand = Path(gt_path).resolve().parent.parent / "phase0" / "data.csv"
    return cand if cand.is_file() else None


def load_yaml_mapping(path: PathLike, what: str) -> dict:
    """A YAML file whose root is a mapping (``%YAML:1.0`` first lines accepted, as OpenCV and
    Kalibr write them); every failure names the file (and line)."""
    spath = os.fspath(path)
    try:
        with open(spath, "r", encoding="utf-8") as handle:
            text = handle.read()
    except OSError as exc:
        raise InputFormatError(spath, f"cannot open: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise not_utf8(spath, what) from None
    if text.startswith("%YAML"):
        text = text.split("\n", 1)[1] if "\n" in text else ""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        line = getattr(getattr(exc, "problem_mark", None), "line", None)
        raise InputFormatError(spath, "invalid YAML", None if line is None else line + 1) from None
    except ValueError as exc:  # a value PyYAML resolves but cannot build, e.g. date 2001-13-01
        raise InputFormatError(spath, f"invalid YAML value ({exc})") from None
    except RecursionError:  # PyYAML composes nested collections recursively
        raise InputFormatError(spath, "invalid YAML (nested too deeply)") from None
    return data if isinstance(data, dict) else {}


def yaml_number(data: dict, key: str, path: PathLike, positive: bool = False) -> float:
    """``data[key]`` as a finite float; a missing or non-numeric value names file and key."""
    if key not in data:
        raise InputFormatError(path, f"key '{key}' missing")
    value = data[key]
    try:
        if isinstance(value, bool):
            raise TypeError
        number = float(value)
    except (TypeError, ValueError, OverflowError):  # OverflowError: an integer beyond float
        raise InputFormatError(path, f"key '{key}' is not a number") from None
    if not np.isfinite(number) or (positive and not number > 0.0):
        raise InputFormatError(path, f"key '{key}' must be " + ("positive" if positive else "finite"))
    return number


@dataclass
class Vehicle:
    """``vehicle.yaml`` (docs/formats.md §1): mass, gravity magnitude, k_i [N/unit^2]."""

    mass_kg: float
    gravity: float
    rotor_thrust_coefficients: List[float]
    source: str = ""


def load_vehicle(path: PathLike) -> Vehicle:
    """``vehicle.yaml``: ``mass_kg`` required; ``gravity`` (default 9.81) and
    ``rotor_thrust_coefficients`` (default none) optional."""
    spath = os.fspath(path)
    data = load_yaml_mapping(spath, "vehicle.yaml")
    mass = yaml_number(data, "mass_kg", spath, positive=True)
    gravity = yaml_number(data, "gravity", spath, positive=True) if "gravity" in data else 9.81
    coeffs = data.get("rotor_thrust_coefficients") or []
    if not isinstance(coeffs, list) or not all(
            isinstance(c, (int, float)) and not isinstance(c, bool) and np.isfinite(c) for c in coeffs):
        raise InputFormatError(spath, "key 'rotor_thrust_coefficients' is not a list of numbers")
    return Vehicle(mass, gravity, [float(c) for c in coeffs], spath)


def load_vehicle_mass(path: PathLike) -> float:
    """``mass_kg`` of a ``vehicle.yaml`` (docs/formats.md §1)."""
    spath = os.fspath(path)
    return yaml_number(load_yaml_mapping(spath, "vehicle.yaml"), "mass_kg", spath, positive=True)


@dataclass
class ImuSeries:
    """``imu0/data.csv``: gyroscope (N, 3) [rad/s] and accelerometer (N, 3) [m/s^2] in I."""

    t_ns: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    source: str = ""


def load_imu(path: PathLike) -> ImuSeries:
    """EuRoC ``imu0/data.csv`` (7 columns, :data:`vid_eval.core.formats.IMU0_COLUMNS`)."""
    names = [n for n, _ in formats.IMU0_COLUMNS]
    tab = read_table(path, {len(names)}, expected_names=names, what="imu0 CSV")
    return ImuSeries(tab.t_ns, tab.values[:, 0:3].copy(), tab.values[:, 3:6].copy(), tab.path)


def load_rotor_speeds(path: PathLike, count: Optional[int] = None) -> Table:
    """``rotor0/data.csv``: one speed column per rotor (``count`` of them when given, the
    rotor0/sensor.yaml ``count``), speeds must not be negative."""
    allowed = {count + 1} if count else range(2, formats.ROTOR0_MAX_ROTORS + 2)
    tab = read_table(path, allowed, what="rotor0 CSV")
    neg = np.argwhere(tab.values < 0.0)
    if neg.size:
        row, col = neg[0]
        raise InputFormatError(tab.path, f"rotor0 CSV: column {col + 2}: negative rotor speed "
                                         f"{tab.values[row, col]:g}", int(tab.lines[row]))
    return tab


def find_mass_source(force_gt_path: PathLike) -> Optional[Path]:
    """Next to ``SEQ/mav0/force0/data.csv`` look for ``mav0/mass0/data.csv``, then
    ``mav0/vehicle.yaml``, then ``SEQ/vehicle.yaml``; return the first that exists."""
    mav0 = Path(force_gt_path).resolve().parent.parent
    for cand in (mav0 / "mass0" / "data.csv", mav0 / "vehicle.yaml", mav0.parent / "vehicle.yaml"):
        if cand.is_file():
            return cand
    return None


def load_nees(path: PathLike) -> NeesCurves:
    """A NEES Monte-Carlo CSV (:data:`formats.NEES_COLUMNS`): the run-averaged NEES of
    orientation, position and F_ext over time, with the run count and the 95 % band."""
    names = [n for n, _ in formats.NEES_COLUMNS]
    tab = read_table(path, {len(names)}, time_in_seconds=True, expected_names=names, what="NEES CSV")
    meta = {}
    with open(tab.path, encoding="utf-8") as fh:
        for lineno, raw in enumerate(fh, start=1):
            if raw.startswith("#") and "runs=" in raw:
                try:
                    meta = {k: float(v) for k, v in (kv.split("=", 1) for kv in raw[1:].split())}
                except ValueError:
                    raise InputFormatError(tab.path, "NEES CSV: expected '# runs=N band_lo=L "
                                                     "band_hi=H'", lineno) from None
                break
    missing = [k for k in ("runs", "band_lo", "band_hi") if k not in meta]
    if missing:
        raise InputFormatError(tab.path, f"NEES CSV: no {', '.join(missing)} in a "
                                         "'# runs=N band_lo=L band_hi=H' line")
    if not (meta["runs"] >= 1 and 0 <= meta["band_lo"] < meta["band_hi"]):
        raise InputFormatError(tab.path, f"NEES CSV: runs {meta['runs']:g} < 1 or band "
                                         f"[{meta['band_lo']:g}, {meta['band_hi']:g}] empty")
    v = tab.values
    return NeesCurves(tab.t_ns, v[:, 0].copy(), v[:, 1].copy(), v[:, 2].copy(), int(meta["runs"]),
                      meta["band_lo"], meta["band_hi"], tab.path)


def load_tracks(path: PathLike) -> Table:
    """Tracked features (:data:`formats.TRACKS_COLUMNS`); ``values`` columns: cam_id,
    feature_id, u, v."""
    names = [n for n, _ in formats.TRACKS_COLUMNS]
    return read_table(path, {len(names)}, expected_names=names, what="tracks CSV", repeated_times=True)
