"""Helpers shared by the test_bag2asl*.py files: read the converted CSV files back."""
from __future__ import annotations

import csv
import pathlib

import numpy as np
from PIL import Image


def rows(path: pathlib.Path) -> list[list[str]]:
    """Data rows of a data.csv (header checked to start with '#')."""
    lines = path.read_text().splitlines()
    assert lines[0].startswith("#"), path
    return [r for r in csv.reader(lines[1:])]


def numeric(path: pathlib.Path) -> list[tuple[int, list[float]]]:
    return [(int(r[0]), [float(v) for v in r[1:]]) for r in rows(path)]


def png(path: pathlib.Path) -> np.ndarray:
    with Image.open(path) as img:
        assert img.mode == "L", (path, img.mode)
        return np.asarray(img).copy()


def f32(x: float) -> float:
    """The double a float32 field carries after a round trip."""
    return float(np.float32(x))
