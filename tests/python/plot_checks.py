"""Checks on matplotlib figures as a reader sees them (issue #25): is an artist visible at all,
or is every pixel of it covered by other curves?

An artist is *visible* when hiding it clearly changes (by more than :data:`MIN_CHANGE` in a
colour channel) at least ``min_pixels`` pixels of the figure rendered with curves not
anti-aliased. A curve drawn exactly under another one of the
same width changes none, however distinct its colour; legend entries are separate artists, so
a legend alone does not count.

On a written PNG (a program's --plot output, no figure object at hand) :func:`assert_plot`
checks what is drawn: its size, the expected curves' colours over enough pixels to be lines, and
for vid-eval's plots the inputs recorded in it (docs/testing.md) - not a PNG header.
"""
from __future__ import annotations

import os
from typing import List, Optional

import numpy as np
from matplotlib.colors import to_rgb
from PIL import Image

from vid_eval.plots.style import read_stamp

CHECK_DPI = 50   # coarse enough to be quick on a loaded machine, fine enough that a 1 px curve shows
MIN_CHANGE = 12  # of 255: a 15 % tint of a band still counts


def render(fig) -> np.ndarray:
    """The figure as an RGB array (Agg canvas) at :data:`CHECK_DPI`, curves drawn without
    anti-aliasing (a thin anti-aliased curve is all edges, tinted by whatever lies under it)."""
    fig.set_dpi(CHECK_DPI)
    for ax in fig.axes:
        for ln in ax.get_lines():
            ln.set_antialiased(False)
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[:, :, :3].astype(np.int16)


def changed_pixels(fig, artist, full: Optional[np.ndarray] = None) -> int:
    """Pixels that clearly change when ``artist`` is hidden (``full``: the figure rendered
    with everything shown, when already known)."""
    full = render(fig) if full is None else full
    artist.set_visible(False)
    try:
        without = render(fig)
    finally:
        artist.set_visible(True)
    return int(np.count_nonzero(np.max(np.abs(full - without), axis=2) > MIN_CHANGE))


def labelled_lines(ax) -> list:
    """The data curves of an axes that have a legend label."""
    return [ln for ln in ax.get_lines() if not ln.get_label().startswith("_")]


def hidden_curves(fig, min_pixels: int = 10) -> List[str]:
    """'axes title: label' of every labelled curve whose removal changes < ``min_pixels``."""
    full = render(fig)
    return [f"{ax.get_title()}: {ln.get_label()}" for ax in fig.axes for ln in labelled_lines(ax)
            if changed_pixels(fig, ln, full) < min_pixels]


def colour_pixels(path: os.PathLike, colour: str, tol: int = 40) -> int:
    """Pixels of the PNG within ``tol`` (per channel, 0-255) of a matplotlib colour."""
    img = np.asarray(Image.open(path).convert("RGB")).astype(int)
    want = np.round(np.array(to_rgb(colour)) * 255).astype(int)
    return int(np.count_nonzero(np.all(np.abs(img - want) <= tol, axis=2)))


def assert_plot(path: os.PathLike, colours: tuple, min_pixels: int = 300, min_size=(300, 600),
                stamp_has: tuple = ()) -> None:
    """The PNG is at least min_size (height, width) pixels; each colour covers min_pixels (a
    curve across the axes, more than a legend entry's ~30); the recorded inputs name stamp_has."""
    with Image.open(path) as img:
        w, h = img.size
    assert h >= min_size[0] and w >= min_size[1], f"{path}: {w}x{h} pixels"
    for c in colours:
        n = colour_pixels(path, c)
        assert n >= min_pixels, f"{path}: {n} pixels of {c}, expected a curve (>= {min_pixels})"
    if stamp_has:
        stamp = read_stamp(path) or ""
        for s in stamp_has:
            assert str(s) in stamp, f"{path}: inputs {stamp!r} do not name {s}"
