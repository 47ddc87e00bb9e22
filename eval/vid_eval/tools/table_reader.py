"""Strict reader for the numeric text tables of docs/formats.md §1/§2 (CSV and TUM whitespace files).

It checks what the metrics rely on and reports the first problem with file and line:
missing/empty file, wrong column count, a value that is not a number, timestamps that are
not strictly increasing. Timestamps are returned as exact int64 nanoseconds.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import Iterable, List, Optional, Sequence

import numpy as np

from ..errors import InputFormatError, PathLike
from ..core.formats import header_names


_INT64_MIN, _INT64_MAX = -(2**63), 2**63 - 1


@dataclass
class Table:
    """A parsed table: exact int64 ns time column, float values of the other columns."""

    path: str
    header: Optional[str]
    t_ns: np.ndarray  # (N,) int64
    values: np.ndarray  # (N, C-1) float64, columns after the timestamp
    lines: np.ndarray  # (N,) 1-based line numbers of the rows in the file


def parse_time(token: str, unit_seconds: bool, path: str, line: int, column: str) -> int:
    """Parse a timestamp to int ns exactly (Decimal avoids float rounding of seconds)."""
    try:
        value = Decimal(token)
    except InvalidOperation:
        raise InputFormatError(path, f"{column}: timestamp '{token}' is not a number", line) from None
    if not value.is_finite():
        raise InputFormatError(path, f"{column}: timestamp '{token}' is not finite", line)
    # int64 nanoseconds hold +-292 years; checked on the exponent first, so that '1e999999'
    # neither overflows the decimal context nor builds a million-digit integer.
    ns = None
    if value.adjusted() < 30:
        ns = int((value * Decimal(1_000_000_000) if unit_seconds else value).to_integral_value())
    if ns is None or not _INT64_MIN <= ns <= _INT64_MAX:
        raise InputFormatError(path, f"{column}: timestamp '{token}' is out of range "
                                     "(int64 nanoseconds)", line)
    return ns


def read_table(
    path: PathLike,
    columns: Iterable[int],
    *,
    delimiter: Optional[str] = ",",
    time_in_seconds: bool = False,
    expected_names: Optional[Sequence[str]] = None,
    what: str = "table",
    repeated_times: bool = False,
) -> Table:
    """Read a numeric table whose first column is a timestamp.

    Args:
        path: file to read.
        columns: allowed column counts of a data row (e.g. ``{8}`` or ``range(8, 100)``).
        delimiter: ``","`` for CSV, ``None`` for any whitespace (TUM).
        time_in_seconds: the first column is seconds (TUM) instead of nanoseconds.
        expected_names: column names the header must carry (checked only if a header exists).
        what: name of the format, used in error messages.
        repeated_times: rows may share a timestamp (one row per feature of a frame); time
            must still never decrease.

    Raises:
        InputFormatError: with file and line for every malformed input.
    """
    spath = os.fspath(path)
    allowed = set(columns)
    if not os.path.isfile(spath):
        raise InputFormatError(spath, f"no such {what} file")
    try:
        handle = open(spath, "r", encoding="utf-8")
    except OSError as exc:
        raise InputFormatError(spath, f"cannot open: {exc.strerror}") from None
    with handle:
        try:
            return _read_rows(handle, spath, allowed, delimiter, time_in_seconds, expected_names, what,
                              repeated_times)
        except UnicodeDecodeError:
            raise not_utf8(spath, what) from None


def not_utf8(path: str, what: str) -> InputFormatError:
    """The error for a file that is not UTF-8 text, at the line of its first bad byte."""
    with open(path, "rb") as handle:
        raw = handle.read()
    try:
        raw.decode("utf-8")
    except UnicodeDecodeError as err:
        return InputFormatError(path, f"{what}: not UTF-8 text (byte 0x{raw[err.start]:02x})",
                                raw.count(b"\n", 0, err.start) + 1)
    return InputFormatError(path, f"{what}: not UTF-8 text")


def _read_rows(handle, spath: str, allowed: set, delimiter: Optional[str], time_in_seconds: bool,
               expected_names: Optional[Sequence[str]], what: str, repeated_times: bool = False) -> Table:
    header: Optional[str] = None
    header_lineno = 1
    times: List[int] = []
    rows: List[List[float]] = []
    lines: List[int] = []
    for lineno, raw in enumerate(handle, start=1):
        text = raw.strip()
        if not text:
            continue
        if text.startswith("#") or text.startswith("%"):
            if header is None and not rows:
                header, header_lineno = text, lineno
            continue
        tokens = [t.strip() for t in (text.split(delimiter) if delimiter else text.split())]
        if len(tokens) not in allowed:
            want = _describe(allowed)
            raise InputFormatError(
                spath, f"{what}: expected {want} columns, found {len(tokens)}", lineno
            )
        if rows and len(tokens) - 1 != len(rows[0]):
            raise InputFormatError(
                spath, f"{what}: {len(tokens)} columns, earlier rows have {len(rows[0]) + 1}",
                lineno,
            )
        column = lambda i: _column(i, header, len(tokens))  # noqa: E731
        t = parse_time(tokens[0], time_in_seconds, spath, lineno, column(0))
        try:
            vals = [float(x) for x in tokens[1:]]
        except ValueError:
            col = next(i for i, x in enumerate(tokens) if i and not _is_float(x))
            raise InputFormatError(spath, f"{what}: {column(col)}: value '{tokens[col]}' "
                                          f"is not a number", lineno) from None
        if not all(np.isfinite(vals)):
            col = 1 + int(np.flatnonzero(~np.isfinite(vals))[0])
            raise InputFormatError(spath, f"{what}: {column(col)}: non-finite value "
                                          f"'{tokens[col]}'", lineno)
        if times and (t < times[-1] or (t == times[-1] and not repeated_times)):
            kind = "repeated" if t == times[-1] else "decreasing"
            raise InputFormatError(
                spath, f"{what}: timestamps not strictly increasing ({kind} timestamp)", lineno
            )
        times.append(t)
        rows.append(vals)
        lines.append(lineno)
    if not rows:
        raise InputFormatError(spath, f"{what}: no data rows (empty file)")
    if expected_names is not None and header is not None:
        _check_names(spath, header, header_lineno, expected_names, what)
    return Table(
        path=spath,
        header=header,
        t_ns=np.asarray(times, dtype=np.int64),
        values=np.asarray(rows, dtype=np.float64),
        lines=np.asarray(lines, dtype=np.int64),
    )


def _check_names(path: str, header: str, lineno: int, expected: Sequence[str], what: str) -> None:
    names = header_names(header)
    if len(names) != len(expected):
        raise InputFormatError(
            path, f"{what}: header has {len(names)} columns, expected {len(expected)}", lineno
        )
    for i, (got, want) in enumerate(zip(names, expected)):
        if got != want:
            raise InputFormatError(
                path, f"{what}: header column {i + 1} is '{got}', expected '{want}'", lineno
            )


def _column(index: int, header: Optional[str], ncols: int) -> str:
    """``column N 'name'`` (1-based), worded as the C++ reader does (docs/formats.md §1); the
    name only when the header has one field per column (else it is a comment, not names)."""
    names = header_names(header) if header is not None else []
    name = f" '{names[index]}'" if len(names) == ncols and names[index] else ""
    return f"column {index + 1}{name}"


def _is_float(token: str) -> bool:
    try:
        float(token)
        return True
    except ValueError:
        return False


def _describe(allowed: set) -> str:
    values = sorted(allowed)
    if len(values) == 1:
        return str(values[0])
    if values == list(range(values[0], values[-1] + 1)) and len(values) > 2:
        return f"{values[0]}..{values[-1]}"
    return " or ".join(str(v) for v in values)
