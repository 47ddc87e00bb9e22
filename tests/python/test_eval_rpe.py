"""RPE on constructed drift cases with known relative errors."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from vid_eval.core.rpe import compute_rpe, cumulative_distance, default_distances
from vid_eval.core.series import Trajectory


def _line(n=1001, step=0.1, yaw_per_m=0.0, scale=1.0):
    """Straight flight along x (step m apart); yaw may drift linearly with distance."""
    s = np.arange(n) * step
    p = np.c_[scale * s, np.zeros(n), np.zeros(n)]
    q = Rotation.from_rotvec(np.c_[np.zeros(n), np.zeros(n), yaw_per_m * s]).as_quat()[:, [3, 0, 1, 2]]
    t = np.arange(n, dtype=np.int64) * 100_000_000
    return Trajectory(t, p, q)


def test_default_distances_are_10_to_50_percent_of_the_length():
    gt = _line()
    assert cumulative_distance(gt.p)[-1] == pytest.approx(100.0)
    assert default_distances(gt) == pytest.approx([10.0, 20.0, 30.0, 40.0, 50.0])


def test_scale_drift_gives_one_percent_translation_error():
    gt, est = _line(), _line(scale=1.01)
    segs = compute_rpe(est, gt, default_distances(gt))
    for seg in segs:
        d = seg.distance
        assert len(seg.trans_err) == round((100.0 - d) / 0.1) + 1  # every start with a full segment
        np.testing.assert_allclose(seg.trans_err, 0.01 * d, rtol=1e-9)
        np.testing.assert_allclose(seg.rot_err_deg, 0.0, atol=1e-9)
        stats = seg.as_dict()
        assert stats["trans_percent"]["mean"] == pytest.approx(1.0, rel=1e-9)
        assert stats["trans_m"]["rmse"] == pytest.approx(0.01 * d, rel=1e-9)


def test_yaw_drift_gives_rotation_error_proportional_to_distance():
    c = np.radians(0.5)  # 0.5 deg per m of travel
    gt, est = _line(), _line(yaw_per_m=c)
    segs = compute_rpe(est, gt, [5.0, 25.0])
    for seg in segs:
        np.testing.assert_allclose(seg.rot_err_deg, 0.5 * seg.distance, rtol=1e-9)
        np.testing.assert_allclose(seg.as_dict()["rot_deg_per_m"]["mean"], 0.5, rtol=1e-9)
        # the estimate moves along world x but believes it is yawed by c*s_i at the start:
        # the relative translation in the start frame is off by 2 d sin(c s_i / 2)
        s_i = seg.start_idx * 0.1
        np.testing.assert_allclose(seg.trans_err, 2 * seg.distance * np.abs(np.sin(c * s_i / 2)),
                                   atol=1e-9)


def test_rpe_ignores_a_constant_pose_offset():
    gt = _line(scale=1.0)
    est = _line(scale=1.0)
    R = Rotation.from_rotvec([0.3, -0.2, 1.0])
    est = Trajectory(est.t_ns, R.apply(est.p) + [4, 5, 6],
                     (R * Rotation.from_quat(est.q[:, [1, 2, 3, 0]])).as_quat()[:, [3, 0, 1, 2]])
    for seg in compute_rpe(est, gt, [10.0, 30.0]):
        np.testing.assert_allclose(seg.trans_err, 0.0, atol=1e-9)
        np.testing.assert_allclose(seg.rot_err_deg, 0.0, atol=1e-6)


def test_too_long_segments_give_no_pairs():
    gt = _line(n=11)  # 1 m long
    seg = compute_rpe(gt, gt, [5.0])[0]
    assert len(seg.trans_err) == 0
