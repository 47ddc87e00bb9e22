#!/usr/bin/env python3
"""Before / after table of two preset sweeps (scripts/preset_sweep.py results.json files).

  .venv/bin/python scripts/sweep_compare.py --before /tmp/before/results.json \
      --after /tmp/after/results.json [--out table.md]

Each side may be several results.json files (for example seed 1 and seeds 2-3 run apart); a
side's configuration names are ignored, so a sweep of one configuration per build compares
directly. Per preset (in the order of the first file): mean over seeds and, in brackets, the
worst seed of ATE [m] (posyaw), world-frame force RMSE [m/s^2] and the maximum attitude error
[deg]. Runs that did not finish (status other than ok) are counted and named under the table;
a preset must have the same seeds on both sides, else the script says which and exits 1.

--paired adds a second table: the ATE change of each seed (after / before - 1, the same rendered
sequence on both sides), as median (smallest .. largest) and the count of seeds better / worse
by more than 1 %. A change whose per-seed spread straddles zero is told from one that moves
every seed; compare it with the spread of a change known not to matter (for example a 2 %
change of pixel_noise_px) to see the chaotic part of a filter's ATE.
"""
from __future__ import annotations

import argparse
import json
import math
import pathlib
import sys

METRICS = [("ate_m", "ATE [m]", "{:.4f}"), ("force_rmse_world", "force RMSE [m/s²]", "{:.3f}"),
           ("att_err_max_deg", "max att. err [°]", "{:.2f}")]


def _load(paths: list[pathlib.Path]) -> list[dict]:
    rows: list[dict] = []
    for p in paths:
        try:
            data = json.loads(p.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise SystemExit(f"sweep_compare: error: {p}: {exc}")
        if not isinstance(data, list):
            raise SystemExit(f"sweep_compare: error: {p}: not a preset_sweep results.json (a list of runs)")
        rows += [r for r in data if not r.get("noise_free")]
    return rows


def _cell(vals: list[float], fmt: str) -> str:
    vals = [v for v in vals if v is not None and math.isfinite(v)]
    if not vals:
        return "–"
    return f"{fmt.format(sum(vals) / len(vals))} ({fmt.format(max(vals))})"


def compare(before: list[dict], after: list[dict]) -> tuple[str, list[str]]:
    """The markdown table and the problems found (missing seeds, failed runs)."""
    presets = list(dict.fromkeys(r["preset"] for r in before + after))
    problems: list[str] = []
    head = "| preset | " + " | ".join(f"{name} before / after" for _, name, _ in METRICS) + " |"
    lines = [head, "|---" * (len(METRICS) + 1) + "|"]
    for preset in presets:
        sides = [[r for r in rows if r["preset"] == preset] for rows in (before, after)]
        seeds = [sorted(r["seed"] for r in side) for side in sides]
        if seeds[0] != seeds[1]:
            problems.append(f"{preset}: seeds before {seeds[0]}, after {seeds[1]}")
            continue
        for label, side in zip(("before", "after"), sides):
            for r in side:
                if r.get("status") != "ok":
                    problems.append(f"{preset} seed {r['seed']} {label}: {r.get('status')}")
        cells = []
        for key, _, fmt in METRICS:
            b, a = ([r.get(key) for r in side if r.get("status") == "ok"] for side in sides)
            cells.append(f"{_cell(b, fmt)} / {_cell(a, fmt)}")
        lines.append(f"| {preset} ({len(seeds[0])}) | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n", problems


def paired(before: list[dict], after: list[dict]) -> str:
    """Markdown table of the per-seed ATE change after / before - 1 (runs ok on both sides)."""
    lines = ["| preset | seeds | ATE change per seed: median (min .. max) | better / worse by > 1 % |",
             "|---|---|---|---|"]
    for preset in dict.fromkeys(r["preset"] for r in before + after):
        ate = [{r["seed"]: r.get("ate_m") for r in rows if r["preset"] == preset and r.get("status") == "ok"}
               for rows in (before, after)]
        changes = sorted(ate[1][s] / ate[0][s] - 1.0 for s in ate[0].keys() & ate[1].keys()
                         if ate[0][s] and ate[1][s] is not None and math.isfinite(ate[0][s]) and math.isfinite(ate[1][s]))
        if not changes:
            continue
        n = len(changes)
        median = changes[n // 2] if n % 2 else 0.5 * (changes[n // 2 - 1] + changes[n // 2])
        better, worse = sum(c < -0.01 for c in changes), sum(c > 0.01 for c in changes)
        lines.append(f"| {preset} | {n} | {median:+.0%} ({changes[0]:+.0%} .. {changes[-1]:+.0%}) | "
                     f"{better} / {worse} |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--before", nargs="+", type=pathlib.Path, required=True, help="results.json of the old code")
    p.add_argument("--after", nargs="+", type=pathlib.Path, required=True, help="results.json of the new code")
    p.add_argument("--out", type=pathlib.Path, default=None, help="also write the table here")
    p.add_argument("--paired", action="store_true", help="also the per-seed ATE change table")
    args = p.parse_args(argv)
    before, after = _load(args.before), _load(args.after)
    table, problems = compare(before, after)
    if args.paired:
        table += "\n" + paired(before, after)
    print(table, end="")
    for msg in problems:
        print(f"sweep_compare: {msg}", file=sys.stderr)
    if args.out:
        args.out.write_text(table)
    return 1 if any("seeds before" in m for m in problems) else 0


if __name__ == "__main__":
    sys.exit(main())
