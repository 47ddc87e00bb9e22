"""A synthetic take-off-and-landing folder with known errors per phase (landed, airborne and
the transition windows), for the per-phase tests of ``vid-eval traj`` and ``vid-eval force``.

Ground truth at 200 Hz for 20 s: landed until sample 1000 (5 s), airborne until sample 3000
(15 s), landed again. The estimate (every second ground-truth sample, in an estimator world
rotated by ``-HEADING`` about z and shifted) carries, per region, a constant world force error,
a constant z position error and a constant attitude error about the body x axis, so that each
phase's numbers are known by hand.
"""
from __future__ import annotations

import pathlib

import numpy as np
from scipy.spatial.transform import Rotation

from eval_testdata import smooth_trajectory, write_csv, write_euroc_gt, write_force_estimate, write_state

MASS = 2.0  # kg
G = 9.81
HEADING = 140.0  # deg, the estimator's world against the ground truth's
T0_NS = 10**18
N = 4000  # ground-truth samples (200 Hz)
LIFTOFF_K, TOUCHDOWN_K = 1000, 3000  # first airborne sample, first landed sample again
HALF_WINDOW_K = 100  # 0.5 s: the default 1 s transition window
F_ERR = {"landed": np.array([0.05, 0.0, 0.0]), "airborne": np.array([0.0, -0.2, 0.0]),
         "window": np.array([0.0, 0.0, 1.5])}  # m/s^2, ground-truth world
Z_ERR = {"landed": 0.02, "airborne": -0.01, "window": 0.05}  # m
ROT_ERR_DEG = {"landed": 0.5, "airborne": 1.0, "window": 2.0}
EST_K = np.arange(10, N - 10, 2)  # ground-truth samples with an estimate


def region(k: np.ndarray) -> np.ndarray:
    """'window' within 0.5 s (inclusive) of an event, else 'landed' / 'airborne'."""
    k = np.asarray(k)
    near = (np.abs(k - LIFTOFF_K) <= HALF_WINDOW_K) | (np.abs(k - TOUCHDOWN_K) <= HALF_WINDOW_K)
    air = (k >= LIFTOFF_K) & (k < TOUCHDOWN_K)
    return np.where(near, "window", np.where(air, "airborne", "landed"))


def truth_mps2(ts: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Ground-truth external force / mass: the ground reaction m g up when landed, a small
    smooth force in the air."""
    air = ((k >= LIFTOFF_K) & (k < TOUCHDOWN_K))[:, None]
    flying = np.c_[0.5 * np.sin(ts), 0.3 * np.cos(ts), np.full_like(ts, 0.2)]
    return np.where(air, flying, [0.0, 0.0, G])


def write_flight(root: pathlib.Path, phases: bool = True) -> dict:
    """Write ``root/seq/mav0`` (force0, poses, phase0 unless ``phases`` is False) and
    ``root/run`` (force.csv, state.csv); return their paths."""
    k = np.arange(N)
    t_ns = T0_NS + k.astype(np.int64) * 5_000_000
    ts = k * 0.005
    p_gt, rot_gt = smooth_trajectory(ts, seed=4)
    f = truth_mps2(ts, k)
    mav0 = root / "seq" / "mav0"
    write_csv(mav0 / "force0" / "data.csv", "#timestamp [ns],f_x [N],f_y [N],f_z [N]", t_ns, f * MASS)
    gt = write_euroc_gt(mav0 / "state_groundtruth_estimate0" / "data.csv", t_ns, p_gt, rot_gt)
    if phases:
        write_phases(mav0 / "phase0" / "data.csv", t_ns, ((k >= LIFTOFF_K) & (k < TOUCHDOWN_K)))
    e = EST_K
    reg = region(e)
    R_EG = Rotation.from_euler("z", -HEADING, degrees=True)
    f_err = np.array([F_ERR[r] for r in reg])
    fw = R_EG.apply(f[e] + f_err)
    fb = rot_gt[e].inv().apply(f[e] + f_err)  # body error R_gt^T e: same norm as the world one
    tilt = Rotation.from_rotvec(np.c_[np.radians([ROT_ERR_DEG[r] for r in reg]), np.zeros((len(e), 2))])
    rot_est = R_EG * rot_gt[e] * tilt
    p_est = R_EG.apply(p_gt[e] + np.c_[np.zeros((len(e), 2)), [Z_ERR[r] for r in reg]]) + [4.0, -1.0, 0.5]
    run = root / "run"
    sigma = np.full((len(e), 3), 0.1)
    force = write_force_estimate(run / "force.csv", t_ns[e], fb, fw, sigma)
    state = write_state(run / "state.csv", t_ns[e], p_est, rot_est, fb, sigma_f=sigma)
    return {"mav0": mav0, "gt": gt, "force0": mav0 / "force0" / "data.csv", "force": force,
            "state": state, "t_ns": t_ns}


def write_phases(path: pathlib.Path, t_ns: np.ndarray, airborne: np.ndarray) -> pathlib.Path:
    """phase0/data.csv: ``#timestamp [ns],phase`` with 0 on the ground, 1 airborne."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as fh:
        fh.write("#timestamp [ns],phase\n")
        for t, a in zip(t_ns, airborne):
            fh.write(f"{int(t)},{int(a)}\n")
    return path
