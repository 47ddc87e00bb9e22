"""Cached simulations (docs/testing.md "Cached inputs"): a folder kept between sessions
(VID_TEST_SEQ_CACHE) is reused only when the same vid_sim binary, scenario, seed and duration
made it; anything else regenerates it instead of testing old output."""
import json

import test_vid_run_helpers as helpers

ARGS = ("euroc_like_short.yaml", 1.0, 7, True)  # 1 s, features only: cheap


def _fresh(monkeypatch, tmp_path):
    monkeypatch.setenv("VID_TEST_SEQ_CACHE", str(tmp_path))
    helpers._CACHE.pop(ARGS, None)
    return helpers.simulate_cached(*ARGS)


def test_made_by_names_simulator_scenario_seed_and_duration():
    key = helpers.made_by(*ARGS)
    assert set(key) == {"vid_sim", "scenario", "seed", "duration_s", "features_only"}
    assert key != helpers.made_by("euroc_like_short.yaml", 1.0, 8, True)
    assert key != helpers.made_by("euroc_like_short.yaml", 2.0, 7, True)
    # a scenario that names a force file is keyed by that file too
    assert "forces/step_pulse.csv" in helpers.made_by("from_file_short.yaml", 1.0, 1, True)


def test_cached_folder_reused_when_unchanged(monkeypatch, tmp_path):
    out = _fresh(monkeypatch, tmp_path)
    marker = out / "marker"
    marker.write_text("kept")
    assert _fresh(monkeypatch, tmp_path) == out and marker.exists()


def test_stale_cached_folder_is_regenerated(monkeypatch, tmp_path):
    """A folder made by another simulator build (its stamp differs) or before stamps existed."""
    out = _fresh(monkeypatch, tmp_path)
    stamp = out / "made_by.json"
    want = json.loads(stamp.read_text())
    for tamper in (lambda: stamp.write_text(json.dumps({**want, "vid_sim": "0" * 64})), stamp.unlink):
        (out / "marker").write_text("old output")
        tamper()
        assert _fresh(monkeypatch, tmp_path) == out
        assert not (out / "marker").exists(), "old output reused"
        assert json.loads(stamp.read_text()) == want
        assert (out / "mav0" / "imu0" / "data.csv").exists()
