"""docs/parameters.md is generated from the typed parameters (scripts/gen_parameters.py,
issue #25): it must be current, and the generator must refuse keys it cannot document."""
from __future__ import annotations

import importlib.util
import subprocess
import sys

import pytest

from test_vid_run_helpers import REPO

SCRIPT = REPO / "scripts" / "gen_parameters.py"


def _gen(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True)


@pytest.fixture
def gen():
    spec = importlib.util.spec_from_file_location("gen_parameters", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    sys.modules["gen_parameters"] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    yield module
    del sys.modules["gen_parameters"]


def test_reference_is_current():
    r = _gen("--check")
    assert r.returncode == 0, r.stderr


def test_stale_reference_fails(tmp_path):
    stale = tmp_path / "parameters.md"
    stale.write_text((REPO / "docs" / "parameters.md").read_text().replace("`11`", "`12`", 1))
    r = _gen("--check", "--out", stale)
    assert r.returncode == 1
    assert r.stderr.strip() == f"gen_parameters: error: {stale} is stale: run python3 scripts/gen_parameters.py"


def test_every_loader_key_documented(gen):
    text = gen.render()
    for key in ("window_size", "force_rate_random_walk", "accel_gate_downweight", "landed_zero_velocity_sigma",
                "num_features", "stereo_track_lk_levels", "gyro_prediction"):
        assert f"| `{key}` |" in text, key
    assert "| `force_frame` | body \\| world | `world` |" in text


def test_undocumented_or_unknown_member_is_an_error(gen, tmp_path):
    header = tmp_path / "p.h"
    loader = tmp_path / "p.cpp"
    header.write_text("struct P {\n  // --- s ---\n  int a = 1;  ///< documented\n  double b = 2.0;\n};\n")
    loader.write_text("  VID_FIELD(a),\n  VID_FIELD(b),\n")
    gen.SOURCES = [gen.Source("p.yaml", "P", str(header), [str(loader)])]
    with pytest.raises(gen.GenError, match="no /// comment for b"):
        gen.render()
    loader.write_text("  VID_FIELD(a),\n  VID_FIELD(b),\n  VID_FIELD(c),\n")
    with pytest.raises(gen.GenError, match=r"loader key\(s\) \['c'\] are no member of P"):
        gen.render()
