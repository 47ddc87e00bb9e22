"""Output files: CSV streams written row by row and PNG images, with disk-full reporting.

Every OS error raised while writing is re-raised as DiskFullError naming the file, so a full
disk (ENOSPC) never surfaces as a traceback or as a silently short file.
"""
from __future__ import annotations

import errno
import pathlib
from typing import IO, Iterable

import numpy as np
from .errors import DiskFullError
from .png import encode_gray8


def _open_out(path: pathlib.Path, mode: str) -> IO:
    """Open an output file (single place, so tests can substitute e.g. /dev/full)."""
    return open(path, mode)  # noqa: SIM115 - closed by the owning sink


def os_error(path: pathlib.Path, err: OSError) -> DiskFullError:
    """Translate an OSError raised while writing PATH into a one-line DiskFullError."""
    if err.errno == errno.ENOSPC:
        return DiskFullError(f"output disk full (ENOSPC) while writing {path}")
    return DiskFullError(f"cannot write {path}: {err.strerror or err}")


def fmt(value) -> str:
    """Shortest text that reads back to exactly the same number (ints stay ints)."""
    if isinstance(value, (bool, np.bool_)):
        return str(int(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return repr(float(value))


class CsvStream:
    """One data.csv: header line, then one row per call, flushed by the OS buffer."""

    def __init__(self, path: pathlib.Path, header: str):
        self.path = path
        self.count = 0
        self.first_ns: int | None = None
        self.last_ns: int | None = None
        self.dropped = 0
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            self._file = _open_out(path, "w")
            self._file.write(header + "\n")
        except OSError as err:
            raise os_error(path, err) from None

    def accepts(self, t_ns: int) -> bool:
        """False (and counted as dropped) for a timestamp not after the previous row's."""
        if self.last_ns is not None and t_ns <= self.last_ns:
            self.dropped += 1
            return False
        return True

    def write(self, t_ns: int, values: Iterable) -> None:
        line = str(int(t_ns)) + "".join("," + fmt(v) for v in values) + "\n"
        self.write_raw(t_ns, line)

    def write_raw(self, t_ns: int, line: str) -> None:
        try:
            self._file.write(line)
        except OSError as err:
            raise os_error(self.path, err) from None
        if self.first_ns is None:
            self.first_ns = t_ns
        self.last_ns = t_ns
        self.count += 1

    def close(self) -> None:
        if self._file is None:
            return
        f, self._file = self._file, None
        try:
            f.close()
        except OSError as err:
            raise os_error(self.path, err) from None

    def rate_hz(self) -> float | None:
        """Mean rate over the written rows (None with fewer than two rows)."""
        if self.count < 2 or self.first_ns is None or self.last_ns == self.first_ns:
            return None
        return (self.count - 1) * 1e9 / (self.last_ns - self.first_ns)


def write_png(path: pathlib.Path, gray: np.ndarray, compress_level: int) -> int:
    """Write an 8-bit single-channel image as PNG; returns the bytes written."""
    data = encode_gray8(gray, compress_level)
    try:
        with _open_out(path, "wb") as f:
            f.write(data)
    except OSError as err:
        raise os_error(path, err) from None
    return len(data)


class PngPool:
    """Encodes and writes PNGs on worker threads (zlib and file writes release the GIL).

    At most 2 x jobs images are in flight, so memory stays bounded; a worker's error (e.g. disk
    full) is re-raised in the caller at the next submit or at close(). jobs <= 1 writes inline.
    """

    def __init__(self, jobs: int, compress_level: int):
        from collections import deque
        from concurrent.futures import ThreadPoolExecutor

        self.level = compress_level
        self.jobs = max(1, int(jobs))
        self.pool = ThreadPoolExecutor(self.jobs) if self.jobs > 1 else None
        self.pending = deque()
        self.png_bytes = 0

    def submit(self, path: pathlib.Path, gray: np.ndarray) -> None:
        if self.pool is None:
            self.png_bytes += write_png(path, gray, self.level)
            return
        self.pending.append(self.pool.submit(write_png, path, gray, self.level))
        while len(self.pending) > 2 * self.jobs:
            self.png_bytes += self.pending.popleft().result()

    def close(self) -> None:
        try:
            while self.pending:
                self.png_bytes += self.pending.popleft().result()
        finally:
            if self.pool is not None:
                for f in self.pending:
                    f.cancel()
                self.pool.shutdown(wait=True)
                self.pool = None
