"""Helpers shared by the peer comparisons (compare.py: OpenVINS, compare_vf.py: VID-Fusion):
sequences, pinned timed runs, per-frame times, trajectory metrics at common frames."""
from __future__ import annotations

import pathlib
import re
import shutil
import subprocess
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "eval"))
from vid_eval.core.alignment import AlignmentError  # noqa: E402
from vid_eval.core.ate import ate_of_paired  # noqa: E402
from vid_eval.tools.loaders import load_trajectory  # noqa: E402
from vid_eval.core.pairing import PairingOptions, pair_trajectories  # noqa: E402
from vid_eval.core.rpe import compute_rpe  # noqa: E402
from vid_eval.core.series import Trajectory  # noqa: E402

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


def trim_rows(src: pathlib.Path, dst: pathlib.Path, t0: int, t1: int) -> int:
    """Copy a CSV keeping the header and the rows with t0 <= timestamp [ns] <= t1; returns how
    many rows were kept."""
    n = 0
    with open(src) as f, open(dst, "w") as g:
        for ln in f:
            if ln.startswith("#") or not ln.strip():
                g.write(ln)
                continue
            t = int(ln.split(",", 1)[0])
            if t0 <= t <= t1:
                g.write(ln)
                n += 1
    return n


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


def publish_table(table: str, out: pathlib.Path, doc: pathlib.Path | None, tag: str) -> None:
    """Write the markdown table to `out`, print it, and put it between `<!-- TAG:begin -->`
    and `<!-- TAG:end -->` in `doc` (if given)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(table)
    print(table)
    if doc:
        text = doc.read_text()
        b, e = f"<!-- {tag}:begin -->", f"<!-- {tag}:end -->"
        if b not in text or e not in text:
            raise SystemExit(f"{doc}: no {b} ... {e} block")
        pre, rest = text.split(b, 1)
        _, post = rest.split(e, 1)
        doc.write_text(pre + b + "\n" + table + e + post)

