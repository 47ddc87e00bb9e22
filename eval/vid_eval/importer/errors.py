"""The two kinds of failure of vid-import, each printed as one line.

A :class:`MapError` is a usage error (a flag, the source map, a column or dataset name that
does not exist): exit 2, as argparse. A data problem (times not increasing, a value that is not
a number, the thrust pointing down) is a :class:`vid_eval.errors.InputFormatError` or
:class:`DataError`: exit 1.
"""
from __future__ import annotations

from ..errors import VidEvalError


class MapError(VidEvalError):
    """The source map or a flag names something that is not there (exit 2)."""


class DataError(VidEvalError):
    """The data contradicts what the map and flags say (exit 1)."""
