"""Batch YAML -> the list of tasks of a batch (no Ray here: planning is plain Python).

A batch (see config/batch/*.yaml and eval/README.md "vid-batch") has any of three parts:

* ``scenarios`` (simulator presets + duration) x ``seeds`` and ``sequences`` (existing dataset
  folders), each x ``grid`` (estimator.yaml keys -> values, Cartesian product) x
  ``estimators``: one **run** = simulate (if needed) -> vid_run -> score;
* ``massid``: the mass-ID study, sharded per trajectory x profile (generate, filters), the ELM
  family per method, then the merged report;
* ``nees``: the NEES Monte-Carlo tests, one task per test case.

Every task has a stable id (its record's file name), so a rerun finds what is already done.
"""
from __future__ import annotations

import itertools
import pathlib
import re
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional

import yaml

from ..tools.sim_runs import yaml_scalar

TOP_KEYS = {"name", "scenarios", "sequences", "seeds", "config", "grid", "estimators", "skip_s",
            "features_only", "memory_mb", "massid", "nees"}
MASSID_KEYS = {"config", "runs", "trajectories", "profiles", "filters", "data_driven", "runs_per_case",
               "train_runs_per_case", "selection_seed", "hidden_nodes", "memory_mb"}
NEES_KEYS = {"tests", "memory_mb"}
ESTIMATOR_KEYS = {"name", "mode", "peer", "config"}
TRAJECTORIES = ["random", "loop", "lemniscate", "zigzag", "square"]
PROFILES = ["constant", "linear_decrease", "step_drop", "step_pickup", "up_down"]
FILTERS = ["ekf", "ukf", "msckf", "swls", "vio"]
DATA_DRIVEN = ["elm", "relm", "oselm"]


class BatchSpecError(Exception):
    """A bad batch file: printed as one line naming the file and the field (exit 2)."""

    def __init__(self, path: pathlib.Path, fieldname: str, msg: str):
        super().__init__(f"{path}: field '{fieldname}': {msg}")


@dataclass
class Task:
    """One unit of work. ``recorded`` tasks are runs of the results table; the others
    (simulating a shared sequence) only prepare inputs and are redone cheaply if missing."""

    id: str
    kind: str
    params: Dict[str, Any]
    deps: List[str] = field(default_factory=list)
    recorded: bool = True
    memory_mb: int = 1024


def safe_id(text: str) -> str:
    """A file-name-safe id: anything but letters, digits and ``._=-`` becomes ``_``."""
    return re.sub(r"[^A-Za-z0-9._=-]+", "_", text)


class _Reader:
    """Typed access to the YAML with errors that name the file and field."""

    def __init__(self, path: pathlib.Path):
        self.path = path

    def fail(self, fieldname: str, msg: str):
        raise BatchSpecError(self.path, fieldname, msg)

    def list_of(self, data: dict, key: str, typ, where: str = "", default=None) -> list:
        name = f"{where}{key}"
        if key not in data:
            if default is None:
                self.fail(name, "missing")
            return list(default)
        val = data[key]
        if not isinstance(val, list) or not val:
            self.fail(name, "expected a non-empty list")
        for v in val:
            if not isinstance(v, typ) or isinstance(v, bool) and typ is not bool:
                self.fail(name, f"expected a list of {getattr(typ, '__name__', typ)}, got {v!r}")
        return val

    def number(self, data: dict, key: str, default, where: str = "", integer: bool = False):
        if key not in data:
            return default
        v = data[key]
        ok = isinstance(v, int) if integer else isinstance(v, (int, float))
        if isinstance(v, bool) or not ok or v < 0:
            self.fail(f"{where}{key}", f"expected a non-negative {'integer' if integer else 'number'}, got {v!r}")
        return v

    def check_keys(self, data, known: set, where: str):
        if not isinstance(data, dict):
            self.fail(where.rstrip(".") or "(top level)", "expected a mapping")
        for k in data:
            if k not in known:
                self.fail(f"{where}{k}", f"unknown key (known: {', '.join(sorted(known))})")


def load_batch(path: pathlib.Path, repo: pathlib.Path) -> List[Task]:
    """Parse and validate a batch YAML; relative paths are relative to the repository."""
    r = _Reader(path)
    try:
        data = yaml.safe_load(path.read_text())
    except OSError as exc:
        raise BatchSpecError(path, "(file)", f"cannot read: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark else "(syntax)"
        raise BatchSpecError(path, where, f"invalid YAML: {getattr(exc, 'problem', exc)}") from None
    r.check_keys(data, TOP_KEYS, "")
    tasks: List[Task] = []
    if "scenarios" in data or "sequences" in data:
        tasks += _estimate_tasks(r, data, repo)
    if "massid" in data:
        tasks += _massid_tasks(r, data["massid"], repo)
    if "nees" in data:
        tasks += _nees_tasks(r, data["nees"])
    if not tasks:
        r.fail("scenarios", "the batch has no runs (give scenarios, sequences, massid or nees)")
    ids = [t.id for t in tasks]
    dup = next((i for i in ids if ids.count(i) > 1), None)
    if dup is not None:  # e.g. grid values 'a b' and 'a_b': one record file for two runs
        r.fail("grid", f"two runs would share the id {dup} (values that differ only in characters "
                       "other than letters, digits and ._=-): rename one")
    return tasks


def _estimate_tasks(r: _Reader, data: dict, repo: pathlib.Path) -> List[Task]:
    memory = r.number(data, "memory_mb", 1024, integer=True)
    skip_s = r.number(data, "skip_s", 5.0)
    features_only = data.get("features_only", True)
    if not isinstance(features_only, bool):
        r.fail("features_only", f"expected true or false, got {features_only!r}")
    base_cfg = data.get("config", "config/sim")
    if not isinstance(base_cfg, str) or not (repo / base_cfg).is_dir():
        r.fail("config", f"no estimator preset folder {base_cfg!r}")
    inputs = []  # (label, params, sim task or None)
    sims: Dict[str, Task] = {}
    if "scenarios" in data:
        seeds = r.list_of(data, "seeds", int)
        for i, sc in enumerate(r.list_of(data, "scenarios", dict)):
            where = f"scenarios[{i}]."
            r.check_keys(sc, {"preset", "duration"}, where)
            preset = sc.get("preset")
            if not isinstance(preset, str) or not (repo / "config" / "sim" / f"{preset}.yaml").exists():
                r.fail(f"{where}preset", f"no simulator preset config/sim/{preset}.yaml")
            duration = r.number(sc, "duration", None, where)
            for seed in seeds:
                label = safe_id(f"{preset}{'_%gs' % duration if duration else ''}_seed{seed}"
                                f"{'' if features_only else '_img'}")
                sims[label] = Task("sim__" + label, "simulate", {"preset": preset, "seed": seed,
                                   "duration": duration, "images": not features_only, "sequence": label},
                                   recorded=False, memory_mb=memory)
                inputs.append((label, {"preset": preset, "duration": duration, "seed": seed,
                                       "sequence": label}, sims[label]))
    for i, seq in enumerate(r.list_of(data, "sequences", str, default=[])):
        folder = (r.path.parent / seq) if not pathlib.Path(seq).is_absolute() else pathlib.Path(seq)
        folder = folder if folder.is_dir() else repo / seq
        if not folder.is_dir():
            r.fail(f"sequences[{i}]", f"no dataset folder {seq!r}")
        label = safe_id(folder.name)
        if any(label == lab for lab, _, _ in inputs):  # day1/flight, day2/flight: keep both apart
            label = safe_id(f"{folder.parent.name}_{folder.name}")
        if any(label == lab for lab, _, _ in inputs):
            r.fail(f"sequences[{i}]", f"{seq!r} has the name of an earlier input ({label}): its "
                                      "records, outputs and plots would overwrite that one's")
        inputs.append((label, {"preset": None, "duration": None, "seed": None, "sequence": label,
                               "dataset": str(folder.resolve())}, None))
    grid = data.get("grid", {}) or {}
    if not isinstance(grid, dict):
        r.fail("grid", "expected a mapping key -> list of values")
    for key, vals in grid.items():
        if not isinstance(vals, list) or not vals:
            r.fail(f"grid.{key}", "expected a non-empty list of values")
    points = [dict(zip(grid, combo)) for combo in itertools.product(*grid.values())] or [{}]
    estimators = []
    for i, est in enumerate(r.list_of(data, "estimators", dict, default=[{"name": "ours"}])):
        where = f"estimators[{i}]."
        r.check_keys(est, ESTIMATOR_KEYS, where)
        if not isinstance(est.get("name"), str):
            r.fail(f"{where}name", "missing (a short label)")
        if est.get("mode", "dynamics") not in ("dynamics", "imu"):
            r.fail(f"{where}mode", f"expected dynamics or imu, got {est['mode']!r}")
        cfg = est.get("config", base_cfg)
        if not (repo / cfg).is_dir():
            r.fail(f"{where}config", f"no estimator preset folder {cfg!r}")
        estimators.append({"estimator": est["name"], "mode": est.get("mode", "dynamics"),
                           "peer": est.get("peer"), "config": str(repo / cfg)})
    tasks = list(sims.values())
    for (label, inp, sim), est, point in itertools.product(inputs, estimators, points):
        pid = "__".join(f"{k}={yaml_scalar(v)}" for k, v in point.items())
        tid = safe_id(f"{label}__{est['estimator']}" + (f"__{pid}" if pid else ""))
        params = dict(inp, **est, overrides=point, skip_s=skip_s)
        tasks.append(Task(tid, "estimate", params, [sim.id] if sim else [], memory_mb=memory))
    return tasks


def _massid_tasks(r: _Reader, m: Any, repo: pathlib.Path) -> List[Task]:
    w = "massid."
    r.check_keys(m, MASSID_KEYS, w)
    cfg = m.get("config", "config/massid/study.yaml")
    if not isinstance(cfg, str) or not (repo / cfg).is_file():
        r.fail(f"{w}config", f"no study settings file {cfg!r}")
    trajs = r.list_of(m, "trajectories", str, w, TRAJECTORIES)
    profs = r.list_of(m, "profiles", str, w, PROFILES)
    filters = r.list_of(m, "filters", str, w, FILTERS)
    learned = r.list_of(m, "data_driven", str, w, DATA_DRIVEN)
    for key, vals, known in (("trajectories", trajs, TRAJECTORIES), ("profiles", profs, PROFILES),
                             ("filters", filters, FILTERS), ("data_driven", learned, DATA_DRIVEN)):
        for v in vals:
            if v not in known:
                r.fail(f"{w}{key}", f"unknown {v!r} (known: {', '.join(known)})")
    runs = r.number(m, "runs", 50, w, integer=True)
    common = {"runs_per_case": r.number(m, "runs_per_case", 10, w, integer=True),
              "selection_seed": r.number(m, "selection_seed", 1, w, integer=True)}
    memory = r.number(m, "memory_mb", 1024, w, integer=True)
    tasks, gen_ids, done_ids = [], [], []
    for t, p in itertools.product(trajs, profs):
        case = f"{t}__{p}"
        gen = Task(f"massid_generate__{case}", "massid_generate",
                   {"config": str(repo / cfg), "runs": runs, "trajectory": t, "profile": p, "case": case},
                   memory_mb=memory)
        run = Task(f"massid_filters__{case}", "massid_run",
                   dict(common, data=case, methods=filters, trajectory=t, profile=p), [gen.id], memory_mb=memory)
        tasks += [gen, run]
        gen_ids.append(gen.id)
        done_ids.append(run.id)
    if learned:
        merge = Task("massid_merge", "massid_merge", {"cases": [f"{t}__{p}" for t, p in
                                                                itertools.product(trajs, profs)]}, gen_ids)
        tasks.append(merge)
        for meth in learned:
            tasks.append(Task(f"massid_{meth}", "massid_run",
                              dict(common, data="all", methods=[meth],
                                   train_runs_per_case=r.number(m, "train_runs_per_case", 2, w, integer=True),
                                   hidden_nodes=r.number(m, "hidden_nodes", 500, w, integer=True)),
                              [merge.id], memory_mb=max(memory, 2048)))
            done_ids.append(tasks[-1].id)
    tasks.append(Task("massid_report", "massid_report", {"parts": done_ids}, done_ids))
    return tasks


def _nees_tasks(r: _Reader, n: Any) -> List[Task]:
    r.check_keys(n, NEES_KEYS, "nees.")
    tests = r.list_of(n, "tests", str, "nees.", ["NeesSim.Vid17LikeDynamicsMode", "NeesSim.Vid17LikeImuMode"])
    memory = r.number(n, "memory_mb", 1024, "nees.", integer=True)
    return [Task(safe_id(f"nees__{t}"), "nees", {"test": t}, memory_mb=memory) for t in tests]


def task_order(tasks: List[Task]) -> List[Task]:
    """Tasks with every dependency before its dependents (the plan is built in that order;
    this checks it and reports an unknown dependency as a bug of the planner)."""
    seen = set()
    for t in tasks:
        missing = [d for d in t.deps if d not in seen]
        if missing:
            raise AssertionError(f"task {t.id} depends on later/unknown {missing}")
        seen.add(t.id)
    return tasks


def find_task(tasks: List[Task], tid: str) -> Optional[Task]:
    """The task with id ``tid`` or None."""
    return next((t for t in tasks if t.id == tid), None)
