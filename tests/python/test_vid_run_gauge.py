"""Issue 30: world-frame force scores are gauge-free end to end (vid_sim -> vid_run -> vid-eval).

The same seed simulated at two initial headings gives the same sensor data in two ground-truth
worlds rotated about gravity; the estimator starts at its own heading either way. Its
world-frame force RMSE (vid_run's summary and vid-eval force) must not depend on the heading,
and must agree with the body-frame figure, which never depended on it.
"""
import json
import subprocess

import pytest

from test_vid_run_helpers import REPO, VENV_BIN, simulate, summary, vid_run

SEQ_S = 10.0


@pytest.fixture(scope="module")
def two_headings(tmp_path_factory):
    """vid18_like_short, features only, seed 4, simulated at heading 0 and 165 deg; one run each."""
    base = tmp_path_factory.mktemp("gauge")
    runs = {}
    for heading in ("0", "165"):
        seq = simulate(base / f"seq{heading}", "vid18_like_short.yaml", SEQ_S, 4, True, heading=heading)
        out = base / f"run{heading}"
        r = vid_run(seq, out, "--config", str(REPO / "config" / "sim"))
        assert r.returncode == 0, r.stderr
        runs[heading] = (seq, out)
    return runs


def _vid_eval_force(seq, out, tmp, *extra):
    js = tmp / f"force{len(list(tmp.glob('force*.json')))}.json"
    subprocess.run([str(VENV_BIN / "vid-eval"), "force", str(out / "force.csv"),
                    str(seq / "mav0" / "force0" / "data.csv"), "--json", str(js), *extra],
                   check=True, capture_output=True, timeout=120)
    return json.loads(js.read_text())


def test_summary_world_force_does_not_depend_on_the_heading(two_headings):
    s0, s165 = (summary(two_headings[h][1]) for h in ("0", "165"))
    assert s165["force_rmse_world_mps2"] == pytest.approx(s0["force_rmse_world_mps2"], rel=0.01)
    assert s165["ate_posyaw_m"] == pytest.approx(s0["ate_posyaw_m"], rel=0.01)
    for s in (s0, s165):
        assert s["force_alignment"]["mode"] == "posyaw"
        # within 5 % of the body-frame figure, which needs no alignment
        assert s["force_rmse_world_mps2"] == pytest.approx(s["force_rmse_body_mps2"], rel=0.05)
    dyaw = s165["force_alignment"]["yaw_deg"] - s0["force_alignment"]["yaw_deg"]
    assert ((dyaw - 165.0 + 180.0) % 360.0) - 180.0 == pytest.approx(0.0, abs=1.0)


def test_vid_eval_force_equals_the_summary_at_any_heading(two_headings, tmp_path):
    for heading, (seq, out) in two_headings.items():
        s = summary(out)
        world = _vid_eval_force(seq, out, tmp_path)
        body = _vid_eval_force(seq, out, tmp_path, "--frame", "body")
        assert world["force_rmse_world_mps2"] == pytest.approx(s["force_rmse_world_mps2"], abs=1e-6)
        assert body["force_rmse_body_mps2"] == pytest.approx(s["force_rmse_body_mps2"], abs=1e-6)
        assert world["alignment"]["yaw_deg"] == pytest.approx(s["force_alignment"]["yaw_deg"], abs=1e-6)


def test_unaligned_world_comparison_shows_the_gauge(two_headings, tmp_path):
    """--align none scores the 165-degree run as the bug did: many times the real error."""
    seq, out = two_headings["165"]
    wrong = _vid_eval_force(seq, out, tmp_path, "--align", "none")
    assert wrong["force_rmse_world_mps2"] > 3 * summary(out)["force_rmse_world_mps2"]
