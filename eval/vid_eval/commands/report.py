"""``vid-eval report RUNS...``: tables over runs, methods and sequences (Markdown / LaTeX)."""
from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import ConfigurationError
from ..tools.runs import METRICS, load_run
from ..tools.tables import build_table, to_latex, to_markdown


def add_parser(sub) -> None:
    """Register the ``report`` sub-command."""
    p = sub.add_parser("report", help="tables over runs (sequence x method, value, decrease %%)",
                       description="Collect metrics from run folders / JSON files and print one "
                                   "table per metric: rows are sequences, columns methods, plus "
                                   "the decrease in % of each method relative to --baseline.")
    p.add_argument("runs", nargs="+", help="run folders (holding summary.json / vid-eval JSON) or JSON files")
    p.add_argument("--metric", action="append", default=None, metavar="NAME|KEY.PATH",
                   help=f"metrics to tabulate: {', '.join(METRICS)} or any dotted JSON key "
                        f"(repeatable; default: every known metric found)")
    p.add_argument("--baseline", default=None, metavar="METHOD",
                   help="method the decrease %% is computed against")
    p.add_argument("--methods", default=None, metavar="A,B,...", help="column order of methods")
    p.add_argument("--format", choices=("markdown", "latex", "both"), default="markdown")
    p.add_argument("--digits", type=int, default=4, help="decimals of the values (default 4)")
    p.add_argument("--out", default=None, metavar="FILE",
                   help="also write the tables to FILE (.md / .tex; 'both' writes FILE.md and FILE.tex)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Load runs, build and print tables."""
    metrics = args.metric or list(METRICS)
    extra = [m for m in metrics if m not in METRICS]
    runs = [load_run(r, extra) for r in args.runs]
    methods = args.methods.split(",") if args.methods else None
    md, tex = [], []
    for name in metrics:
        info = METRICS.get(name)
        title = f"{info.label} [{info.unit}]" if info else name
        table = build_table(runs, name, title, info.unit if info else "", args.baseline, methods)
        if not table.sequences:
            continue
        md.append(to_markdown(table, args.digits))
        tex.append(to_latex(table, args.digits))
    if not md:
        raise ConfigurationError(f"none of the metrics {', '.join(metrics)} found in the given runs")
    text_md, text_tex = "\n".join(md), "\n".join(tex)
    if args.format in ("markdown", "both"):
        print(text_md)
    if args.format in ("latex", "both"):
        print(text_tex)
    if args.out:
        out = Path(args.out)
        out.parent.mkdir(parents=True, exist_ok=True)
        if args.format == "both":
            Path(f"{out}.md").write_text(text_md, encoding="utf-8")
            Path(f"{out}.tex").write_text(text_tex, encoding="utf-8")
        else:
            out.write_text(text_md if args.format == "markdown" else text_tex, encoding="utf-8")
    return 0
