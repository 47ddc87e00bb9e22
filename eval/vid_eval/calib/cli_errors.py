"""The one error rule of the calibration tools (vid-fit-thrust, vid-allan): bad input is one
line ``PROG: error: ...`` on stderr and exit 1 (usage errors exit 2 earlier, in the parser)."""
from __future__ import annotations

import argparse
import sys
from typing import Callable

from ..errors import VidEvalError


def run_reporting_errors(prog: str, run: Callable[[argparse.Namespace], int], args: argparse.Namespace) -> int:
    """``run(args)``; a VidEvalError or OSError becomes one stderr line naming the file, exit 1."""
    try:
        return run(args)
    except VidEvalError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        print(f"{prog}: error: {exc.filename or ''}: {exc.strerror}", file=sys.stderr)
        return 1
