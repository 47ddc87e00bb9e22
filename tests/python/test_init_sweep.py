"""scripts/init_sweep.py (docs/notes/initialization.md): one mid-flight start against both
ground-truth references, and the shadow dataset of --gt-without-bias (only the accelerometer
bias columns of the ground truth zeroed, every other file the original)."""
import json
import subprocess
import sys

import numpy as np

from test_vid_run_helpers import REPO, build_dir, simulate_cached


def test_one_start_against_both_references(tmp_path):
    seq = simulate_cached("vid17_like.yaml", 24.0, 1, True)
    r = subprocess.run([sys.executable, str(REPO / "scripts" / "init_sweep.py"), "--vid-run",
                        str(build_dir() / "bin" / "vid_run"), "--config", str(REPO / "config" / "sim"),
                        "--dataset", str(seq), "--starts", "10", "--seconds", "4", "--gt-without-bias",
                        "--out", str(tmp_path)], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    row = json.loads(r.stdout.splitlines()[0])
    assert row["how"] == "in_flight" and row["rc"] == 0 and row["rc_gt"] == 0 and row["rc_gt_nobias"] == 0
    assert row["delay_s"] <= 1.5
    assert row["ate_ratio"] == row["ate"] / row["ate_gt"]
    assert row["ate_ratio_nobias"] == row["ate"] / row["ate_gt_nobias"]
    assert "within +20 %: " in r.stdout and "without b_a" in r.stdout

    gt_file = "mav0/state_groundtruth_estimate0/data.csv"
    orig = np.loadtxt(seq / gt_file, delimiter=",", comments="#")
    shadow = np.loadtxt(tmp_path / f"{seq.name}_nobias" / gt_file, delimiter=",", comments="#")
    assert shadow.shape == orig.shape
    assert np.all(shadow[:, 14:17] == 0.0) and np.any(orig[:, 14:17] != 0.0)
    np.testing.assert_array_equal(shadow[:, :14], orig[:, :14])
    assert (tmp_path / f"{seq.name}_nobias" / "mav0" / "imu0").resolve() == (seq / "mav0" / "imu0").resolve()


def test_dataset_first_time_is_the_earliest_stream_start(tmp_path):
    import pytest
    from vid_eval.errors import InputFormatError
    from vid_eval.tools.loaders import dataset_first_time_ns

    seq = simulate_cached("vid17_like.yaml", 24.0, 1, True)
    firsts = [int(next(ln for ln in csv.read_text().splitlines() if ln and not ln.startswith("#")).split(",")[0])
              for csv in (seq / "mav0").glob("*/data.csv")]
    assert dataset_first_time_ns(seq) == min(firsts)
    (tmp_path / "mav0" / "imu0").mkdir(parents=True)
    (tmp_path / "mav0" / "imu0" / "data.csv").write_text("#timestamp [ns],w_x\n")
    with pytest.raises(InputFormatError, match="no mav0"):
        dataset_first_time_ns(tmp_path)
