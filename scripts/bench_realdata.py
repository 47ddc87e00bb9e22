#!/usr/bin/env python3
"""The real-flight benchmark: the Blackbird clover flight (real 100 Hz IMU, real collective
thrust from the measured rotor speeds, motion capture) through the tools a user gets, both
estimator modes, scored against the motion-capture truth.

Steps (each one a program of the project, printed as it runs):
1. ``python -m vid_eval.importer --map blackbird_lio`` writes the dataset folder (IMU and thrust
   from z-down to the project's frames, ground truth, vehicle.yaml) with the IMU noise measured
   on this flight (--gyro-noise / --accel-noise, see docs/results.md "Real flight");
2. ``vid-eval mocap-truth --apply-sync``: the mocap clock and the mocap-body-to-IMU rotation
   (0.74 deg on this flight) applied to the ground truth, and force0 = mocap acceleration minus
   thrust (the external-force truth, never from the accelerometer);
3. ``vid_sim --camera-along`` (scene config/sim/recorded_room.yaml): stereo features along the
   synced IMU path (after step 2, so the synthetic camera is attached to the IMU, as a
   calibrated camera would be);
4. ``vid_run --init groundtruth`` with the estimator's defaults (pixel_noise_px 0.5: the synthetic
   features' noise) in ``--mode dynamics`` and ``--mode imu`` over each window;
5. scores: posyaw ATE and body-frame force RMSE (summary.json, the project's metrics), force
   jumps, the force NEES (diagonal sigma of force.csv) inside the two-sided 95 % chi2(3) band;
6. with ``--starts 0 20 40 60 80``: in-flight starts (issue #49), ``vid_run --start S`` to the end
   in dynamics mode initialized from the data (``init_mode: auto``, no ground truth) and from the
   ground truth at the same time: time from S to the first estimate, ATE of both, their ratio.

The data stays outside the repository (../shared/realdata); results go to OUT/results.json and
OUT/table.md.

  .venv/bin/python scripts/bench_realdata.py --out /tmp/bench_real
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "eval"))

from vid_eval.tools.sim_runs import config_with_overrides  # noqa: E402

# IMU noise of this flight, measured on it in flight (vibration included) by `vid-allan --flight`:
# gyro minus the mocap body rate 5.74e-3 rad/s/sqrt(Hz) (an upper bound: the mocap's own noise is
# in it), accelerometer minus the thrust + drag model 1.41e-2 m/s^2/sqrt(Hz).
NOISE = {"--gyro-noise": "5.7e-3", "--gyro-walk": "1e-4", "--accel-noise": "0.014", "--accel-walk": "4e-3"}
WINDOWS = {"whole": (None, None), "0-60s": (0.0, 60.0)}


def run(cmd: list[str]) -> None:
    print("+", " ".join(cmd), flush=True)
    # This checkout's vid_eval, whatever the venv has installed.
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(REPO / "eval"), os.environ.get("PYTHONPATH", "")]))
    subprocess.run(cmd, check=True, env=env)


def prepare(data: pathlib.Path, folder: pathlib.Path, build: pathlib.Path) -> None:
    py = sys.executable
    run([py, "-m", "vid_eval.importer", "--map", "blackbird_lio", str(data), str(folder), "--mass", "0.915",
         "--imu-frame", "frd", "--world-frame", "enu", "--overwrite", *sum(NOISE.items(), ())])
    run([py, "-m", "vid_eval.cli", "mocap-truth", str(folder), "--apply-sync", "--json", str(folder / "sync.json")])
    gt = np.loadtxt(folder / "mav0/state_groundtruth_estimate0/data.csv", delimiter=",", comments="#")
    tum = folder / "synced_path.tum"
    with open(tum, "w") as f:  # t x y z qx qy qz qw
        for r in gt:
            f.write(f"{r[0] * 1e-9:.9f} {r[1]:.9f} {r[2]:.9f} {r[3]:.9f} {r[5]:.12f} {r[6]:.12f} {r[7]:.12f} {r[4]:.12f}\n")
    run([str(build / "bin/vid_sim"), "--scenario", str(REPO / "config/sim/recorded_room.yaml"), "--camera-along",
         str(tum), "--out", str(folder), "--features-only", "--overwrite", "--quiet"])


def force_nees_in_band(folder: pathlib.Path, run_dir: pathlib.Path, mass_kg: float) -> dict:
    """Body-frame force NEES against force0 (diagonal sigma of force.csv), skipping the first 3 s."""
    gt = np.loadtxt(folder / "mav0/state_groundtruth_estimate0/data.csv", delimiter=",", comments="#")
    f0 = np.loadtxt(folder / "mav0/force0/data.csv", delimiter=",", comments="#")
    R = Rotation.from_quat(gt[:, [5, 6, 7, 4]])
    F_W = np.stack([np.interp(gt[:, 0], f0[:, 0], f0[:, 1 + k]) for k in range(3)], 1) / mass_kg
    F_I = R.inv().apply(F_W)
    est = np.loadtxt(run_dir / "force.csv", delimiter=",", comments="#")
    keep = (est[:, 0] > est[0, 0] + 3e9) & (est[:, 0] <= gt[-1, 0])
    est = est[keep]
    truth = np.stack([np.interp(est[:, 0], gt[:, 0], F_I[:, k]) for k in range(3)], 1)
    nees = (((est[:, 1:4] - truth) / est[:, 7:10]) ** 2).sum(1)
    lo, hi = chi2.ppf(0.025, 3), chi2.ppf(0.975, 3)
    return {"nees_mean": float(nees.mean()), "nees_in_band": float(np.mean((nees > lo) & (nees < hi)))}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", default=str(REPO.parent / "shared/realdata/blackbird_clover"))
    ap.add_argument("--build", default=str(REPO / "build"), help="build folder with bin/vid_run, bin/vid_sim")
    ap.add_argument("--config", help="estimator preset folder (default: the estimator's defaults)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="estimator.yaml override")
    ap.add_argument("--out", required=True)
    ap.add_argument("--reuse", action="store_true", help="keep an imported folder from an earlier run")
    ap.add_argument("--starts", nargs="*", type=float, default=[], metavar="S",
                    help="also in-flight starts at these seconds: auto vs ground-truth initialization")
    args = ap.parse_args()
    out, build = pathlib.Path(args.out), pathlib.Path(args.build)
    folder = out / "blackbird_clover"
    if not (pathlib.Path(args.data) / "README.md").is_file():
        ap.error(f"--data {args.data}: not the Blackbird clover folder (see ../shared/realdata; it is not in the repository)")
    if not (args.reuse and (folder / "mav0/feat0/data.csv").exists()):
        prepare(pathlib.Path(args.data), folder, build)
    # Synthetic features carry 0.5 px noise (recorded_room.yaml); the rest is the preset's.
    overrides = {"pixel_noise_px": 0.5}
    overrides.update(dict(kv.split("=", 1) for kv in args.set))
    base = pathlib.Path(args.config) if args.config else out / "defaults"
    if not args.config:  # the estimator's own defaults: a preset with nothing in it
        base.mkdir(parents=True, exist_ok=True)
        (base / "estimator.yaml").write_text("# the estimator's defaults (docs/parameters.md)\n")
    cfg = config_with_overrides(base, overrides, out / "config")
    rows = []
    for win, (start, end) in WINDOWS.items():
        for mode in ("dynamics", "imu"):
            rd = out / "runs" / f"{win}_{mode}"
            cmd = [str(build / "bin/vid_run"), "--dataset", str(folder), "--config", str(cfg), "--mode", mode,
                   "--init", "groundtruth", "--out", str(rd), "--quiet"]
            if start is not None:
                cmd += ["--start", str(start), "--end", str(end)]
            if mode == "dynamics":  # the causal outputs are unchanged by the smoother
                cmd += ["--smooth", "0.3"]
            run(cmd)
            s = json.loads((rd / "summary.json").read_text())
            row = {"window": win, "mode": mode, "ate_m": s["ate_posyaw_m"], "status": s["status"],
                   "force_rmse_body": s.get("force_rmse_body_mps2"),
                   "force_rmse_body_smoothed": s.get("force_rmse_body_mps2_smoothed"), "force_jumps": s["counts"]["force_jumps"],
                   "accel_nis": s.get("noise_fit", {}).get("accel_nis_per_axis")}
            if mode == "dynamics":
                row.update(force_nees_in_band(folder, rd, 0.915))
            rows.append(row)
    (out / "results.json").write_text(json.dumps(rows, indent=1))
    lines = ["| window | mode | ATE [m] | body force RMSE [m/s²] (smoothed 0.3 s) | force jumps | force NEES mean (in 95 % band) |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        f = f"{r['force_rmse_body']:.3f} ({r['force_rmse_body_smoothed']:.3f})" if r["force_rmse_body"] is not None else "–"
        nees = f"{r['nees_mean']:.1f} ({100 * r['nees_in_band']:.0f} %)" if "nees_mean" in r else "–"
        lines.append(f"| {r['window']} | {r['mode']} | {r['ate_m']:.4f} | {f} | {r['force_jumps']} | {nees} |")
    table = "\n".join(lines)
    if args.starts:
        table += "\n\n" + init_starts(args.starts, folder, cfg, build, out)
    (out / "table.md").write_text(table + "\n")
    print(table)
    return 0


def first_stamp_s(csv: pathlib.Path) -> float:
    with open(csv) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                return int(line.split(",", 1)[0]) * 1e-9
    return float("inf")


def first_estimate_s(run_dir: pathlib.Path) -> float:
    for line in (run_dir / "trajectory_tum.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            return float(line.split()[0])
    return float("nan")


def init_starts(starts: list[float], folder: pathlib.Path, cfg: pathlib.Path, build: pathlib.Path,
                out: pathlib.Path) -> str:
    """Issue #49 on the real flight: from each start, dynamics mode initialized from the data
    (init_mode auto: this flight never hovers, so the in-flight initializer) and from the ground
    truth; the time to the first estimate and the ATE over the rest of the flight."""
    t0 = min(first_stamp_s(csv) for csv in (folder / "mav0").glob("*/data.csv"))  # vid_run's --start origin
    rows = []
    for start in starts:
        row = {"start_s": start}
        for init in ("auto", "groundtruth"):
            rd = out / "starts" / f"{start:g}_{init}"
            cmd = [str(build / "bin/vid_run"), "--dataset", str(folder), "--config", str(cfg), "--mode", "dynamics",
                   "--out", str(rd), "--quiet", "--start", str(start)]
            cmd += ["--init", "groundtruth"] if init == "groundtruth" else []
            print("+", " ".join(cmd), flush=True)
            proc = subprocess.run(cmd)
            s = json.loads((rd / "summary.json").read_text()) if (rd / "summary.json").exists() else {}
            row[init] = {"exit": proc.returncode, "status": s.get("status"), "ate_m": s.get("ate_posyaw_m"),
                         "init_after_s": first_estimate_s(rd) - t0 - start if proc.returncode == 0 else None,
                         "how": [e["how"] for e in s.get("initializations", {}).get("events", [])]}
        rows.append(row)
    (out / "starts.json").write_text(json.dumps(rows, indent=1))
    lines = ["| start [s] | initialized after [s] (how) | ATE auto [m] | ATE from ground truth [m] | ratio |",
             "|---|---|---|---|---|"]
    for r in rows:
        a, g = r["auto"], r["groundtruth"]
        if a["ate_m"] is None or g["ate_m"] is None:
            lines.append(f"| {r['start_s']:g} | exit {a['exit']} ({a['status']}) | – | – | – |")
            continue
        lines.append(f"| {r['start_s']:g} | {a['init_after_s']:.2f} ({', '.join(a['how'])}) | {a['ate_m']:.4f} | "
                     f"{g['ate_m']:.4f} | {a['ate_m'] / g['ate_m']:.2f} |")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
