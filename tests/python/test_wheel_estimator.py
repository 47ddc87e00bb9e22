"""The estimator's Python package as a wheel (#52): scripts/setup.sh builds it once with
scikit-build-core (python/pyproject.toml) into build-py/dist and installs it into .venv; here the
same wheel goes into a fresh venv outside the checkout and `vid_msckf.run_dataset` on a 5 s
simulated sequence writes the trajectory `vid_run` writes, byte for byte."""
from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

from test_vid_run_helpers import REPO, VENV_BIN, program, simulate_cached, vid_run

SIM_CONFIG = REPO / "config" / "sim"


def wheel() -> pathlib.Path:
    dist = pathlib.Path(os.environ.get("VID_WHEEL_DIR", REPO / "build-py")) / "dist"
    found = sorted(dist.glob("vid_msckf-*.whl"))
    if len(found) != 1:
        pytest.fail(f"expected one vid_msckf wheel in {dist}, found {len(found)}: run scripts/setup.sh")
    return found[0]


def run(cmd, cwd, timeout=600):
    # No PYTHONPATH: the module must come from the venv, not from build/python.
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    r = subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)
    assert r.returncode == 0, f"{cmd}: {r.stdout}\n{r.stderr}"
    return r.stdout


def test_setup_installed_the_wheel_into_the_project_venv(tmp_path):
    where = run([VENV_BIN / "python", "-c", "import vid_msckf; print(vid_msckf.__file__)"], tmp_path).strip()
    assert "site-packages" in where and str(REPO / "build") not in where, where


def test_wheel_in_a_fresh_venv_runs_like_vid_run(tmp_path):
    whl = wheel()
    venv = tmp_path / "venv"
    run(["/usr/bin/python3", "-m", "venv", venv], tmp_path)
    run([venv / "bin" / "pip", "install", "-q", whl], tmp_path)  # numpy from the package index
    work = tmp_path / "elsewhere"  # not inside the source tree
    work.mkdir()
    seq = simulate_cached("vid17_like_short.yaml", 5.0, 1, features_only=False)
    script = (f"import vid_msckf; "
              f"s = vid_msckf.run_dataset({str(seq)!r}, {str(work / 'py')!r}, config={str(SIM_CONFIG)!r}); "
              f"print('@', vid_msckf.__file__); print('@', vid_msckf.__version__, vid_msckf.git_sha); "
              f"print('@', s['status'])")
    # the estimator's own log lines go to stdout too: ours are the three marked '@ '
    out = [ln[2:] for ln in run([venv / "bin" / "python", "-c", script], work).splitlines() if ln.startswith("@ ")]
    where, version, status = out
    assert where.startswith(str(venv)), where  # the wheel's module, not this checkout's build
    assert status == "ok"
    # built from this checkout: the version line of the programs built beside it
    line = subprocess.run([str(program("vid_run")), "--version"], capture_output=True, text=True).stdout
    assert f"{version.split()[0]} (git {version.split()[1]})" in line, (version, line)
    r = vid_run(seq, tmp_path / "cli", "--config", str(SIM_CONFIG))
    assert r.returncode == 0, r.stderr
    ours = (work / "py" / "trajectory_tum.txt").read_bytes()
    assert len(ours.splitlines()) > 50
    assert ours == (tmp_path / "cli" / "trajectory_tum.txt").read_bytes()

