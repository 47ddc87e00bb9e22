"""The source map: which file, dataset or column of a log holds which quantity.

A small YAML file (docs/own-vehicle.md, "Importing a log that is not a bag")::

    pieces: "*/"                 # optional glob under INPUT; each match is one piece of the log
    imu:    {file: imu.csv, time: t, time_unit: s, gyro: [wx, wy, wz], accel: [ax, ay, az]}
    thrust: {file: imu.csv, time: t, time_unit: s, thrust: T, unit: m/s^2}   # or rotors:
    rotors: {file: esc.csv, time: t, time_unit: us, speeds: [n1, n2, n3, n4], unit: rpm}
    mocap:  {file: mocap.csv, time: t, time_unit: ns, position: [x, y, z],
             quaternion: [qw, qx, qy, qz], quaternion_order: wxyz, velocity: [vx, vy, vz]}

A column is a header name or a 0-based index (text files), or a dataset path (HDF5); one name
of a 2-D dataset / several names give several columns. Presets ship in ``maps/`` and are
named without ``.yaml`` (``--map blackbird_lio``). Every unknown key or bad value is a
:class:`MapError` naming the map file and the key.
"""
from __future__ import annotations

import importlib.resources
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple, Union

from ..tools.loaders import load_yaml_mapping
from .errors import MapError

ColumnRef = Union[str, int]

TIME_UNITS = {"s": 10**9, "ms": 10**6, "us": 10**3, "ns": 1}
QUAT_ORDERS = ("wxyz", "xyzw")
THRUST_UNITS = ("m/s^2", "N")
ROTOR_UNITS = ("rpm", "rad/s")

# stream -> {quantity: allowed column counts}; the other keys of each stream are options
QUANTITIES: Dict[str, Dict[str, Tuple[int, ...]]] = {
    "imu": {"gyro": (3,), "accel": (3,)},
    "thrust": {"thrust": (1, 3)},
    "rotors": {"speeds": tuple(range(1, 17))},
    "mocap": {"position": (3,), "quaternion": (4,), "velocity": (3,)},
}
OPTIONAL = {("mocap", "velocity")}
OPTIONS = {"imu": {}, "thrust": {"unit": THRUST_UNITS}, "rotors": {"unit": ROTOR_UNITS},
           "mocap": {"quaternion_order": QUAT_ORDERS}}
COMMON = ("file", "time", "time_unit")


def presets_dir() -> Path:
    """The folder of the shipped source maps."""
    return Path(str(importlib.resources.files("vid_eval.importer") / "maps"))


def preset_names() -> List[str]:
    return sorted(p.stem for p in presets_dir().glob("*.yaml"))


@dataclass
class StreamSpec:
    """One stream of the map: where its columns are and how to read them."""

    name: str                       # imu | thrust | rotors | mocap
    file: str                       # relative to each piece folder (or absolute)
    time: ColumnRef
    time_unit: str
    columns: Dict[str, List[ColumnRef]]   # quantity -> column references
    options: Dict[str, str] = field(default_factory=dict)

    def where(self, key: str) -> str:
        return f"{self.name}.{key}"


@dataclass
class SourceMap:
    path: str
    pieces: Optional[str]
    streams: Dict[str, StreamSpec]

    def stream(self, name: str) -> Optional[StreamSpec]:
        return self.streams.get(name)


def resolve_map_path(name: str) -> Path:
    """A preset name (``blackbird_lio``) or a path to a YAML file."""
    if os.sep not in name and not name.endswith((".yaml", ".yml")):
        cand = presets_dir() / f"{name}.yaml"
        if cand.is_file():
            return cand
        raise MapError(f"--map {name}: no such preset (presets: {', '.join(preset_names())}) "
                       "and not a .yaml file")
    path = Path(name)
    if not path.is_file():
        raise MapError(f"--map {name}: no such file")
    return path


def _columns(value, path: str, where: str) -> List[ColumnRef]:
    items = value if isinstance(value, list) else [value]
    if not items or not all(isinstance(c, (str, int)) and not isinstance(c, bool) for c in items):
        raise MapError(f"{path}: key '{where}': expected a column name or index, or a list of them")
    return list(items)


def _stream(name: str, doc, path: str, overrides: Dict[str, str]) -> StreamSpec:
    if not isinstance(doc, dict):
        raise MapError(f"{path}: key '{name}': expected a mapping (file, time, columns)")
    allowed = set(COMMON) | set(QUANTITIES[name]) | set(OPTIONS[name])
    for key in doc:
        if key not in allowed:
            raise MapError(f"{path}: key '{name}.{key}': unknown (allowed: {', '.join(sorted(allowed))})")
    for key in ("file", "time"):
        if key not in doc:
            raise MapError(f"{path}: key '{name}.{key}' missing")
    if not isinstance(doc["file"], str) or not doc["file"]:
        raise MapError(f"{path}: key '{name}.file': expected a file name")
    time_unit = overrides.get("time_unit") or doc.get("time_unit", "s")
    if time_unit not in TIME_UNITS:
        raise MapError(f"{path}: key '{name}.time_unit': '{time_unit}' is not one of {', '.join(TIME_UNITS)}")
    columns = {}
    for q in QUANTITIES[name]:
        if q in doc:
            columns[q] = _columns(doc[q], path, f"{name}.{q}")
        elif (name, q) not in OPTIONAL:
            raise MapError(f"{path}: key '{name}.{q}' missing")
    options = {}
    for key, allowed_values in OPTIONS[name].items():
        value = overrides.get(key) or doc.get(key, allowed_values[0])
        if value not in allowed_values:
            raise MapError(f"{path}: key '{name}.{key}': '{value}' is not one of {', '.join(allowed_values)}")
        options[key] = value
    time = _columns(doc["time"], path, f"{name}.time")
    if len(time) != 1:
        raise MapError(f"{path}: key '{name}.time': expected one column")
    return StreamSpec(name, doc["file"], time[0], time_unit, columns, options)


def load_map(name: str, overrides: Optional[Dict[str, str]] = None) -> SourceMap:
    """Load and check a source map (preset name or path); ``overrides`` (``time_unit``,
    ``quaternion_order``) replace the map's values, as the command-line flags do."""
    path = resolve_map_path(name)
    spath = str(path)
    try:
        doc = load_yaml_mapping(spath, "source map")
    except Exception as exc:  # an unreadable map is a usage error, one line
        raise MapError(str(exc)) from None
    if not doc:
        raise MapError(f"{spath}: empty source map (expected keys imu, thrust or rotors, mocap)")
    known = {"pieces", *QUANTITIES}
    for key in doc:
        if key not in known:
            raise MapError(f"{spath}: key '{key}': unknown (allowed: {', '.join(sorted(known))})")
    if "imu" not in doc:
        raise MapError(f"{spath}: key 'imu' missing (the IMU is required)")
    if "thrust" in doc and "rotors" in doc:
        raise MapError(f"{spath}: keys 'thrust' and 'rotors': give one of them")
    pieces = doc.get("pieces")
    if pieces is not None and (not isinstance(pieces, str) or not pieces):
        raise MapError(f"{spath}: key 'pieces': expected a glob pattern such as '*/'")
    streams = {name: _stream(name, doc[name], spath, overrides or {})
               for name in QUANTITIES if name in doc}
    return SourceMap(spath, pieces, streams)
