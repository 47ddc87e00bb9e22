"""What a plot test asserts about a PNG (docs/testing.md): not just that a file exists, but
that it is the figure asked for: its size, the curves of the expected colours drawn with enough
pixels to be lines (not a legend swatch), and, for vid-eval's plots, the inputs recorded in it.
"""
from __future__ import annotations

import os

import numpy as np
from matplotlib.colors import to_rgb
from PIL import Image

from vid_eval.plots.style import read_stamp


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
