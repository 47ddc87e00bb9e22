"""Options and helpers shared by the sub-commands (pairing flags, JSON output)."""
from __future__ import annotations

import argparse
import json
import os
import re
from pathlib import Path
from typing import Any, Dict, Optional, Sequence

from ..tools.loaders import find_phases, load_phases
from ..core.pairing import PairingOptions
from ..core.phases import DEFAULT_WINDOW_S, PhaseSegmentation, segment_phases
from ..usage import positive_float


def add_pairing_args(p: argparse.ArgumentParser) -> None:
    """--max-diff, --offset, --interpolate, --max-gap."""
    g = p.add_argument_group("time association")
    g.add_argument("--max-diff", type=float, default=0.01, metavar="S",
                   help="nearest-timestamp tolerance [s] (default 0.01, as evo)")
    g.add_argument("--offset", type=float, default=0.0, metavar="S",
                   help="time offset [s] added to the estimate's timestamps (t_est + offset = t_gt)")
    g.add_argument("--interpolate", action="store_true",
                   help="interpolate the ground truth at estimate times (linear / SLERP) "
                        "instead of nearest matching")
    g.add_argument("--max-gap", type=float, default=None, metavar="S",
                   help="with --interpolate: skip estimate times inside ground-truth gaps longer than S")


def add_output_args(p: argparse.ArgumentParser) -> None:
    """--json, --plot, --method, --sequence."""
    g = p.add_argument_group("output")
    g.add_argument("--json", metavar="OUT", help="write the results as JSON to OUT")
    g.add_argument("--plot", metavar="DIR", help="write PNG plots into DIR")
    g.add_argument("--plot-prefix", metavar="NAME", default=None,
                   help="start the plot file names with NAME_ (default: SEQUENCE_METHOD_ from "
                        "--sequence/--method, else nothing); a plot of other inputs is never "
                        "overwritten")
    g.add_argument("--method", help="method name stored in the JSON (for `vid-eval report`)")
    g.add_argument("--sequence", help="sequence name stored in the JSON (for `vid-eval report`)")


def add_phase_args(p: argparse.ArgumentParser) -> None:
    """--phases, --phase-window (issue #29: errors per flight phase)."""
    g = p.add_argument_group("flight phases (reported when phase0 is found)")
    g.add_argument("--phases", metavar="FILE", default=None,
                   help="phase0 CSV '#timestamp [ns],phase' (0 on the ground, 1 airborne); "
                        "default: mav0/phase0/data.csv next to GT when it exists")
    g.add_argument("--phase-window", type=positive_float, default=DEFAULT_WINDOW_S, metavar="S",
                   help="length of the transition window centred on each lift-off and "
                        f"touchdown [s] (default {DEFAULT_WINDOW_S:g})")


def phases_from_args(args: argparse.Namespace, gt_path: str) -> Optional[PhaseSegmentation]:
    """The flight phases of ``--phases``, else of phase0 next to ``gt_path``; None without."""
    path = args.phases or find_phases(gt_path)
    if path is None:
        return None
    return segment_phases(load_phases(abspath(path)), args.phase_window)


def seconds_to_ns(s: float) -> int:
    """Seconds -> int nanoseconds (rounded)."""
    return int(round(float(s) * 1e9))


def pairing_from_args(args: argparse.Namespace, min_pairs: int = 2) -> PairingOptions:
    """Build :class:`PairingOptions` from the parsed flags."""
    return PairingOptions(
        mode="interpolate" if args.interpolate else "nearest",
        max_diff_ns=seconds_to_ns(args.max_diff),
        offset_ns=seconds_to_ns(args.offset),
        max_gap_ns=None if args.max_gap is None else seconds_to_ns(args.max_gap),
        min_pairs=min_pairs,
    )


def finish(args: argparse.Namespace, result: Dict[str, Any]) -> None:
    """Add run names and write the JSON when asked."""
    if getattr(args, "method", None):
        result["method"] = args.method
    if getattr(args, "sequence", None):
        result["sequence"] = args.sequence
    if args.json:
        out = Path(args.json)
        if out.parent and not out.parent.exists():
            out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")


def plot_names(args: argparse.Namespace, command: str, bases: Sequence[str]) -> Dict[str, str]:
    """File names of the command's plots (``--plot-prefix``, else ``SEQUENCE_METHOD_``),
    checked before anything is computed: none may hold the plot of other inputs (issue #25).
    Returns base name -> file name; empty without ``--plot``."""
    if not args.plot:
        return {}
    from ..plots.style import check_plot_targets  # matplotlib only when plotting

    prefix = args.plot_prefix
    if prefix is None:
        prefix = "_".join(x for x in (getattr(args, "sequence", None), getattr(args, "method", None)) if x)
    prefix = re.sub(r"[^A-Za-z0-9._=-]+", "_", prefix)
    names = {b: (f"{prefix}_{b}" if prefix else b) for b in bases}
    args.plot_stamp = f"{command} est={abspath(args.est)} gt={abspath(args.gt)}"
    check_plot_targets(args.plot, names.values(), args.plot_stamp)
    return names


def abspath(p: str) -> str:
    """Absolute path string for the JSON records."""
    return os.path.abspath(p)
