"""The plots a user expects (issue #25), checked as a reader sees them.

* The world-frame force plot of the demo command (`vid-eval force force.csv force0 --frame
  world`, no --state) carries the ±3σ band, taken from force.csv's body sigma rotated with the
  run's own state.csv, and the band is visible.
* The NEES plot has axis labels, a legend, the 95 % chi2 band of the file's run count, and
  every curve visible.
* Two evaluations into one plot folder never overwrite each other's figures.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from matplotlib.collections import PolyCollection
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

import vid_eval.plots.force as force_plots
from eval_testdata import (run_cli_in_process, smooth_trajectory, write_csv, write_euroc_gt,
                           write_force_estimate, write_state, write_tum)
from plot_checks import changed_pixels, hidden_curves
from test_vid_run_helpers import REPO
from vid_eval.tools.loaders import load_nees
from vid_eval.plots.nees import nees_figure
from vid_eval.plots.style import read_stamp

MASS = 2.0
HEADING_DEG = 165.0
SIGMA_BODY = np.array([0.05, 0.1, 0.2])  # anisotropic: the world band depends on the rotation


def _run_folder(tmp_path, seed=3):
    """A dataset (force0, poses) and a run folder (force.csv, state.csv) whose world frame has
    its own heading, as vid_run writes them."""
    n = 1200
    t_ns = 10**18 + np.arange(n, dtype=np.int64) * 5_000_000
    ts = np.arange(n) * 0.005
    p_gt, rot_gt = smooth_trajectory(ts, seed)
    f_w = np.c_[3 * np.sin(ts), 2 * np.cos(0.5 * ts), -1 + np.sin(2 * ts)]
    mav0 = tmp_path / "seq" / "mav0"
    write_csv(mav0 / "force0" / "data.csv", "#timestamp [ns],f_x [N],f_y [N],f_z [N]", t_ns, f_w)
    write_euroc_gt(mav0 / "state_groundtruth_estimate0" / "data.csv", t_ns, p_gt, rot_gt)
    R_EG = Rotation.from_euler("z", -HEADING_DEG, degrees=True)
    k = np.arange(0, n, 2)
    a_w = R_EG.apply(f_w[k] / MASS + 0.05)
    rot_est = R_EG * rot_gt[k]
    a_b = rot_est.inv().apply(a_w)
    sigma = np.tile(SIGMA_BODY, (len(k), 1))
    run = tmp_path / "run"
    write_force_estimate(run / "force.csv", t_ns[k], a_b, a_w, sigma)
    write_state(run / "state.csv", t_ns[k], R_EG.apply(p_gt[k]) + [4.0, -1.0, 0.5], rot_est, a_b, sigma_f=sigma)
    # expected world band: body sigma rotated into the estimator's world, then into the truth's
    R = (R_EG.inv() * rot_est).as_matrix()
    sigma_w = np.sqrt(np.einsum("nij,nj->ni", R ** 2, sigma ** 2))
    return mav0, run, (t_ns[k], R_EG.inv().apply(a_w), sigma_w)


def _band(ax):
    bands = [c for c in ax.collections if isinstance(c, PolyCollection) and "3σ" in c.get_label()]
    assert len(bands) == 1, [c.get_label() for c in ax.collections]
    return bands[0]


def test_demo_force_plot_has_the_3sigma_band_from_force_csv(tmp_path, monkeypatch):
    """The demo's command line (force.csv and force0 only): the world plot has the band, equal
    to force.csv's body sigma rotated with state.csv's orientations, and it can be seen."""
    mav0, run, (t_ns, f_w, sigma_w) = _run_folder(tmp_path)
    figures = []
    monkeypatch.setattr(force_plots, "save", lambda fig, *a, **k: figures.append(fig))
    out = tmp_path / "f.json"
    proc = run_cli_in_process("force", run / "force.csv", mav0 / "force0" / "data.csv", "--frame", "world",
                              "--mass", MASS, "--json", out, "--plot", tmp_path / "plots")
    assert proc.returncode == 0, proc.stderr
    assert "no ±3σ band" not in proc.stdout
    res = json.loads(out.read_text())
    assert res["force"]["fraction_within_3sigma"] is not None
    fig = figures[0]
    te = (t_ns - t_ns[0]) * 1e-9
    for k, ax in enumerate(fig.axes[:3]):
        band = _band(ax)
        v = band.get_paths()[0].vertices
        inner = v[(v[:, 0] > te[5]) & (v[:, 0] < te[-5])]
        upper = np.interp(inner[:, 0], te, f_w[:, k] + 3 * sigma_w[:, k])
        lower = np.interp(inner[:, 0], te, f_w[:, k] - 3 * sigma_w[:, k])
        on_edge = np.minimum(abs(inner[:, 1] - upper), abs(inner[:, 1] - lower))
        assert np.max(on_edge) < 1e-6, f"axis {k}: band is not est ± 3 sigma_world"
        assert changed_pixels(fig, band) > 1000, f"axis {k}: band hidden"
    assert not hidden_curves(fig)


def test_force_plot_without_orientations_says_why_it_has_no_band(tmp_path, monkeypatch):
    mav0, run, _ = _run_folder(tmp_path)
    (run / "state.csv").unlink()
    figures = []
    monkeypatch.setattr(force_plots, "save", lambda fig, *a, **k: figures.append(fig))
    proc = run_cli_in_process("force", run / "force.csv", mav0 / "force0" / "data.csv", "--frame", "world",
                              "--mass", MASS, "--align", "none", "--plot", tmp_path / "plots")
    assert proc.returncode == 0, proc.stderr
    assert "note: no ±3σ band in the world frame" in proc.stdout
    assert not [c for c in figures[0].axes[0].collections if "3σ" in c.get_label()]


def test_nees_plot_has_labels_legend_and_the_chi2_band():
    """docs/results' NEES curves (20 runs of vid17_like): the band drawn is the file's, the
    file's band is the chi2 quantiles (C++ uses Wilson-Hilferty: within 0.5 %), every curve
    can be seen, the legend names the band and each curve's share inside it."""
    nees = load_nees(REPO / "docs" / "results" / "nees_vid17_like_dynamics.csv")
    k = 3 * nees.runs
    assert nees.band_lo == pytest.approx(chi2.ppf(0.025, k) / nees.runs, rel=5e-3)
    assert nees.band_hi == pytest.approx(chi2.ppf(0.975, k) / nees.runs, rel=5e-3)
    fig = nees_figure(nees, skip_s=5.0)
    ax = fig.axes[0]
    assert "NEES" in ax.get_ylabel() and "3 dof" in ax.get_ylabel()
    assert "[s]" in ax.get_xlabel()
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(f"95 % band of the mean of {nees.runs} χ²(3)" in t for t in texts), texts
    for name in ("orientation", "position", "force"):
        assert any(t.startswith(name) and "% inside" in t for t in texts), (name, texts)
    band = next(p for p in ax.patches if "95 % band" in p.get_label())
    ys = band.get_path().transformed(band.get_patch_transform()).vertices[:, 1]
    assert (min(ys), max(ys)) == pytest.approx((nees.band_lo, nees.band_hi))
    assert changed_pixels(fig, band) > 1000
    assert not hidden_curves(fig)


def test_nees_command_shares_and_one_line_errors(tmp_path):
    out = tmp_path / "n.json"
    csv = REPO / "docs" / "results" / "nees_vid17_like_dynamics.csv"
    proc = run_cli_in_process("nees", csv, "--json", out, "--plot", tmp_path / "p")
    assert proc.returncode == 0, proc.stderr
    shares = json.loads(out.read_text())["files"][0]["fraction_inside"]
    nees = load_nees(csv)
    for name, v in nees.curves().items():  # recomputed here from the raw rows
        t = nees.t_ns * 1e-9
        keep = t >= 5.0
        assert shares[name] == pytest.approx(np.mean((v[keep] >= nees.band_lo) & (v[keep] <= nees.band_hi)))
    assert (tmp_path / "p" / "nees_vid17_like_dynamics.png").is_file()
    bad = tmp_path / "nees_bad.csv"
    bad.write_text("#t [s],nees_theta [],nees_p [],nees_F []\n0,3,3,3\n0.1,3,3,3\n")
    proc = run_cli_in_process("nees", bad)
    assert proc.returncode == 1
    assert proc.stderr.count("\n") == 1 and "nees_bad.csv" in proc.stderr and "runs=" in proc.stderr


def _traj_case(tmp_path, name, seed):
    ts = np.arange(400) * 0.05
    p, rot = smooth_trajectory(ts, seed)
    t_ns = 10**18 + (ts * 1e9).astype(np.int64)
    gt = write_euroc_gt(tmp_path / "gt.csv", t_ns, p, rot)
    (tmp_path / name).mkdir()
    est = write_tum(tmp_path / name / "trajectory_tum.txt", ts + 1e9, p + 0.01 * seed, rot)
    return est, gt


def test_two_runs_into_one_plot_folder_never_overwrite_each_other(tmp_path):
    """Two estimates evaluated into one folder: the second is refused in one line before
    anything is written (the first run's plots unchanged); with --method (or --plot-prefix)
    both sets coexist; rerunning the same inputs replaces its own plots."""
    plots = tmp_path / "plots"
    est_a, gt = _traj_case(tmp_path, "dyn", 1)
    est_b, _ = _traj_case(tmp_path, "imu", 2)
    assert run_cli_in_process("traj", est_a, gt, "--plot", plots).returncode == 0
    before = (plots / "traj_views.png").read_bytes()
    assert "dyn/trajectory_tum.txt" in read_stamp(plots / "traj_views.png")
    proc = run_cli_in_process("traj", est_b, gt, "--plot", plots, "--json", tmp_path / "b.json")
    assert proc.returncode == 1
    assert proc.stderr.count("\n") == 1 and "traj_views.png: holds the plot of other inputs" in proc.stderr
    assert (plots / "traj_views.png").read_bytes() == before
    assert not (tmp_path / "b.json").exists()
    assert run_cli_in_process("traj", est_a, gt, "--plot", plots).returncode == 0  # same inputs: fine
    assert run_cli_in_process("traj", est_a, gt, "--plot", plots, "--method", "dyn").returncode == 0
    assert run_cli_in_process("traj", est_b, gt, "--plot", plots, "--method", "imu").returncode == 0
    assert run_cli_in_process("traj", est_b, gt, "--plot", plots, "--plot-prefix", "b").returncode == 0
    names = sorted(p.name for p in plots.glob("*.png"))
    assert names == sorted(f"{pre}traj_{k}.png" for pre in ("", "dyn_", "imu_", "b_")
                           for k in ("views", "errors", "rpe"))
    assert "imu/trajectory_tum.txt" in read_stamp(plots / "imu_traj_errors.png")
