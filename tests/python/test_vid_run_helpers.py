"""Helpers of the vid_run end-to-end tests (no tests here): build paths, simulated sequences, runs.

Sequences are generated once per test session (vid_sim with fixed seeds) into a temporary
folder; runs write into their own folders. Nothing here decides a test's outcome.
"""
import atexit
import hashlib
import json
import os
import tempfile
import pathlib
import shutil
import signal
import subprocess
import time

import numpy as np
from vid_eval.core.ate import compute_ate
from vid_eval.tools.loaders import load_trajectory

REPO = pathlib.Path(__file__).resolve().parents[2]
VENV_BIN = REPO / ".venv" / "bin"


def build_dir() -> pathlib.Path:
    return pathlib.Path(os.environ.get("VID_BUILD_DIR", REPO / "build"))


def program(name: str) -> pathlib.Path:
    path = build_dir() / "bin" / name
    if not path.exists():
        raise FileNotFoundError(f"{path} not built: run scripts/build.sh first")
    return path


def simulate(out: pathlib.Path, scenario: str, duration_s: float, seed: int, features_only: bool,
             heading: str = "random", noise_free: bool = False) -> pathlib.Path:
    """vid_sim into ``out``. The initial heading in the ground-truth world is drawn from the seed
    by default (real recordings start at any heading; the estimator starts at its own)."""
    cmd = [str(program("vid_sim")), "--scenario", str(REPO / "config" / "sim" / scenario), "--out", str(out),
           "--seed", str(seed), "--duration", str(duration_s), "--initial-heading", heading, "--quiet"]
    if features_only:
        cmd.append("--features-only")
    if noise_free:
        cmd.append("--no-noise")
    subprocess.run(cmd, check=True, capture_output=True, text=True, timeout=600)
    return out


_CACHE_DIR = None
_CACHE = {}


def made_by(scenario: str, duration_s: float, seed: int, features_only: bool) -> dict:
    """What a simulated folder is a function of (docs/testing.md "Cached inputs"): the vid_sim
    binary, the scenario file (and any force file it names), seed, duration, features only."""
    path = REPO / "config" / "sim" / scenario
    files = {"vid_sim": program("vid_sim"), "scenario": path}
    for line in path.read_text().splitlines():  # e.g. from_file's `file: forces/step_pulse.csv`
        if line.strip().startswith("file:"):
            name = line.split("file:", 1)[1].split("#")[0].strip()
            files[name] = path.parent / name
    key = {k: hashlib.sha256(f.read_bytes()).hexdigest() for k, f in files.items()}
    return {**key, "seed": seed, "duration_s": duration_s, "features_only": features_only}


def simulate_cached(scenario: str, duration_s: float, seed: int, features_only: bool) -> pathlib.Path:
    """simulate() once per (scenario, duration, seed, features_only) per process, shared by the
    test modules (a rendered sequence costs ~20 s of CPU)."""
    global _CACHE_DIR
    key = (scenario, duration_s, seed, features_only)
    if key not in _CACHE:
        name = f"{pathlib.Path(scenario).stem}_{duration_s:g}s_seed{seed}{'_feat' if features_only else ''}"
        keep = os.environ.get("VID_TEST_SEQ_CACHE")  # developer option: keep sequences between sessions
        if keep:  # reused only if made by the same simulator, scenario, seed and duration
            out = pathlib.Path(keep) / name
            stamp, want = out / "made_by.json", made_by(scenario, duration_s, seed, features_only)
            if not stamp.exists() or json.loads(stamp.read_text()) != want:
                shutil.rmtree(out, ignore_errors=True)
                simulate(out, scenario, duration_s, seed, features_only)
                stamp.write_text(json.dumps(want, indent=1))
            _CACHE[key] = out
        else:
            if _CACHE_DIR is None:
                _CACHE_DIR = pathlib.Path(tempfile.mkdtemp(prefix="vid_run_seq_"))
                atexit.register(shutil.rmtree, _CACHE_DIR, True)
            _CACHE[key] = simulate(_CACHE_DIR / name, scenario, duration_s, seed, features_only)
    return _CACHE[key]


def vid_run(dataset: pathlib.Path, out: pathlib.Path, *args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    cmd = [str(program("vid_run")), "--dataset", str(dataset), "--out", str(out), "--quiet", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env={**os.environ, "CI": "true"})


def summary(out: pathlib.Path) -> dict:
    return json.loads((out / "summary.json").read_text())


def run_and_score(seq: pathlib.Path, out: pathlib.Path, config: pathlib.Path, skip_s: float = 0.0) -> dict:
    """vid_run --config on a simulated folder, then `vid-eval force --json` and the ATE:
    {"summary", "force" (the JSON), "att_err_max_deg" (after skip_s seconds)}."""
    r = vid_run(seq, out, "--config", str(config))
    assert r.returncode == 0, r.stderr
    js = out / "force_eval.json"
    subprocess.run([str(VENV_BIN / "vid-eval"), "force", str(out / "force.csv"),
                    str(seq / "mav0" / "force0" / "data.csv"), "--json", str(js)],
                   check=True, capture_output=True, timeout=120)
    ate = compute_ate(load_trajectory(out / "trajectory_tum.txt"),
                      load_trajectory(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv"))
    t = (ate.est_aligned.t_ns - ate.gt.t_ns[0]) * 1e-9
    return {"summary": summary(out), "force": json.loads(js.read_text()),
            "att_err_max_deg": float(np.max(ate.rot_err_deg[t > skip_s]))}


def tum_rows(path: pathlib.Path) -> list:
    return [line.split() for line in path.read_text().splitlines() if line and not line.startswith("#")]


def first_timestamp_ns(dataset: pathlib.Path) -> int:
    """First time stamp over all data.csv streams (vid_run's --start/--end origin)."""
    first = None
    for csv in (dataset / "mav0").glob("*/data.csv"):
        for line in csv.read_text().splitlines():
            if line and not line.startswith("#"):
                t = int(line.split(",")[0])
                first = t if first is None else min(first, t)
                break
    return first


def link_copy(src: pathlib.Path, dst: pathlib.Path) -> pathlib.Path:
    """Copy a dataset folder with every file as a symlink (cheap); callers replace the files
    they corrupt with real ones (unlink first: writing through a symlink would change src)."""
    shutil.copytree(src, dst, copy_function=os.symlink)
    return dst


def replace_file(path: pathlib.Path, data: bytes) -> None:
    path.unlink()
    path.write_bytes(data)


def interrupt_vid_run(dataset: pathlib.Path, out: pathlib.Path, after_estimates: int, poll_s: float = 0.02):
    """Start vid_run (config/sim, CI quiet), send SIGINT once `after_estimates` rows of
    trajectory_tum.txt are on disk, and return (returncode, stderr). Fails the test if the run
    ends before it could be interrupted."""
    proc = subprocess.Popen([str(program("vid_run")), "--dataset", str(dataset), "--out", str(out), "--quiet",
                             "--config", str(REPO / "config" / "sim")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "CI": "true"})
    traj = out / "trajectory_tum.txt"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if traj.exists() and len(tum_rows(traj)) >= after_estimates:
            break
        time.sleep(poll_s)
    assert proc.poll() is None, "vid_run finished before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    return proc.returncode, err
