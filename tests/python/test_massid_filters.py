"""End-to-end `vid_massid generate | run | report` for the model-based methods (issue #10):
a tiny study (2 trajectories x 2 profiles x 1 run, 8 s) through the CLI, the tables, the plots,
and the one-line errors on bad input."""
import csv
import pathlib
import subprocess

import pytest
from plot_checks import assert_plot

METHODS = ["ekf", "ukf", "msckf", "swls", "vio"]


@pytest.fixture(scope="module")
def study(tmp_path_factory, request):
    from conftest import build_dir

    prog = build_dir() / "bin" / "vid_massid"
    if not prog.exists():
        pytest.fail(f"{prog} not built")
    root = tmp_path_factory.mktemp("massid")
    cfg = root / "study.yaml"
    cfg.write_text("duration_s: 8\n")
    data, out = root / "data", root / "out"
    subprocess.run([prog, "generate", "--config", cfg, "--out", data, "--runs", "1",
                    "--trajectories", "loop,lemniscate", "--profiles", "constant,step_drop",
                    "--threads", "2", "--quiet"], check=True, capture_output=True)
    subprocess.run([prog, "run", "--data", data, "--out", out, "--runs-per-case", "1",
                    "--threads", "2", "--methods", ",".join(METHODS)], check=True, capture_output=True)
    rep = subprocess.run([prog, "report", "--results", out], capture_output=True, text=True)
    return prog, data, out, rep


def test_run_writes_one_row_per_run_and_method(study):
    _, _, out, _ = study
    rows = list(csv.DictReader((out / "runs.csv").open()))
    assert len(rows) == 2 * 2 * len(METHODS)
    assert {r["method"] for r in rows} == set(METHODS)
    for r in rows:
        assert int(r["samples"]) == 801
        # every method identifies the mass: RMSPE well below the 20 % initial error
        assert 0.0 < float(r["rmspe_pct"]) < 8.0, r
        assert float(r["mean_update_cpu_ms"]) > 0.0


def test_estimates_csv_has_truth_inputs_and_every_method(study):
    _, _, out, _ = study
    f = out / "estimates" / "loop" / "step_drop" / "run_000.csv"
    rows = list(csv.reader(f.open()))
    assert rows[0] == ["t", "mass_true", "thrust_cmd", "wx", "wy", "wz"] + METHODS
    assert len(rows) == 802
    last = [float(x) for x in rows[-1]]
    for m in last[6:]:
        assert abs(m / last[1] - 1.0) < 0.05  # after the step drop the estimates follow


def test_report_tables_and_plots(study):
    _, _, out, rep = study
    assert rep.returncode == 0, rep.stderr
    rdir = out / "report"
    summary = (rdir / "summary.md").read_text()
    assert "## loop" in summary and "## lemniscate" in summary
    assert "| step_drop |" in summary and "Targets on loop" in summary
    rows = list(csv.DictReader((rdir / "loop.csv").open()))
    assert {(r["profile"], r["method"]) for r in rows} == {(p, m) for p in ("constant", "step_drop") for m in METHODS}
    for name in ("loop.png", "lemniscate.png", "inputs.png"):
        assert_plot(rdir / "plots" / name, ("tab:red",), min_pixels=100)


def test_unknown_method_is_one_line_error(study, tmp_path):
    prog, data, _, _ = study
    r = subprocess.run([prog, "run", "--data", data, "--out", tmp_path / "o", "--methods", "ekf,kalman"],
                       capture_output=True, text=True)
    assert r.returncode != 0
    assert "kalman" in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_report_without_runs_names_the_file(study, tmp_path):
    prog, _, _, _ = study
    r = subprocess.run([prog, "report", "--results", tmp_path], capture_output=True, text=True)
    assert r.returncode != 0
    assert "runs.csv" in r.stderr


def test_report_without_vid_eval_keeps_the_tables_and_says_so(study, tmp_path):
    """The figures come from the installed `vid-eval massid-plots`, never a guessed script path:
    without it, one line naming what to do, a non-zero exit, and the tables already written."""
    import os
    import shutil

    prog, _, out, _ = study
    results = tmp_path / "results"
    shutil.copytree(out, results, ignore=shutil.ignore_patterns("report"))
    env = {**os.environ, "VID_EVAL": str(tmp_path / "no-such-vid-eval")}
    r = subprocess.run([prog, "report", "--results", results], capture_output=True, text=True, env=env)
    assert r.returncode != 0
    errors = [line for line in r.stderr.splitlines() if "error" in line]
    assert len(errors) == 1 and "vid-eval not found" in errors[0] and "--no-plots" in errors[0], r.stderr
    assert (results / "report" / "summary.md").stat().st_size > 0
