"""A mean external force near 2 g over a run (issue #52): what an accelerometer whose sign or frame
is flipped against the thrust gives in dynamics mode, which the negative-thrust check cannot see
(the thrust is positive). vid_run says so in one named warning line, kept in summary.json
`warnings`; a clean run stays far below the threshold."""
import pytest

from bad_inputs_data import SIM_CONFIG
from bad_inputs_faults import flip_accelerometer
from test_vid_run_helpers import link_copy, simulate_cached, summary, vid_run


@pytest.fixture(scope="module")
def feat():
    return simulate_cached("vid17_like_short.yaml", 3.0, 1, features_only=True)


def test_clean_run_has_no_force_warning(feat, tmp_path):
    r = vid_run(feat, tmp_path / "out", "--config", SIM_CONFIG)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    s = summary(tmp_path / "out")
    assert s["warnings"] == []
    assert s["force_check"]["mean_norm_g"] < 0.5 and s["force_check"]["warn_above_g"] == 1.5


def test_flipped_accelerometer_gives_2g_and_one_named_warning(feat, tmp_path):
    ds = link_copy(feat, tmp_path / "ds")
    flip_accelerometer(ds)
    r = vid_run(ds, tmp_path / "out", "--config", SIM_CONFIG)
    lines = r.stderr.splitlines()
    assert r.returncode == 0 and len(lines) == 1, r.stderr
    assert lines[0].startswith("vid_run: warning: external_force_near_2g:") and "a_RS_S" in lines[0], lines[0]
    s = summary(tmp_path / "out")
    assert 1.8 < s["force_check"]["mean_norm_g"] < 2.3  # measured 2.08: gravity explained twice
    assert len(s["warnings"]) == 1 and s["warnings"][0].startswith("external_force_near_2g:")


def test_imu_mode_has_no_force_check(feat, tmp_path):
    r = vid_run(feat, tmp_path / "out", "--config", SIM_CONFIG, "--mode", "imu")
    assert r.returncode == 0, r.stderr
    s = summary(tmp_path / "out")
    assert "force_check" not in s and s["warnings"] == []
