"""``vid-eval nees CSV...``: the NEES Monte-Carlo curves of the consistency tests, the share of
time inside the 95 % band, and a plot per file.

The CSVs are what ``vio_core_nees_sim_test`` / ``vio_core_nees_test`` write into
``<build>/vio_core_nees/`` (format: :data:`vid_eval.core.formats.NEES_COLUMNS`).
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..tools.loaders import load_nees
from .common import abspath


def add_parser(sub) -> None:
    """Register the ``nees`` sub-command."""
    p = sub.add_parser("nees", help="NEES Monte-Carlo curves: share inside the 95 %% band, plots",
                       description="Read nees_*.csv of the consistency tests, print the share of "
                                   "time each NEES is inside the 95 %% chi2 band (after --skip) "
                                   "and plot each file as <stem>.png.")
    p.add_argument("csv", nargs="+", help="nees_*.csv (e.g. build/vio_core_nees/nees_vid17_like_dynamics.csv)")
    p.add_argument("--skip", type=float, default=5.0, metavar="S",
                   help="score from t = S seconds on (default 5, as the tests)")
    p.add_argument("--plot", metavar="DIR", help="write <stem>.png per CSV into DIR")
    p.add_argument("--json", metavar="OUT", help="write the shares as JSON to OUT")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Load every file first (one bad file stops before any output), then print and plot."""
    loaded = [load_nees(path) for path in args.csv]
    stems = [Path(n.source).stem for n in loaded]
    if len(set(stems)) != len(stems):  # one plot file per stem: two equal stems would collide
        dup = next(s for s in stems if stems.count(s) > 1)
        raise ValueError(f"two inputs named {dup}.csv would write the same plot {dup}.png")
    out = {"command": "nees", "skip_s": args.skip, "files": []}
    for nees, stem in zip(loaded, stems):
        shares = {name: nees.fraction_inside(v, args.skip) for name, v in nees.curves().items()}
        print(f"{stem}: {nees.runs} runs, band [{nees.band_lo:.3f}, {nees.band_hi:.3f}]; inside: "
              + ", ".join(f"{k} {v:.3f}" for k, v in shares.items()))
        out["files"].append({"csv": abspath(nees.source), "runs": nees.runs,
                             "band": [nees.band_lo, nees.band_hi], "fraction_inside": shares})
    if args.plot:
        from ..plots.nees import plot_nees
        from ..plots.style import check_plot_targets

        stamps = [f"nees csv={abspath(n.source)}" for n in loaded]
        for stem, stamp in zip(stems, stamps):  # all checked before the first is written
            check_plot_targets(args.plot, [f"{stem}.png"], stamp)
        for nees, stem, stamp in zip(loaded, stems, stamps):
            plot_nees(nees, args.plot, f"{stem}.png", args.skip, stamp)
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2) + "\n", encoding="utf-8")
    return 0
