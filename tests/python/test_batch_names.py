"""vid-batch never writes two runs or two plots to one file name (issue #25): two sequence
folders of the same name, grid values that map to one id, scenario labels that map to one box
plot name."""
from __future__ import annotations

import pytest

from conftest import REPO
from vid_eval.batch.report import _boxplots
from vid_eval.batch.spec import BatchSpecError, load_batch


def _seq(root, *parts):
    folder = root.joinpath(*parts)
    (folder / "mav0").mkdir(parents=True)
    return folder


def test_two_sequences_of_one_name_get_two_ids(tmp_path):
    a, b = _seq(tmp_path, "day1", "flight"), _seq(tmp_path, "day2", "flight")
    spec = tmp_path / "b.yaml"
    spec.write_text(f"sequences: [{a}, {b}]\n")
    ids = [t.id for t in load_batch(spec, REPO)]
    assert ids == ["flight__ours", "day2_flight__ours"]


def test_runs_that_would_share_an_id_are_refused(tmp_path):
    a = _seq(tmp_path, "x", "flight")
    spec = tmp_path / "b.yaml"
    spec.write_text(f"sequences: [{a}]\ngrid: {{tag: ['a b', 'a_b']}}\n")
    with pytest.raises(BatchSpecError, match="field 'grid'.*share the id flight__ours__tag=a_b"):
        load_batch(spec, REPO)
    spec.write_text(f"sequences: [{a}, {a}, {a}]\n")
    with pytest.raises(BatchSpecError, match=r"field 'sequences\[2\]'.*name of an earlier input"):
        load_batch(spec, REPO)


def test_box_plots_of_labels_with_one_file_name_do_not_overwrite(tmp_path):
    recs = [{"kind": "estimate", "status": "ok", "estimator": "ours", "ate_m": 0.01 * k,
             "force_rmse_world": 0.1, "att_err_max_deg": 1.0, "run_s": 2.0, **lab}
            for k, lab in enumerate([{"preset": "vid17_like", "duration": 12}, {"sequence": "vid17_like_12_s"}])]
    written = _boxplots(recs, tmp_path)
    assert sorted(p.name for p in written) == ["box_preset_vid17_like_12_s.png", "box_preset_vid17_like_12_s_2.png"]
    assert all(p.is_file() for p in written)
