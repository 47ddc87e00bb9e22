"""Bad input -> exactly one line on stderr naming file (and line) and a non-zero exit."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from eval_testdata import smooth_trajectory, write_tum


def _vid(*args):
    return subprocess.run([sys.executable, "-m", "vid_eval.cli", *map(str, args)],
                          capture_output=True, text=True)


@pytest.fixture
def good_gt(tmp_path):
    ts = 100.0 + np.arange(0, 10, 0.05)
    p, r = smooth_trajectory(ts)
    return write_tum(tmp_path / "gt.txt", ts, p, r)


def _one_line_error(proc, *needles):
    assert proc.returncode != 0
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("vid-eval: error: ")
    for n in needles:
        assert n in lines[0], lines[0]
    assert "Traceback" not in proc.stderr


def test_wrong_column_count(tmp_path, good_gt):
    bad = tmp_path / "est.txt"
    bad.write_text("# header\n100.0 0 0 0 0 0 0 1\n100.05 0 0 0 0 0 1\n")
    _one_line_error(_vid("traj", bad, good_gt), f"{bad}:3:", "expected 8 columns, found 7")


def test_unsorted_timestamps(tmp_path, good_gt):
    bad = tmp_path / "est.txt"
    bad.write_text("100.0 0 0 0 0 0 0 1\n100.1 0 0 0 0 0 0 1\n100.05 0 0 0 0 0 0 1\n")
    _one_line_error(_vid("traj", bad, good_gt), f"{bad}:3:", "not strictly increasing")


def test_repeated_timestamp_in_csv(tmp_path, good_gt):
    bad = tmp_path / "gt.csv"
    bad.write_text("#timestamp,x,y,z,qw,qx,qy,qz\n1,0,0,0,1,0,0,0\n2,0,0,0,1,0,0,0\n2,0,0,0,1,0,0,0\n")
    _one_line_error(_vid("traj", good_gt, bad, "--gt-format", "euroc"), f"{bad}:4:", "repeated")


def test_non_overlapping_timestamps(tmp_path, good_gt):
    ts = 5000.0 + np.arange(0, 10, 0.05)
    p, r = smooth_trajectory(ts)
    est = write_tum(tmp_path / "est.txt", ts, p, r)
    _one_line_error(_vid("traj", est, good_gt), "0 matching timestamps", str(est))


@pytest.mark.parametrize("content", ["", "# only a header\n", "\n\n"])
def test_empty_file(tmp_path, good_gt, content):
    empty = tmp_path / "est.txt"
    empty.write_text(content)
    _one_line_error(_vid("traj", empty, good_gt), str(empty), "empty")


def test_missing_file(tmp_path, good_gt):
    _one_line_error(_vid("traj", tmp_path / "nope.txt", good_gt), "nope.txt")


def test_not_a_number(tmp_path, good_gt):
    bad = tmp_path / "est.txt"
    bad.write_text("100.0 0 0 0 0 0 0 1\n100.05 0 abc 0 0 0 0 1\n")
    _one_line_error(_vid("traj", bad, good_gt), f"{bad}:2:", "column 3: value 'abc'")


def test_force_csv_wrong_header_and_columns(tmp_path):
    gt = tmp_path / "force0.csv"
    gt.write_text("#timestamp [ns],f_x [N],f_y [N],f_z [N]\n1,0,0,0\n2,0,0,0\n")
    bad = tmp_path / "force.csv"
    bad.write_text("#timestamp [ns],fb_x,fb_y,fb_z,fw_x,fw_y,fw_z,sigma_x,sigma_y,sigma_z\n"
                   "1,0,0,0,0,0,0,0.1,0.1,0.1\n2,0,0,0,0,0,0,0.1,0.1\n")
    _one_line_error(_vid("force", bad, gt, "--mass", "1"), f"{bad}:3:", "expected 10 columns")
    renamed = tmp_path / "force2.csv"
    renamed.write_text("#timestamp [ns],fx,fb_y,fb_z,fw_x,fw_y,fw_z,sigma_x,sigma_y,sigma_z\n"
                       "1,0,0,0,0,0,0,0.1,0.1,0.1\n")
    _one_line_error(_vid("force", renamed, gt, "--mass", "1"), f"{renamed}:1:", "'fx'")


def test_mass_non_positive(tmp_path):
    gt = tmp_path / "mass0.csv"
    gt.write_text("#timestamp [ns],mass [kg]\n1,2.0\n2,0.0\n")
    _one_line_error(_vid("mass", gt, gt), f"{gt}:3:", "positive")


def test_zero_quaternion(tmp_path, good_gt):
    bad = tmp_path / "est.txt"
    bad.write_text("100.0 0 0 0 0 0 0 1\n100.05 0 0 0 0 0 0 0\n")
    _one_line_error(_vid("traj", bad, good_gt), f"{bad}:2:", "quaternion")


def test_usage_error_exits_2(good_gt):
    proc = _vid("traj", good_gt, good_gt, "--align", "bogus")
    assert proc.returncode == 2


def test_help_lists_subcommands():
    proc = _vid("--help")
    assert proc.returncode == 0
    for cmd in ("traj", "force", "mass", "report"):
        assert cmd in proc.stdout
