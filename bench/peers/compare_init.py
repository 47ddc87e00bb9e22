#!/usr/bin/env python3
"""Mid-flight starts: our in-flight initializer against OpenVINS's dynamic initializer (issue #49).

For every rendered sequence and start S, both estimators start from the data at S (``vid_run
--start S --init auto``, ``ov_driver --start S --set init_dyn_use=true``) on the same images,
each with its own frontend, and run to S + SECONDS (fast_yaw: S + 7 s of its 20 s). Per run:
whether and when it initialized (seconds of data after S until its first estimate), and the
posyaw ATE of both over the same span, from the later of the two initializations to S + SECONDS (``vid_eval`` on the estimates in
that span, each trajectory on its own times; ``-`` where one did not initialize).

OpenVINS: the driver's settings of the simulated peer tables (bench/peers/README.md) with its
dynamic initializer on, its EuRoC initialization window (``init_window_time`` 2 s, 6 poses, 10 deg
of rotation needed, MLE refinement on) and no zero-velocity updates; ``--ov-window 1`` runs it with
our 1 s window as well. Sequences: ``vid_sim --scenario config/sim/X.yaml --seed 1 --duration 60``
(rendered, not ``--features-only``); fast_yaw keeps its 20 s.

    .venv/bin/python bench/peers/compare_init.py --data /tmp/ovd --sequences vid17_like,fast_yaw \\
        --starts 10,20,30 [--fast-yaw-starts 5,8,12] [--seconds 12] [--work build-peers/init]
"""
from __future__ import annotations

import argparse
import json
import pathlib
import subprocess
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "eval"))
from vid_eval.core.ate import compute_ate  # noqa: E402
from vid_eval.tools.loaders import dataset_first_time_ns, load_trajectory  # noqa: E402


def run(cmd: list[str]) -> int:
    print("+ " + " ".join(cmd), file=sys.stderr, flush=True)
    return subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode


def first_pose_ns(traj: pathlib.Path) -> int | None:
    for line in traj.read_text().splitlines() if traj.exists() else []:
        if line and not line.startswith("#"):
            return int(round(float(line.split()[0]) * 1e9))
    return None


def ate_in_span(traj: pathlib.Path, gt: pathlib.Path, t0_ns: int, t1_ns: int, work: pathlib.Path) -> float | None:
    keep = [ln for ln in traj.read_text().splitlines()
            if ln and not ln.startswith("#") and t0_ns <= round(float(ln.split()[0]) * 1e9) <= t1_ns]
    if len(keep) < 10:
        return None
    part = work / (traj.parent.name + "_span.txt")
    part.write_text("\n".join(keep) + "\n")
    r = compute_ate(load_trajectory(part), load_trajectory(gt), "posyaw")
    return r.pos_rmse


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=pathlib.Path, required=True, help="folder of rendered sequences (one per name)")
    ap.add_argument("--sequences", default="vid17_like,vid18_like,euroc_like,rope_snap,vid17_real_sensors,fast_yaw")
    ap.add_argument("--starts", default="10,20,30,45")
    ap.add_argument("--fast-yaw-starts", default="5,8,12")
    ap.add_argument("--seconds", type=float, default=12.0)
    ap.add_argument("--fast-yaw-seconds", type=float, default=7.0, help="fast_yaw is 20 s long")
    ap.add_argument("--ov-window", default="2", help="OpenVINS init_window_time values, comma-separated")
    ap.add_argument("--vid-run", type=pathlib.Path, default=ROOT / "build" / "bin" / "vid_run")
    ap.add_argument("--ov", type=pathlib.Path, default=ROOT / "build-peers" / "bin" / "ov_driver")
    ap.add_argument("--work", type=pathlib.Path, default=ROOT / "build-peers" / "init")
    a = ap.parse_args()
    for exe in (a.vid_run, a.ov):
        if not exe.exists():
            ap.error(f"{exe}: not built (bench/peers/openvins/build.sh builds ov_driver)")
    a.work.mkdir(parents=True, exist_ok=True)
    rows = []
    for name in a.sequences.split(","):
        ds = a.data / name
        if not (ds / "mav0" / "cam0").is_dir():
            ap.error(f"{ds}: no rendered sequence (vid_sim --scenario config/sim/{name}.yaml --seed 1 --duration 60)")
        gt = ds / "mav0" / "state_groundtruth_estimate0" / "data.csv"
        t0 = dataset_first_time_ns(ds)
        starts = a.fast_yaw_starts if name == "fast_yaw" else a.starts
        seconds = a.fast_yaw_seconds if name == "fast_yaw" else a.seconds
        for s in (float(x) for x in starts.split(",")):
            t_s, t_e = t0 + int(s * 1e9), t0 + int((s + seconds) * 1e9)
            runs = {}
            o = a.work / f"ours_{name}_{s:g}"
            run([str(a.vid_run), "--dataset", str(ds), "--out", str(o), "--config", str(ROOT / "config" / "sim"),
                 "--quiet", "--init", "auto", "--start", f"{s:g}", "--end", f"{s + seconds:g}"])
            runs["ours"] = o
            for w in a.ov_window.split(","):
                o = a.work / f"ov{w}_{name}_{s:g}"
                run([str(a.ov), "--dataset", str(ds), "--out", str(o), "--cams", "2", "--start", f"{s:g}",
                     "--set", "init_dyn_use=true", "--set", "try_zupt=false", "--set", f"init_window_time={w}"])
                runs[f"OpenVINS (window {w} s)"] = o
            # Initialized = a first estimate before S + seconds (OpenVINS runs on to the data's end).
            first = {k: first_pose_ns(v / "trajectory_tum.txt") for k, v in runs.items()}
            first = {k: f if f is not None and f <= t_e else None for k, f in first.items()}
            common = max([f for f in first.values() if f is not None], default=None)
            for k, v in runs.items():
                f = first[k]
                ok = f is not None
                ate = ate_in_span(v / "trajectory_tum.txt", gt, common, t_e, a.work) if ok else None
                row = {"sequence": name, "start": s, "estimator": k, "initialized": ok,
                       "init_after_s": (f - t_s) * 1e-9 if ok else None, "ate_common_m": ate,
                       "span_s": (t_e - common) * 1e-9 if common else None}
                print(json.dumps(row), flush=True)
                rows.append(row)
    (a.work / "results.json").write_text(json.dumps(rows, indent=1))
    print("\n| estimator | initialized | after [s], median (max) | ATE over the common span [m], median (max) |")
    print("|---|---|---|---|")
    for k in dict.fromkeys(r["estimator"] for r in rows):
        rs = [r for r in rows if r["estimator"] == k]
        ok = [r for r in rs if r["initialized"]]
        d = [r["init_after_s"] for r in ok]
        e = [r["ate_common_m"] for r in ok if r["ate_common_m"] is not None]
        fmt = lambda v: f"{np.median(v):.2f} ({np.max(v):.2f})" if v else "-"  # noqa: E731
        fmt3 = lambda v: f"{np.median(v):.4f} ({np.max(v):.4f})" if v else "-"  # noqa: E731
        print(f"| {k} | {len(ok)}/{len(rs)} | {fmt(d)} | {fmt3(e)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
