"""The evaluation package outside this repository (#25): build the wheel, install it into a
fresh venv, and run vid-eval and vid-bag2asl from a folder outside the source tree (package
data: topic maps and the VID-Dataset preset; version from git on --version)."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from eval_testdata import smooth_trajectory, write_tum
from test_vid_run_helpers import REPO


def run(cmd, cwd, timeout=900):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    r = subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True,
                       timeout=timeout, env=env)
    assert r.returncode == 0, f"{cmd}: {r.stdout}\n{r.stderr}"
    return r


def test_wheel_installs_and_runs_outside_the_repository(tmp_path):
    wheels = tmp_path / "wheels"
    leftover = REPO / "eval" / "build"  # setuptools builds in the source tree
    had_build = leftover.exists()
    try:
        run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", wheels, REPO / "eval"], tmp_path)
    finally:
        if not had_build:
            shutil.rmtree(leftover, ignore_errors=True)
    (wheel,) = wheels.glob("vid_eval-*.whl")
    venv = tmp_path / "venv"
    run(["/usr/bin/python3", "-m", "venv", venv], tmp_path)
    run([venv / "bin" / "pip", "install", "-q", wheel], tmp_path)
    work = tmp_path / "elsewhere"  # not inside the source tree
    work.mkdir()
    # --version: the git version setuptools-scm gave the wheel
    version = run([venv / "bin" / "vid-eval", "--version"], work).stdout.split()[-1]
    assert version.startswith("0.") and version == wheel.name.split("-")[1]
    assert run([venv / "bin" / "vid-bag2asl", "--version"], work).stdout.split()[-1] == version
    # vid-eval traj on two TUM files
    t = 1_700_000_000.0 + np.arange(0, 20.0, 0.05)
    p, rot = smooth_trajectory(t - t[0], seed=3)
    write_tum(work / "gt.txt", t, p, rot)
    write_tum(work / "est.txt", t, p + 0.01, rot * Rotation.from_rotvec([0, 0, 0.01]))
    out = run([venv / "bin" / "vid-eval", "traj", "est.txt", "gt.txt", "--align", "se3",
               "--json", "ate.json"], work)
    # se3 alignment takes out the constant 1 cm shift; the 0.01 rad yaw offset stays in the rotation
    ate = json.loads((work / "ate.json").read_text())
    assert ate["ate_pos_rmse_m"] < 1e-9, out.stdout
    assert ate["ate_rot_rmse_deg"] == pytest.approx(np.degrees(0.01), rel=1e-6)
    # vid-bag2asl with its packaged topic map and VID-Dataset preset
    run([sys.executable, "-m", "vid_eval.bag2asl.synthetic", work / "vid17.bag", "--seconds", "2"], work)
    run([venv / "bin" / "vid-bag2asl", "vid17.bag", "asl", "--no-progress"], work)
    mav0 = work / "asl" / "mav0"
    for f in ("imu0/data.csv", "imu0/sensor.yaml", "cam0/sensor.yaml", "rotor0/data.csv"):
        assert (mav0 / f).is_file(), f
    assert "vehicle.yaml" in {p.name for p in (work / "asl").rglob("vehicle.yaml")}
    # the package in the venv is the wheel's, not this source tree
    where = run([venv / "bin" / "python", "-c", "import vid_eval; print(vid_eval.__file__)"], work).stdout
    assert str(REPO) not in where
