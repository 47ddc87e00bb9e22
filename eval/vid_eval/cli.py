"""``vid-eval`` entry point: sub-commands traj, force, mass, report, force-bound, nees, view, mocap-truth,
massid-plots, elm-plots.

Any :class:`~vid_eval.errors.VidEvalError` (bad file, no overlap, missing mass, ...) is
printed as one line ``vid-eval: error: ...`` on stderr with exit status 1; usage errors
exit with 2 (argparse).
"""
from __future__ import annotations

import argparse
import sys
from typing import List, Optional

from .commands import bound, force, mass, mocap_truth, nees, report, study_plots, traj, view
from .errors import VidEvalError
from .usage import OneLineParser

EXIT_INPUT_ERROR = 1


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with all sub-commands."""
    p = OneLineParser(
        prog="vid-eval",
        description="Evaluate VID-MSCKF (or any estimator's) outputs: trajectory ATE/RPE, "
                    "external force, mass; plots and comparison tables.")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for mod in (traj, force, mass, report, bound, nees, view, mocap_truth, study_plots):
        mod.add_parser(sub)
    return p


def main(argv: Optional[List[str]] = None) -> int:
    """Parse, run, and turn expected errors into one line and a non-zero exit."""
    args = build_parser().parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except VidEvalError as exc:
        print(f"vid-eval: error: {exc}", file=sys.stderr)
        return EXIT_INPUT_ERROR
    except ValueError as exc:  # argument values only detectable late (e.g. bad RPE length)
        print(f"vid-eval: error: {exc}", file=sys.stderr)
        return EXIT_INPUT_ERROR
    except BrokenPipeError:  # output piped into e.g. `head`: not an error of ours
        sys.stderr.close()
        return 0
    except OSError as exc:
        print(f"vid-eval: error: {exc.filename or ''}: {exc.strerror}", file=sys.stderr)
        return EXIT_INPUT_ERROR


if __name__ == "__main__":
    sys.exit(main())
