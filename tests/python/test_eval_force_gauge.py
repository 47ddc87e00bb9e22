"""World-frame force scoring is gauge-free: the estimator's world has its own heading.

An estimate whose world frame is rotated about gravity against the ground truth's (as every
real recording is: the estimator starts at heading 0, the motion-capture world does not) must
score the same as an estimate in the ground truth's own frame.
"""
from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from eval_testdata import (run_cli_in_process, smooth_trajectory, write_csv, write_euroc_gt,
                           write_force_estimate, write_state, write_tum)
from vid_eval.core.alignment import Alignment
from vid_eval.tools.gauge import WorldGauge, rotate_world
from vid_eval.core.series import VectorSeries

MASS = 2.0
C_WORLD = np.array([0.1, -0.2, 0.3])  # estimate error in the ground truth's world [m/s^2]


def _case(tmp_path, heading_deg: float, seed: int = 3, with_state: bool = True):
    """Dataset with force0 + poses; an estimate (force.csv, state.csv) whose world frame is
    the ground truth's rotated by -heading about z and shifted (the estimator's own gauge)."""
    n = 2400  # 12 s at 200 Hz (force-bound skips the first 5 s)
    t_ns = 10**18 + np.arange(n, dtype=np.int64) * 5_000_000
    ts = np.arange(n) * 0.005
    p_gt, rot_gt = smooth_trajectory(ts, seed)
    f_w = np.c_[3 * np.sin(ts), 2 * np.cos(0.5 * ts), -1 + np.sin(2 * ts)]  # N, GT world
    mav0 = tmp_path / "seq" / "mav0"
    write_csv(mav0 / "force0" / "data.csv", "#timestamp [ns],f_x [N],f_y [N],f_z [N]", t_ns, f_w)
    write_euroc_gt(mav0 / "state_groundtruth_estimate0" / "data.csv", t_ns, p_gt, rot_gt)
    # Estimator world E: R_EG = Rz(-heading); p_E = R_EG p_G + offset.
    R_EG = Rotation.from_euler("z", -heading_deg, degrees=True)
    k = np.arange(10, n - 10, 2)
    est_t = t_ns[k]
    a_w_est = R_EG.apply(f_w[k] / MASS + C_WORLD)
    rot_est = R_EG * rot_gt[k]
    a_b_est = rot_est.inv().apply(a_w_est)
    sigma = np.full((len(k), 3), 0.1)
    run = tmp_path / "run"
    force = write_force_estimate(run / "force.csv", est_t, a_b_est, a_w_est, sigma)
    if with_state:
        write_state(run / "state.csv", est_t, R_EG.apply(p_gt[k]) + [4.0, -1.0, 0.5], rot_est,
                    a_b_est, sigma_f=sigma)
    return mav0, force


def _score(tmp_path, force, mav0, *extra):
    out = tmp_path / f"f{len(list(tmp_path.glob('f*.json')))}.json"
    proc = run_cli_in_process("force", force, mav0 / "force0" / "data.csv", "--mass", MASS,
                              "--json", out, *extra)
    assert proc.returncode == 0, proc.stderr
    return json.loads(out.read_text()), proc.stdout


@pytest.mark.parametrize("heading_deg", [0.0, 165.0, -97.0])
def test_world_rmse_does_not_depend_on_the_estimators_heading(tmp_path, heading_deg):
    mav0, force = _case(tmp_path, heading_deg)
    d, stdout = _score(tmp_path, force, mav0)
    assert d["force_rmse_world_mps2"] == pytest.approx(np.linalg.norm(C_WORLD), rel=1e-6)
    assert [d["force"]["rmse_mps2"][a] for a in "xyz"] == pytest.approx(np.abs(C_WORLD), abs=1e-6)
    al = d["alignment"]
    assert al["mode"] == "posyaw"
    assert ((al["yaw_deg"] - heading_deg + 180.0) % 360.0) - 180.0 == pytest.approx(0.0, abs=1e-6)
    assert al["est_trajectory"].endswith("state.csv") and al["gt_trajectory"].endswith("data.csv")
    assert "posyaw-aligned" in stdout


def test_random_headings_agree_with_the_body_frame(tmp_path):
    """Per seed a random heading: world RMSE equal to the unrotated one, and to the body one
    when the error is a pure world offset of constant size (rotation keeps the norm)."""
    rng = np.random.default_rng(2026)
    ref = None
    for i, heading in enumerate(rng.uniform(-180.0, 180.0, 4)):
        sub = tmp_path / f"h{i}"
        sub.mkdir()
        mav0, force = _case(sub, float(heading), seed=5)
        d, _ = _score(sub, force, mav0)
        b, _ = _score(sub, force, mav0, "--frame", "body")
        ref = ref or d["force_rmse_world_mps2"]
        assert d["force_rmse_world_mps2"] == pytest.approx(ref, rel=1e-6)
        assert d["force_rmse_world_mps2"] == pytest.approx(b["force_rmse_body_mps2"], rel=1e-6)


def test_align_none_shows_the_gauge_error(tmp_path):
    """Without alignment a 165-degree gauge is scored as a huge error: the bug this fixes."""
    mav0, force = _case(tmp_path, 165.0)
    d, stdout = _score(tmp_path, force, mav0, "--align", "none")
    assert d["force_rmse_world_mps2"] > 5 * np.linalg.norm(C_WORLD)
    assert d["alignment"]["mode"] == "none"
    assert "not aligned" in stdout


def test_explicit_trajectories_and_se3(tmp_path):
    mav0, force = _case(tmp_path, 120.0)
    state = force.parent / "state.csv"
    moved = tmp_path / "elsewhere.csv"
    moved.write_text(state.read_text())
    state.unlink()
    d, _ = _score(tmp_path, force, mav0, "--traj", moved, "--align", "se3",
                  "--gt-state", mav0 / "state_groundtruth_estimate0" / "data.csv")
    assert d["force_rmse_world_mps2"] == pytest.approx(np.linalg.norm(C_WORLD), rel=1e-6)
    assert d["alignment"]["mode"] == "se3" and d["alignment"]["est_trajectory"] == str(moved)


def test_world_frame_without_a_trajectory_is_refused_in_one_line(tmp_path):
    mav0, force = _case(tmp_path, 165.0, with_state=False)
    proc = run_cli_in_process("force", force, mav0 / "force0" / "data.csv", "--mass", MASS)
    assert proc.returncode != 0
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "trajectory" in proc.stderr and "--frame body" in proc.stderr


def test_force_bound_split_is_gauge_free(tmp_path):
    """`vid-eval force-bound --estimate` splits the error after the same alignment."""
    mav0, force = _case(tmp_path, 165.0)
    (mav0 / "vehicle.yaml").write_text(f"mass_kg: {MASS}\n")
    out = tmp_path / "b.json"
    proc = run_cli_in_process("force-bound", mav0.parent, "--sigma-p-mm", "1", "--estimate", force,
                              "--json", out)
    assert proc.returncode == 0, proc.stderr
    est = json.loads(out.read_text())["estimate"]
    assert est["rmse"] == pytest.approx(np.linalg.norm(C_WORLD), rel=1e-6)
    assert est["slow_rmse"] == pytest.approx(np.linalg.norm(C_WORLD), rel=1e-3)
    assert est["alignment"]["yaw_deg"] == pytest.approx(165.0, abs=1e-6)


def test_rotate_world_rotates_values_and_sigma():
    R = Rotation.from_euler("z", 90, degrees=True).as_matrix()
    s = VectorSeries(np.array([1, 2]), np.array([[1.0, 0, 0], [0, 2.0, 0]]), "world", "m/s^2",
                     np.array([[0.1, 0.3, 0.2], [0.1, 0.3, 0.2]]))
    r = rotate_world(s, WorldGauge(Alignment(R=R, mode="posyaw"), "", "", 0))
    assert r.values == pytest.approx(np.array([[0.0, 1.0, 0], [-2.0, 0, 0]]), abs=1e-12)
    assert r.sigma[0] == pytest.approx([0.3, 0.1, 0.2], abs=1e-12)


def test_smoothed_force_is_aligned_by_the_smoothed_trajectory(tmp_path):
    """``vid_run --smooth`` writes force_smoothed.csv (force.csv's columns) next to
    trajectory_smoothed_tum.txt: scoring it aligns with that trajectory, not the causal one."""
    mav0, force = _case(tmp_path, 40.0, with_state=False)
    run = force.parent
    heading = 40.0
    n = 2400
    t_ns = 10**18 + np.arange(n, dtype=np.int64) * 5_000_000
    ts = np.arange(n) * 0.005
    p_gt, rot_gt = smooth_trajectory(ts, 3)
    k = np.arange(10, n - 10, 2)
    R_EG = Rotation.from_euler("z", -heading, degrees=True)
    # The causal trajectory in a wrong heading (its alignment would rotate the force wrongly).
    R_bad = Rotation.from_euler("z", 70.0, degrees=True)
    write_tum(run / "trajectory_tum.txt", t_ns[k] * 1e-9, R_bad.apply(p_gt[k]), R_bad * rot_gt[k])
    write_tum(run / "trajectory_smoothed_tum.txt", t_ns[k] * 1e-9, R_EG.apply(p_gt[k]) + [1.0, 2.0, 0.0],
              R_EG * rot_gt[k])
    smoothed = run / "force_smoothed.csv"
    smoothed.write_text(force.read_text())
    d, _ = _score(tmp_path, smoothed, mav0)
    assert d["alignment"]["est_trajectory"].endswith("trajectory_smoothed_tum.txt")
    assert d["force_rmse_world_mps2"] == pytest.approx(np.linalg.norm(C_WORLD), rel=1e-6)
    d_causal, _ = _score(tmp_path, force, mav0)
    assert d_causal["alignment"]["est_trajectory"].endswith("trajectory_tum.txt")
