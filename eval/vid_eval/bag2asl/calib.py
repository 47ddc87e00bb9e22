"""Preset (config/vid_dataset: Kalibr-style chains, vehicle.yaml, rotor sensor) -> the
EuRoC/§4 sensor.yaml and vehicle.yaml files of the output folder, and the mass rule."""
from __future__ import annotations

import importlib.resources
import pathlib
import re

import numpy as np
import yaml

from .errors import ConfigError, UsageError
from . import sinks
from .sinks import fmt, os_error

# The VID-Dataset preset ships with the package (a link to config/vid_dataset in the source tree).
DEFAULT_PRESET = pathlib.Path(str(importlib.resources.files("vid_eval.bag2asl") / "presets" / "vid_dataset"))

_SEQ_NAME = re.compile(r"^(?:vid|seq|sequence)?[_-]?0*(\d{1,2})$", re.IGNORECASE)
_GRAMS = re.compile(r"(?:^|_)(load)?(\d+(?:\.\d+)?)g(?=_|$)")


def _load_yaml(path: pathlib.Path) -> dict:
    try:
        doc = yaml.safe_load(path.read_text())
    except OSError as err:
        raise ConfigError(f"{path}: cannot read preset file: {err.strerror or err}") from None
    except yaml.YAMLError as err:
        raise ConfigError(f"{path}: invalid YAML: {err}") from None
    if not isinstance(doc, dict):
        raise ConfigError(f"{path}: expected a mapping")
    return doc


def _key(doc: dict, key: str, path, where: str = ""):
    if key not in doc:
        raise ConfigError(f"{path}: missing key {where}{key}")
    return doc[key]


class Preset:
    """The files of a preset folder, validated on load."""

    def __init__(self, folder: pathlib.Path):
        self.folder = folder
        if not folder.is_dir():
            raise ConfigError(f"{folder}: preset folder not found (use --preset DIR)")
        self.imu_path = folder / "imu.yaml"
        self.cam_path = folder / "camchain-imucam.yaml"
        self.vehicle_path = folder / "vehicle.yaml"
        self.rotor_path = folder / "rotor_sensor.yaml"
        self.imu = _key(_load_yaml(self.imu_path), "imu0", self.imu_path)
        self.cams = _load_yaml(self.cam_path)
        self.vehicle = _load_yaml(self.vehicle_path)
        self.rotor = _load_yaml(self.rotor_path)
        seq_path = folder / "sequences.yaml"
        self.sequences = _load_yaml(seq_path).get("sequences", {}) if seq_path.exists() else {}
        for k in ("mass_kg", "gravity", "rotor_thrust_coefficients"):
            _key(self.vehicle, k, self.vehicle_path)
        coeffs = self.vehicle["rotor_thrust_coefficients"]
        if not isinstance(coeffs, list) or not coeffs or not all(
                isinstance(c, (int, float)) and not isinstance(c, bool) for c in coeffs):
            raise ConfigError(f"{self.vehicle_path}: key rotor_thrust_coefficients: expected a list of numbers")


def mass_for(bag_path: pathlib.Path, flag: float | None, preset: Preset) -> tuple[float, str]:
    """(mass kg, how it was found). Rule (bag2asl/README.md "Mass rule"): --mass; known VID sequence
    (published file name or 'N' / 'vidN' / 'seqN' / 'sequence_N'); '<grams>g' in the name plus
    any 'load<grams>g'; else the preset's vehicle.yaml mass (with a warning by the caller)."""
    if flag is not None:
        if not flag > 0:
            raise UsageError(f"--mass: expected a positive mass in kg, got {flag}")
        return float(flag), "--mass"
    name = bag_path.name
    stem = name[:-4] if name.endswith(".bag") else name
    for num, entry in preset.sequences.items():
        if isinstance(entry, dict) and entry.get("file") in (name, stem + ".bag") and "mass_kg" in entry:
            return float(entry["mass_kg"]), f"VID sequence {num} (sequences.yaml, file name)"
    m = _SEQ_NAME.match(stem)
    if m and int(m.group(1)) in preset.sequences and "mass_kg" in preset.sequences[int(m.group(1))]:
        num = int(m.group(1))
        return float(preset.sequences[num]["mass_kg"]), f"VID sequence {num} (sequences.yaml, number)"
    grams = _GRAMS.findall(stem)
    base = [float(g) for load, g in grams if not load]
    if base:
        total = base[0] + sum(float(g) for load, g in grams if load)
        return round(total / 1000.0, 9), f"file name ({'+'.join(load + g + 'g' for load, g in grams)})"
    return float(preset.vehicle["mass_kg"]), f"preset default ({preset.vehicle_path})"


def _write_text(path: pathlib.Path, text: str) -> None:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with sinks._open_out(path, "w") as f:
            f.write(text)
    except OSError as err:
        raise os_error(path, err) from None


def _flow(values) -> str:
    return "[" + ", ".join(fmt(v) for v in values) + "]"


def _matrix4(rows, path, where) -> np.ndarray:
    mat = np.array(rows, dtype=float)
    if mat.shape != (4, 4):
        raise ConfigError(f"{path}: {where}: expected a 4x4 matrix")
    return mat


def invert_pose(T: np.ndarray) -> np.ndarray:
    R, t = T[:3, :3], T[:3, 3]
    out = np.eye(4)
    out[:3, :3] = R.T
    out[:3, 3] = -(R.T @ t)
    return out + 0.0  # turn -0.0 into 0.0


def write_camera_yaml(preset: Preset, cam: str, out: pathlib.Path, rate_hz: float | None,
                      resolution, topic: str) -> None:
    c = _key(preset.cams, cam, preset.cam_path)
    where = f"{cam}."
    T_CI = _matrix4(_key(c, "T_cam_imu", preset.cam_path, where), preset.cam_path, where + "T_cam_imu")
    T_IC = invert_pose(T_CI)
    model = _key(c, "distortion_model", preset.cam_path, where)
    dist = {"radtan": "radial-tangential", "equidistant": "equidistant"}.get(model)
    if dist is None:
        raise ConfigError(f"{preset.cam_path}: {cam}.distortion_model: expected radtan or equidistant")
    res = resolution or _key(c, "resolution", preset.cam_path, where)
    text = (f"# {cam}: converted by vid-bag2asl from {preset.cam_path.name}\n"
            "sensor_type: camera\n"
            f"comment: from {topic}\n"
            "T_BS:\n  cols: 4\n  rows: 4\n"
            f"  data: {_flow(T_IC.reshape(-1))}\n"
            f"rate_hz: {fmt(round(rate_hz, 3)) if rate_hz else fmt(30.0)}\n"
            f"resolution: {_flow([int(v) for v in res])}\n"
            f"camera_model: {_key(c, 'camera_model', preset.cam_path, where)}\n"
            f"intrinsics: {_flow(_key(c, 'intrinsics', preset.cam_path, where))}\n"
            f"distortion_model: {dist}\n"
            f"distortion_coefficients: {_flow(_key(c, 'distortion_coeffs', preset.cam_path, where))}\n"
            f"timeshift_cam_imu: {fmt(c.get('timeshift_cam_imu', 0.0))}\n")
    _write_text(out / cam / "sensor.yaml", text)


def write_imu_yaml(preset: Preset, out: pathlib.Path, rate_hz: float | None, topic: str) -> None:
    p, i = preset.imu_path, preset.imu
    T = _matrix4(i.get("T_i_b", np.eye(4).tolist()), p, "imu0.T_i_b")
    text = ("# imu0: converted by vid-bag2asl from " + p.name + "\n"
            "sensor_type: imu\n"
            f"comment: from {topic}\n"
            "T_BS:\n  cols: 4\n  rows: 4\n"
            f"  data: {_flow(T.reshape(-1))}\n"
            f"rate_hz: {fmt(round(rate_hz, 3) if rate_hz else _key(i, 'update_rate', p, 'imu0.'))}\n"
            f"gyroscope_noise_density: {fmt(_key(i, 'gyroscope_noise_density', p, 'imu0.'))}\n"
            f"gyroscope_random_walk: {fmt(_key(i, 'gyroscope_random_walk', p, 'imu0.'))}\n"
            f"accelerometer_noise_density: {fmt(_key(i, 'accelerometer_noise_density', p, 'imu0.'))}\n"
            f"accelerometer_random_walk: {fmt(_key(i, 'accelerometer_random_walk', p, 'imu0.'))}\n")
    _write_text(out / "imu0" / "sensor.yaml", text)


def write_rotor_yaml(preset: Preset, out: pathlib.Path, name: str, unit: str | None, count: int,
                     rate_hz: float | None, noise: float | None) -> None:
    r = preset.rotor
    text = ("# rotor speeds: written by vid-bag2asl (count and rate measured from the data)\n"
            "sensor_type: rotor_speed\n"
            f"unit: {unit or r.get('unit', 'rpm')}\n"
            f"count: {count}\n"
            f"rate_hz: {fmt(round(rate_hz, 3) if rate_hz else r.get('rate_hz', 100))}\n"
            f"noise_density: {fmt(noise if noise is not None else r.get('noise_density', 1.0))}\n")
    _write_text(out / name / "sensor.yaml", text)


def write_vehicle_yaml(preset: Preset, out: pathlib.Path, mass_kg: float, mass_source: str) -> None:
    v = preset.vehicle
    k = v["rotor_thrust_coefficients"]
    text = (f"# vehicle: written by vid-bag2asl from {preset.vehicle_path}\n"
            f"# mass source: {mass_source}\n"
            f"mass_kg: {fmt(mass_kg)}\n"
            f"gravity: {fmt(v['gravity'])}\n"
            f"rotor_thrust_coefficients: {_flow(k)}\n")
    for extra in ("rotor_directions", "rotor_positions"):
        if extra in v:
            text += f"{extra}: {yaml.safe_dump(v[extra], default_flow_style=True).strip()}\n"
    _write_text(out / "vehicle.yaml", text)
