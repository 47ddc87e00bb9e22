#!/usr/bin/env python3
"""The peer table on the real Blackbird flight (issue #47): real 100 Hz IMU, real collective
thrust from the measured rotor speeds, motion capture, and stereo images rendered along the
mocap path (config/sim/recorded_room.yaml). Rows: ours ``--mode dynamics``, ours ``--mode
imu``, VID-Fusion (mono + thrust), OpenVINS (stereo MSCKF); windows: the whole flight (151 s)
and its first 60 s.

    .venv/bin/python bench/peers/compare_real.py [--data ../shared/realdata/blackbird_clover]
        [--vid-build build] [--peers-bin build-peers/bin] [--work build-peers/real]
        [--rows ours_dynamics,ours_imu,vf,ov] [--windows full,60s] [--doc docs/peers.md]

Only the rows named in ``--rows`` are run; the others are taken from the earlier run in WORK
(``results.json``), and everything is re-scored together, so after an estimator change

    .venv/bin/python bench/peers/compare_real.py --rows ours_dynamics,ours_imu --vid-build NEW_BUILD

re-runs only ours (the prepared data and the peers' outputs are reused). ``--variant
NAME=KIND:ARGS`` adds a row (KIND ov, vf or ours) with extra arguments, scored beside the table
(e.g. ``ov_slam0=ov:--max-slam 0``).

Data (bench/peers/real_data.py, once, into WORK/seq): vid-import with the measured IMU noise,
``vid-eval mocap-truth --apply-sync``, ``vid_sim --camera-along`` on the synced ground truth.
Scoring: every row's trajectory at the same camera-frame times (the frames at which every table
row has an estimate; ours, written at IMU rate, is interpolated to them), ground truth
interpolated there, posyaw ATE (vid_eval, the code of ``vid-eval traj``); force RMSE
(``vid-eval force --frame body``, and ``--frame world``) of ours dynamics and VID-Fusion over the
same span against force0 (mocap acceleration minus thrust); ms per frame from each one's
timing.csv (frames after initialization), all runs pinned to one core.
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import shlex
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from compare_vf import vid_eval_force  # noqa: E402
from peers_common import ROOT, fmt, frame_ms, loadavg, publish_table, timed, trim_rows  # noqa: E402
from real_data import prepare, window  # noqa: E402
from vid_eval.core.ate import ate_of_paired  # noqa: E402
from vid_eval.core.geometry import lerp, slerp_wxyz  # noqa: E402
from vid_eval.tools.loaders import load_trajectory  # noqa: E402
from vid_eval.core.pairing import PairingOptions, pair_trajectories  # noqa: E402
from vid_eval.core.series import Trajectory  # noqa: E402

WINDOWS = {"full": (0.0, 1000.0), "60s": (0.0, 60.0)}  # [start, length] s after the first IMU sample
TABLE_ROWS = ["ours_dynamics", "ours_imu", "vf", "ov"]
LABEL = {"ours_dynamics": "ours dynamics", "ours_imu": "ours imu", "vf": "VID-Fusion", "ov": "OpenVINS"}
# The peers at their best settings on this data (docs/peers.md "Real flight", where the
# alternatives tried are scored): OpenVINS stereo MSCKF with its own EuRoC frontend (200 points,
# 5x5 grid, 10 px, histogram equalization), SLAM features on, its dynamic initializer (the
# vehicle never stands still); VID-Fusion with the driver's defaults (their sim_config.yaml,
# every image published, ours' feature budget): their real_drone.yaml choices (10 Hz, 30 px,
# thrust noise 0.9) restart it more often here.
OV_ARGS = ("--cams 2 --num-pts 200 --clones 11 --max-msckf 60 --set grid_x=5 --set grid_y=5 --set min_px_dist=10 "
           "--set 'histogram_method=\"HISTOGRAM\"' --set init_dyn_use=true --set try_zupt=false")
VF_ARGS = ""


def command(args, kind: str, seq: pathlib.Path, out: pathlib.Path, extra: str) -> list:
    if kind in ("ours_dynamics", "ours_imu", "ours"):
        mode = "imu" if kind == "ours_imu" else "dynamics"
        return [str(args.vid_build / "bin" / "vid_run"), "--dataset", str(seq), "--out", str(out),
                "--config", str(args.ours_config), "--mode", mode, "--init", "groundtruth",
                "--features", "images", "--decode-threads", "0", "--quiet"] + shlex.split(extra)
    # a variant's "--no-defaults" drops the table's peer arguments (--ov-args / --vf-args)
    ex = shlex.split(extra)
    own = [] if "--no-defaults" in ex else None
    ex = [a for a in ex if a != "--no-defaults"]
    if kind == "ov":
        return [str(args.peers_bin / "ov_driver"), "--dataset", str(seq), "--out", str(out)] \
            + (own if own is not None else shlex.split(args.ov_args)) + ex
    if kind == "vf":
        return [str(args.peers_bin / "vidfusion_driver"), "--dataset", str(seq), "--out", str(out)] \
            + (own if own is not None else shlex.split(args.vf_args)) + ex
    raise SystemExit(f"unknown row kind {kind}")


def run_row(args, name: str, kind: str, extra: str, seq: pathlib.Path, wdir: pathlib.Path) -> dict:
    out = wdir / name
    out.mkdir(parents=True, exist_ok=True)
    cmd = command(args, kind, seq, out, extra)
    r = timed(args, cmd, out / "run.log")
    r.update({"name": name, "kind": kind, "cmd": shlex.join(cmd), "dir": str(out),
              "ended": time.strftime("%Y-%m-%d %H:%M")})
    print(f"[real] {wdir.name}/{name}: rc {r['rc']}, wall {r['wall_s']:.1f} s, load before {r['load_before']:.2f}",
          flush=True)
    return r


def traj_of(d: pathlib.Path):
    f = d / "trajectory_tum.txt"
    return load_trajectory(f, "tum") if f.exists() and f.stat().st_size > 0 else None


def at_times(tr: Trajectory, t: np.ndarray, exact: bool) -> Trajectory:
    """tr at times t: exact stamps (peers, one pose per frame) or interpolated (ours, IMU rate)."""
    if exact:
        idx = np.searchsorted(tr.t_ns, t)
        return Trajectory(t, tr.p[idx], tr.q[idx], tr.source)
    return Trajectory(t, lerp(tr.t_ns, tr.p, t), slerp_wxyz(tr.t_ns, tr.q, t), tr.source)


def covered(tr: Trajectory, t: np.ndarray, exact: bool) -> np.ndarray:
    if exact:
        return np.isin(t, tr.t_ns)
    return (t >= tr.t_ns[0]) & (t <= tr.t_ns[-1])


def ate(tr: Trajectory, gt: Trajectory, t: np.ndarray, exact: bool) -> dict:
    est = at_times(tr, t, exact)
    pe, pg = pair_trajectories(est, gt, PairingOptions(mode="interpolate", min_pairs=3))
    r = ate_of_paired(pe, pg, "posyaw")
    return {"ate_posyaw_m": r.pos_rmse, "rot_deg": r.rot_rmse_deg, "pairs": int(len(pe.t_ns)),
            "span_s": float((t[-1] - t[0]) * 1e-9)}


def score_window(args, wname: str, seq: pathlib.Path, rows: dict) -> dict:
    """ATE of every row at the common frames, force of the dynamics rows over that span."""
    gt = load_trajectory(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv")
    frames = np.array([int(ln.split(",", 1)[0]) for ln in (seq / "mav0" / "cam0" / "data.csv").read_text().splitlines()
                       if ln.strip() and not ln.startswith("#")], dtype=np.int64)
    frames = frames[(frames >= gt.t_ns[0]) & (frames <= gt.t_ns[-1])]
    trajs = {n: traj_of(pathlib.Path(r["dir"])) for n, r in rows.items()}
    exact = {n: not r["kind"].startswith("ours") for n, r in rows.items()}
    common = np.ones(len(frames), bool)
    for n in TABLE_ROWS:
        if trajs.get(n) is not None:
            common &= covered(trajs[n], frames, exact[n])
    t_common = frames[common]
    out = {"frames": int(len(frames)), "common_frames": int(len(t_common)),
           "frames_span_s": float((frames[-1] - frames[0]) * 1e-9),
           "common_from_s": float((t_common[0] - frames[0]) * 1e-9) if len(t_common) else None, "rows": {}}
    for n, r in rows.items():
        d = pathlib.Path(r["dir"])
        s = {"rc": r["rc"], "cmd": r["cmd"]}
        tr = trajs[n]
        if tr is not None and len(t_common) >= 3:
            m = covered(tr, t_common, exact[n])
            if m.sum() >= 3:
                s["common"] = ate(tr, gt, t_common[m], exact[n])
            own = frames[covered(tr, frames, exact[n])]
            s["own"] = ate(tr, gt, own, exact[n])
            s["own"]["from_s"] = float((own[0] - frames[0]) * 1e-9)
        if (d / "timing.csv").exists():
            ms = frame_ms(d / "timing.csv", r["kind"].startswith("ours"))
            if len(ms):
                s["ms_median"], s["ms_mean"] = float(np.median(ms)), float(np.mean(ms))
        for extra in ("summary.json",):
            if (d / extra).exists():
                sj = json.loads((d / extra).read_text())
                s["summary"] = {k: sj.get(k) for k in ("init_after_s", "reboots", "frames_updated",
                                                        "mean_slam_features", "mean_msckf_features_per_update")
                                if k in sj}
        fcsv = d / "force.csv"
        if r["kind"] in ("ours_dynamics", "ours", "vf") and tr is not None and fcsv.exists() and len(t_common):
            span = d / "force_common_span.csv"
            trim_rows(fcsv, span, int(t_common[0]), int(t_common[-1]))
            for frame in ("body", "world"):
                s[f"force_{frame}"] = vid_eval_force(args, span, d / "trajectory_tum.txt", seq,
                                                     d / f"force_eval_{frame}.json", frame)
        out["rows"][n] = s
    return out


def render(args, results: dict, scores: dict) -> str:
    cpu = next((ln.split(":", 1)[1].strip() for ln in pathlib.Path("/proc/cpuinfo").read_text().splitlines()
                if ln.startswith("model name")), "unknown")
    loads = [r["load_before"] for w in scores for r in results[w]["rows"].values()]
    ended = max(r["ended"] for w in scores for r in results[w]["rows"].values())
    lines = [f"Machine: {cpu}, {os.cpu_count()} cores, Linux {platform.release()}; every run pinned to core "
             f"{args.core}, one run each, last run {ended}; largest 1-min load average before a run "
             f"{max(loads):.2f}" + (" (**ms per frame provisional: other processes shared the machine**)"
                                     if max(loads) > 1.2 else "") + ". Rows named `like_this` are the "
             "alternatives of the Settings list.", ""]
    for wname, sc in scores.items():
        meta = results[wname]
        loads = [r["load_before"] for r in meta["rows"].values()]
        start = WINDOWS[wname][0]
        lines.append(f"**{wname}** ({start:.0f}-{start + sc['frames_span_s']:.0f} s of the flight; "
                     f"{sc['common_frames']} of {sc['frames']} frames common to all rows, from "
                     f"{fmt(sc['common_from_s'], 1)} s; 1-min load before the runs "
                     f"{min(loads):.2f}-{max(loads):.2f})")
        lines.append("")
        lines.append("| estimator | ATE posyaw [m], common frames | force RMSE body [m/s²] | force RMSE world "
                     "[m/s²] | ms per frame median (mean) | ATE on its own frames [m] (from s) | notes |")
        lines.append("|---|---|---|---|---|---|---|")
        for n in [x for x in TABLE_ROWS if x in sc["rows"]] + [x for x in sc["rows"] if x not in TABLE_ROWS]:
            s = sc["rows"][n]
            label = LABEL.get(n, f"`{n}`")
            c = s.get("common", {})
            fb = s.get("force_body", {}).get("force_rmse_mps2")
            fw = s.get("force_world", {}).get("force_rmse_mps2")
            own = s.get("own")
            sm = s.get("summary", {})
            notes = []
            if s["rc"] != 0:
                notes.append(f"exit {s['rc']}")
            if sm.get("init_after_s") is not None and n not in ("ours_dynamics", "ours_imu"):
                notes.append(f"init after {sm['init_after_s']:.1f} s")
            if sm.get("reboots"):
                notes.append(f"{sm['reboots']} restarts")
            if sm.get("mean_slam_features") is not None:
                notes.append(f"{sm['mean_slam_features']:.0f} SLAM feats")
            if c and c["pairs"] < sc["common_frames"]:
                notes.append(f"{c['pairs']} frames")
            ms = (f"{s['ms_median']:.2f} ({s['ms_mean']:.2f})" if "ms_median" in s else "n/a")
            lines.append(f"| {label} | {fmt(c.get('ate_posyaw_m'))} | {fmt(fb)} | {fmt(fw)} | {ms} | "
                         + (f"{fmt(own['ate_posyaw_m'])} ({own['from_s']:.1f})" if own else "no estimate")
                         + f" | {'; '.join(notes)} |")
        lines.append("")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", type=pathlib.Path, default=ROOT.parent / "shared" / "realdata" / "blackbird_clover")
    ap.add_argument("--vid-build", type=pathlib.Path, default=ROOT / "build",
                    help="the project's build: bin/vid_run (ours rows) and bin/vid_sim (rendering)")
    ap.add_argument("--peers-bin", type=pathlib.Path, default=ROOT / "build-peers" / "bin")
    ap.add_argument("--work", type=pathlib.Path, default=ROOT / "build-peers" / "real")
    ap.add_argument("--ours-config", type=pathlib.Path, default=ROOT / "bench" / "peers" / "ours_real")
    ap.add_argument("--rows", default=",".join(TABLE_ROWS), help="rows to (re)run now")
    ap.add_argument("--windows", default="full,60s")
    ap.add_argument("--variant", action="append", default=[], metavar="NAME=KIND:ARGS")
    ap.add_argument("--ov-args", default=OV_ARGS)
    ap.add_argument("--vf-args", default=VF_ARGS)
    ap.add_argument("--core", type=int, default=1, help="CPU every run is pinned to")
    ap.add_argument("--doc", type=pathlib.Path, default=None)
    args = ap.parse_args()
    for p in (args.vid_build, args.ours_config):
        if not p.exists():
            raise SystemExit(f"{p}: no such folder")
    args.work.mkdir(parents=True, exist_ok=True)
    full = prepare(args.data, args.work / "seq", args.vid_build / "bin" / "vid_sim")
    res_path = args.work / "results.json"
    results = json.loads(res_path.read_text()) if res_path.exists() else {}
    variants = {}
    for v in args.variant:
        name, _, rest = v.partition("=")
        kind, _, extra = rest.partition(":")
        variants[name] = (kind, extra)
    todo = [r for r in args.rows.split(",") if r] + list(variants)
    scores = {}
    for wname in [w for w in args.windows.split(",") if w]:
        start, length = WINDOWS[wname]
        seq = full if wname == "full" else window(full, args.work / f"seq_{wname}", start, length)
        wres = results.setdefault(wname, {"rows": {}})
        for name in todo:
            kind, extra = variants.get(name, (name, ""))
            wres["rows"][name] = run_row(args, name, kind, extra, seq, args.work / wname)
            res_path.write_text(json.dumps(results, indent=1, default=float))
        scores[wname] = score_window(args, wname, seq, wres["rows"])
    (args.work / "scores.json").write_text(json.dumps(scores, indent=1, default=float))
    table = render(args, results, scores)
    publish_table(table, args.work / "table.md", args.doc, "real-table")
    return 0


if __name__ == "__main__":
    sys.exit(main())
