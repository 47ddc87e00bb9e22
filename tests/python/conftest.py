"""Shared pytest fixtures: paths to the repository, the C++ build and its programs."""
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def build_dir() -> pathlib.Path:
    return pathlib.Path(os.environ.get("VID_BUILD_DIR", REPO / "build"))


@pytest.fixture
def repo_root() -> pathlib.Path:
    return REPO


@pytest.fixture
def cpp_program():
    """Return the path of a built C++ program; fail (not skip) when it was not built."""

    def find(name: str) -> pathlib.Path:
        path = build_dir() / "bin" / name
        if not path.exists():
            pytest.fail(f"{path} not built: run scripts/build.sh first")
        return path

    return find
