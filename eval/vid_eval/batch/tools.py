"""Executing one task of a batch (plain Python, no Ray): the C++ programs, scoring, records.

Layout of a batch folder OUT (shared storage on a cluster):
``records/<id>.json`` (one per finished run, written atomically), ``logs/<id>.log``,
``runs/<id>/`` (program outputs), ``seq/<sequence>/`` (simulated sequences, shared by runs),
``massid/`` (study data and results), ``results.parquet`` / ``results.csv`` (the table).
"""
from __future__ import annotations

import json
import os
import pathlib
import shutil
import socket
import subprocess
import time
from typing import Dict, List, Optional

from ..tools.sim_runs import REPO, config_with_overrides, score_run, sequence_exists, simulate_command


class TaskError(Exception):
    """A run failed; the message is the one-line error of the results table."""


def program(build: pathlib.Path, name: str, sub: str = "bin") -> str:
    """Path of a built program, or TaskError naming it."""
    path = build / sub / name
    if not path.exists():
        raise TaskError(f"{path} not built (run scripts/build.sh or pass --build-dir)")
    return str(path)


def write_json_atomic(path: pathlib.Path, data: dict) -> None:
    """Write JSON via a temporary file and rename, so a reader never sees half a record."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, indent=1, default=str) + "\n")
    os.replace(tmp, path)


def record_path(out: pathlib.Path, tid: str) -> pathlib.Path:
    """Where the record of task ``tid`` lives."""
    return out / "records" / f"{tid}.json"


def read_record(out: pathlib.Path, tid: str) -> Optional[dict]:
    """The finished record of ``tid``, or None if the task never finished."""
    try:
        return json.loads(record_path(out, tid).read_text())
    except (OSError, json.JSONDecodeError):
        return None


def _run(cmd: List[str], log: pathlib.Path) -> None:
    """Run a program, appending its output to ``log``; TaskError with its last stderr line."""
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        proc = subprocess.run(cmd, stdout=f, stderr=subprocess.PIPE, text=True)
        f.write(proc.stderr)
    if proc.returncode != 0:
        lines = [ln for ln in proc.stderr.strip().splitlines() if ln.strip()]
        last = lines[-1].strip() if lines else "no error output"
        raise TaskError(f"{pathlib.Path(cmd[0]).name} exited with {proc.returncode}: {last}")


def _fresh(path: pathlib.Path) -> pathlib.Path:
    """A temporary sibling of ``path`` to write into before renaming it into place, so that a
    killed task leaves no half-written output that a rerun would take as done."""
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.parent.mkdir(parents=True, exist_ok=True)
    return tmp


def _publish(tmp: pathlib.Path, path: pathlib.Path) -> None:
    shutil.rmtree(path, ignore_errors=True)
    os.replace(tmp, path)


def do_simulate(p: dict, out: pathlib.Path, build: pathlib.Path, log: pathlib.Path) -> dict:
    """Simulate a sequence once (shared by every run on it)."""
    seq = out / "seq" / p["sequence"]
    if sequence_exists(seq):
        return {"sequence_path": str(seq)}
    tmp = _fresh(seq)
    scenario = REPO / "config" / "sim" / f"{p['preset']}.yaml"
    _run(simulate_command(program(build, "vid_sim"), scenario, tmp, p["seed"], p["images"],
                          duration=p["duration"]), log)
    _publish(tmp, seq)
    return {"sequence_path": str(seq)}


def do_estimate(p: dict, out: pathlib.Path, build: pathlib.Path, log: pathlib.Path, tid: str) -> dict:
    """vid_run (or a peer) on the sequence with the run's overrides, then the scores."""
    seq = pathlib.Path(p["dataset"]) if p.get("dataset") else out / "seq" / p["sequence"]
    run_dir = out / "runs" / tid
    if p.get("peer"):
        # Peers (bench/peers/) are built separately; only OpenVINS exists so far.
        path = REPO / "build-peers" / "bin" / "ov_driver"
        if p["peer"] != "openvins" or not path.exists():
            raise TaskError(f"peer '{p['peer']}' not built ({path}; see bench/peers/README.md)")
        raise TaskError(f"peer '{p['peer']}': running peers through vid-batch is not implemented yet "
                        "(use bench/peers/compare.py)")
    cfg = config_with_overrides(pathlib.Path(p["config"]), p["overrides"], out / "configs" / tid)
    tmp = _fresh(run_dir)
    t0 = time.time()
    _run([program(build, "vid_run"), "--dataset", str(seq), "--out", str(tmp), "--config", str(cfg),
          "--mode", p["mode"], "--quiet", "--decode-threads", "0"], log)
    run_s = time.time() - t0
    _publish(tmp, run_dir)
    t0 = time.time()
    scores = score_run(seq, run_dir, p["skip_s"])
    if scores.get("status") not in (None, "ok"):
        raise TaskError(f"vid_run status {scores['status']}")
    return dict(scores, run_s=run_s, score_s=time.time() - t0, output=str(run_dir))


def do_massid_generate(p: dict, out: pathlib.Path, build: pathlib.Path, log: pathlib.Path) -> dict:
    """One trajectory x profile shard of the study data (run seeds do not depend on the shard)."""
    data = out / "massid" / "data" / p["case"]
    tmp = _fresh(data)
    _run([program(build, "vid_massid"), "generate", "--config", p["config"], "--out", str(tmp),
          "--runs", str(p["runs"]), "--trajectories", p["trajectory"], "--profiles", p["profile"],
          "--threads", "1", "--quiet"], log)
    _publish(tmp, data)
    return {"runs": p["runs"], "output": str(data)}


def do_massid_merge(p: dict, out: pathlib.Path) -> dict:
    """One dataset folder over all shards (manifest runs concatenated, run folders linked) so
    that the ELM family trains across trajectories as `vid_massid run` does on the full data."""
    root = out / "massid" / "data"
    tmp = _fresh(root / "all")
    tmp.mkdir()
    header, runs, trajs, profs = None, [], [], []
    for case in p["cases"]:
        text = (root / case / "manifest.yaml").read_text()
        head, sep, body = text.partition("\nruns:\n")
        if not sep or "format: vid_massid_dataset" not in head:
            raise TaskError(f"{root / case / 'manifest.yaml'}: not a vid_massid dataset manifest")
        header = header or head
        runs += [ln for ln in body.splitlines() if ln.strip()]
        t, prof = case.split("__")
        trajs += [t] if t not in trajs else []
        profs += [prof] if prof not in profs else []
        (tmp / t).mkdir(exist_ok=True)
        os.symlink(os.path.relpath(root / case / t / prof, tmp / t), tmp / t / prof)
    lines = []
    for ln in header.splitlines():
        if ln.startswith("  trajectories:"):
            ln = f"  trajectories: [{', '.join(trajs)}]"
        elif ln.startswith("  profiles:"):
            ln = f"  profiles: [{', '.join(profs)}]"
        lines.append(ln)
    (tmp / "manifest.yaml").write_text("\n".join(lines) + "\nruns:\n" + "\n".join(runs) + "\n")
    _publish(tmp, root / "all")
    return {"runs": len(runs), "output": str(root / "all")}


def _massid_means(runs_csv: pathlib.Path) -> Dict[str, float]:
    """Per method: evaluated runs, mean RMSPE [%] and mean CPU time per update [ms]."""
    import csv
    acc: Dict[str, List[List[float]]] = {}
    with open(runs_csv) as f:
        for row in csv.DictReader(f):
            acc.setdefault(row["method"], []).append([float(row["rmspe_pct"]), float(row["mean_update_cpu_ms"])])
    res: Dict[str, float] = {}
    for meth, vals in acc.items():
        res[f"{meth}_runs"] = len(vals)
        res[f"{meth}_rmspe_pct"] = sum(v[0] for v in vals) / len(vals)
        res[f"{meth}_update_cpu_ms"] = sum(v[1] for v in vals) / len(vals)
    return res


def do_massid_run(p: dict, out: pathlib.Path, build: pathlib.Path, log: pathlib.Path, tid: str) -> dict:
    """`vid_massid run` of some methods on one shard (filters) or on the merged data (ELM)."""
    res = out / "massid" / "results" / tid
    tmp = _fresh(res)
    cmd = [program(build, "vid_massid"), "run", "--data", str(out / "massid" / "data" / p["data"]),
           "--out", str(tmp), "--methods", ",".join(p["methods"]), "--runs-per-case", str(p["runs_per_case"]),
           "--selection-seed", str(p["selection_seed"]), "--threads", "1"]
    if "train_runs_per_case" in p:
        cmd += ["--train-runs-per-case", str(p["train_runs_per_case"]), "--hidden-nodes", str(p["hidden_nodes"])]
    _run(cmd, log)
    _publish(tmp, res)
    return dict(_massid_means(res / "runs.csv"), output=str(res))


def do_massid_report(p: dict, out: pathlib.Path, build: pathlib.Path, log: pathlib.Path) -> dict:
    """All parts' runs.csv in one results folder, then `vid_massid report` (tables)."""
    res = out / "massid" / "results"
    tmp = _fresh(res / "all")
    tmp.mkdir()
    header, rows = None, []
    for part in p["parts"]:
        lines = (res / part / "runs.csv").read_text().splitlines()
        header = header or lines[0]
        rows += lines[1:]
    (tmp / "runs.csv").write_text("\n".join([header] + rows) + "\n")
    _publish(tmp, res / "all")
    _run([program(build, "vid_massid"), "report", "--results", str(res / "all"), "--no-plots"], log)
    return dict(_massid_means(res / "all" / "runs.csv"), output=str(res / "all" / "report"))


def do_nees(p: dict, out: pathlib.Path, build: pathlib.Path, log: pathlib.Path) -> dict:
    """One NEES Monte-Carlo test case; the fractions of time inside the 95 % band."""
    exe = program(build, "vio_core_nees_sim_test", "tests/vio_core")
    try:
        _run([exe, f"--gtest_filter={p['test']}"], log)
        failed = None
    except TaskError as exc:
        failed = exc
    text = log.read_text()
    res: Dict[str, float] = {}
    for line in text.splitlines():
        if "inside:" in line:
            for part in line.split("inside:")[1].split(","):
                key, _, val = part.strip().partition(" ")
                res[f"nees_inside_{key}"] = float(val)
    if failed:
        raise TaskError(f"{failed} ({', '.join(f'{k} {v:.3f}' for k, v in res.items())})")
    return res


def execute(task: dict, out: str, build: str) -> dict:
    """Run one task, write its record (recorded tasks) and return it. Never raises: a failure
    is a record with status 'failed' and a one-line error, so the batch carries on."""
    out_p, build_p = pathlib.Path(out), pathlib.Path(build)
    tid, kind, p = task["id"], task["kind"], task["params"]
    log = out_p / "logs" / f"{tid}.log"
    log.parent.mkdir(parents=True, exist_ok=True)
    log.write_text("")
    rec = {"id": tid, "kind": kind, **{k: v for k, v in p.items() if not isinstance(v, (dict, list))},
           **{f"param.{k}": v for k, v in p.get("overrides", {}).items()},
           "host": socket.gethostname(), "log": str(log)}
    t0 = time.time()
    try:
        if kind == "simulate":
            metrics = do_simulate(p, out_p, build_p, log)
        elif kind == "estimate":
            metrics = do_estimate(p, out_p, build_p, log, tid)
        elif kind == "massid_generate":
            metrics = do_massid_generate(p, out_p, build_p, log)
        elif kind == "massid_merge":
            metrics = do_massid_merge(p, out_p)
        elif kind == "massid_run":
            metrics = do_massid_run(p, out_p, build_p, log, tid)
        elif kind == "massid_report":
            metrics = do_massid_report(p, out_p, build_p, log)
        elif kind == "nees":
            metrics = do_nees(p, out_p, build_p, log)
        else:
            raise TaskError(f"unknown task kind {kind!r}")
        rec.update(metrics, status="ok", error=None)
    except TaskError as exc:
        rec.update(status="failed", error=str(exc))
    except Exception as exc:  # a scoring or I/O bug must not stop the other runs
        rec.update(status="failed", error=f"{type(exc).__name__}: {exc}".splitlines()[0])
    rec["wall_s"] = time.time() - t0
    rec["finished_unix"] = time.time()
    if task.get("recorded", True):
        write_json_atomic(record_path(out_p, tid), rec)
    return rec
