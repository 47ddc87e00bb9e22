#!/usr/bin/env python3
"""Accuracy of vid_run over simulator presets x seeds x estimator configurations, as one table.

For each preset and seed: vid_sim writes the sequence once (features only unless --images;
--no-noise for noise-free copies); for each configuration vid_run estimates it; the scores
come from vid_eval (the same code as `vid-eval traj` / `vid-eval force`):

* ATE [m] (posyaw), world-frame force RMSE [m/s^2] (gauge-free: rotated by the alignment),
* max attitude error after --skip seconds [deg] (after the alignment),
* force lag [ms] (cross-correlation) and step settling (median / max [s], # not settled),
* the online time offset at the end when it is estimated: error against the simulator's [ms],
  its sigma and NEES,
* accelerometer samples rejected and down-weighted (fractions) and force jumps detected (vid_run's
  summary).

A configuration is NAME=DIR[:KEY=VALUE,...]: an estimator preset folder (as vid_run --config)
plus estimator.yaml keys that override it (written to a temporary copy). Example, the
before/after table of a default change:

  .venv/bin/python scripts/preset_sweep.py --presets vid17_like rope_snap --seeds 1 2 3 \\
      --config before=config/sim:force_jump_detection=false --config after=config/sim \\
      --out /tmp/sweep

Writes OUT/results.json and OUT/table.md; prints the table (mean over seeds, worst in brackets).
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import os
import pathlib
import subprocess
import sys
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "eval"))

from vid_eval.tools.sim_runs import config_with_overrides, resolve_path, score_run, simulate  # noqa: E402


def _bin(build: pathlib.Path, name: str) -> str:
    path = build / "bin" / name
    if not path.exists():
        sys.exit(f"preset_sweep: error: {path} not built (run scripts/build.sh)")
    return str(path)


def _config_dir(spec: str, work: pathlib.Path) -> tuple[str, pathlib.Path]:
    """NAME=DIR[:KEY=VALUE,...] -> (name, folder with the overrides applied)."""
    if "=" not in spec:
        sys.exit(f"preset_sweep: error: --config '{spec}': expected NAME=DIR[:KEY=VALUE,...]")
    name, rest = spec.split("=", 1)
    folder, _, over = rest.partition(":")
    src = resolve_path(folder)
    if not src.is_dir():
        sys.exit(f"preset_sweep: error: --config '{spec}': no folder {src}")
    overrides = dict(kv.partition("=")[::2] for kv in over.split(",")) if over else {}
    return name, config_with_overrides(src, overrides, work / f"config_{name}")


def _job(args, build, work, preset, seed, noise_free, configs):
    tag = f"{preset}_seed{seed}{'_nonoise' if noise_free else ''}{'_img' if args.images else ''}"
    seq = work / "seq" / tag
    simulate(_bin(build, "vid_sim"), preset, seed, seq, args.images, noise_free, args.duration)
    rows = []
    for name, cfg in configs:
        run = work / "run" / f"{tag}__{name}"
        t0 = time.time()
        proc = subprocess.run([_bin(build, "vid_run"), "--dataset", str(seq), "--out", str(run), "--config",
                               str(cfg), "--quiet", "--decode-threads", "0"], capture_output=True, text=True)
        row = {"preset": preset, "seed": seed, "noise_free": noise_free, "config": name,
               "wall_s": time.time() - t0}
        if proc.returncode != 0:
            row["error"] = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "vid_run failed"
        else:
            row.update(score_run(seq, run, args.skip))
        rows.append(row)
        print(f"[sweep] {tag} {name}: " + ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                                                   for k, v in row.items() if k not in ("preset", "seed",
                                                                                         "noise_free", "config")),
              flush=True)
    return rows


COLUMNS = [("ate_m", "ATE [m]", "{:.4f}", max), ("force_rmse_world", "force RMSE [m/s²]", "{:.3f}", max),
           ("att_err_max_deg", "max att. err [°]", "{:.2f}", max), ("lag_ms", "lag [ms]", "{:.0f}", max),
           ("settling_max_s", "settling max [s]", "{:.2f}", max),
           ("td_err_ms", "t_d err [ms]", "{:+.2f}", lambda v: max(v, key=abs)),
           ("td_sigma_ms", "t_d σ [ms]", "{:.2f}", max), ("td_nees", "t_d NEES", "{:.1f}", max),
           ("accel_rejected_fraction", "accel rejected", "{:.2%}", max),
           ("accel_downweighted_fraction", "accel down-weighted", "{:.2%}", max), ("force_jumps", "jumps", "{:.0f}", max),
           # vid_run --smooth (estimator smoother_lag_s > 0): the fixed-lag smoothed outputs
           ("ate_m_smoothed", "smoothed ATE [m]", "{:.4f}", max),
           ("force_rmse_world_smoothed", "smoothed force RMSE [m/s²]", "{:.3f}", max),
           ("settling_max_s_smoothed", "smoothed settling max [s]", "{:.2f}", max)]


def table(rows: list[dict], configs: list[str]) -> str:
    """Markdown: one line per (preset, noise) and configuration; mean over seeds, worst in brackets."""
    head = "| preset | config | seeds | " + " | ".join(c[1] for c in COLUMNS) + " |"
    lines = [head, "|" + "---|" * (3 + len(COLUMNS))]
    keys = sorted({(r["preset"], r["noise_free"]) for r in rows}, key=lambda k: (k[1], k[0]))
    for preset, nf in keys:
        for cfg in configs:
            sel = [r for r in rows if r["preset"] == preset and r["noise_free"] == nf and r["config"] == cfg]
            cells = []
            for key, _, fmt, worst in COLUMNS:
                vals = [r[key] for r in sel if r.get(key) is not None]
                if not vals:
                    cells.append("–")
                    continue
                cells.append(fmt.format(float(np.mean(vals))) +
                             (f" ({fmt.format(worst(vals))})" if len(vals) > 1 else ""))
            errs = sum(1 for r in sel if "error" in r)
            name = preset + (" (no noise)" if nf else "")
            lines.append(f"| {name} | {cfg} | {len(sel) - errs}{f' ({errs} failed)' if errs else ''} | "
                         + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--presets", nargs="+", required=True, help="scenario names in config/sim/")
    p.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3])
    p.add_argument("--config", action="append", required=True, metavar="NAME=DIR[:K=V,...]")
    p.add_argument("--noise-free", action="store_true", help="also run noise-free copies")
    p.add_argument("--noise-free-only", action="store_true", help="only noise-free copies")
    p.add_argument("--images", action="store_true", help="render images (slow) instead of feat0")
    p.add_argument("--duration", type=float, default=None, help="override the presets' duration [s]")
    p.add_argument("--skip", type=float, default=5.0, help="attitude error counted after S seconds")
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--build", default=os.environ.get("VID_BUILD_DIR", str(REPO / "build")))
    p.add_argument("--out", required=True)
    args = p.parse_args(argv)
    work = pathlib.Path(args.out)
    work.mkdir(parents=True, exist_ok=True)
    build = pathlib.Path(args.build)
    configs = [_config_dir(c, work) for c in args.config]
    noise = [True] if args.noise_free_only else ([False, True] if args.noise_free else [False])
    jobs = [(preset, seed, nf) for preset in args.presets for seed in args.seeds for nf in noise]
    rows: list[dict] = []
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        futures = [ex.submit(_job, args, build, work, pr, sd, nf, configs) for pr, sd, nf in jobs]
        for f in cf.as_completed(futures):
            rows.extend(f.result())
    (work / "results.json").write_text(json.dumps(rows, indent=1) + "\n")
    md = table(rows, [c[0] for c in configs])
    (work / "table.md").write_text(md + "\n")
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
