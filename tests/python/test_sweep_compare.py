"""scripts/sweep_compare.py: the before / after table of two preset sweeps."""
from __future__ import annotations

import json
import pathlib
import subprocess
import sys

SCRIPT = pathlib.Path(__file__).resolve().parents[2] / "scripts" / "sweep_compare.py"


def _run(seed, ate, force, att, status="ok", preset="impacts"):
    return {"preset": preset, "seed": seed, "noise_free": False, "config": "x", "status": status,
            "ate_m": ate, "force_rmse_world": force, "att_err_max_deg": att}


def _sweep(tmp_path, name, rows):
    p = tmp_path / f"{name}.json"
    p.write_text(json.dumps(rows))
    return p


def test_mean_and_worst_seed_per_preset_across_files(tmp_path):
    before = [_sweep(tmp_path, "b1", [_run(1, 0.010, 0.5, 1.0)]),
              _sweep(tmp_path, "b23", [_run(2, 0.020, 0.7, 3.0), _run(3, 0.030, 0.6, 2.0)])]
    after = _sweep(tmp_path, "a", [_run(s, 0.01 * s, None, 1.0) for s in (1, 2, 3)])
    r = subprocess.run([sys.executable, str(SCRIPT), "--before", *map(str, before), "--after", str(after),
                        "--out", str(tmp_path / "t.md")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    row = [ln for ln in r.stdout.splitlines() if ln.startswith("| impacts")]
    assert row == ["| impacts (3) | 0.0200 (0.0300) / 0.0200 (0.0300) | 0.600 (0.700) / – | "
                   "2.00 (3.00) / 1.00 (1.00) |"]
    assert (tmp_path / "t.md").read_text() == r.stdout


def test_different_seeds_and_failed_runs_are_named(tmp_path):
    before = _sweep(tmp_path, "b", [_run(1, 0.01, 0.5, 1.0), _run(2, 0.01, 0.5, 1.0),
                                    _run(1, 0.01, 0.5, 1.0, preset="hover")])
    after = _sweep(tmp_path, "a", [_run(1, 0.01, 0.5, 1.0), _run(2, 9.9, 9.9, 9.9, status="diverged"),
                                   _run(2, 0.01, 0.5, 1.0, preset="hover")])
    r = subprocess.run([sys.executable, str(SCRIPT), "--before", str(before), "--after", str(after)],
                       capture_output=True, text=True)
    assert r.returncode == 1
    assert "impacts seed 2 after: diverged" in r.stderr
    assert "hover: seeds before [1], after [2]" in r.stderr
    # the failed run is not averaged in
    assert "| impacts (2) | 0.0100 (0.0100) / 0.0100 (0.0100) |" in r.stdout


def test_paired_table_gives_the_per_seed_ate_change(tmp_path):
    before = _sweep(tmp_path, "b", [_run(s, 0.010, 0.5, 1.0) for s in (1, 2, 3)])
    # seed 1 -20 %, seed 2 +0.5 % (within 1 %), seed 3 +50 %; seed 4 only after: not paired
    after = _sweep(tmp_path, "a", [_run(1, 0.008, 0.5, 1.0), _run(2, 0.01005, 0.5, 1.0),
                                   _run(3, 0.015, 0.5, 1.0), _run(4, 0.1, 0.5, 1.0, preset="hover")])
    r = subprocess.run([sys.executable, str(SCRIPT), "--before", str(before), "--after", str(after), "--paired"],
                       capture_output=True, text=True)
    assert "| impacts | 3 | +0% (-20% .. +50%) | 1 / 1 |" in r.stdout, r.stdout
    assert "| hover |" not in r.stdout.split("better / worse")[1]
