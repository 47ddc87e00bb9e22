"""The idealized force-estimation bound (vid_eval.core.force_bound, `vid-eval force-bound`)."""
import json

import numpy as np
import pytest

from vid_eval.cli import main
from vid_eval.core.force_bound import (BoundSetup, _model, force_bound, kalman_force,
                                  resample_force, simulate_measurements, split_by_time_scale)


def _batch_map(y_a, y_p, x0, P0, q, sigma_p, setup):
    """Smoothed states of one axis as the minimizer of the full quadratic cost."""
    n = y_a.size
    dt = 1.0 / setup.imu_rate_hz
    A, Q = _model(dt, q)
    cam_every = int(round(setup.imu_rate_hz / setup.camera_rate_hz))
    r_a = setup.accel_noise_density ** 2 / dt
    H = np.zeros((4 * n, 4 * n))
    g = np.zeros(4 * n)
    P0i, Qi = np.linalg.inv(P0), np.linalg.inv(Q)
    H[:4, :4] += P0i
    g[:4] += P0i @ x0
    for i in range(1, n):
        J = np.zeros((4, 4 * n))
        J[:, 4 * i - 4:4 * i] = -A
        J[:, 4 * i:4 * i + 4] = np.eye(4)
        H += J.T @ Qi @ J
    for i in range(n):
        H[4 * i + 2, 4 * i + 2] += 1.0 / r_a
        g[4 * i + 2] += y_a[i] / r_a
        if i % cam_every == 0:
            H[4 * i, 4 * i] += 1.0 / sigma_p ** 2
            g[4 * i] += y_p[i] / sigma_p ** 2
    return np.linalg.solve(H, g).reshape(n, 4)


def test_rts_smoother_equals_batch_least_squares():
    setup = BoundSetup(imu_rate_hz=1.0, camera_rate_hz=0.5, accel_noise_density=0.3)
    rng = np.random.default_rng(5)
    t = np.arange(0.0, 40.0, 1.0)
    F = np.stack([np.sin(t), np.cos(0.5 * t), 0.2 * t], axis=1)
    _, F4, p4 = resample_force(t, F, setup.imu_rate_hz)
    y_a, y_p = simulate_measurements(F4, p4, 0.01, setup, rng)
    x0 = np.zeros((4, 3))
    P0 = np.diag([0.1, 0.2, 0.5, 0.3])
    sm = kalman_force(y_a, y_p, x0, P0, 0.7, 0.01, setup, smooth=True)
    for k in range(3):
        ref = _batch_map(y_a[:, k], y_p[:, k], x0[:, k], P0, 0.7, 0.01, setup)
        np.testing.assert_allclose(sm[:, :, k], ref, rtol=1e-6, atol=1e-9)
    # The filter's last estimate is the smoother's last estimate.
    fi = kalman_force(y_a, y_p, x0, P0, 0.7, 0.01, setup, smooth=False)
    np.testing.assert_allclose(fi[-1], sm[-1], rtol=1e-12, atol=1e-12)


def test_resampled_position_is_the_double_integral():
    t = np.linspace(0.0, 4.0, 801)
    F = np.tile([0.5, -1.0, 2.0], (t.size, 1))
    tt, F4, p4 = resample_force(t, F, 400.0)
    np.testing.assert_allclose(F4, np.tile([0.5, -1.0, 2.0], (tt.size, 1)))
    # Rectangle rule: p_i = c dt^2 (i+1)(i+2)/2 -> c t^2 / 2 to O(dt).
    np.testing.assert_allclose(p4[-1], 0.5 * np.array([0.5, -1.0, 2.0]) * tt[-1] ** 2, rtol=2e-3)


def _smooth_force(seconds=40.0):
    t = np.arange(0.0, seconds, 0.005)
    F = np.stack([1.5 * np.sin(0.9 * t) + 0.4 * np.sin(2.3 * t + 1.0),
                  np.cos(0.6 * t), 0.3 * np.sin(1.7 * t)], axis=1)
    return t, F


def test_bound_improves_with_camera_precision_and_smoother_beats_filter():
    t, F = _smooth_force()
    res = force_bound(t, F, [0.25e-3, 1e-3, 4e-3], q_grid=(0.2, 1.0, 5.0))
    filt = [r.filter_rmse for r in res]
    assert filt[0] < filt[1] < filt[2]
    for r in res:
        assert r.smoother_rmse < r.filter_rmse
        assert r.filter_rmse == pytest.approx(np.sqrt(np.sum(np.square(r.filter_rmse_axes))))


def test_bound_without_camera_is_accelerometer_limited():
    """Camera noise so large it adds nothing: the filter averages the accelerometer only and
    can not beat sigma_a / sqrt(T) on a force that stays constant for T = 30 s."""
    t = np.arange(0.0, 35.0, 0.005)
    F = np.tile([1.0, 0.0, -2.0], (t.size, 1))
    setup = BoundSetup(accel_noise_density=0.1, skip_s=5.0)
    (r,) = force_bound(t, F, [10.0], q_grid=(0.01,), setup=setup)
    per_axis_floor = 0.1 / np.sqrt(35.0)
    assert min(r.filter_rmse_axes) > per_axis_floor
    assert max(r.filter_rmse_axes) < 0.2  # and it does converge


def test_split_by_time_scale_separates_offset_and_noise():
    rng = np.random.default_rng(2)
    t = np.arange(0.0, 60.0, 0.0025)
    err = np.tile([0.1, -0.05, 0.0], (t.size, 1)) + 0.2 * rng.standard_normal((t.size, 3))
    total, slow, fast = split_by_time_scale(t, err, 2.0)
    assert slow == pytest.approx(np.hypot(0.1, 0.05), rel=0.05)
    assert fast == pytest.approx(0.2 * np.sqrt(3), rel=0.02)
    assert total == pytest.approx(np.hypot(slow, fast), rel=0.02)


def _write_dataset(root, t_ns, f_N, mass=2.0):
    mav0 = root / "mav0"
    (mav0 / "force0").mkdir(parents=True)
    (mav0 / "mass0").mkdir()
    (mav0 / "imu0").mkdir()
    rows = "\n".join(f"{t},{f[0]:.17g},{f[1]:.17g},{f[2]:.17g}" for t, f in zip(t_ns, f_N))
    (mav0 / "force0" / "data.csv").write_text("#timestamp [ns],f_x [N],f_y [N],f_z [N]\n" + rows + "\n")
    (mav0 / "mass0" / "data.csv").write_text(f"#timestamp [ns],mass [kg]\n{t_ns[0]},{mass}\n")
    (mav0 / "imu0" / "sensor.yaml").write_text("rate_hz: 200\naccelerometer_noise_density: 0.05\n")
    return mav0


def test_cli_reads_the_dataset_and_writes_json(tmp_path, capsys):
    t, F = _smooth_force(12.0)
    t_ns = (1_000_000_000 + t * 1e9).astype(np.int64)
    _write_dataset(tmp_path / "seq", t_ns, 2.0 * F)
    out = tmp_path / "b.json"
    assert main(["force-bound", str(tmp_path / "seq"), "--sigma-p-mm", "0.5", "2",
                 "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["imu_rate_hz"] == 200.0 and data["accel_noise_density"] == 0.05
    assert data["camera_rate_hz"] == 30.0  # no cam0/sensor.yaml: the default
    assert [r["sigma_p_m"] for r in data["results"]] == [0.0005, 0.002]
    assert data["results"][0]["filter_rmse"] < data["results"][1]["filter_rmse"]
    # Same numbers as the library on the mass-normalized force.
    ref = force_bound(t, F, [0.0005], setup=BoundSetup(imu_rate_hz=200.0,
                                                       accel_noise_density=0.05))
    assert data["results"][0]["filter_rmse"] == pytest.approx(ref[0].filter_rmse, rel=1e-9)
    assert "sigma_p [mm]" in capsys.readouterr().out


def test_cli_without_force_ground_truth_is_one_line_error(tmp_path, capsys):
    (tmp_path / "seq" / "mav0").mkdir(parents=True)
    assert main(["force-bound", str(tmp_path / "seq")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "force0" in err[0]


def test_jump_oracle_helps_on_steps_and_changes_nothing_on_smooth_forces():
    """A filter told when the force jumps re-learns the level after each step: far lower error
    on steps; on a smooth force no sample crosses the threshold, so nothing changes."""
    t = np.arange(0.0, 30.0, 0.005)
    steps = np.zeros((t.size, 3))
    steps[:, 0] = np.where((t // 4.0) % 2 == 1, 3.0, 0.0)  # 3 m/s^2 steps every 4 s
    setup = BoundSetup(skip_s=5.0)
    (plain,) = force_bound(t, steps, [0.0005], setup=setup)
    (oracle,) = force_bound(t, steps, [0.0005], setup=setup, jump_min=0.2)
    assert oracle.filter_rmse < 0.7 * plain.filter_rmse
    ts, smooth = _smooth_force(30.0)
    (a,) = force_bound(ts, smooth, [0.0005], setup=setup)
    (b,) = force_bound(ts, smooth, [0.0005], setup=setup, jump_min=0.2)
    assert b.filter_rmse == pytest.approx(a.filter_rmse, rel=1e-12)
