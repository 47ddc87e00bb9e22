"""``vid-batch report DIR``: statistics per group, seed-style tables and box plots.

Groups of estimator runs = (scenario, configuration), configuration = estimator plus the
grid's parameter values; the seeds of a group are its samples. Tables reuse vid-eval's
comparison tables (vid_eval.tools.tables: mean over repeats, scenario x configuration).
"""
from __future__ import annotations

import math
import pathlib
from typing import Dict, List, Tuple

import numpy as np

from ..tools.runs import Run
from ..tools.sim_runs import yaml_scalar
from ..tools.tables import build_table, to_markdown

# (column, label, unit) of the estimator runs' metrics that get tables and plots.
METRICS = [("ate_m", "ATE", "m"), ("force_rmse_world", "Force RMSE (world)", "m/s²"),
           ("att_err_max_deg", "Max attitude error", "deg"), ("run_s", "vid_run wall time", "s")]


def _scenario(r: dict) -> str:
    if r.get("preset"):
        return r["preset"] + (f" {r['duration']:g} s" if r.get("duration") else "")
    return str(r.get("sequence"))


def _config(r: dict) -> str:
    params = sorted((k[6:], v) for k, v in r.items() if k.startswith("param."))
    return " ".join([str(r.get("estimator"))] + [f"{k}={yaml_scalar(v)}" for k, v in params])


def _stats(vals: List[float]) -> Tuple[float, float, float]:
    a = np.asarray(vals, float)
    return float(np.mean(a)), float(np.median(a)), float(np.percentile(a, 95))


def _fmt(x) -> str:
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.4g}"


def group_stats(records: List[dict]) -> List[dict]:
    """mean / median / p95 of every metric per (scenario, configuration) of the ok runs, or per
    task kind for the other jobs (mass-ID, NEES)."""
    groups: Dict[Tuple[str, str], List[dict]] = {}
    for r in records:
        if r.get("status") != "ok":
            continue
        key = (_scenario(r), _config(r)) if r.get("kind") == "estimate" else (r.get("kind"), r["id"])
        groups.setdefault(key, []).append(r)
    rows = []
    for (scen, cfg), rs in groups.items():
        numeric = sorted({k for r in rs for k, v in r.items() if isinstance(v, (int, float))
                          and not isinstance(v, bool) and k not in ("seed", "duration", "finished_unix")})
        for k in numeric:
            vals = [r[k] for r in rs if isinstance(r.get(k), (int, float)) and r[k] is not None]
            if vals:
                mean, med, p95 = _stats(vals)
                rows.append({"group": scen, "config": cfg, "metric": k, "n": len(vals),
                             "mean": mean, "median": med, "p95": p95})
    return rows


def _box_figure(plt, rows: List[dict], labels: List[str], label_of, title: str, path: pathlib.Path) -> None:
    """One box per label and metric: the metric's values of the rows with that label."""
    fig, axes = plt.subplots(1, len(METRICS), figsize=(4 * len(METRICS), 3.5 + 0.15 * len(labels)))
    for ax, (key, label, unit) in zip(axes, METRICS):
        data = [[r[key] for r in rows if label_of(r) == lab and r.get(key) is not None] for lab in labels]
        ax.boxplot([d if d else [np.nan] for d in data], vert=False)
        ax.set_yticks(range(1, len(labels) + 1), labels, fontsize=7)
        ax.set_title(f"{label} [{unit}]", fontsize=9)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _boxplots(records: List[dict], out: pathlib.Path) -> List[pathlib.Path]:
    """Per scenario: each metric's distribution over seeds per configuration; per grid parameter:
    the metric against the parameter's values (all scenarios pooled)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ok = [r for r in records if r.get("kind") == "estimate" and r.get("status") == "ok"]
    out.mkdir(parents=True, exist_ok=True)
    written: List[pathlib.Path] = []

    def unique(name: str) -> pathlib.Path:  # two labels may map to one file name: never overwrite
        path, n = out / f"{name}.png", 2
        while path in written:
            path, n = out / f"{name}_{n}.png", n + 1
        return path

    for scen in sorted({_scenario(r) for r in ok}):
        rs = [r for r in ok if _scenario(r) == scen]
        path = unique(f"box_preset_{scen.replace(' ', '_')}")
        _box_figure(plt, rs, sorted({_config(r) for r in rs}), _config, f"{scen}: {len(rs)} runs", path)
        written.append(path)
    for param in sorted({k for r in ok for k in r if k.startswith("param.")}):
        path = unique(f"box_param_{param[6:]}")
        _box_figure(plt, ok, sorted({yaml_scalar(r[param]) for r in ok if param in r}), lambda r: yaml_scalar(r.get(param)),
                    f"{param[6:]} (all scenarios)", path)
        written.append(path)
    return written


def report(records: List[dict], out: pathlib.Path) -> str:
    """Write OUT/report/{summary.md, stats.csv, *.png}; return the Markdown printed."""
    rep = out / "report"
    rep.mkdir(parents=True, exist_ok=True)
    stats = group_stats(records)
    lines = ["# vid-batch report", "", f"{len(records)} runs, "
             f"{sum(r.get('status') == 'ok' for r in records)} ok.", ""]
    est = [r for r in records if r.get("kind") == "estimate" and r.get("status") == "ok"]
    runs = [Run(_config(r), _scenario(r), r["id"], {k: float(r[k]) for k, _, _ in METRICS
                                                      if isinstance(r.get(k), (int, float))}) for r in est]
    for key, label, unit in METRICS:
        t = build_table(runs, key, f"{label} [{unit}], mean over seeds", unit)
        if t.sequences:
            lines += [to_markdown(t, 4)]
    lines += ["## mean / median / p95 per group", "", "| group | config | metric | n | mean | median | p95 |",
              "|---|---|---|---:|---:|---:|---:|"]
    lines += [f"| {s['group']} | {s['config']} | {s['metric']} | {s['n']} | {_fmt(s['mean'])} | "
              f"{_fmt(s['median'])} | {_fmt(s['p95'])} |" for s in stats]
    failed = [r for r in records if r.get("status") != "ok"]
    if failed:
        lines += ["", "## failed", ""] + [f"* {r['id']}: {r.get('error')}" for r in failed]
    md = "\n".join(lines) + "\n"
    (rep / "summary.md").write_text(md)
    with open(rep / "stats.csv", "w") as f:
        f.write("group,config,metric,n,mean,median,p95\n")
        for s in stats:
            f.write(f"\"{s['group']}\",\"{s['config']}\",{s['metric']},{s['n']},{s['mean']!r},"
                    f"{s['median']!r},{s['p95']!r}\n")
    _boxplots(records, rep)
    return md
