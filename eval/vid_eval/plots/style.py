"""Shared figure setup and saving for all plots.

Every PNG vid-eval writes records the inputs it was made from (a PNG text chunk, key
``vid-eval inputs``). Before a command writes into a plot folder it checks that none of its
file names holds the plot of *other* inputs (:func:`check_plot_targets`): two runs evaluated
into one folder must not overwrite each other's figures silently (issue #25). Rerunning the
same command on the same files replaces its own plots as before.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Iterable, Optional

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from ..errors import ConfigurationError  # noqa: E402

EST_COLOR = "tab:blue"
GT_COLOR = "black"
ERR_COLOR = "tab:red"
AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")
STAMP_KEY = "vid-eval inputs"


def new_figure(rows: int = 1, cols: int = 1, width: float = 10.0, height: float = 4.0, **kw):
    """A figure with a grid of axes, sized for readability at a glance."""
    plt.rcParams.update({"font.size": 10, "axes.grid": True, "grid.alpha": 0.3})
    return plt.subplots(rows, cols, figsize=(width, height), **kw)


def read_stamp(path: os.PathLike) -> Optional[str]:
    """The inputs recorded in a PNG written by :func:`save`, or None (no stamp, not a PNG)."""
    from PIL import Image

    try:
        with Image.open(path) as img:
            return getattr(img, "text", {}).get(STAMP_KEY)
    except (OSError, ValueError):
        return None


def check_plot_targets(out_dir: os.PathLike, names: Iterable[str], stamp: str) -> None:
    """Refuse (one line, before anything is written) when a file of ``names`` in ``out_dir``
    holds a plot made from other inputs than ``stamp``."""
    for name in names:
        path = Path(out_dir) / name
        old = read_stamp(path) if path.is_file() else None
        if old is not None and old != stamp:
            raise ConfigurationError(
                f"{path}: holds the plot of other inputs ({old}); not overwritten: give "
                f"--plot-prefix NAME (or --method/--sequence), another --plot folder, or delete it")


def save(fig, out_dir: os.PathLike, name: str, stamp: Optional[str] = None) -> Path:
    """Save ``fig`` as ``out_dir/name`` (PNG, 120 dpi) with ``stamp`` (the inputs) in its
    metadata, create the folder, close the figure."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.tight_layout()
    fig.savefig(path, dpi=120, metadata={STAMP_KEY: stamp} if stamp else None)
    plt.close(fig)
    return path
