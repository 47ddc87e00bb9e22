"""A log in pieces: find them (the map's ``pieces`` glob), read each stream from every piece and
join them in time order.

Rules of the join: pieces are ordered by their first timestamp; a row whose timestamp another
piece already holds with the same values is a duplicate, dropped and counted; the same time
with other values, or pieces that interleave, is an error naming both files (two different
logs, or a clock reset, would otherwise be silently merged).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List

import numpy as np

from .columns import Columns, read_stream
from .errors import DataError, MapError
from .sourcemap import SourceMap, StreamSpec


@dataclass
class Stream:
    """One stream joined over all pieces."""

    name: str
    t_ns: np.ndarray
    values: Dict[str, np.ndarray]
    files: List[str]
    duplicates: int = 0


def find_pieces(smap: SourceMap, root: Path) -> List[Path]:
    """The piece folders: matches of the map's ``pieces`` glob under ``root``, else ``root``."""
    if not root.exists():
        raise MapError(f"{root}: no such input file or folder")
    if root.is_file():
        return [root.parent]
    if not smap.pieces:
        return [root]
    found = sorted(p for p in root.glob(smap.pieces) if p.is_dir())
    if not found:
        raise MapError(f"{root}: no piece matches '{smap.pieces}' (source map {smap.path}, key 'pieces')")
    return found


def _file_of(spec: StreamSpec, piece: Path, root: Path) -> Path:
    if root.is_file():  # INPUT is a file: every stream of the map reads that file
        return root
    p = Path(spec.file)
    return p if p.is_absolute() else piece / p


def read_joined(spec: StreamSpec, smap: SourceMap, pieces: List[Path], root: Path) -> Stream:
    """Read ``spec`` from every piece and join the parts (sorted by time, duplicates dropped)."""
    parts = [read_stream(spec, _file_of(spec, piece, root), smap.path) for piece in pieces]
    parts.sort(key=lambda c: int(c.t_ns[0]))
    return join(spec.name, parts)


def join(name: str, parts: List[Columns]) -> Stream:
    """Join time-sorted parts; see the module's rules."""
    t_all = [parts[0].t_ns]
    v_all = {q: [v] for q, v in parts[0].values.items()}
    files = [parts[0].path]
    duplicates = 0
    last = int(parts[0].t_ns[-1])
    prev = parts[0]
    for part in parts[1:]:
        t = part.t_ns
        overlap = t <= last
        if overlap.any():
            n = int(overlap.sum())
            if not overlap[:n].all():  # pragma: no cover - rows are increasing per file
                raise DataError(f"{part.path}: rows not in time order")
            held = np.concatenate(t_all)
            pos = np.searchsorted(held, t[:n])
            same_time = (pos < held.size) & (held[np.minimum(pos, held.size - 1)] == t[:n])
            if not same_time.all():
                k = int(np.flatnonzero(~same_time)[0])
                raise DataError(f"{part.path}: {name} piece overlaps {prev.path} in time "
                                f"({n} rows up to {(last - int(t[0])) * 1e-9:.3f} s) with timestamps the "
                                f"other piece does not have (first at row {k + 1}): two different logs? "
                                "join only consecutive pieces of one log")
            for q, v in part.values.items():
                held_v = np.concatenate(v_all[q])[pos]
                if not np.allclose(held_v, v[:n], rtol=1e-9, atol=1e-12):
                    k = int(np.flatnonzero(~np.isclose(held_v, v[:n], rtol=1e-9, atol=1e-12).all(axis=1))[0])
                    raise DataError(f"{part.path}: {name} row {k + 1} repeats a timestamp of {prev.path} "
                                    f"with other '{q}' values: two different logs?")
            duplicates += n
            t = t[n:]
            part = Columns(part.path, t, {q: v[n:] for q, v in part.values.items()},
                           None if part.lines is None else part.lines[n:])
        if t.size:
            t_all.append(t)
            for q, v in part.values.items():
                v_all[q].append(v)
            last = int(t[-1])
        files.append(part.path)
        prev = part
    return Stream(name, np.concatenate(t_all), {q: np.concatenate(v) for q, v in v_all.items()},
                  files, duplicates)


@dataclass
class Gaps:
    """Gaps of a stream: intervals longer than 1.5 x the median sample interval."""

    count: int
    largest_s: float
    median_dt_s: float


def gaps(t_ns: np.ndarray) -> Gaps:
    if t_ns.size < 2:
        return Gaps(0, 0.0, 0.0)
    d = np.diff(t_ns)
    med = float(np.median(d))
    big = d > 1.5 * med
    return Gaps(int(big.sum()), float(d.max()) * 1e-9 if big.any() else 0.0, med * 1e-9)
