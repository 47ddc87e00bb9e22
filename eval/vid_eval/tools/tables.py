"""Comparison tables in the shape of the seed's tables 4/5: sequence x method, value, decrease.

``decrease % = (baseline - method) / baseline * 100`` for a metric where lower is better
(positive = the method improves on the baseline). Rendered as Markdown or LaTeX.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence

from .runs import Run


@dataclass
class Table:
    """Rows (sequences) x value columns (methods), plus decrease columns vs a baseline."""

    title: str
    unit: str
    sequences: List[str]
    methods: List[str]
    values: Dict[str, Dict[str, float]]  # sequence -> method -> value (mean over repeats)
    baseline: Optional[str]

    def decrease(self, seq: str, method: str) -> Optional[float]:
        """Decrease [%] of ``method`` relative to the baseline on ``seq``."""
        if self.baseline is None or method == self.baseline:
            return None
        b = self.values.get(seq, {}).get(self.baseline)
        v = self.values.get(seq, {}).get(method)
        if b is None or v is None or b == 0:
            return None
        return (b - v) / b * 100.0


def build_table(runs: Sequence[Run], metric: str, title: str, unit: str,
                baseline: Optional[str] = None, methods: Optional[Sequence[str]] = None) -> Table:
    """Average repeated runs of the same (sequence, method); keep first-seen order."""
    acc: Dict[str, Dict[str, List[float]]] = {}
    seq_order: List[str] = []
    meth_order: List[str] = []
    for r in runs:
        if metric not in r.values:
            continue
        if r.sequence not in seq_order:
            seq_order.append(r.sequence)
        if r.method not in meth_order:
            meth_order.append(r.method)
        acc.setdefault(r.sequence, {}).setdefault(r.method, []).append(r.values[metric])
    if methods:
        meth_order = [m for m in methods if m in meth_order] + [m for m in meth_order if m not in methods]
    if baseline in meth_order:  # baseline first, as the seed's tables
        meth_order.remove(baseline)
        meth_order.insert(0, baseline)
    else:
        baseline = None
    vals = {s: {m: sum(v) / len(v) for m, v in d.items()} for s, d in acc.items()}
    return Table(title, unit, seq_order, meth_order, vals, baseline)


def _fmt(v: Optional[float], digits: int) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "–"
    return f"{v:.{digits}f}"


def _header_and_rows(t: Table, digits: int):
    header = ["Sequence"] + [f"{m} [{t.unit}]" for m in t.methods]
    others = [m for m in t.methods if m != t.baseline] if t.baseline else []
    header += [f"Decrease {m} vs {t.baseline} [%]" for m in others]
    rows = []
    for s in t.sequences:
        row = [s] + [_fmt(t.values[s].get(m), digits) for m in t.methods]
        row += [_fmt(t.decrease(s, m), 1) for m in others]
        rows.append(row)
    if len(t.sequences) > 1:
        means = {m: [t.values[s][m] for s in t.sequences if m in t.values[s]] for m in t.methods}
        row = ["Mean"] + [_fmt(sum(v) / len(v) if v else None, digits) for v in means.values()]
        for m in others:
            d = [t.decrease(s, m) for s in t.sequences]
            d = [x for x in d if x is not None]
            row.append(_fmt(sum(d) / len(d) if d else None, 1))
        rows.append(row)
    return header, rows


def to_markdown(t: Table, digits: int = 4) -> str:
    """GitHub Markdown table with a bold title line."""
    header, rows = _header_and_rows(t, digits)
    lines = [f"**{t.title}**", "", "| " + " | ".join(header) + " |",
             "|" + "|".join(["---"] + ["---:"] * (len(header) - 1)) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def _tex(s: str) -> str:
    for a, b in (("\\", "\\textbackslash{}"), ("_", "\\_"), ("%", "\\%"), ("&", "\\&"),
                 ("#", "\\#"), ("²", "$^2$"), ("–", "--")):
        s = s.replace(a, b)
    return s


def to_latex(t: Table, digits: int = 4) -> str:
    """A ``table`` environment with booktabs rules (needs \\usepackage{booktabs})."""
    header, rows = _header_and_rows(t, digits)
    cols = "l" + "r" * (len(header) - 1)
    out = ["\\begin{table}[t]", "\\centering", f"\\caption{{{_tex(t.title)}}}",
           f"\\begin{{tabular}}{{{cols}}}", "\\toprule",
           " & ".join(_tex(h) for h in header) + " \\\\", "\\midrule"]
    for i, r in enumerate(rows):
        if r[0] == "Mean" and i == len(rows) - 1 and len(rows) > 1:
            out.append("\\midrule")
        out.append(" & ".join(_tex(c) for c in r) + " \\\\")
    out += ["\\bottomrule", "\\end{tabular}", "\\end{table}"]
    return "\n".join(out) + "\n"
