"""Simulate a preset, run an estimator on it with overridden settings, score the run.

Shared by ``scripts/preset_sweep.py`` and ``vid-batch`` so that a sweep table and a batch
table mean the same numbers. Scores come from the same code as ``vid-eval traj`` /
``vid-eval force``.
"""
from __future__ import annotations

import json
import os
import pathlib
import re
import shutil
import subprocess
from typing import Mapping, Optional

import numpy as np

from ..core.ate import compute_ate
from ..core.force_frames import newton_to_accel
from ..core.force_response import force_response
from .gauge import fit_world_gauge, rotate_world
from .loaders import (find_mass_source, load_force_estimate, load_force_gt, load_mass,
                      load_trajectory, load_vehicle_mass)
from ..core.pairing import PairingOptions, pair_vectors

REPO = pathlib.Path(__file__).resolve().parents[3]  # eval/vid_eval/tools/sim_runs.py


def sequence_exists(seq: pathlib.Path) -> bool:
    """True when ``seq`` holds a complete simulated sequence (vid_sim wrote its IMU file)."""
    return (seq / "mav0" / "imu0" / "data.csv").exists()


def simulate_command(vid_sim: str, scenario: pathlib.Path, seq: pathlib.Path, seed: int,
                     images: bool = False, noise_free: bool = False,
                     duration: Optional[float] = None) -> list:
    """The vid_sim command line that writes ``scenario`` with ``seed`` into ``seq``."""
    cmd = [vid_sim, "--scenario", str(scenario), "--out", str(seq), "--seed", str(seed), "--quiet"]
    if duration:
        cmd += ["--duration", str(duration)]
    if not images:
        cmd.append("--features-only")
    if noise_free:
        cmd.append("--no-noise")
    return cmd


def simulate(vid_sim: str, preset: str, seed: int, seq: pathlib.Path, images: bool = False,
             noise_free: bool = False, duration: Optional[float] = None) -> None:
    """Write config/sim/<preset>.yaml with ``seed`` into ``seq`` unless it is already there."""
    if sequence_exists(seq):
        return
    scenario = REPO / "config" / "sim" / f"{preset}.yaml"
    subprocess.run(simulate_command(vid_sim, scenario, seq, seed, images, noise_free, duration),
                   check=True, capture_output=True, text=True)


def yaml_scalar(value: object) -> str:
    """``value`` as YAML text: booleans as true/false (a YAML batch gives Python bools)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value).strip()


def config_with_overrides(src: pathlib.Path, overrides: Mapping[str, object],
                          dst: pathlib.Path) -> pathlib.Path:
    """``src`` (an estimator preset folder) if no overrides, else a copy in ``dst`` whose
    estimator.yaml has the ``key: value`` overrides: a top-level key already in the file is
    replaced on its line, a new one appended (vid_run rejects a key given twice)."""
    if not overrides:
        return src
    shutil.rmtree(dst, ignore_errors=True)
    shutil.copytree(src, dst)
    est = dst / "estimator.yaml"
    text = est.read_text() if est.exists() else ""
    for key, value in overrides.items():
        line = f"{str(key).strip()}: {yaml_scalar(value)}"
        pattern = re.compile(rf"^{re.escape(str(key).strip())}\s*:.*$", re.MULTILINE)
        text, replaced = pattern.subn(lambda _: line, text)
        if not replaced:
            text += f"\n{line}\n"
    est.write_text(text)
    return dst


def resolve_path(folder: str, base: pathlib.Path = REPO) -> pathlib.Path:
    """A folder given relative to ``base`` (the repository) or absolute."""
    return pathlib.Path(folder) if os.path.isabs(folder) else base / folder


def score_run(seq: pathlib.Path, run: pathlib.Path, skip_s: float) -> dict:
    """Scores of one vid_run output folder ``run`` against the sequence ``seq``'s truth.

    ATE [m] (posyaw), world-frame force RMSE (gauge-free), max attitude error after ``skip_s``
    seconds [deg], force lag [ms] and step settling, accelerometer accounting (vid_run's summary);
    with ``vid_run --smooth`` outputs also the smoothed ATE, force RMSE and settling (``*_smoothed``).
    """
    mav0 = seq / "mav0"
    s = json.loads((run / "summary.json").read_text())
    out = {"status": s.get("status"), "ate_m": s.get("ate_posyaw_m"),
           "force_rmse_world": s.get("force_rmse_world_mps2"),
           "force_rmse_body": s.get("force_rmse_body_mps2")}
    acc = s.get("accel", {})
    out["accel_rejected_fraction"] = acc.get("rejected_fraction",
                                             s["counts"]["accel_rejected"] / max(1, s["counts"]["imu_samples"]))
    out["accel_downweighted_fraction"] = acc.get("downweighted_fraction", 0.0)
    out["force_jumps"] = acc.get("force_jumps", 0)
    est_traj = load_trajectory(run / "trajectory_tum.txt")
    gt_traj = load_trajectory(mav0 / "state_groundtruth_estimate0" / "data.csv")
    ate = compute_ate(est_traj, gt_traj, "posyaw")
    t_rel = (ate.est_aligned.t_ns - gt_traj.t_ns[0]) * 1e-9
    late = t_rel > skip_s
    out["att_err_max_deg"] = float(np.max(ate.rot_err_deg[late])) if late.any() else None
    if (mav0 / "force0" / "data.csv").exists() and out["force_rmse_world"] is not None:
        gt = load_force_gt(mav0 / "force0" / "data.csv")
        src = find_mass_source(mav0 / "force0" / "data.csv")
        mass = load_vehicle_mass(src) if src.suffix == ".yaml" else load_mass(src)
        gt = newton_to_accel(gt, mass)
        _, world = load_force_estimate(run / "force.csv")
        world = rotate_world(world, fit_world_gauge(est_traj, gt_traj, "posyaw"))
        pe, pg = pair_vectors(world, gt, PairingOptions())
        r = force_response(pe, pg)
        summ = r.summary()
        out["lag_ms"] = None if r.lag is None else r.lag * 1e3
        out["steps"] = summ["steps"]
        out["settling_median_s"] = summ["settling_median_s"]
        out["settling_max_s"] = summ["settling_max_s"]
        out["not_settled"] = summ["not_settled"]
        smoothed = run / "force_smoothed.csv"
        if smoothed.exists() and (run / "trajectory_smoothed_tum.txt").exists():
            # vid_run --smooth: the fixed-lag smoothed force, aligned by its own trajectory.
            out["ate_m_smoothed"] = s.get("ate_posyaw_m_smoothed")
            out["force_rmse_world_smoothed"] = s.get("force_rmse_world_mps2_smoothed")
            traj_s = load_trajectory(run / "trajectory_smoothed_tum.txt")
            _, world_s = load_force_estimate(smoothed)
            world_s = rotate_world(world_s, fit_world_gauge(traj_s, gt_traj, "posyaw"))
            r_s = force_response(*pair_vectors(world_s, gt, PairingOptions()))
            out["settling_max_s_smoothed"] = r_s.summary()["settling_max_s"]
    out.update(score_time_offset(mav0, run))
    return out


def score_time_offset(mav0: pathlib.Path, run: pathlib.Path) -> dict:
    """The online camera-IMU time offset at the end of ``run`` (vid_run's time_offset.csv, written
    when t_d is estimated) against the simulator's truth (mav0/time_offset0, the constant part;
    0 without the file): error [ms] and its NEES. Empty when t_d was not estimated."""
    est_file = run / "time_offset.csv"
    if not est_file.exists():
        return {}
    est = np.loadtxt(est_file, delimiter=",", comments="#", ndmin=2)
    truth_file = mav0 / "time_offset0" / "data.csv"
    truth = 0.0
    if truth_file.exists():
        rows = np.loadtxt(truth_file, delimiter=",", comments="#", ndmin=2)
        truth = float(rows[-1, 1])
    err, sigma = float(est[-1, 1]) - truth, float(est[-1, 2])
    return {"td_err_ms": err * 1e3, "td_sigma_ms": sigma * 1e3, "td_nees": (err / sigma) ** 2 if sigma > 0 else None}
