"""The one argument parser of the Python programs (vid-eval, vid-bag2asl, vid-batch): a usage
error is one line "PROG: error: ... (see --help)" on stderr and exit 2, as in the C++ programs
(argparse's default prints the usage block first)."""
from __future__ import annotations

import argparse
import math
import sys


class OneLineParser(argparse.ArgumentParser):
    """argparse.ArgumentParser whose usage errors are one line and which knows ``--version``
    (the package version, from git); sub-parsers inherit it."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        from . import __version__
        self.add_argument("--version", action="version", version=f"%(prog)s {__version__}")

    def error(self, message: str):  # noqa: D401 - argparse's hook
        print(f"{self.prog}: error: {message} (see --help)", file=sys.stderr)
        sys.exit(2)


def positive_float(text: str) -> float:
    """argparse ``type=``: a finite number > 0, else a usage error naming the text."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not (value > 0 and math.isfinite(value)):
        raise argparse.ArgumentTypeError(f"must be positive and finite, got {text}")
    return value
