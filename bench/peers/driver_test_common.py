"""Skeleton shared by the peer driver smoke tests (test_ov_driver.py, test_vidfusion_driver.py):
where the project's binaries and a peer driver are, the skip marker when either is missing, and
the simulated sequence. Only runs programs (no peer code)."""
from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("VID_BIN", ROOT / "build" / "bin"))
sys.path.insert(0, str(ROOT / "eval"))


def driver(env: str, name: str) -> pathlib.Path:
    """The peer driver: $env, else build-peers/bin/<name>."""
    return pathlib.Path(os.environ.get(env, ROOT / "build-peers" / "bin" / name))


def skip_without(drv: pathlib.Path, name: str):
    """Module mark: skip unless the peer build and vid_sim are present."""
    return pytest.mark.skipif(not drv.exists() or not (BIN / "vid_sim").exists(),
                              reason=f"peer build (build-peers/bin/{name}) or vid_sim not present")


def simulate(tmp_path_factory, preset: str, seconds: int) -> pathlib.Path:
    """config/sim/<preset>.yaml simulated for `seconds` s (its own seed) into a temporary folder."""
    d = tmp_path_factory.mktemp("peers") / f"{preset}_{seconds}s"
    subprocess.run([str(BIN / "vid_sim"), "--scenario", str(ROOT / f"config/sim/{preset}.yaml"),
                    "--out", str(d), "--duration", str(seconds), "--quiet"], check=True)
    return d
