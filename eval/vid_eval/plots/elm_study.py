"""Figures of the data-driven mass-identification study (seed figures 13-17 analogs):
`vid-eval elm-plots OUT_DIR`, which `vid_massid elm-study --plots` runs.

Reads OUT_DIR/series/<trajectory>__<profile>.csv (written by `vid_massid elm-study`:
t, mass_true, then one column per method) and writes
  OUT_DIR/figures/elm_<trajectory>.png   estimate vs truth: a row per mass profile, a column
                                         per method (equal methods would hide each other)
  OUT_DIR/figures/elm_mass_profiles.png  the true mass profiles of the plotted runs
  OUT_DIR/figures/elm_hidden_nodes.png   table 1 (RMSE and |beta| vs hidden nodes), if present
"""
from __future__ import annotations

import csv
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .methods import CaseSeries, methods_grid, ordered  # noqa: E402

PROFILE_ORDER = ["constant", "linear_decrease", "step_drop", "step_pickup", "up_down"]
METHOD_ORDER = ["relm", "elm", "oselm"]  # the first is the reference the others are compared to
# hidden-nodes plot: ELM and RELM coincide; RELM solid with dots under ELM dashed with hollow
# squares, so both stay visible where they are equal (issue #25)
NODE_STYLES = {"relm": dict(ls="-", marker="o", ms=3, zorder=2),
               "elm": dict(ls="--", marker="s", ms=7, mfc="none", zorder=3)}


def read_series(path: Path) -> tuple[list[str], np.ndarray]:
    with path.open() as f:
        header = next(csv.reader(f))
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return header, data


def elm_figure(traj: str, files: dict[str, Path]):
    """One row per mass profile, one column per method (each with the truth), see
    vid_eval.plots.methods."""
    cases, methods = [], None
    for profile in ordered(files, PROFILE_ORDER):
        header, d = read_series(files[profile])
        methods = methods or ordered(header[2:], METHOD_ORDER)
        cases.append(CaseSeries(profile, d[:, 0], d[:, 1],
                                {name: d[:, j] for j, name in enumerate(header) if j >= 2}))
    return methods_grid(cases, methods, f"{traj}: data-driven mass estimates on held-out runs")


def plot_trajectories(out: Path) -> list[Path]:
    groups: dict[str, dict[str, Path]] = defaultdict(dict)
    for p in sorted((out / "series").glob("*__*.csv")):
        traj, profile = p.stem.split("__", 1)
        groups[traj][profile] = p
    written = []
    fig_dir = out / "figures"
    fig_dir.mkdir(parents=True, exist_ok=True)
    profiles_fig, pax = plt.subplots(1, 1, figsize=(7, 4))
    plotted_profiles = set()
    for traj, files in groups.items():
        fig = elm_figure(traj, files)
        for profile in ordered(files, PROFILE_ORDER):
            if profile not in plotted_profiles:
                _, d = read_series(files[profile])
                pax.plot(d[:, 0], d[:, 1] / d[0, 1], label=profile)
                plotted_profiles.add(profile)
        fig.tight_layout()
        path = fig_dir / f"elm_{traj}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    if plotted_profiles:
        pax.set_xlabel("t [s]")
        pax.set_ylabel("m(t) / m(0)")
        pax.set_title("mass profiles (held-out runs)")
        pax.legend(fontsize=8)
        pax.grid(alpha=0.3)
        profiles_fig.tight_layout()
        path = fig_dir / "elm_mass_profiles.png"
        profiles_fig.savefig(path, dpi=110)
        written.append(path)
    plt.close(profiles_fig)
    return written


def hidden_nodes_figure(rows: list[dict]):
    """Held-out RMSE and |beta| against the hidden-node count: colour = trajectory, line and
    marker = method (legend in two parts)."""
    from matplotlib.lines import Line2D

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.4))
    trajs = list(dict.fromkeys(r["trajectory"] for r in rows))
    colors = {t: f"C{i}" for i, t in enumerate(trajs)}
    for traj in trajs:
        for method, style in NODE_STYLES.items():
            sel = [r for r in rows if r["trajectory"] == traj and r["method"] == method]
            if not sel:
                continue
            L = [int(r["hidden"]) for r in sel]
            kw = dict(style, color=colors[traj], lw=1.2, label=f"{traj} {method}")
            a1.plot(L, [float(r["test_rmse_pct"]) for r in sel], **kw)
            a2.plot(L, [float(r["weight_norm"]) for r in sel], **kw)
    a1.set_ylabel("held-out RMSE [%]")
    a1.set_yscale("log")
    a2.set_ylabel("|beta|")
    a2.set_yscale("log")
    from matplotlib.ticker import FuncFormatter

    plain = FuncFormatter(lambda v, _: f"{v:g}")  # 3 rather than 3x10^0 on the log axes
    for a in (a1, a2):
        a.set_xlabel("hidden nodes")
        a.grid(alpha=0.3)
        a.yaxis.set_major_formatter(plain)
        a.yaxis.set_minor_formatter(plain)
    handles = [Line2D([], [], color=colors[t], lw=2, label=t) for t in trajs]
    handles += [Line2D([], [], color="0.3", lw=1.2, label=m, **{k: v for k, v in s.items() if k != "zorder"})
                for m, s in NODE_STYLES.items()]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8)
    fig.suptitle("ELM and RELM against the number of hidden nodes (equal values overlap: dots inside squares)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return fig


def plot_hidden_nodes(out: Path) -> list[Path]:
    table = out / "table1_hidden_nodes.csv"
    if not table.exists():
        return []
    fig = hidden_nodes_figure(list(csv.DictReader(table.open())))
    path = out / "figures" / "elm_hidden_nodes.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]
