"""The results table of a batch: one row per run, Parquet (pyarrow) and CSV."""
from __future__ import annotations

import json
import pathlib
from typing import Dict, List

FIRST = ["id", "kind", "status", "error", "sequence", "preset", "duration", "seed", "estimator", "mode"]


def _column(values: list):
    """A pyarrow array with one type per column (numbers as int64/float64, else strings)."""
    import pyarrow as pa
    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return pa.array(values, pa.bool_())
    if present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
        typ = pa.int64() if all(isinstance(v, int) for v in present) else pa.float64()
        return pa.array(values, typ)
    return pa.array([None if v is None else str(v) for v in values], pa.string())


def write_table(records: List[dict], out: pathlib.Path) -> None:
    """OUT/results.parquet and OUT/results.csv from the records (columns: union of keys)."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq
    keys: List[str] = [k for k in FIRST if any(k in r for r in records)]
    for r in records:
        keys += [k for k in r if k not in keys]
    table = pa.table({k: _column([r.get(k) for r in records]) for k in keys}) if records else pa.table({})
    pq.write_table(table, out / "results.parquet")
    pacsv.write_csv(table, out / "results.csv")


def read_records(out: pathlib.Path) -> List[Dict]:
    """Every record of a batch folder (the table's rows), sorted by id."""
    return [json.loads(p.read_text()) for p in sorted((out / "records").glob("*.json"))]
