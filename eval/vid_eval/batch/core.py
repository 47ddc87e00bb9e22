"""Scheduling a batch on Ray: skip what is done, submit the rest with declared resources,
follow the progress, write the results table.

Ray is imported here only (and lazily by the CLI), so vid-eval and the C++ never need it.
"""
from __future__ import annotations

import dataclasses
import pathlib
import sys
import time
from typing import Dict, List, Optional

from .spec import Task, task_order
from .table import write_table
from .tools import execute, read_record, write_json_atomic, record_path


def _remote_execute(ray):
    @ray.remote(num_cpus=1)
    def run_task(task: dict, out: str, build: str, *deps: dict) -> dict:
        # A dependency that failed fails this task without running it (one-line reason).
        bad = [d for d in deps if d.get("status") != "ok"]
        if bad:
            rec = {"id": task["id"], "kind": task["kind"], "status": "failed", "wall_s": 0.0,
                   "error": f"dependency {bad[0]['id']} failed: {bad[0].get('error')}"}
            if task.get("recorded", True):
                write_json_atomic(record_path(pathlib.Path(out), task["id"]), rec)
            return rec
        return execute(task, out, build)
    return run_task


def init_ray(address: Optional[str], workers: Optional[int]):
    """``ray.init`` on this machine (``workers`` CPUs, default all) or joining ``address``."""
    import ray
    kw = dict(include_dashboard=False, log_to_driver=False, configure_logging=False)
    if address:
        ray.init(address=address, **kw)
    else:
        ray.init(num_cpus=workers, **kw)
    return ray


def run_batch(tasks: List[Task], out: pathlib.Path, build: pathlib.Path, address: Optional[str] = None,
              workers: Optional[int] = None, progress: bool = True) -> Dict[str, dict]:
    """Run every task not already finished with status ok; return all records by id."""
    from tqdm import tqdm

    tasks = task_order(tasks)
    out.mkdir(parents=True, exist_ok=True)
    done: Dict[str, dict] = {}
    for t in tasks:
        rec = read_record(out, t.id) if t.recorded else None
        if rec is not None and rec.get("status") == "ok":
            done[t.id] = rec
    todo = [t for t in tasks if t.id not in done]
    n_runs = sum(t.recorded for t in tasks)
    n_todo = sum(t.recorded for t in todo)
    print(f"vid-batch: {n_runs} runs: {n_runs - n_todo} already done, {n_todo} to run", flush=True)
    if todo:
        ray = init_ray(address, workers)
        try:
            run_task = _remote_execute(ray)
            refs, meta = {}, {}
            for t in todo:  # plan order: dependencies are submitted first
                deps = [refs[d] for d in t.deps if d in refs]
                ref = run_task.options(memory=t.memory_mb * 2 ** 20, name=t.id).remote(
                    dataclasses.asdict(t), str(out), str(build), *deps)
                refs[t.id] = ref
                meta[ref] = t
            pending = list(refs.values())
            bar = tqdm(total=n_todo, unit="run", disable=not progress, file=sys.stderr, smoothing=0.1)
            while pending:
                ready, pending = ray.wait(pending, num_returns=1)
                t = meta[ready[0]]
                rec = ray.get(ready[0])
                if t.recorded:
                    done[t.id] = rec
                    bar.update(1)
                    if rec.get("status") != "ok":
                        bar.write(f"vid-batch: {t.id}: failed: {rec.get('error')}")
            bar.close()
        finally:
            ray.shutdown()
    records = {t.id: done[t.id] for t in tasks if t.recorded and t.id in done}
    write_table(list(records.values()), out)
    return records


def summarize(records: Dict[str, dict], out: pathlib.Path, ran: Optional[float] = None) -> int:
    """Print the failures (one line each) and the table paths; 1 if any run failed."""
    failed = [r for r in records.values() if r.get("status") != "ok"]
    for r in failed:
        print(f"  FAILED {r['id']}: {r.get('error')} (log: {r.get('log', '-')})")
    took = f" in {ran:.1f} s" if ran is not None else ""
    print(f"vid-batch: {len(records) - len(failed)} ok, {len(failed)} failed{took}; "
          f"table: {out / 'results.parquet'} and {out / 'results.csv'}")
    return 1 if failed else 0


def timed_run(tasks: List[Task], out: pathlib.Path, build: pathlib.Path, **kw) -> int:
    """run_batch + summarize with the wall time."""
    t0 = time.time()
    records = run_batch(tasks, out, build, **kw)
    return summarize(records, out, time.time() - t0)
