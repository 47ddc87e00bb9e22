"""The VID-Fusion side of bench/peers/compare.py (``--what vf``, issue #20): runs, scoring
(force RMSE and ATE over the same span, decrease %, force lag), force plots, the seed-shaped
table. GPL note: this file only runs programs; vidfusion_driver (GPL-3) is a separate process."""
from __future__ import annotations

import json
import os
import pathlib
import platform
import subprocess
import sys
import time

import numpy as np

from peers_common import (ROOT, ensure_sequence, eval_pair, fmt, frame_ms, load_trajectory, loadavg, mono_preset,
                          publish_table, timed, trim_rows)


def vid_eval_force(args, force_csv: pathlib.Path, traj: pathlib.Path, seq: pathlib.Path,
                   out_json: pathlib.Path, frame: str = "world") -> dict:
    """The project's force scoring (``vid-eval force``; world: gauge-free, posyaw; body: the
    truth rotated into the body with the ground-truth orientation), this checkout's vid_eval."""
    cmd = [sys.executable, "-m", "vid_eval.cli", "force", str(force_csv), str(seq / "mav0" / "force0" / "data.csv"),
           "--traj", str(traj), "--frame", frame, "--json", str(out_json)]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "eval") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        print(f"[compare] vid-eval force failed on {force_csv}: {r.stderr.strip()}", flush=True)
        return {"force_rmse_mps2": float("nan"), "lag_ms": None}
    j = json.loads(out_json.read_text())
    lag = j.get("response", {}).get("lag_ms", {}).get("combined")
    return {"force_rmse_mps2": j[f"force_rmse_{frame}_mps2"], "lag_ms": lag,
            "rmse_axis_mps2": j["force"].get("rmse_axis"), "pairs": j["force"].get("pairs")}


def plot_forces(args, key: str, seq: pathlib.Path, ours_dir: pathlib.Path, vf_dir: pathlib.Path,
                sc: dict) -> None:
    """Truth, ours and VID-Fusion world force (each rotated into the truth's world with its own
    posyaw trajectory alignment, vid_eval.tools.gauge), one figure."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from vid_eval.core.force_frames import newton_to_accel
    from vid_eval.tools.gauge import rotate_world, world_gauge_from_files
    from vid_eval.tools.loaders import load_force_estimate, load_force_gt, load_vehicle_mass

    gt_traj = seq / "mav0" / "state_groundtruth_estimate0" / "data.csv"
    mass = load_vehicle_mass(seq / "mav0" / "vehicle.yaml")
    truth = newton_to_accel(load_force_gt(seq / "mav0" / "force0" / "data.csv"), mass)
    curves = []
    for name, d, fcsv in (("VID-MSCKF", ours_dir, ours_dir / "force_span.csv"),
                          ("VID-Fusion", vf_dir, vf_dir / "force.csv")):
        _, world = load_force_estimate(fcsv)
        g = world_gauge_from_files(d / "trajectory_tum.txt", gt_traj, "posyaw")
        curves.append((name, rotate_world(world, g)))
    t0 = curves[1][1].t_ns[0]
    fig, ax = plt.subplots(3, 1, figsize=(12, 8), sharex=True)
    m = (truth.t_ns >= t0) & (truth.t_ns <= curves[1][1].t_ns[-1])
    for i, a in enumerate("xyz"):
        ax[i].plot((truth.t_ns[m] - t0) * 1e-9, truth.values[m, i], "k-", lw=1.2, label="truth")
        for (name, ser), st in zip(curves, ("-", "-")):
            ax[i].plot((ser.t_ns - t0) * 1e-9, ser.values[:, i], st, lw=0.8,
                       label=f"{name} (RMSE {sc[name]:.3f} m/s²)" if i == 0 else name)
        ax[i].set_ylabel(f"F_{a} / m [m/s²]")
    ax[0].legend(fontsize=8, loc="upper right")
    ax[0].set_title(f"{key}: external force per unit mass, world (posyaw gauge)")
    ax[2].set_xlabel("s after VID-Fusion's first estimate")
    fig.tight_layout()
    pdir = args.work / "plots"
    pdir.mkdir(parents=True, exist_ok=True)
    fig.savefig(pdir / f"vf_{key}.png", dpi=90)
    plt.close(fig)


def eval_vf_row(args, key: str, seq: pathlib.Path, ours_dirs, vf_dirs) -> dict:
    """Accuracy of ours (repeat 0: deterministic) and of every VID-Fusion repeat (its Ceres
    solver has a wall-clock budget, max_solver_time, so its result varies with the machine's
    load: all repeats are scored, the table gives the median and the range)."""
    od = pathlib.Path(ours_dirs[0])
    per = []
    for rep, vd in enumerate(map(pathlib.Path, vf_dirs)):
        tr = vd / "trajectory_tum.txt"
        if not tr.exists() or tr.stat().st_size == 0:
            per.append(None)
            continue
        ev = eval_pair(seq, od, vd)
        vt = load_trajectory(tr, "tum")
        t0, t1 = int(vt.t_ns[0]), int(vt.t_ns[-1])
        trim_rows(od / "force.csv", od / f"force_span_{rep}.csv", t0, t1)
        fo = vid_eval_force(args, od / f"force_span_{rep}.csv", od / "trajectory_tum.txt", seq,
                            od / f"force_eval_{rep}.json")
        fv = vid_eval_force(args, vd / "force.csv", tr, seq, vd / "force_eval.json")
        per.append({"ate_ours_m": ev["ours"]["ate_posyaw_m"], "ate_vf_m": ev["ov"]["ate_posyaw_m"],
                    "ate_pairs": ev["ours"]["pairs"], "force_ours": fo, "force_vf": fv,
                    "span_s": (t1 - t0) * 1e-9})
        if rep == 0:
            try:
                (od / "force_span.csv").write_text((od / f"force_span_{rep}.csv").read_text())
                plot_forces(args, key, seq, od, vd, {"VID-MSCKF": fo["force_rmse_mps2"],
                                                    "VID-Fusion": fv["force_rmse_mps2"]})
            except Exception as e:  # a plot must not lose the numbers
                print(f"[compare] plot {key}: {e}", flush=True)
    ok = [x for x in per if x is not None]
    out = {"vf_ok": bool(ok), "per_repeat": per}
    if not ok:
        return out

    def med(f):
        v = np.array([f(x) for x in ok], dtype=float)
        v = v[np.isfinite(v)] if np.any(np.isfinite(v)) else v
        return float(np.median(v)), float(np.min(v)), float(np.max(v))
    out["force_ours_mps2"] = med(lambda x: x["force_ours"]["force_rmse_mps2"])
    out["force_vf_mps2"] = med(lambda x: x["force_vf"]["force_rmse_mps2"])
    out["ate_ours_m"] = med(lambda x: x["ate_ours_m"])
    out["ate_vf_m"] = med(lambda x: x["ate_vf_m"])
    out["lag_ours_ms"] = med(lambda x: np.nan if x["force_ours"]["lag_ms"] is None else x["force_ours"]["lag_ms"])
    out["lag_vf_ms"] = med(lambda x: np.nan if x["force_vf"]["lag_ms"] is None else x["force_vf"]["lag_ms"])
    out["span_s"] = med(lambda x: x["span_s"])
    return out


def run_vf(args) -> int:
    args.work.mkdir(parents=True, exist_ok=True)
    mono = mono_preset(args)
    seqs = [x for x in args.vf_sequences.split(",") if x]
    setups = [x for x in args.vf_setups.split(",") if x]
    raw, max_load, t_start = {}, 0.0, time.time()
    for name in seqs:
        seq = ensure_sequence(args, name)
        if not (seq / "mav0" / "rotor0").exists():
            print(f"[compare] {name}: no rotor0/, not a VID-Fusion sequence; skipped", flush=True)
            continue
        # VID-Fusion (mono) once per repeat, shared by the rows of every ours setup
        vruns = []
        for rep in range(args.repeats):
            vd = args.work / f"vf_{name}" / f"vf_{rep}"
            vd.mkdir(parents=True, exist_ok=True)
            r = timed(args, [str(args.vf), "--dataset", str(seq), "--out", str(vd)] + args.vf_args.split(),
                      vd / "run.log")
            r["ms"] = frame_ms(vd / "timing.csv", False) if (vd / "timing.csv").exists() else np.array([])
            r["dir"] = vd
            r["summary"] = json.loads((vd / "summary.json").read_text()) if (vd / "summary.json").exists() else {}
            vruns.append(r)
            max_load = max(max_load, r["load_before"])
            print(f"[compare] vf {name} rep {rep}: rc {r['rc']}, init after {r['summary'].get('init_after_s')} s, "
                  f"reboots {r['summary'].get('reboots')}, median "
                  f"{np.median(r['ms']) if len(r['ms']) else float('nan'):.2f} ms (load {loadavg():.2f})", flush=True)
        for setup in setups:
            key = f"{name}_{setup}_dynamics"
            oruns = []
            for rep in range(args.repeats):
                od = args.work / f"vf_{name}" / f"ours_{setup}_{rep}"
                od.mkdir(parents=True, exist_ok=True)
                cmd = [str(args.bin / "vid_run"), "--dataset", str(seq), "--out", str(od),
                       "--config", str(ROOT / "config" / "sim" if setup == "stereo" else mono),
                       "--mode", "dynamics", "--decode-threads", "0", "--quiet"]
                r = timed(args, cmd, od / "run.log")
                r["ms"] = frame_ms(od / "timing.csv", True)
                r["dir"] = od
                oruns.append(r)
                max_load = max(max_load, r["load_before"])
            row = {"sequence": name, "setup": setup, "seq": str(seq), "ours_dirs": [str(r["dir"]) for r in oruns],
                   "vf_dirs": [str(r["dir"]) for r in vruns]}
            row.update(eval_vf_row(args, key, seq, [r["dir"] for r in oruns], [r["dir"] for r in vruns]))
            row["ours_ms"] = float(np.median([np.median(r["ms"]) for r in oruns]))
            row["vf_ms"] = (float(np.median([np.median(r["ms"]) for r in vruns]))
                            if all(len(r["ms"]) for r in vruns) else float("nan"))
            row["ours_cpu_s"] = float(np.median([r["cpu_s"] for r in oruns]))
            row["vf_cpu_s"] = float(np.median([r["cpu_s"] for r in vruns]))
            row["ours_rss_mb"] = max(r["peak_rss_kb"] for r in oruns) / 1024.0
            row["vf_rss_mb"] = max(r["peak_rss_kb"] for r in vruns) / 1024.0
            row["vf_rc"] = [r["rc"] for r in vruns]
            row["vf_summaries"] = [r["summary"] for r in vruns]
            raw[key] = row
            print(f"[compare] {key}: " + json.dumps({k: v for k, v in row.items() if k != "vf_summaries"},
                                                     default=float), flush=True)
            meta = {"core": args.core, "repeats": args.repeats, "max_load": max_load,
                    "minutes": (time.time() - t_start) / 60, "ended": time.strftime("%Y-%m-%d %H:%M")}
            (args.work / "vf_results.json").write_text(json.dumps({**raw, "_meta": meta}, indent=1, default=float))
    meta = {"core": args.core, "repeats": args.repeats, "max_load": max_load,
            "minutes": (time.time() - t_start) / 60, "ended": time.strftime("%Y-%m-%d %H:%M")}
    return render_vf(args, list(raw.values()), meta)


def render_vf(args, rows, meta) -> int:
    def dec(ours, theirs):
        if not np.isfinite(ours) or not np.isfinite(theirs) or theirs <= 0:
            return "n/a"
        return f"{100.0 * (theirs - ours) / theirs:+.0f} %"

    def rng(t, p=3):  # (median, min, max) of VID-Fusion's repeats
        if not np.isfinite(t[0]):
            return "n/a"
        return f"{t[0]:.{p}f}" + (f" ({t[1]:.{p}f}–{t[2]:.{p}f})" if t[2] > t[1] else "")

    cpu = "unknown"
    for ln in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
        if ln.startswith("model name"):
            cpu = ln.split(":", 1)[1].strip()
            break
    lines = [f"Machine: {cpu}, {os.cpu_count()} cores, Linux {platform.release()}; both estimators pinned to the "
             f"same core (`taskset -c {meta['core']}`), {meta['repeats']} repeat(s), largest 1-min load average "
             f"before a run: {meta['max_load']:.2f}"
             + (" (**provisional: above 1.2, other processes shared the machine; ms/frame inflated**)"
                if meta["max_load"] > 1.2 else "") + f"; ended {meta['ended']}, {meta['minutes']:.0f} min. "
             "VID-Fusion: median over repeats (range in brackets; its solver has a wall-clock budget).", "",
             "| sequence | ours | force RMSE [m/s²] ours / VID-Fusion | decrease | ATE posyaw [m] ours / VID-Fusion "
             "| decrease | force lag [ms] ours / VID-Fusion | median ms/frame ours / VID-Fusion | speed ratio "
             "| VID-Fusion init after [s]; reboots per run | span [s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        vs = r.get("vf_summaries", [])
        init = (f"{vs[0].get('init_after_s', float('nan')):.1f}; " + ", ".join(str(x.get("reboots", "?")) for x in vs)
                if vs else "n/a")
        ratio = fmt(r["vf_ms"] / r["ours_ms"], 1) + "x" if np.isfinite(r["vf_ms"]) else "n/a"
        if not r["vf_ok"]:
            lines.append(f"| {r['sequence']} | {r['setup']} dynamics | VID-Fusion: no estimate | | | | | "
                         f"{r['ours_ms']:.2f} / {fmt(r['vf_ms'], 2)} | {ratio} | {init} | - |")
            continue
        fo, fv, ao, av = r["force_ours_mps2"], r["force_vf_mps2"], r["ate_ours_m"], r["ate_vf_m"]
        lines.append(
            f"| {r['sequence']} | {r['setup']} dynamics "
            f"| {fo[0]:.3f} / {rng(fv)} | {dec(fo[0], fv[0])} "
            f"| {ao[0]:.3f} / {rng(av)} | {dec(ao[0], av[0])} "
            f"| {rng(r['lag_ours_ms'], 0)} / {rng(r['lag_vf_ms'], 0)} "
            f"| {r['ours_ms']:.2f} / {fmt(r['vf_ms'], 2)} | {ratio} | {init} | {r['span_s'][0]:.1f} |")
    table = "\n".join(lines) + "\n"
    publish_table(table, args.work / "vf_table.md", args.doc, "vf-table")
    return 0


def render_saved(args) -> int:
    """The VID-Fusion table from the vf_results.json of the work folders in args.render,
    re-scored from the saved outputs (cheap; the same code as the run)."""
    rows, meta = [], []
    for w in args.render.split(","):
        data = json.loads((pathlib.Path(w) / "vf_results.json").read_text())
        meta.append(data.pop("_meta"))
        for row in data.values():
            if "vf_dirs" not in row:  # results.json of an older run: the folders by name
                base = pathlib.Path(w) / f"vf_{row['sequence']}"
                n = meta[-1]["repeats"]
                row["seq"] = str(args.seq_dir / row["sequence"])
                row["vf_dirs"] = [str(base / f"vf_{k}") for k in range(n)]
                row["ours_dirs"] = [str(base / f"ours_{row['setup']}_{k}") for k in range(n)]
                row["vf_summaries"] = [json.loads((pathlib.Path(d) / "summary.json").read_text())
                                       for d in row["vf_dirs"] if (pathlib.Path(d) / "summary.json").exists()]
            if "vf_dirs" in row:  # re-score from the saved outputs (cheap; same code as the run)
                row.update(eval_vf_row(args, f"{row['sequence']}_{row['setup']}_dynamics",
                                       pathlib.Path(row["seq"]), row["ours_dirs"], row["vf_dirs"]))
            rows.append(row)
    args.work = pathlib.Path(args.render.split(",")[0])
    m = {"core": ",".join(sorted({str(x["core"]) for x in meta})), "repeats": min(x["repeats"] for x in meta),
         "max_load": max(x["max_load"] for x in meta), "minutes": max(x["minutes"] for x in meta),
         "ended": max(x["ended"] for x in meta)}
    return render_vf(args, rows, m)
