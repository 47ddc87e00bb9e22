"""Loaders, format detection, association (evo's rule, tolerance, offset) and interpolation."""
from __future__ import annotations

import numpy as np
import pytest
from evo.core import sync
from scipy.spatial.transform import Rotation, Slerp

from eval_testdata import smooth_trajectory, write_euroc_gt, write_state, write_tum
from vid_eval.core import formats
from vid_eval.core.association import associate
from vid_eval.errors import AssociationError
from vid_eval.tools.loaders import detect_trajectory_format, load_state, load_trajectory
from vid_eval.core.pairing import PairingOptions, pair_trajectories
from vid_eval.core.series import Trajectory


def test_state_header_is_the_documented_contract():
    line = formats.header_line(formats.STATE_COLUMNS)
    assert line.startswith("#timestamp [ns],p_x [m],p_y [m],p_z [m],q_w [],q_x [],q_y [],q_z []")
    assert len(formats.STATE_COLUMNS) == 38
    assert formats.header_names(line)[-1] == "sigma_f_z"
    assert formats.header_line(formats.FORCE_COLUMNS) == (
        "#timestamp [ns],fb_x [m s^-2],fb_y [m s^-2],fb_z [m s^-2],fw_x [m s^-2],fw_y [m s^-2],"
        "fw_z [m s^-2],sigma_x [m s^-2],sigma_y [m s^-2],sigma_z [m s^-2]")


def test_formats_are_detected_and_loaded_identically(tmp_path):
    ts = 1_000.0 + np.arange(0, 5, 0.01)
    p, r = smooth_trajectory(ts - ts[0])
    t_ns = np.round(ts * 1e9).astype(np.int64)
    tum = write_tum(tmp_path / "a.txt", ts, p, r)
    euroc = write_euroc_gt(tmp_path / "b.csv", t_ns, p, r)
    state = write_state(tmp_path / "state.csv", t_ns, p, r, np.zeros((len(ts), 3)))
    assert [detect_trajectory_format(x) for x in (tum, euroc, state)] == ["tum", "euroc", "state"]
    trajs = [load_trajectory(x) for x in (tum, euroc, state)]
    for tr in trajs:
        np.testing.assert_array_equal(tr.t_ns, t_ns)  # TUM seconds parsed exactly to ns
        np.testing.assert_allclose(tr.p, p, atol=1e-9)
        np.testing.assert_allclose(np.abs(np.sum(tr.q * r.as_quat()[:, [3, 0, 1, 2]], axis=1)), 1.0,
                                   atol=1e-9)
    st = load_state(state)
    assert st.sigma["p"].shape == (len(ts), 3)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_association_matches_evo_indices(seed):
    rng = np.random.default_rng(seed)
    t_gt = np.cumsum(rng.uniform(0.004, 0.006, 800))
    t_est = np.sort(rng.uniform(-0.5, 5.0, [200, 800, 2000][seed]))
    t_est = t_est[np.diff(t_est, prepend=-1) > 1e-6]
    tol = 0.003
    i_ref, i_est = (None, None)
    if len(t_est) > len(t_gt):  # as associate_trajectories(ref, est): equal counts walk est
        i_ref, i_est = sync.matching_time_indices(t_gt, t_est, tol)
    else:
        i_est, i_ref = sync.matching_time_indices(t_est, t_gt, tol)
    m = associate(np.round(t_est * 1e9).astype(np.int64), np.round(t_gt * 1e9).astype(np.int64),
                  max_diff_ns=int(tol * 1e9))
    assert list(m.est_idx) == list(i_est)
    assert list(m.gt_idx) == list(i_ref)


def test_association_tolerance_offset_and_failure():
    t_gt = np.arange(0, 100, dtype=np.int64) * 10_000_000
    t_est = t_gt[::3] + 3_000_000 - 1_000_000_000  # 3 ms late, clock 1 s behind
    with pytest.raises(AssociationError, match="0 matching"):
        associate(t_est, t_gt, max_diff_ns=5_000_000)
    m = associate(t_est, t_gt, max_diff_ns=5_000_000, offset_ns=1_000_000_000)
    np.testing.assert_array_equal(m.gt_idx, np.arange(0, 100, 3))
    with pytest.raises(AssociationError):
        associate(t_est, t_gt, max_diff_ns=2_000_000, offset_ns=1_000_000_000)


def test_interpolation_is_linear_for_position_and_slerp_for_rotation():
    t_gt = np.array([0, 1_000_000_000, 2_000_000_000], dtype=np.int64)
    rots = Rotation.from_rotvec([[0, 0, 0], [0, 0, 1.0], [0.5, 0, 1.0]])
    gt = Trajectory(t_gt, np.array([[0, 0, 0], [2.0, 0, 0], [2.0, 4.0, 0]]),
                    rots.as_quat()[:, [3, 0, 1, 2]])
    t_q = np.array([250_000_000, 1_500_000_000, 2_500_000_000], dtype=np.int64)
    est = Trajectory(t_q, np.zeros((3, 3)), np.tile([1.0, 0, 0, 0], (3, 1)))
    pe, pg = pair_trajectories(est, gt, PairingOptions(mode="interpolate", min_pairs=1))
    assert len(pe) == 2  # the query after the last GT sample is dropped
    np.testing.assert_allclose(pg.p, [[0.5, 0, 0], [2.0, 2.0, 0]])
    expect = Slerp([0, 1, 2], rots)([0.25, 1.5]).as_quat()[:, [3, 0, 1, 2]]
    np.testing.assert_allclose(np.abs(np.sum(pg.q * expect, axis=1)), 1.0, atol=1e-12)
