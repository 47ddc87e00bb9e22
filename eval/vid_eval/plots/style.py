"""Shared figure setup and saving for all plots."""
from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

EST_COLOR = "tab:blue"
GT_COLOR = "black"
ERR_COLOR = "tab:red"
AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")


def new_figure(rows: int = 1, cols: int = 1, width: float = 10.0, height: float = 4.0, **kw):
    """A figure with a grid of axes, sized for readability at a glance."""
    plt.rcParams.update({"font.size": 10, "axes.grid": True, "grid.alpha": 0.3})
    return plt.subplots(rows, cols, figsize=(width, height), **kw)


def save(fig, out_dir: os.PathLike, name: str) -> Path:
    """Save ``fig`` as ``out_dir/name`` (PNG, 120 dpi), create the folder, close the figure."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
