"""Figures of the data-driven mass-identification study (seed figures 13-17 analogs).

Usage: python elm_plots.py OUT_DIR
Reads OUT_DIR/series/<trajectory>__<profile>.csv (written by `vid_massid elm-study`:
t, mass_true, then one column per method) and writes
  OUT_DIR/figures/elm_<trajectory>.png   estimate vs truth, one panel per mass profile
  OUT_DIR/figures/elm_mass_profiles.png  the true mass profiles of the plotted runs
  OUT_DIR/figures/elm_hidden_nodes.png   table 1 (RMSE and |beta| vs hidden nodes), if present
"""
from __future__ import annotations

import csv
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

PROFILE_ORDER = ["constant", "linear_decrease", "step_drop", "step_pickup", "up_down"]
STYLES = {"elm": ("tab:orange", ":"), "relm": ("tab:blue", "-"), "oselm": ("tab:green", "--")}


def read_series(path: Path) -> tuple[list[str], np.ndarray]:
    with path.open() as f:
        header = next(csv.reader(f))
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return header, data


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
        profiles = [p for p in PROFILE_ORDER if p in files] + sorted(set(files) - set(PROFILE_ORDER))
        fig, axes = plt.subplots(len(profiles), 1, figsize=(9, 2.2 * len(profiles)), sharex=True,
                                 squeeze=False)
        for ax, profile in zip(axes[:, 0], profiles):
            header, d = read_series(files[profile])
            t, truth = d[:, 0], d[:, 1]
            ax.plot(t, truth, color="k", lw=2.0, label="truth")
            for j, name in enumerate(header[2:], start=2):
                color, ls = STYLES.get(name, (None, "-"))
                rmspe = 100.0 * np.sqrt(np.mean(((d[:, j] - truth) / truth) ** 2))
                ax.plot(t, d[:, j], color=color, ls=ls, lw=1.0, label=f"{name} ({rmspe:.1f} %)")
            ax.set_ylabel("mass [kg]")
            ax.set_title(f"{traj} / {profile}", fontsize=9)
            ax.legend(fontsize=7, loc="upper right", ncol=4)
            ax.grid(alpha=0.3)
            if profile not in plotted_profiles:
                pax.plot(t, truth / truth[0], label=profile)
                plotted_profiles.add(profile)
        axes[-1, 0].set_xlabel("t [s]")
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


def plot_hidden_nodes(out: Path) -> list[Path]:
    table = out / "table1_hidden_nodes.csv"
    if not table.exists():
        return []
    rows = list(csv.DictReader(table.open()))
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for traj in dict.fromkeys(r["trajectory"] for r in rows):
        for method in ("elm", "relm"):
            sel = [r for r in rows if r["trajectory"] == traj and r["method"] == method]
            if not sel:
                continue
            L = [int(r["hidden"]) for r in sel]
            ls = ":" if method == "elm" else "-"
            a1.plot(L, [float(r["test_rmse_pct"]) for r in sel], ls=ls, marker="o", ms=3,
                    label=f"{traj} {method}")
            a2.semilogy(L, [float(r["weight_norm"]) for r in sel], ls=ls, marker="o", ms=3)
    a1.set_xlabel("hidden nodes")
    a1.set_ylabel("held-out RMSE [%]")
    a1.set_yscale("log")
    a2.set_xlabel("hidden nodes")
    a2.set_ylabel("|beta|")
    a1.legend(fontsize=6, ncol=2)
    for a in (a1, a2):
        a.grid(alpha=0.3)
    fig.tight_layout()
    path = out / "figures" / "elm_hidden_nodes.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = Path(argv[1])
    if not (out / "series").is_dir() and not (out / "table1_hidden_nodes.csv").exists():
        print(f"elm_plots: {out}: no series/ folder or table1_hidden_nodes.csv", file=sys.stderr)
        return 1
    written = plot_trajectories(out) + plot_hidden_nodes(out)
    for p in written:
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
