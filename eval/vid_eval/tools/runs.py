"""Run descriptors for ``vid-eval report``: find a run's JSON files, its names and metrics.

Convention (documented in eval/README.md):

* A RUN argument is a folder or a JSON file. A folder contributes every ``*.json`` directly
  inside it (``summary.json`` of ``vid_run --out``, and ``vid-eval traj/force/mass --json``
  outputs such as ``eval_traj.json``); a file contributes itself.
* Names: the keys ``"method"`` and ``"sequence"`` of any of those JSON objects (top level, or
  inside ``"run": {...}``) win; otherwise the folder is named ``.../<sequence>/<method>/``
  (method = folder name, sequence = its parent's name); a folder named ``<sequence>__<method>``
  is also understood.
* Metrics: see :data:`METRICS`; each is looked up by a list of key paths (first found wins).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

from ..errors import InputFormatError


@dataclass(frozen=True)
class Metric:
    """A reportable number: label for tables, unit, key paths, lower-is-better."""

    name: str
    label: str
    unit: str
    paths: Tuple[str, ...]
    lower_is_better: bool = True


METRICS: Dict[str, Metric] = {m.name: m for m in [
    Metric("ate", "ATE", "m", ("ate_pos_rmse_m", "ate.pos_m.rmse", "ate_posyaw_m", "ate_m",
                               "ate_se3_m", "ate_rmse_m")),
    Metric("ate_rot", "ATE rotation", "deg", ("ate_rot_rmse_deg", "ate.rot_deg.rmse")),
    Metric("force", "Force RMSE", "m/s²", ("force.rmse_mps2.norm", "force_rmse_world_mps2",
                                           "force_rmse_body_mps2", "force_rmse_mps2")),
    Metric("force_n", "Force RMSE", "N", ("force.rmse_N.norm", "force_rmse_N")),
    Metric("mass", "Mass RMSPE", "%", ("mass_rmspe_percent", "mass.rmspe_percent", "rmspe_percent")),
    Metric("mass_rmse", "Mass RMSE", "kg", ("mass_rmse_kg", "mass.rmse_kg")),
    Metric("time", "Mean update time", "ms", ("update_time_mean_ms", "timing.total.mean_ms",
                                              "stages.total.mean_ms")),
]}


@dataclass
class Run:
    """One run: its names and every metric found in its JSON files."""

    method: str
    sequence: str
    path: str
    values: Dict[str, float] = field(default_factory=dict)
    data: List[dict] = field(default_factory=list)


def lookup(data: dict, path: str) -> Optional[float]:
    """Value at a dotted key path if it is a number, else None."""
    cur = data
    for key in path.split("."):
        if not isinstance(cur, dict) or key not in cur:
            return None
        cur = cur[key]
    if isinstance(cur, bool) or not isinstance(cur, (int, float)):
        return None
    return float(cur)


def _read_json(path: Path) -> dict:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputFormatError(path, f"cannot read: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise InputFormatError(path, f"invalid JSON: {exc.msg}", exc.lineno) from None
    if not isinstance(data, dict):
        raise InputFormatError(path, "JSON top level must be an object")
    return data


def _names(objs: Sequence[dict], folder: Path) -> Tuple[str, str]:
    method = sequence = None
    for o in objs:
        for src in (o, o.get("run") if isinstance(o.get("run"), dict) else {}):
            method = method or (src.get("method") if isinstance(src.get("method"), str) else None)
            sequence = sequence or (src.get("sequence") if isinstance(src.get("sequence"), str) else None)
    if "__" in folder.name and not (method and sequence):
        seq, meth = folder.name.split("__", 1)
        method, sequence = method or meth, sequence or seq
    return method or folder.name, sequence or folder.parent.name or "-"


def load_run(arg: str, extra_metrics: Sequence[str] = ()) -> Run:
    """Read one RUN (folder or JSON file) following the convention above."""
    p = Path(arg)
    if p.is_dir():
        files = sorted(p.glob("*.json"))
        if not files:
            raise InputFormatError(p, "run folder holds no *.json (summary.json or vid-eval --json output)")
        folder = p
    elif p.is_file():
        files, folder = [p], p.parent
    else:
        raise InputFormatError(p, "no such run folder or JSON file")
    objs = [_read_json(f) for f in files]
    method, sequence = _names(objs, folder.resolve())
    run = Run(method, sequence, str(p), data=objs)
    wanted = {name: m.paths for name, m in METRICS.items()}
    wanted.update({k: (k,) for k in extra_metrics})
    for name, paths in wanted.items():
        for o in objs:
            v = next((x for x in (lookup(o, k) for k in paths) if x is not None), None)
            if v is not None:
                run.values[name] = v
                break
    return run
