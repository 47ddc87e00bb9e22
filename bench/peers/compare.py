#!/usr/bin/env python3
"""VID-MSCKF (build/bin/vid_run) against OpenVINS (build-peers/bin/ov_driver), side by side.

For every sequence, camera setup (stereo, mono) and repeat, both estimators run one after the
other on the same single core (``taskset -c CORE``) under ``/usr/bin/time -v``; the table has

    sequence, mode, ATE (posyaw and se3) and RPE ours/theirs, median and p95 ms per frame,
    peak RSS, speed ratio (theirs / ours, median ms per frame)

* ATE/RPE: vid_eval (the code of ``vid-eval traj``), both trajectories evaluated at the same
  camera-frame times (ours is written at IMU rate: it is sampled at the frames OpenVINS has an
  estimate for, so both cover the same span). RPE: translation RMSE [m] over sub-trajectories
  of 10 % of the ground-truth path, after the posyaw alignment.
* ms per frame: per-frame wall time from "decoded images in memory" to "state out" (ours:
  ``timing.csv`` total, which excludes PNG decoding; ov_driver decodes before its timer too),
  frames after initialization; median / p95 over frames, then the median over repeats.
* peak RSS and whole-process wall time: ``/usr/bin/time -v`` of the whole process (both decode
  images inline on the one core: ``vid_run --decode-threads 0``).
* the 1-minute load average before every run is recorded; the table states the largest.

    .venv/bin/python bench/peers/compare.py [--sequences a,b] [--repeats 3] [--core 1]
        [--work build-peers/compare] [--doc docs/peers.md]

VID-Fusion (``--what vf``; build-peers/bin/vidfusion_driver, bench/peers/vidfusion): on the
VID-like sequences with rotor data (default vid17_like, vid18_like, vid_loaded, rope_snap,
impacts) ours in dynamics mode (mono, the same sensors as VID-Fusion, and stereo) and
VID-Fusion run on the same core; the table is laid out like the seed report's tables 4/5:
force RMSE (world, gauge-free: ``vid-eval force``, the estimate rotated into the ground truth's
world by the posyaw trajectory alignment) and ATE of both, "decrease %" of ours vs VID-Fusion,
force lag (``vid-eval force`` response), ms per frame. Both are scored over the same span
(from VID-Fusion's first estimate to the end) and ATE at the same camera-frame times. Force
plots (truth, ours, VID-Fusion): ``WORK/plots/vf_*.png``.

    .venv/bin/python bench/peers/compare.py --what vf [--vf-sequences a,b] [--repeats 3] [--core 1]
        [--doc docs/peers.md]

Missing sequences are simulated first (``vid_sim --scenario config/sim/X.yaml --seed <preset
seed> --duration 60``; fast_yaw keeps its 20 s). ``--doc`` replaces the block between
``<!-- peers-table:begin -->`` and ``<!-- peers-table:end -->`` in that file.
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from compare_vf import render_saved, run_vf  # noqa: E402
from peers_common import (DEFAULT_SEQS, ROOT, VF_SEQS, ensure_sequence, eval_pair, fmt, frame_ms,  # noqa: E402
                          loadavg, mono_preset, publish_table, timed)


def plot(args, key: str, ev: dict, t_ours: np.ndarray, t_ov: np.ndarray | None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pdir = args.work / "plots"
    pdir.mkdir(exist_ok=True)
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    gt = ev["gt"]
    ax[0].plot(gt.p[:, 0], gt.p[:, 1], "k-", lw=1, label="ground truth")
    ax[0].plot(ev["ours"]["_aligned"].p[:, 0], ev["ours"]["_aligned"].p[:, 1], "-", lw=1,
               label=f"VID-MSCKF (ATE {ev['ours']['ate_posyaw_m']:.3f} m)")
    if "ov" in ev:
        ax[0].plot(ev["ov"]["_aligned"].p[:, 0], ev["ov"]["_aligned"].p[:, 1], "-", lw=1,
                   label=f"OpenVINS (ATE {ev['ov']['ate_posyaw_m']:.3f} m)")
    ax[0].set_aspect("equal")
    ax[0].set_xlabel("x [m]")
    ax[0].set_ylabel("y [m]")
    ax[0].set_title(f"{key}: top view, posyaw-aligned")
    ax[0].legend(fontsize=8)
    ax[1].plot(t_ours, ".", ms=2, label="VID-MSCKF")
    if t_ov is not None:
        ax[1].plot(t_ov, ".", ms=2, label="OpenVINS")
    ax[1].set_yscale("log")
    ax[1].set_xlabel("frame after initialization")
    ax[1].set_ylabel("wall ms per frame (one core)")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(pdir / f"{key}.png", dpi=90)
    plt.close(fig)


# ------------------------------------------------------------------------------ VID-Fusion


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sequences", default=",".join(DEFAULT_SEQS))
    ap.add_argument("--setups", default="stereo,mono", help="stereo,mono")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--core", type=int, default=1, help="CPU both estimators are pinned to")
    ap.add_argument("--bin", type=pathlib.Path, default=ROOT / "build" / "bin",
                    help="folder with vid_sim and vid_run (the project's build)")
    ap.add_argument("--ov", type=pathlib.Path, default=ROOT / "build-peers" / "bin" / "ov_driver")
    ap.add_argument("--seq-dir", type=pathlib.Path, default=ROOT / "build-peers" / "seq")
    ap.add_argument("--work", type=pathlib.Path, default=ROOT / "build-peers" / "compare")
    ap.add_argument("--no-dynamics", action="store_true", help="skip the extra ours-dynamics rows")
    ap.add_argument("--doc", type=pathlib.Path, default=None, help="markdown file to put the table in")
    ap.add_argument("--ov-args", default="", help="extra ov_driver arguments (e.g. '--set k=v')")
    ap.add_argument("--render", default=None, metavar="W1,W2",
                    help="only write the table from the results.json of these work folders "
                         "(e.g. two halves of the sequence list run on two cores)")
    ap.add_argument("--what", choices=("ov", "vf"), default="ov",
                    help="ov: the OpenVINS table (default); vf: the VID-Fusion table")
    ap.add_argument("--vf", type=pathlib.Path, default=ROOT / "build-peers" / "bin" / "vidfusion_driver")
    ap.add_argument("--vf-sequences", default=",".join(VF_SEQS))
    ap.add_argument("--vf-setups", default="mono,stereo",
                    help="our camera setups compared with VID-Fusion (which is mono)")
    ap.add_argument("--vf-args", default="", help="extra vidfusion_driver arguments")
    args = ap.parse_args()
    if args.what == "vf":
        return render_saved(args) if args.render else run_vf(args)
    if args.render:
        rows, meta = [], []
        for w in args.render.split(","):
            data = json.loads((pathlib.Path(w) / "results.json").read_text())
            meta.append(data.pop("_meta"))
            rows.extend(data.values())
        return render(args, rows, meta)
    args.work.mkdir(parents=True, exist_ok=True)
    mono = mono_preset(args)
    seqs = [s for s in args.sequences.split(",") if s]
    setups = [s for s in args.setups.split(",") if s]
    budget = ["--num-pts", "150", "--clones", "11", "--max-msckf", "60"]  # = config/sim (ours)

    rows, raw = [], {}
    max_load = 0.0
    t_start = time.time()
    for name in seqs:
        seq = ensure_sequence(args, name)
        has_rotors = (seq / "mav0" / "rotor0").exists()
        for setup in setups:
            cams = 2 if setup == "stereo" else 1
            variants = [("imu", True)]
            if setup == "stereo" and has_rotors and not args.no_dynamics:
                variants.append(("dynamics", False))
            for mode, with_ov in variants:
                key = f"{name}_{setup}_{mode}"
                runs = {"ours": [], "ov": []}
                for rep in range(args.repeats):
                    od = args.work / key / f"ours_{rep}"
                    cmd = [str(args.bin / "vid_run"), "--dataset", str(seq), "--out", str(od),
                           "--config", str(ROOT / "config" / "sim" if cams == 2 else mono),
                           "--mode", mode, "--decode-threads", "0", "--quiet"]
                    od.mkdir(parents=True, exist_ok=True)
                    r = timed(args, cmd, od / "run.log")
                    r["ms"] = frame_ms(od / "timing.csv", True)
                    r["dir"] = od
                    runs["ours"].append(r)
                    max_load = max(max_load, r["load_before"])
                    if with_ov:
                        vd = args.work / key / f"ov_{rep}"
                        vd.mkdir(parents=True, exist_ok=True)
                        cmd = [str(args.ov), "--dataset", str(seq), "--out", str(vd), "--cams", str(cams)] \
                            + budget + args.ov_args.split()
                        r = timed(args, cmd, vd / "run.log")
                        r["ms"] = frame_ms(vd / "timing.csv", False) if (vd / "timing.csv").exists() else np.array([])
                        r["dir"] = vd
                        runs["ov"].append(r)
                        max_load = max(max_load, r["load_before"])
                    print(f"[compare] {key} rep {rep}: ours {np.median(runs['ours'][-1]['ms']):.2f} ms"
                          + (f", ov {np.median(runs['ov'][-1]['ms']) if len(runs['ov'][-1]['ms']) else float('nan'):.2f} ms"
                             if with_ov else "") + f" (load {loadavg():.2f})", flush=True)
                ev = eval_pair(seq, runs["ours"][0]["dir"], runs["ov"][0]["dir"] if with_ov else None)

                def agg(rs):
                    if not rs or any(len(r["ms"]) == 0 for r in rs):
                        return None
                    sj = rs[0]["dir"] / "summary.json"
                    ov_sum = json.loads(sj.read_text()) if sj.exists() else {}
                    return {"median_ms": float(np.median([np.median(r["ms"]) for r in rs])),
                            "p95_ms": float(np.median([np.percentile(r["ms"], 95) for r in rs])),
                            "peak_rss_mb": max(r["peak_rss_kb"] for r in rs) / 1024.0,
                            "wall_s": float(np.median([r["wall_s"] for r in rs])),
                            "cpu_s": float(np.median([r["cpu_s"] for r in rs])),
                            "rc": [r["rc"] for r in rs], "frames": int(len(rs[0]["ms"])),
                            "features_per_update": ov_sum.get("mean_msckf_features_per_update"),
                            "slam_features": ov_sum.get("mean_slam_features"),
                            "init_after_s": ov_sum.get("init_after_s")}
                o, v = agg(runs["ours"]), agg(runs["ov"]) if with_ov else None
                plot(args, key, ev, runs["ours"][0]["ms"], runs["ov"][0]["ms"] if with_ov else None)
                row = {"sequence": name, "setup": setup, "mode": mode, "ours": o, "ov": v,
                       "eval_ours": {k: x for k, x in ev["ours"].items() if not k.startswith("_")},
                       "eval_ov": {k: x for k, x in ev.get("ov", {}).items() if not k.startswith("_")}}
                rows.append(row)
                raw[key] = row
                raw["_meta"] = {"core": args.core, "repeats": args.repeats, "max_load": max_load,
                                "minutes": (time.time() - t_start) / 60, "ended": time.strftime("%Y-%m-%d %H:%M")}
                (args.work / "results.json").write_text(json.dumps(raw, indent=1, default=float))
                raw.pop("_meta")
    return render(args, rows, [{"core": args.core, "repeats": args.repeats, "max_load": max_load,
                                "minutes": (time.time() - t_start) / 60, "ended": time.strftime("%Y-%m-%d %H:%M")}])


def render(args, rows, meta) -> int:
    max_load = max(m["max_load"] for m in meta)
    cores = ",".join(sorted({str(m["core"]) for m in meta}))
    repeats = min(m["repeats"] for m in meta)

    lines = []
    cpu = "unknown"
    for ln in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if ln.startswith("model name"):
            cpu = ln.split(":", 1)[1].strip()
            break
    lines.append(f"Machine: {cpu}, {os.cpu_count()} cores, Linux {platform.release()}; both estimators "
                 f"pinned to the same core (`taskset -c {cores}`"
                 + ("; one sequence list per core" if len(meta) > 1 else "") + "), "
                 f"{repeats} repeat(s), largest 1-min load average before a run: {max_load:.2f}"
                 + (" (**provisional: above 1.2, other processes shared the machine**)" if max_load > 1.2 else "")
                 + f"; ended {max(m['ended'] for m in meta)}, {max(m['minutes'] for m in meta):.0f} min.")
    lines.append("")
    lines.append("| sequence | mode | ATE posyaw [m] ours / OV | ATE se3 [m] ours / OV | RPE [m] (d) ours / OV "
                 "| median ms/frame ours / OV | p95 ms/frame ours / OV | peak RSS [MB] ours / OV "
                 "| wall [s] ours / OV | process CPU [s] ours / OV | speed ratio (ms/frame; CPU) "
                 "| OV MSCKF feats/update (SLAM) |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        o, v, eo, ev_ = r["ours"], r["ov"], r["eval_ours"], r["eval_ov"]
        mode = f"{r['setup']} {r['mode']}" + ("" if v is not None or r["mode"] == "imu" else " (ours only)")

        def pair(a, b, p=3):
            return f"{fmt(a, p)} / {fmt(b, p)}" if r["ov"] is not None or b is not None else fmt(a, p)
        ratio = (fmt(v["median_ms"] / o["median_ms"], 1) + "x; " + fmt(v["cpu_s"] / o["cpu_s"], 1) + "x"
                 if (o and v) else "-")
        feats = (f"{v['features_per_update']:.1f} ({v['slam_features']:.1f})" if v and v.get("features_per_update") is not None
                 else "-")
        lines.append(
            f"| {r['sequence']} | {mode} "
            f"| {pair(eo.get('ate_posyaw_m'), ev_.get('ate_posyaw_m'))} "
            f"| {pair(eo.get('ate_se3_m'), ev_.get('ate_se3_m'))} "
            f"| {pair(eo.get('rpe_trans_rmse_m'), ev_.get('rpe_trans_rmse_m'))} ({eo.get('rpe_d_m') or '-'} m) "
            f"| {pair(o and o['median_ms'], v and v['median_ms'], 2)} "
            f"| {pair(o and o['p95_ms'], v and v['p95_ms'], 2)} "
            f"| {pair(o and o['peak_rss_mb'], v and v['peak_rss_mb'], 0)} "
            f"| {pair(o and o['wall_s'], v and v['wall_s'], 1)} "
            f"| {pair(o and o['cpu_s'], v and v['cpu_s'], 1)} "
            f"| {ratio} | {feats} |")
    table = "\n".join(lines) + "\n"
    publish_table(table, args.work / "table.md", args.doc, "peers-table")
    return 0


if __name__ == "__main__":
    sys.exit(main())
