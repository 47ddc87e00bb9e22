"""--version on every program (#25): one line with the project version and, for the C++
programs, the git commit they were built from; summary.json records the same commit."""
from __future__ import annotations

import json
import subprocess

import pytest

from test_vid_run_helpers import REPO, VENV_BIN, program, simulate_cached, vid_run

CPP = ["vid_run", "vid_live", "vid_replay", "vid_sim", "vid_track", "vid_info", "vid_massid"]
PY = ["vid-eval", "vid-bag2asl", "vid-batch", "vid-soak", "vid-fit-thrust", "vid-allan"]


def head_sha() -> str:
    sha = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short=12", "HEAD"],
                         capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", str(REPO), "diff", "--quiet", "HEAD", "--"]).returncode
    return sha + ("-dirty" if dirty == 1 else "")


@pytest.mark.parametrize("name", CPP)
def test_cpp_version_names_the_commit(name):
    r = subprocess.run([str(program(name)), "--version"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 1 and lines[0] == f"{name} 0.1.0 (git {head_sha()})", r.stdout


@pytest.mark.parametrize("name", PY)
def test_python_version(name):
    r = subprocess.run([str(VENV_BIN / name), "--version"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"{name} 0."), r.stdout


def test_summary_records_the_commit(tmp_path):
    seq = simulate_cached("vid17_like_short.yaml", 6.0, 1, features_only=True)
    r = vid_run(seq, tmp_path / "run", "--end", "3")
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert s["version"] == {"vid_msckf": "0.1.0", "git": head_sha()}
