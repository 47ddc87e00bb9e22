"""Plots of the mass-identification study (seed figures 7-11): `vid-eval massid-plots`, which
`vid_massid report` runs.

Reads OUT/runs.csv and OUT/estimates/<trajectory>/<profile>/run_NNN.csv written by
`vid_massid run` and writes, into --out:

* ``<trajectory>.png``: a row per mass profile and a column per method, the true mass under
  each method's estimate of the lowest-numbered evaluated run (the seed's figures 7-11 overlay
  them; overlaid, the converged estimates hid each other);
* ``inputs.png``: the commanded inputs per trajectory (thrust-to-weight ratio T / (m g) and
  body-rate magnitude |w|), to explain why a trajectory that drives the controller near its
  limits (lemniscate) degrades the observers.
"""
from __future__ import annotations

import csv
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .methods import CaseSeries, methods_grid, ordered  # noqa: E402

PROFILE_ORDER = ["constant", "linear_decrease", "step_drop", "step_pickup", "up_down"]
TRAJ_ORDER = ["random", "loop", "lemniscate", "zigzag", "square"]
METHOD_ORDER = ["ekf", "ukf", "msckf", "swls", "vio"]  # the first is the reference the others are compared to
NOT_METHODS = ("t", "mass_true", "thrust_cmd", "wx", "wy", "wz")
GRAVITY = 9.81


def read_estimates(path: pathlib.Path) -> dict[str, np.ndarray]:
    """Columns of one estimates CSV as float arrays; raises ValueError naming file and line."""
    with path.open() as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if not header or header[:2] != ["t", "mass_true"]:
            raise ValueError(f"{path}:1: expected header starting with t,mass_true")
        rows = []
        for lineno, row in enumerate(reader, start=2):
            if len(row) != len(header):
                raise ValueError(f"{path}:{lineno}: expected {len(header)} fields, got {len(row)}")
            try:
                rows.append([float(x) for x in row])
            except ValueError as e:
                raise ValueError(f"{path}:{lineno}: {e}") from None
    if not rows:
        raise ValueError(f"{path}: no samples")
    data = np.asarray(rows)
    return {name: data[:, i] for i, name in enumerate(header)}


def find_runs(results: pathlib.Path) -> dict[tuple[str, str], pathlib.Path]:
    """(trajectory, profile) -> estimates CSV of the lowest-numbered run."""
    found: dict[tuple[str, str], pathlib.Path] = {}
    for path in sorted((results / "estimates").glob("*/*/run_*.csv")):
        key = (path.parent.parent.name, path.parent.name)
        found.setdefault(key, path)
    if not found:
        raise ValueError(f"{results / 'estimates'}: no run_*.csv (run `vid_massid run` first)")
    return found


def plot_trajectory(traj: str, runs: dict[tuple[str, str], pathlib.Path], out: pathlib.Path) -> pathlib.Path:
    fig = trajectory_figure(traj, runs)
    fig.tight_layout()
    path = out / f"{traj}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def trajectory_figure(traj: str, runs: dict[tuple[str, str], pathlib.Path]):
    """A row per mass profile, a column per method, each with the truth (vid_eval.plots.methods:
    overlaid, the filters' converged estimates hid each other)."""
    cases = []
    for prof in ordered({p for (t, p) in runs if t == traj}, PROFILE_ORDER):
        d = read_estimates(runs[(traj, prof)])
        ests = {k: v for k, v in d.items() if k not in NOT_METHODS}
        cases.append(CaseSeries(f"{prof} ({runs[(traj, prof)].stem})", d["t"], d["mass_true"], ests))
    methods = ordered(set(cases[0].estimates), METHOD_ORDER)
    # the first 0.1-0.3 s of start-up transients would squeeze the rest into a line
    return methods_grid(cases, methods, f"{traj}: mass estimates of the filters",
                        ylim=lambda c: (0.7 * c.truth.min(), 1.35 * c.truth.max()))


def plot_inputs(runs: dict[tuple[str, str], pathlib.Path], out: pathlib.Path) -> pathlib.Path:
    trajs = ordered({t for (t, _) in runs}, TRAJ_ORDER)
    fig, axes = plt.subplots(len(trajs), 2, figsize=(11, 2.2 * len(trajs)), sharex=True, squeeze=False)
    for row, traj in zip(axes, trajs):
        prof = ordered({p for (t, p) in runs if t == traj}, PROFILE_ORDER)[0]
        d = read_estimates(runs[(traj, prof)])
        twr = d["thrust_cmd"] / (d["mass_true"] * GRAVITY)
        w = np.sqrt(d["wx"] ** 2 + d["wy"] ** 2 + d["wz"] ** 2)
        row[0].plot(d["t"], twr, lw=0.8)
        row[0].set_ylabel("T / (m g)")
        row[0].set_title(f"{traj} ({prof}): thrust-to-weight, p99 {np.percentile(twr, 99):.2f}", fontsize=9)
        row[1].plot(d["t"], w, lw=0.8, color="tab:red")
        row[1].set_ylabel("|w| [rad/s]")
        row[1].set_title(f"{traj}: body-rate magnitude, p99 {np.percentile(w, 99):.2f} rad/s", fontsize=9)
        for ax in row:
            ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t [s]")
    axes[-1, 1].set_xlabel("t [s]")
    fig.tight_layout()
    path = out / "inputs.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
