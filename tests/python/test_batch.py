"""vid-batch (issue #24): a 12-run batch on a local Ray with 2 workers, killed for real midway and
resumed; results equal to the same runs done one by one; the mass-ID shards equal the
monolithic programs; bad batch files fail with one line. Ray is required (no skip)."""
import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import textwrap
import time

import pyarrow.parquet as pq
import pytest

from conftest import REPO, build_dir

BATCH = textwrap.dedent("""\
    scenarios:
      - {preset: vid17_like, duration: 12}
      - {preset: force_steps, duration: 12}
    seeds: [1, 2, 3]
    config: config/sim
    grid:
      force_random_walk: [1.0, 3.0]
    estimators:
      - {name: ours, mode: dynamics}
    skip_s: 3
    """)


def vid_batch(*args, **kw):
    env = dict(os.environ, VID_BUILD_DIR=str(build_dir()))
    return subprocess.run([sys.executable, "-m", "vid_eval.batch.cli", *map(str, args)], env=env,
                          capture_output=True, text=True, **kw)


def snapshot(records: pathlib.Path) -> dict:
    return {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in records.glob("*.json")}


@pytest.fixture(scope="module")
def killed_and_resumed(tmp_path_factory):
    """Start the 12-run batch, SIGKILL its whole process group once 3 runs are recorded, rerun."""
    import ray  # noqa: F401  (the batch extra must be installed: fail, never skip)
    work = tmp_path_factory.mktemp("batch")
    spec = work / "batch.yaml"
    spec.write_text(BATCH)
    out = work / "out"
    env = dict(os.environ, VID_BUILD_DIR=str(build_dir()))
    proc = subprocess.Popen([sys.executable, "-m", "vid_eval.batch.cli", "run", str(spec), "--out", str(out),
                             "--workers", "2", "--no-progress"], env=env, start_new_session=True,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    records = out / "records"
    deadline = time.time() + 150
    while time.time() < deadline and len(list(records.glob("*.json"))) < 3 and proc.poll() is None:
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    time.sleep(3)  # anything Ray left running would write more records now
    before = snapshot(records)
    assert 3 <= len(before) < 12, f"kill came too late: {len(before)} records"
    assert snapshot(records) == before, "runs still finishing after the kill"
    resumed = vid_batch("run", spec, "--out", out, "--workers", "2", "--no-progress", timeout=300)
    return {"out": out, "spec": spec, "before": before, "resumed": resumed}


def test_batch_killed_midway_resumes_only_missing_runs(killed_and_resumed):
    r = killed_and_resumed["resumed"]
    out, before = killed_and_resumed["out"], killed_and_resumed["before"]
    assert r.returncode == 0, r.stdout + r.stderr
    ok_before = [n for n, (_, data) in before.items() if json.loads(data)["status"] == "ok"]
    assert f"12 runs: {len(ok_before)} already done, {12 - len(ok_before)} to run" in r.stdout
    after = snapshot(out / "records")
    assert len(after) == 12
    for name in ok_before:  # finished runs were not rerun: the same file, untouched
        assert after[name] == before[name], name
    table = pq.read_table(out / "results.parquet").to_pylist()
    assert len(table) == 12 and all(row["status"] == "ok" for row in table)
    assert sorted(row["id"] for row in table) == sorted(p[:-5] for p in after)
    csv_lines = (out / "results.csv").read_text().strip().splitlines()
    assert len(csv_lines) == 13
    assert {row["param.force_random_walk"] for row in table} == {1.0, 3.0}
    # A third invocation has nothing to do.
    again = vid_batch("run", killed_and_resumed["spec"], "--out", out, "--workers", "2", "--no-progress", timeout=120)
    assert again.returncode == 0 and "12 runs: 12 already done, 0 to run" in again.stdout


def test_batch_equals_runs_one_by_one(killed_and_resumed, tmp_path):
    """Same seeds -> the same numbers as simulating, estimating and scoring each run alone."""
    from vid_eval.tools.sim_runs import score_run
    out = killed_and_resumed["out"]
    rows = {r["id"]: r for r in pq.read_table(out / "results.parquet").to_pylist()}
    bindir = build_dir() / "bin"
    for rid in ("force_steps_12s_seed2__ours__force_random_walk=3.0", "vid17_like_12s_seed3__ours__force_random_walk=1.0"):
        row = rows[rid]
        seq = tmp_path / f"seq_{rid}"
        subprocess.run([bindir / "vid_sim", "--scenario", REPO / "config" / "sim" / f"{row['preset']}.yaml",
                        "--out", seq, "--seed", str(row["seed"]), "--duration", "12", "--features-only", "--quiet"],
                       check=True, capture_output=True)
        cfg = tmp_path / f"cfg_{rid}"
        cfg.mkdir()
        for f in (REPO / "config" / "sim").iterdir():
            if f.is_file():
                (cfg / f.name).write_bytes(f.read_bytes())
        est = cfg / "estimator.yaml"
        text, n = re.subn(r"(?m)^force_random_walk:.*$", f"force_random_walk: {row['param.force_random_walk']}",
                          est.read_text())
        assert n == 1
        est.write_text(text)
        run = tmp_path / f"run_{rid}"
        subprocess.run([bindir / "vid_run", "--dataset", seq, "--out", run, "--config", cfg, "--mode", "dynamics",
                        "--quiet", "--decode-threads", "0"], check=True, capture_output=True)
        summary = json.loads((run / "summary.json").read_text())
        # The swept value reached the estimator (an appended duplicate key once did not).
        batch_summary = json.loads((pathlib.Path(row["output"]) / "summary.json").read_text())
        for used in (summary, batch_summary):
            assert used["config"]["estimator"]["force_random_walk"] == row["param.force_random_walk"]
        assert row["ate_m"] == summary["ate_posyaw_m"]
        assert row["force_rmse_world"] == summary["force_rmse_world_mps2"]
        assert (run / "trajectory_tum.txt").read_bytes() == (pathlib.Path(row["output"]) / "trajectory_tum.txt").read_bytes()
        alone = score_run(seq, run, 3.0)
        for key, value in alone.items():
            assert row[key] == value, key


def test_batch_report(killed_and_resumed):
    out = killed_and_resumed["out"]
    r = vid_batch("report", out)
    assert r.returncode == 0, r.stderr
    rows = [r for r in pq.read_table(out / "results.parquet").to_pylist()]
    ate = sorted(x["ate_m"] for x in rows if x["preset"] == "force_steps" and x["param.force_random_walk"] == 1.0)
    stats = (out / "report" / "stats.csv").read_text().splitlines()
    line = next(s for s in stats if s.startswith('"force_steps 12 s","ours force_random_walk=1.0",ate_m,'))
    n, mean, median = line.split(",")[3:6]
    assert int(n) == 3 and float(mean) == pytest.approx(sum(ate) / 3) and float(median) == pytest.approx(ate[1])
    assert "ATE [m], mean over seeds" in r.stdout
    for name in ("box_preset_force_steps_12_s.png", "box_preset_vid17_like_12_s.png",
                 "box_param_force_random_walk.png"):
        assert (out / "report" / name).stat().st_size > 1000


def test_massid_shards_equal_monolithic_programs(tmp_path, cpp_program):
    """The study through vid-batch (generate shards, filters per case, ELM on the merged data,
    report) gives the same run files and the same ELM results as the programs run whole."""
    massid = cpp_program("vid_massid")
    spec = tmp_path / "m.yaml"
    spec.write_text("massid:\n  trajectories: [loop]\n  profiles: [constant, step_drop]\n  runs: 3\n"
                    "  runs_per_case: 1\n  train_runs_per_case: 1\n  filters: [ekf]\n  data_driven: [relm]\n"
                    "  hidden_nodes: 50\n")
    out = tmp_path / "out"
    r = vid_batch("run", spec, "--out", out, "--workers", "2", "--no-progress", timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "7 runs: 0 already done, 7 to run" in r.stdout
    whole = tmp_path / "whole"
    subprocess.run([massid, "generate", "--config", REPO / "config/massid/study.yaml", "--out", whole, "--runs", "3",
                    "--trajectories", "loop", "--profiles", "constant,step_drop", "--threads", "2", "--quiet"],
                   check=True, capture_output=True)
    for prof in ("constant", "step_drop"):
        for i in range(3):
            rel = f"loop/{prof}/run_{i:03d}.csv"
            assert (out / "massid/data/all" / rel).read_bytes() == (whole / rel).read_bytes(), rel
    res = tmp_path / "res"
    subprocess.run([massid, "run", "--data", whole, "--out", res, "--methods", "relm", "--runs-per-case", "1",
                    "--train-runs-per-case", "1", "--hidden-nodes", "50", "--threads", "1"], check=True, capture_output=True)

    def rmspe(path):
        return sorted((ln.split(",")[2], ln.split(",")[6]) for ln in path.read_text().splitlines()[1:]
                      if ln.split(",")[4] == "relm")
    assert rmspe(out / "massid/results/massid_relm/runs.csv") == rmspe(res / "runs.csv")
    assert (out / "massid/results/all/report/summary.md").exists()
    rows = pq.read_table(out / "results.parquet").to_pylist()
    assert {row["kind"] for row in rows} == {"massid_generate", "massid_run", "massid_merge", "massid_report"}


@pytest.mark.parametrize("text,field", [
    ("scenarios: [{preset: no_such_preset}]\nseeds: [1]\n", "scenarios[0].preset"),
    ("scenarios: [{preset: vid17_like}]\nseeds: one\n", "seeds"),
    ("scenarios: [{preset: vid17_like}]\nseeds: [1]\ngrid: {force_random_walk: 2}\n", "grid.force_random_walk"),
    ("scenarios: [{preset: vid17_like}]\nseeds: [1]\nestimators: [{name: x, mode: fast}]\n", "estimators[0].mode"),
    ("scenario: []\n", "scenario"),
    ("massid: {trajectories: [circle]}\n", "massid.trajectories"),
    ("scenarios: [{preset: vid17_like\n", "line"),
])
def test_bad_batch_file_is_one_line_exit_2(tmp_path, capsys, text, field):
    from vid_eval.batch.cli import main
    spec = tmp_path / "bad.yaml"
    spec.write_text(text)
    assert main(["run", str(spec), "--out", str(tmp_path / "out")]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"vid-batch: error: {spec}: field '{field}"), lines
    assert not (tmp_path / "out").exists()  # nothing started


def test_bad_batch_file_exit_status_of_the_program(tmp_path):
    spec = tmp_path / "bad.yaml"
    spec.write_text("seeds: [1]\nscenarios: [{preset: vid17_like, duraton: 5}]\n")
    r = vid_batch("run", spec, "--out", tmp_path / "out", timeout=60)
    assert r.returncode == 2
    assert r.stderr.strip().startswith(f"vid-batch: error: {spec}: field 'scenarios[0].duraton': unknown key")


def test_missing_program_is_named(tmp_path, capsys):
    from vid_eval.batch.cli import main
    spec = tmp_path / "b.yaml"
    spec.write_text("scenarios: [{preset: vid17_like, duration: 5}]\nseeds: [1]\n")
    assert main(["run", str(spec), "--out", str(tmp_path / "out"), "--build-dir", str(tmp_path / "nobuild")]) == 2
    assert capsys.readouterr().err.strip() == \
        f"vid-batch: error: {tmp_path / 'nobuild' / 'bin' / 'vid_run'} not built (run scripts/build.sh or pass --build-dir)"


def test_nees_task_reads_the_test_output(tmp_path):
    """The NEES job's plumbing (no Ray, a stand-in test program): fractions parsed from the
    test's line, a failing test is a failed record with those fractions in its error."""
    from vid_eval.batch.tools import execute
    exe = tmp_path / "build" / "tests" / "vio_core" / "vio_core_nees_sim_test"
    exe.parent.mkdir(parents=True)
    exe.write_text("#!/bin/sh\necho \"vid17_like dynamics: 20 runs x 60 s, band [2.3, 3.8]; "
                   "inside: theta 0.950, p 0.931, F 0.902\"\n[ \"$1\" = --gtest_filter=NeesSim.Ok ] || exit 1\n")
    exe.chmod(0o755)
    ok = execute({"id": "nees_ok", "kind": "nees", "params": {"test": "NeesSim.Ok"}}, str(tmp_path / "out"),
                 str(tmp_path / "build"))
    assert ok["status"] == "ok"
    assert (ok["nees_inside_theta"], ok["nees_inside_p"], ok["nees_inside_F"]) == (0.95, 0.931, 0.902)
    bad = execute({"id": "nees_bad", "kind": "nees", "params": {"test": "NeesSim.Bad"}}, str(tmp_path / "out"),
                  str(tmp_path / "build"))
    assert bad["status"] == "failed" and "exited with 1" in bad["error"] and "theta 0.950" in bad["error"]
    assert json.loads((tmp_path / "out" / "records" / "nees_bad.json").read_text())["status"] == "failed"
