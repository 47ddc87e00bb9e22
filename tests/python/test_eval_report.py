"""`vid-eval report`: runs -> sequence x method tables with decrease %, Markdown and LaTeX."""
from __future__ import annotations

import json

import pytest

from eval_testdata import run_cli_in_process

from vid_eval.tools.runs import load_run


def _vid(*args):
    return run_cli_in_process(*args)


@pytest.fixture
def runs(tmp_path):
    """seq17/seq18 x VID-Fusion/Ours: names from folders, from summary keys, and from JSON keys."""
    def put(path, obj):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(obj))
        return path.parent

    r = [
        put(tmp_path / "seq17" / "VID-Fusion" / "summary.json",
            {"force_rmse_world_mps2": 0.206, "ate_posyaw_m": 0.0456}),
        put(tmp_path / "seq17" / "Ours" / "eval_force.json",
            {"command": "force", "force": {"rmse_mps2": {"norm": 0.072}}}),
        put(tmp_path / "x" / "a" / "summary.json",
            {"method": "VID-Fusion", "sequence": "seq18", "force_rmse_world_mps2": 0.160}),
        put(tmp_path / "seq18__Ours" / "eval.json", {"force_rmse_world_mps2": 0.074,
                                                     "ate_pos_rmse_m": 0.0499}),
    ]
    (tmp_path / "seq17" / "Ours" / "eval_traj.json").write_text(json.dumps({"ate_pos_rmse_m": 0.0362}))
    return r


def test_run_names_follow_the_convention(runs):
    got = [(x.sequence, x.method) for x in map(load_run, map(str, runs))]
    assert got == [("seq17", "VID-Fusion"), ("seq17", "Ours"), ("seq18", "VID-Fusion"),
                   ("seq18", "Ours")]
    ours17 = load_run(str(runs[1]))
    assert ours17.values["force"] == 0.072 and ours17.values["ate"] == 0.0362


def test_markdown_table_values_and_decrease(runs, tmp_path):
    proc = _vid("report", *runs, "--metric", "force", "--baseline", "VID-Fusion", "--out",
                tmp_path / "t.md")
    assert proc.returncode == 0, proc.stderr
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("| seq") or ln.startswith("| Mean")]
    assert lines[0] == "| seq17 | 0.2060 | 0.0720 | 65.0 |"  # (0.206-0.072)/0.206 = 65.05 %
    assert lines[1] == "| seq18 | 0.1600 | 0.0740 | 53.8 |"  # (0.160-0.074)/0.160 = 53.75 %
    assert lines[2] == "| Mean | 0.1830 | 0.0730 | 59.4 |"
    assert "Decrease Ours vs VID-Fusion [%]" in proc.stdout
    assert (tmp_path / "t.md").read_text().strip() == proc.stdout.strip()


def test_latex_table(runs):
    proc = _vid("report", *runs, "--metric", "ate", "--baseline", "VID-Fusion", "--format", "latex")
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    assert "\\toprule" in out and "\\bottomrule" in out
    assert "seq17 & 0.0456 & 0.0362 & 20.6 \\\\" in out  # (0.0456-0.0362)/0.0456
    assert "seq18 & -- & 0.0499 & -- \\\\" in out


def test_report_without_metrics_fails_cleanly(tmp_path):
    run = tmp_path / "r"
    run.mkdir()
    (run / "summary.json").write_text("{\"counts\": 3}")
    proc = _vid("report", run)
    assert proc.returncode != 0 and len(proc.stderr.strip().splitlines()) == 1
    (run / "summary.json").write_text("{not json")
    proc = _vid("report", run)
    assert proc.returncode != 0 and "invalid JSON" in proc.stderr
