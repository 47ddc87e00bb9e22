"""``vid-batch``: batch evaluation on Ray (install with ``pip install -e 'eval[batch]'``).

  vid-batch run BATCH.yaml --out DIR [--address ADDR] [--workers N] [--build-dir B]
  vid-batch report DIR

Exit status: 0 all runs ok, 1 a run failed (listed at the end), 2 a bad batch file or usage.
"""
from __future__ import annotations

import argparse
import os
import pathlib
import shutil
import sys
from typing import List, Optional

from ..tools.sim_runs import REPO
from .spec import BatchSpecError, load_batch
from ..usage import OneLineParser

EXIT_BAD_SPEC = 2

REQUIRED = {"estimate": ["vid_run"], "simulate": ["vid_sim"], "massid_generate": ["vid_massid"]}


def _default_build() -> str:
    return os.environ.get("VID_BUILD_DIR", str(REPO / "build"))


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of vid-batch."""
    p = OneLineParser(prog="vid-batch", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    r = sub.add_parser("run", help="run (or resume) a batch")
    r.add_argument("batch", type=pathlib.Path, help="batch YAML (see config/batch/)")
    r.add_argument("--out", type=pathlib.Path, required=True, help="batch folder (shared storage on a cluster)")
    r.add_argument("--address", default=None, help="Ray cluster address (default: a local Ray)")
    r.add_argument("--workers", type=int, default=None, help="local CPUs for Ray (default: all cores)")
    r.add_argument("--build-dir", default=_default_build(),
                   help="C++ build folder with bin/ (default: $VID_BUILD_DIR or <repo>/build)")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    rep = sub.add_parser("report", help="statistics, tables and box plots of a batch folder")
    rep.add_argument("dir", type=pathlib.Path)
    return p


def _check_programs(tasks, build: pathlib.Path) -> Optional[str]:
    """One line naming the first program the batch needs that is not built."""
    for kind in sorted({t.kind for t in tasks}):
        for name in REQUIRED.get(kind, []):
            if not (build / "bin" / name).exists():
                return f"{build / 'bin' / name} not built (run scripts/build.sh or pass --build-dir)"
    return None


def _run(args) -> int:
    from .core import timed_run  # imports Ray lazily: `report` and --help work without it
    try:
        tasks = load_batch(args.batch, REPO)
    except BatchSpecError as exc:
        print(f"vid-batch: error: {exc}", file=sys.stderr)
        return EXIT_BAD_SPEC
    build = pathlib.Path(args.build_dir)
    missing = _check_programs(tasks, build)
    if missing:
        print(f"vid-batch: error: {missing}", file=sys.stderr)
        return EXIT_BAD_SPEC
    args.out.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(args.batch, args.out / "batch.yaml")  # what this folder's runs were planned from
    return timed_run(tasks, args.out.resolve(), build.resolve(), address=args.address,
                     workers=args.workers, progress=not args.no_progress)


def _report(args) -> int:
    from .report import report
    from .table import read_records
    records = read_records(args.dir)
    if not records:
        print(f"vid-batch: error: {args.dir}: no records (not a vid-batch folder?)", file=sys.stderr)
        return 1
    print(report(records, args.dir), end="")
    print(f"vid-batch: wrote {args.dir / 'report'}")
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    """Entry point of the ``vid-batch`` console script."""
    args = build_parser().parse_args(argv)
    return _run(args) if args.command == "run" else _report(args)


if __name__ == "__main__":
    sys.exit(main())
