"""ATE: se3/sim3 equal evo's APE on the same files; posyaw against known offsets and its
closed form; the ate_posyaw library function."""
from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from evo.core import metrics, sync
from evo.tools import file_interface
from scipy.optimize import minimize_scalar
from scipy.spatial.transform import Rotation

from eval_testdata import smooth_trajectory, write_euroc_gt, write_tum
from vid_eval.core.alignment import align, posyaw
from vid_eval.core.ate import ate_posyaw, compute_ate
from vid_eval.core.geometry import rot_z
from vid_eval.tools.loaders import load_trajectory
from vid_eval.core.pairing import PairingOptions


def _make_pair(tmp_path, case: int):
    """Ground truth and a distorted, noisy, re-timed estimate; returns (est, gt, gt_kind)."""
    rng = np.random.default_rng(100 + case)
    t_gt = 1_403_636_000.0 + np.arange(0, 30.0, 0.005)  # 200 Hz
    p, rot = smooth_trajectory(t_gt - t_gt[0], seed=case)
    rate = [4, 10, 1, 7][case]  # estimate every k-th GT time; case 2: denser than GT (below)
    t_est = t_gt[20:-20:rate] + rng.uniform(-0.0015, 0.0015, len(t_gt[20:-20:rate]))
    pe, re = smooth_trajectory(t_est - t_gt[0], seed=case)
    R_off = Rotation.from_rotvec(rng.normal(0, 0.8, 3))
    scale = [1.0, 1.2, 0.9, 1.05][case]
    drift = np.cumsum(rng.normal(0, 0.01, (len(t_est), 3)), axis=0)
    pe = scale * R_off.apply(pe + drift) + rng.normal(0, 1, 3)
    re = R_off * re * Rotation.from_rotvec(rng.normal(0, 0.03, (len(t_est), 3)))
    est = write_tum(tmp_path / f"est{case}.txt", t_est, pe, re)
    if case == 2:  # sparse ground truth (20 Hz), estimate at 200 Hz: evo walks the GT
        keep = slice(0, None, 10)
        t_gt, p, rot = t_gt[keep], p[keep], rot[keep]
    if case in (1, 3):
        gt = write_euroc_gt(tmp_path / f"gt{case}" / "data.csv",
                            np.round(t_gt * 1e9).astype(np.int64), p, rot)
        return est, gt, "euroc"
    return est, write_tum(tmp_path / f"gt{case}.txt", t_gt, p, rot), "tum"


def _evo_ape(est_path, gt_path, kind, with_scale, max_diff=0.01, offset=0.0):
    ref = (file_interface.read_euroc_csv_trajectory(str(gt_path)) if kind == "euroc"
           else file_interface.read_tum_trajectory_file(str(gt_path)))
    est = file_interface.read_tum_trajectory_file(str(est_path))
    ref, est = sync.associate_trajectories(ref, est, max_diff=max_diff, offset_2=offset)
    est.align(ref, correct_scale=with_scale)
    out = []
    for rel in (metrics.PoseRelation.translation_part, metrics.PoseRelation.rotation_angle_deg):
        ape = metrics.APE(rel)
        ape.process_data((ref, est))
        out.append(ape.get_statistic(metrics.StatisticsType.rmse))
    return out[0], out[1], est.num_poses


@pytest.mark.parametrize("case", [0, 1, 2, 3])
@pytest.mark.parametrize("mode", ["se3", "sim3"])
def test_ate_matches_evo(tmp_path, case, mode):
    est_path, gt_path, kind = _make_pair(tmp_path, case)
    evo_pos, evo_rot, evo_n = _evo_ape(est_path, gt_path, kind, mode == "sim3")
    res = compute_ate(load_trajectory(est_path), load_trajectory(gt_path), mode)
    assert len(res.pos_err) == evo_n
    assert res.pos_rmse == pytest.approx(evo_pos, abs=1e-9)
    assert res.rot_rmse_deg == pytest.approx(evo_rot, abs=1e-9)
    assert res.pos_rmse > 1e-3  # the case is not trivially zero


def test_ate_matches_evo_with_time_offset(tmp_path):
    est_path, gt_path, kind = _make_pair(tmp_path, 0)
    # shift the estimate's clock by -0.25 s and undo it with the offset option
    lines = [ln.split() for ln in est_path.read_text().splitlines() if not ln.startswith("#")]
    shifted = tmp_path / "shifted.txt"
    shifted.write_text("".join(f"{float(ln[0]) - 0.25:.9f} " + " ".join(ln[1:]) + "\n" for ln in lines))
    evo_pos, evo_rot, evo_n = _evo_ape(shifted, gt_path, kind, False, offset=0.25)
    opt = PairingOptions(offset_ns=250_000_000)
    res = compute_ate(load_trajectory(shifted), load_trajectory(gt_path), "se3", pairing=opt)
    assert len(res.pos_err) == evo_n
    assert res.pos_rmse == pytest.approx(evo_pos, abs=1e-9)
    assert res.rot_rmse_deg == pytest.approx(evo_rot, abs=1e-9)


def test_cli_json_matches_evo(tmp_path):
    est_path, gt_path, kind = _make_pair(tmp_path, 1)
    out = tmp_path / "traj.json"
    proc = subprocess.run([sys.executable, "-m", "vid_eval.cli", "traj", str(est_path), str(gt_path),
                           "--align", "sim3", "--json", str(out)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(out.read_text())
    evo_pos, evo_rot, evo_n = _evo_ape(est_path, gt_path, kind, True)
    assert data["ate"]["pairs"] == evo_n
    assert data["ate_pos_rmse_m"] == pytest.approx(evo_pos, abs=1e-9)
    assert data["ate_rot_rmse_deg"] == pytest.approx(evo_rot, abs=1e-9)


def _posyaw_case(yaw_deg=37.0, t=(1.5, -2.0, 0.7), noise=0.0, seed=3):
    rng = np.random.default_rng(seed)
    ts = np.arange(0, 20.0, 0.05)
    p_gt, r_gt = smooth_trajectory(ts, seed=seed)
    Rz = rot_z(np.radians(yaw_deg))
    # p_gt = Rz p_est + t  =>  p_est = Rz^T (p_gt - t); orientations R_gt = Rz R_est
    p_est = (p_gt - np.asarray(t)) @ Rz + rng.normal(0, noise, p_gt.shape)
    r_est = Rotation.from_matrix(Rz.T) * r_gt
    t_ns = (ts * 1e9).astype(np.int64) + 10**18
    q = lambda r: r.as_quat()[:, [3, 0, 1, 2]]  # noqa: E731
    return t_ns, p_est, q(r_est), p_gt, q(r_gt), Rz, np.asarray(t)


def test_posyaw_recovers_known_yaw_and_translation():
    t_ns, p_est, q_est, p_gt, q_gt, Rz, t = _posyaw_case()
    res = ate_posyaw(t_ns, p_est, t_ns, p_gt, q_est, q_gt)
    assert res.alignment.yaw_deg == pytest.approx(37.0, abs=1e-9)
    np.testing.assert_allclose(res.alignment.R, Rz, atol=1e-12)
    np.testing.assert_allclose(res.alignment.t, t, atol=1e-9)
    assert res.pos_rmse < 1e-9
    assert res.rot_rmse_deg < 1e-5


def test_posyaw_is_the_least_squares_yaw_and_rotates_about_gravity_only():
    t_ns, p_est, q_est, p_gt, q_gt, _, _ = _posyaw_case(yaw_deg=-120.0, noise=0.2, seed=5)
    al = posyaw(p_est, p_gt)
    # rotation about z only
    assert al.R[2, 2] == pytest.approx(1.0)
    np.testing.assert_allclose(al.R[2, :2], 0.0, atol=1e-15)
    np.testing.assert_allclose(al.R[:2, 2], 0.0, atol=1e-15)

    def cost(yaw):  # translation eliminated in closed form for a given yaw
        R = rot_z(yaw)
        r = p_est @ R.T
        return np.sum((r - r.mean(0) - (p_gt - p_gt.mean(0))) ** 2)

    best = minimize_scalar(cost, bounds=(al.yaw_deg * np.pi / 180 - 0.5, al.yaw_deg * np.pi / 180 + 0.5),
                           method="bounded", options={"xatol": 1e-12})
    assert np.degrees(best.x) == pytest.approx(al.yaw_deg, abs=1e-4)
    assert al.yaw_deg == pytest.approx(-120.0, abs=2.0)
    np.testing.assert_allclose(al.t, p_gt.mean(0) - al.R @ p_est.mean(0), atol=1e-12)


def test_posyaw_does_not_absorb_roll_but_se3_does():
    t_ns, p_est, q_est, p_gt, q_gt, _, _ = _posyaw_case()
    tilt = Rotation.from_rotvec([0.1, 0, 0]).as_matrix()
    p_tilted = p_est @ tilt.T
    assert align(p_tilted, p_gt, "se3").apply_positions(p_tilted) == pytest.approx(p_gt, abs=1e-9)
    res = ate_posyaw(t_ns, p_tilted, t_ns, p_gt)
    assert res.pos_rmse > 0.01
    assert res.rot_err_deg is None


def test_posyaw_align_frames_uses_only_the_first_poses():
    t_ns, p_est, q_est, p_gt, q_gt, _, _ = _posyaw_case()
    p_bad = p_est.copy()
    p_bad[100:] += np.array([0.0, 0.0, 5.0])  # corrupt the later part only
    res_first = ate_posyaw(t_ns, p_bad, t_ns, p_gt, n_align=100)
    np.testing.assert_allclose(res_first.pos_err[:100], 0.0, atol=1e-9)
    np.testing.assert_allclose(res_first.pos_err[100:], 5.0, atol=1e-9)
    res_all = ate_posyaw(t_ns, p_bad, t_ns, p_gt)
    assert res_all.pos_err[:100].max() > 1.0


def test_ate_posyaw_associates_with_tolerance_and_offset():
    t_ns, p_est, q_est, p_gt, q_gt, _, _ = _posyaw_case()
    # estimate clock 2 s behind, 3 ms jitter: offset +2 s, tolerance 5 ms finds every pose
    rng = np.random.default_rng(0)
    t_est = t_ns - 2_000_000_000 + rng.integers(-3_000_000, 3_000_000, len(t_ns))
    res = ate_posyaw(t_est, p_est, t_ns, p_gt, q_est, q_gt, max_diff_ns=5_000_000,
                     offset_ns=2_000_000_000)
    assert len(res.pos_err) == len(t_ns)
    assert res.pos_rmse < 1e-9


def test_pieces_after_a_reinitialization_are_aligned_on_their_own(tmp_path):
    """A vid_run trajectory re-initialized at 12 s: the second piece is in a new world frame
    (yaw 1 rad, shifted 5 m); with the marker line each piece is aligned on its own and the
    noise-free estimate scores zero, one alignment scores the frame change."""
    t = 1_403_636_000.0 + np.arange(0, 20.0, 0.01)
    p, rot = smooth_trajectory(t - t[0], seed=4)
    gt = write_euroc_gt(tmp_path / "gt.csv", np.round(t * 1e9).astype(np.int64), p, rot)
    k = np.searchsorted(t, t[0] + 12.0)
    frame = Rotation.from_rotvec([0, 0, 1.0])
    p_est, rot_est = p.copy(), rot
    p_est[k:] = frame.apply(p[k:]) + [5.0, -2.0, 0.3]
    rot_est = Rotation.concatenate([rot[:k], frame * rot[k:]])
    est = write_tum(tmp_path / "est.txt", t, p_est, rot_est)
    lines = est.read_text().splitlines()
    lines.insert(1 + k, f"# re-initialized at {t[k]:.9f}: a new world frame from here on")
    est.write_text("\n".join(lines) + "\n")
    from vid_eval.core.ate import compute_ate_pieces
    from vid_eval.tools.loaders import reinit_marks
    marks = reinit_marks(est)
    assert marks.tolist() == [int(round(t[k] * 1e9))]
    res = compute_ate_pieces(load_trajectory(est), load_trajectory(gt), marks)
    assert [len(a.pos_err) for a in res.pieces] == [k, len(t) - k]
    assert res.pooled.pos_rmse < 1e-6 and res.pooled.rot_rmse_deg < 1e-4
    assert res.pieces[1].alignment.as_dict() != res.pieces[0].alignment.as_dict()
    assert compute_ate(load_trajectory(est), load_trajectory(gt)).pos_rmse > 1.0
    # the command line: per piece by default, --one-alignment on request
    out = subprocess.run([sys.executable, "-m", "vid_eval.cli", "traj", str(est), str(gt), "--json",
                          str(tmp_path / "a.json")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    j = json.loads((tmp_path / "a.json").read_text())
    assert j["ate_pos_rmse_m"] < 1e-6 and len(j["ate_pieces"]["pieces"]) == 2
    assert j["ate_pieces"]["pieces"][1]["t_start_ns"] == marks[0]
    out = subprocess.run([sys.executable, "-m", "vid_eval.cli", "traj", str(est), str(gt), "--one-alignment",
                          "--json", str(tmp_path / "b.json")], capture_output=True, text=True)
    assert json.loads((tmp_path / "b.json").read_text())["ate_pos_rmse_m"] > 1.0


def test_a_bad_reinitialization_marker_names_its_line(tmp_path):
    t = 1_403_636_000.0 + np.arange(0, 2.0, 0.01)
    p, rot = smooth_trajectory(t - t[0], seed=1)
    est = write_tum(tmp_path / "est.txt", t, p, rot)
    est.write_text(est.read_text() + "# re-initialized at soon: a new world frame from here on\n")
    from vid_eval.errors import InputFormatError
    from vid_eval.tools.loaders import reinit_marks
    with pytest.raises(InputFormatError, match=r"est.txt.*202|line 202"):
        reinit_marks(est)
