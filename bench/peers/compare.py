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
import re
import shutil
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "eval"))
from vid_eval.alignment import AlignmentError  # noqa: E402
from vid_eval.ate import ate_of_paired  # noqa: E402
from vid_eval.loaders import load_trajectory  # noqa: E402
from vid_eval.pairing import PairingOptions, pair_trajectories  # noqa: E402
from vid_eval.rpe import compute_rpe  # noqa: E402
from vid_eval.series import Trajectory  # noqa: E402

DEFAULT_SEQS = ["vid17_like", "vid18_like", "euroc_like", "fast_yaw", "rope_snap", "impacts"]
VF_SEQS = ["vid17_like", "vid18_like", "vid_loaded", "rope_snap", "impacts"]
DURATION = {"fast_yaw": 20.0}  # the preset's own length; the others are cut to 60 s


def sh(cmd, **kw):
    return subprocess.run(cmd, check=True, **kw)


def preset_seed(name: str) -> int:
    for line in (ROOT / "config" / "sim" / f"{name}.yaml").read_text().splitlines():
        m = re.match(r"^seed:\s*(\d+)", line)
        if m:
            return int(m.group(1))
    raise SystemExit(f"no seed in config/sim/{name}.yaml")


def ensure_sequence(args, name: str) -> pathlib.Path:
    d = args.seq_dir / name
    if (d / ".complete").exists():
        return d
    if d.exists():
        shutil.rmtree(d)
    cmd = [str(args.bin / "vid_sim"), "--scenario", str(ROOT / "config" / "sim" / f"{name}.yaml"),
           "--out", str(d), "--seed", str(preset_seed(name)),
           "--duration", str(DURATION.get(name, 60.0)), "--quiet"]
    print("[compare] simulating:", " ".join(cmd), flush=True)
    sh(["nice", "-n", "10"] + cmd)
    (d / ".complete").write_text(" ".join(cmd) + "\n")
    return d


def mono_preset(args) -> pathlib.Path:
    """config/sim with the second camera off (estimator use_stereo, frontend stereo)."""
    d = args.work / "preset_sim_mono"
    d.mkdir(parents=True, exist_ok=True)
    for f in (ROOT / "config" / "sim").glob("*.yaml"):
        if f.name not in ("estimator.yaml", "frontend.yaml"):
            continue
        text = f.read_text()
        text = re.sub(r"(?m)^use_stereo:\s*true", "use_stereo: false", text)
        text = re.sub(r"(?m)^stereo:\s*true", "stereo: false", text)
        (d / f.name).write_text(text)
    return d


def loadavg() -> float:
    return float(pathlib.Path("/proc/loadavg").read_text().split()[0])


def timed(args, cmd, log: pathlib.Path) -> dict:
    """Run cmd pinned to one core under /usr/bin/time -v; whole-process wall time and peak RSS."""
    tv = log.with_suffix(".time")
    full = ["taskset", "-c", str(args.core), "/usr/bin/time", "-v", "-o", str(tv)] + cmd
    load = loadavg()
    with open(log, "w") as f:
        rc = subprocess.run(full, stdout=f, stderr=subprocess.STDOUT).returncode
    text = tv.read_text()
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)", text)
    wall = (int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3)))
    cpu = sum(float(re.search(rf"{k} time \(seconds\): ([\d.]+)", text).group(1)) for k in ("User", "System"))
    return {"rc": rc, "peak_rss_kb": rss, "wall_s": wall, "cpu_s": cpu, "load_before": load}


def frame_ms(timing_csv: pathlib.Path, ours: bool) -> np.ndarray:
    rows = [ln.split(",") for ln in timing_csv.read_text().splitlines() if ln and not ln.startswith("#")]
    if ours:  # rows start at initialization; last column = total [ms]
        return np.array([float(r[-1]) for r in rows])
    return np.array([float(r[1]) for r in rows if r[2] == "1"])  # initialized frames


def subset(tr: Trajectory, mask) -> Trajectory:
    return Trajectory(tr.t_ns[mask], tr.p[mask], tr.q[mask], tr.source)


def common_frames(a: Trajectory, b: Trajectory, tol_ns=1_000_000):
    """Masks of a and b keeping samples that have a partner in the other within tol."""
    def near(x, y):
        i = np.clip(np.searchsorted(y, x), 1, len(y) - 1)
        d = np.minimum(np.abs(x - y[i - 1]), np.abs(x - y[i]))
        return d <= tol_ns
    ma = near(a.t_ns, b.t_ns)
    mb = near(b.t_ns, a.t_ns[ma])
    return ma & near(a.t_ns, b.t_ns[mb]), mb


def metrics(est: Trajectory, gt: Trajectory, rpe_d: float) -> dict:
    pe, pg = pair_trajectories(est, gt, PairingOptions(max_diff_ns=2_000_000, min_pairs=3))
    out = {"pairs": int(len(pe.t_ns))}
    for mode in ("posyaw", "se3"):
        try:
            r = ate_of_paired(pe, pg, mode)
        except AlignmentError:  # hover in place (fast_yaw): positions nearly a point, no se3 fit
            out[f"ate_{mode}_m"] = out[f"ate_{mode}_rot_deg"] = float("nan")
            continue
        out[f"ate_{mode}_m"] = r.pos_rmse
        out[f"ate_{mode}_rot_deg"] = r.rot_rmse_deg
        if mode == "posyaw" and rpe_d is None:
            out.update({"rpe_d_m": None, "rpe_trans_rmse_m": float("nan"), "rpe_pairs": 0, "_aligned": r.est_aligned})
        elif mode == "posyaw":
            seg = compute_rpe(r.est_aligned, r.gt, [rpe_d])[0]
            out["rpe_d_m"] = rpe_d
            out["rpe_trans_rmse_m"] = float(np.sqrt(np.mean(seg.trans_err ** 2))) if len(seg.trans_err) else float("nan")
            out["rpe_pairs"] = int(len(seg.trans_err))
            out["_aligned"] = r.est_aligned
    return out


def eval_pair(seq: pathlib.Path, ours_dir: pathlib.Path, ov_dir: pathlib.Path | None) -> dict:
    gt = load_trajectory(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv")
    ours = load_trajectory(ours_dir / "trajectory_tum.txt", "tum")
    res = {}
    if ov_dir is not None and (ov_dir / "trajectory_tum.txt").stat().st_size > 0:
        ov = load_trajectory(ov_dir / "trajectory_tum.txt", "tum")
        ma, mb = common_frames(ours, ov)
        ours_c, ov_c = subset(ours, ma), subset(ov, mb)
    else:
        ov_c = None
        tcam = np.array([int(ln.split(",")[0]) for ln in (ours_dir / "timing.csv").read_text().splitlines()
                         if ln and not ln.startswith("#")], dtype=np.int64)
        ours_c = subset(ours, common_frames(ours, Trajectory(tcam, np.zeros((len(tcam), 3)),
                                                             np.tile([1.0, 0, 0, 0], (len(tcam), 1))))[0])
    # RPE length: 10 % of the ground-truth path over the evaluated span
    span = (gt.t_ns >= ours_c.t_ns[0]) & (gt.t_ns <= ours_c.t_ns[-1])
    path = float(np.sum(np.linalg.norm(np.diff(gt.p[span], axis=0), axis=1)))
    rpe_d = round(0.1 * path, 2) if path >= 1.0 else None  # fast_yaw hovers in place: no RPE
    res["ours"] = metrics(ours_c, gt, rpe_d)
    if ov_c is not None:
        res["ov"] = metrics(ov_c, gt, rpe_d)
    res["gt"] = gt
    return res


def fmt(x, p=3):
    return "n/a" if x is None or (isinstance(x, float) and not np.isfinite(x)) else f"{x:.{p}f}"


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
def vid_eval_force(args, force_csv: pathlib.Path, traj: pathlib.Path, seq: pathlib.Path,
                   out_json: pathlib.Path) -> dict:
    """The project's gauge-free force scoring (``vid-eval force``, world frame, posyaw)."""
    exe = pathlib.Path(sys.executable).parent / "vid-eval"
    cmd = [str(exe), "force", str(force_csv), str(seq / "mav0" / "force0" / "data.csv"),
           "--traj", str(traj), "--json", str(out_json)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        print(f"[compare] vid-eval force failed on {force_csv}: {r.stderr.strip()}", flush=True)
        return {"force_rmse_mps2": float("nan"), "lag_ms": None}
    j = json.loads(out_json.read_text())
    lag = j.get("response", {}).get("lag_ms", {}).get("combined")
    return {"force_rmse_mps2": j["force_rmse_world_mps2"], "lag_ms": lag,
            "rmse_axis_mps2": j["force"].get("rmse_axis"), "pairs": j["force"].get("pairs")}


def trim_rows(src: pathlib.Path, dst: pathlib.Path, t0: int, t1: int) -> None:
    """Copy a CSV keeping the header and the rows with t0 <= timestamp [ns] <= t1."""
    with open(src) as f, open(dst, "w") as g:
        for ln in f:
            if ln.startswith("#") or not ln.strip():
                g.write(ln)
                continue
            t = int(ln.split(",", 1)[0])
            if t0 <= t <= t1:
                g.write(ln)


def plot_forces(args, key: str, seq: pathlib.Path, ours_dir: pathlib.Path, vf_dir: pathlib.Path,
                sc: dict) -> None:
    """Truth, ours and VID-Fusion world force (each rotated into the truth's world with its own
    posyaw trajectory alignment, vid_eval.gauge), one figure."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from vid_eval.force_frames import newton_to_accel
    from vid_eval.gauge import rotate_world, world_gauge_from_files
    from vid_eval.loaders import load_force_estimate, load_force_gt, load_vehicle_mass

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
    (args.work / "vf_table.md").write_text(table)
    print(table)
    if args.doc:
        text = args.doc.read_text()
        b, e = "<!-- vf-table:begin -->", "<!-- vf-table:end -->"
        if b not in text or e not in text:
            raise SystemExit(f"{args.doc}: no {b} ... {e} block")
        pre, rest = text.split(b, 1)
        _, post = rest.split(e, 1)
        args.doc.write_text(pre + b + "\n" + table + e + post)
    return 0


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
    if args.what == "vf" and args.render:
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
    if args.what == "vf":
        return run_vf(args)
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
    args.work.mkdir(parents=True, exist_ok=True)
    (args.work / "table.md").write_text(table)
    print(table)
    if args.doc:
        text = args.doc.read_text()
        b, e = "<!-- peers-table:begin -->", "<!-- peers-table:end -->"
        if b not in text or e not in text:
            raise SystemExit(f"{args.doc}: no {b} ... {e} block")
        pre, rest = text.split(b, 1)
        _, post = rest.split(e, 1)
        args.doc.write_text(pre + b + "\n" + table + e + post)
    return 0


if __name__ == "__main__":
    sys.exit(main())
