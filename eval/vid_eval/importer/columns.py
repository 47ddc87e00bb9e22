"""Read the columns a stream of the source map names from one file: text (CSV or blank
separated, with or without a header) or HDF5 (h5py).

Times become exact int64 nanoseconds: text timestamps are parsed as decimals (a 19-digit
seconds value keeps its nanoseconds), HDF5 integer times are exact, HDF5 float seconds are
rounded to the nearest ns (float64 resolves ~0.25 us at 1.5e9 s).
"""
from __future__ import annotations

from decimal import Decimal, InvalidOperation
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..errors import InputFormatError
from .errors import MapError
from .sourcemap import TIME_UNITS, ColumnRef, QUANTITIES, StreamSpec

HDF5_SUFFIXES = (".h5", ".hdf5", ".hdf")


class Columns:
    """The quantities of one stream read from one file: ``t_ns`` (N,) and ``values[q]`` (N, k)."""

    def __init__(self, path: str, t_ns: np.ndarray, values: Dict[str, np.ndarray], lines: Optional[np.ndarray]):
        self.path = path
        self.t_ns = t_ns
        self.values = values
        self.lines = lines  # 1-based line of each row (text files), None for HDF5

    def where(self, row: int) -> Tuple[str, Optional[int]]:
        return self.path, (int(self.lines[row]) if self.lines is not None else None)


def read_stream(spec: StreamSpec, path: Path, map_path: str) -> Columns:
    """Read ``spec``'s time and quantities from ``path``; checks the column counts."""
    if not path.is_file():
        raise MapError(f"{path}: no such file (source map {map_path}, key '{spec.where('file')}')")
    reader = _Hdf5(path, map_path) if path.suffix.lower() in HDF5_SUFFIXES else _Text(path, map_path)
    t_ns = reader.time_ns(spec.time, TIME_UNITS[spec.time_unit], spec.where("time"))
    values = {}
    for q, refs in spec.columns.items():
        block = reader.columns(refs, spec.where(q))
        allowed = QUANTITIES[spec.name][q]
        if block.shape[1] not in allowed:
            want = " or ".join(str(a) for a in allowed) if len(allowed) < 4 else f"{allowed[0]}..{allowed[-1]}"
            raise MapError(f"{path}: key '{spec.where(q)}' ({map_path}): {block.shape[1]} column(s), "
                           f"expected {want}")
        if block.shape[0] != t_ns.shape[0]:
            raise InputFormatError(path, f"'{spec.where(q)}': {block.shape[0]} rows but the time "
                                         f"column has {t_ns.shape[0]}")
        bad = np.flatnonzero(~np.isfinite(block).all(axis=1))
        if bad.size:
            raise InputFormatError(path, f"'{spec.where(q)}': non-finite value", reader.line(int(bad[0])))
        values[q] = block
    cols = Columns(str(path), t_ns, values, reader.lines)
    _check_increasing(cols, spec)
    return cols


def _check_increasing(cols: Columns, spec: StreamSpec) -> None:
    d = np.diff(cols.t_ns)
    bad = np.flatnonzero(d <= 0)
    if bad.size:
        kind = "repeated" if d[bad[0]] == 0 else "decreasing"
        path, line = cols.where(int(bad[0]) + 1)
        where = "" if line is not None else f" (row {int(bad[0]) + 1})"
        raise InputFormatError(path, f"'{spec.where('time')}': {kind} timestamp{where}; a file's "
                                     "rows must be in time order", line)


class _Text:
    """A CSV or blank-separated table; the header (first line, ``#`` optional) names columns."""

    def __init__(self, path: Path, map_path: str):
        self.path, self.map_path = path, map_path
        self.names: List[str] = []
        rows, lines = [], []
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            raise InputFormatError(path, "not UTF-8 text") from None
        delim = None
        for lineno, raw in enumerate(text.splitlines(), start=1):
            s = raw.strip()
            if not s:
                continue
            if delim is None:
                delim = "," if "," in s else None
            tokens = [t.strip() for t in (s.split(delim) if delim else s.split())]
            if not rows and not self.names and (s.startswith("#") or not _is_number(tokens[0])):
                tokens[0] = tokens[0].lstrip("#").strip()
                if not tokens[0] and len(tokens) > 1 and delim is None:  # "# ts x y": '#' alone
                    tokens = tokens[1:]
                self.names = [t.split(" [")[0].split("[")[0].strip() for t in tokens]
                continue
            if s.startswith("#"):
                continue
            if rows and len(tokens) != len(rows[0]):
                raise InputFormatError(path, f"{len(tokens)} columns, earlier rows have {len(rows[0])}", lineno)
            rows.append(tokens)
            lines.append(lineno)
        if not rows:
            raise InputFormatError(path, "no data rows (empty file)")
        self.rows = rows
        self.lines = np.asarray(lines, dtype=np.int64)

    def line(self, row: int) -> int:
        return int(self.lines[row])

    def _index(self, ref: ColumnRef, where: str) -> int:
        ncol = len(self.rows[0])
        if isinstance(ref, int):
            if not 0 <= ref < ncol:
                raise MapError(f"{self.path}: key '{where}' ({self.map_path}): column index {ref} "
                               f"out of range (the file has {ncol} columns, 0-based)")
            return ref
        if ref not in self.names:
            have = ", ".join(self.names) if self.names else "no header line: use 0-based indices"
            raise MapError(f"{self.path}: key '{where}' ({self.map_path}): no column '{ref}' ({have})")
        return self.names.index(ref)

    def time_ns(self, ref: ColumnRef, unit_ns: int, where: str) -> np.ndarray:
        j = self._index(ref, where)
        out = np.empty(len(self.rows), dtype=np.int64)
        scale = Decimal(unit_ns)
        for i, row in enumerate(self.rows):
            try:
                value = Decimal(row[j])
                if not value.is_finite() or value.adjusted() > 25:
                    raise InvalidOperation
                out[i] = int((value * scale).to_integral_value())
            except (InvalidOperation, OverflowError):
                raise InputFormatError(self.path, f"'{where}': timestamp '{row[j]}' is not a number "
                                                  "(or out of range)", self.line(i)) from None
        return out

    def columns(self, refs: List[ColumnRef], where: str) -> np.ndarray:
        idx = [self._index(r, where) for r in refs]
        out = np.empty((len(self.rows), len(idx)))
        for i, row in enumerate(self.rows):
            for k, j in enumerate(idx):
                try:
                    out[i, k] = float(row[j])
                except ValueError:
                    name = self.names[j] if j < len(self.names) else str(j)
                    raise InputFormatError(self.path, f"'{where}' column '{name}': value '{row[j]}' "
                                                      "is not a number", self.line(i)) from None
        return out


class _Hdf5:
    """An HDF5 file: each reference is a dataset path; a 2-D dataset gives its columns."""

    lines = None

    def __init__(self, path: Path, map_path: str):
        try:
            import h5py
        except ImportError:  # pragma: no cover - h5py is a dependency of the package
            raise MapError(f"{path}: reading HDF5 needs h5py (pip install h5py)") from None
        self.path, self.map_path = path, map_path
        try:
            with h5py.File(path, "r") as f:
                self.data = {}
                f.visititems(lambda name, obj: self.data.__setitem__(name, obj[()])
                             if isinstance(obj, h5py.Dataset) else None)
        except OSError as exc:
            raise InputFormatError(path, f"not a readable HDF5 file ({exc})") from None

    def line(self, row: int) -> None:
        return None

    def _dataset(self, ref: ColumnRef, where: str) -> np.ndarray:
        key = str(ref).strip("/")
        if key not in self.data:
            raise MapError(f"{self.path}: key '{where}' ({self.map_path}): no dataset '{ref}' "
                           f"(datasets: {', '.join(sorted(self.data))})")
        arr = np.asarray(self.data[key])
        if arr.ndim == 1:
            arr = arr[:, None]
        if arr.ndim != 2 or not np.issubdtype(arr.dtype, np.number):
            raise MapError(f"{self.path}: key '{where}': dataset '{ref}' is not a numeric 1-D or 2-D array "
                           f"(shape {arr.shape})")
        return arr

    def time_ns(self, ref: ColumnRef, unit_ns: int, where: str) -> np.ndarray:
        arr = self._dataset(ref, where)
        if arr.shape[1] != 1:
            raise MapError(f"{self.path}: key '{where}': dataset '{ref}' has {arr.shape[1]} columns, expected 1")
        t = arr[:, 0]
        if np.issubdtype(t.dtype, np.integer):
            return t.astype(np.int64) * unit_ns
        if not np.isfinite(t).all():
            raise InputFormatError(self.path, f"'{where}': non-finite timestamp at row "
                                              f"{int(np.flatnonzero(~np.isfinite(t))[0])}")
        return np.rint(t.astype(np.float64) * unit_ns).astype(np.int64)

    def columns(self, refs: List[ColumnRef], where: str) -> np.ndarray:
        blocks = [self._dataset(r, where).astype(np.float64) for r in refs]
        if len({b.shape[0] for b in blocks}) != 1:
            raise InputFormatError(self.path, f"'{where}': datasets of different lengths "
                                              f"({', '.join(str(b.shape[0]) for b in blocks)})")
        return np.hstack(blocks)


def _is_number(token: str) -> bool:
    try:
        float(token)
        return True
    except ValueError:
        return False
