#!/usr/bin/env python3
"""How well can any estimator know the body force of a real flight? A bound from the data.

The estimator's force is, at heart, accelerometer minus thrust, filtered. Here that signal is
given every advantage an estimator cannot have, and scored against the same motion-capture force
truth as `scripts/bench_realdata.py`:

* zero-phase (non-causal) Butterworth low-passes of (accelerometer - thrust / m) at 1-8 Hz, with
  the constant offset taken from the truth itself (an oracle accelerometer bias);
* an oracle affine calibration: truth ~ A a_lp + s T_lp e_z + c (13 numbers fitted to the truth
  by least squares: accelerometer scale and misalignment, thrust scale, bias), in-sample and
  fitted on the first half / scored on the second.

If even these stay above a target, the target asks for more than the sensors (and the truth)
hold: the rest is truth error (mocap positions differentiated twice, 5 Hz), effects no affine
model of these two signals describes, or both.

  .venv/bin/python scripts/realdata_force_bound.py /tmp/bench_real/blackbird_clover

(the folder bench_realdata.py imports: mav0/imu0, thrust0, state_groundtruth_estimate0, force0).
"""
from __future__ import annotations

import argparse
import pathlib
import sys

import numpy as np
from scipy.signal import butter, filtfilt
from scipy.spatial.transform import Rotation

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "eval"))
from vid_eval.tools.loaders import load_vehicle  # noqa: E402
from vid_eval.tools.table_reader import read_table  # noqa: E402


def _table(path: pathlib.Path) -> np.ndarray:
    """Time [ns] (as float) and the value columns of a docs/formats.md §1 CSV."""
    tab = read_table(path, range(2, 200), what=path.parent.name)
    return np.hstack([tab.t_ns[:, None].astype(float), tab.values])


def rmse(e: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(e ** 2, axis=1))))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dataset", type=pathlib.Path, help="imported folder (OUT/blackbird_clover of bench_realdata.py)")
    ap.add_argument("--edge", type=float, default=2.0, help="seconds left out at both ends of the truth")
    args = ap.parse_args()
    mav = args.dataset / "mav0"
    mass = load_vehicle(mav / "vehicle.yaml").mass_kg
    imu, thrust = _table(mav / "imu0" / "data.csv"), _table(mav / "thrust0" / "data.csv")
    gt, force = _table(mav / "state_groundtruth_estimate0" / "data.csv"), _table(mav / "force0" / "data.csv")

    t, acc = imu[:, 0], imu[:, 4:7]
    T = np.interp(t, thrust[:, 0], thrust[:, 1]) / mass
    q_xyzw = np.stack([np.interp(t, gt[:, 0], gt[:, k]) for k in (5, 6, 7, 4)], axis=1)
    R_WI = Rotation.from_quat(q_xyzw / np.linalg.norm(q_xyzw, axis=1)[:, None])
    f_W = np.stack([np.interp(t, force[:, 0], force[:, k]) for k in (1, 2, 3)], axis=1) / mass
    truth_I = R_WI.inv().apply(f_W)
    ok = (t > force[0, 0] + args.edge * 1e9) & (t < force[-1, 0] - args.edge * 1e9)
    rate = 1e9 / np.median(np.diff(t))
    raw = acc.copy()
    raw[:, 2] -= T

    print("| estimate of the body force (oracle help) | RMSE [m/s²] |\n|---|---|")
    for fc in (1.0, 2.0, 3.0, 5.0, 8.0):
        b, a = butter(2, fc / (rate / 2))
        est = filtfilt(b, a, raw, axis=0)
        bias = np.mean(est[ok] - truth_I[ok], axis=0)
        print(f"| (accel - thrust/m), zero-phase {fc:g} Hz, bias from the truth | {rmse(est[ok] - bias - truth_I[ok]):.3f} |")
    b, a = butter(2, 3.0 / (rate / 2))
    X = np.hstack([filtfilt(b, a, acc, axis=0), filtfilt(b, a, T)[:, None], np.ones((len(t), 1))])[ok]
    y = truth_I[ok]
    W, *_ = np.linalg.lstsq(X, y, rcond=None)
    print(f"| affine calibration fitted to the truth (13 numbers), 3 Hz, in-sample | {rmse(X @ W - y):.3f} |")
    h = len(y) // 2
    W1, *_ = np.linalg.lstsq(X[:h], y[:h], rcond=None)
    print(f"| the same fitted on the first half, scored on the second | {rmse(X[h:] @ W1 - y[h:]):.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
