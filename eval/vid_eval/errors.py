"""Typed errors of the evaluation package.

Every error that comes from bad input names the file (and the line when there is one), so
the command line can print exactly one line that tells the user what to fix.
"""
from __future__ import annotations

import os
from typing import Optional, Union

PathLike = Union[str, "os.PathLike[str]"]


class VidEvalError(Exception):
    """Base class of every error the package raises on purpose."""


class InputFormatError(VidEvalError):
    """A file is missing, empty or malformed (wrong column count, bad number, unsorted time).

    The message reads ``FILE:LINE: what is wrong`` (``FILE: ...`` when no line applies).
    """

    def __init__(self, path: PathLike, message: str, line: Optional[int] = None) -> None:
        self.path = os.fspath(path)
        self.line = line
        self.reason = message
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: {message}")


class AssociationError(VidEvalError):
    """Two time series cannot be matched (no overlap, too few pairs within the tolerance)."""


class ConfigurationError(VidEvalError):
    """Contradictory or missing options (for instance no mass for a conversion to m/s^2)."""
