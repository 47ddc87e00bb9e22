"""vid-eval mocap-truth on synthetic folders with a known mocap clock offset and IMU-mocap
rotation, a known thrust-stream offset, and an exactly known external force."""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from conftest import REPO
from test_import_synth import G, MASS, T0_NS, _attitude, flight, run_eval
from vid_eval.importer.force_truth import force_truth
from vid_eval.importer.sync import gyro_mocap_sync, lag
from vid_eval.importer.writer import DEFAULT_IMU_NOISE, Imported, write_dataset
from vid_eval.tools.loaders import load_force_gt
from vid_eval.tools.table_reader import read_table

D_MOCAP_S = 0.0073                       # mocap stamps late by 7.3 ms
R_IM = Rotation.from_rotvec(np.radians(2.0) * np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]))
D_THRUST_S = 0.030                       # thrust stamps late by 30 ms


def _folder(tmp_path, d_mocap=D_MOCAP_S, R_IM=R_IM, d_thrust=D_THRUST_S, drag=0.3):
    """IMU 200 Hz; mocap 100 Hz off the IMU grid (+1.7 ms), pose of a body M with R_WM = R_WI R_IM,
    stamped d_mocap late; thrust 200 Hz stamped d_thrust late. The accelerometer sees a linear
    body drag -drag v_I besides the thrust (as rotors do)."""
    f = flight(seconds=30.0)
    t = (f.t_ns - T0_NS) * 1e-9
    v_I = f.R.inv().apply(f.v)
    accel = f.accel.copy()
    thrust = accel[:, 2] + drag * v_I[:, 2]  # a_z = T/m - drag v_z
    tau_ns = T0_NS + 1_700_000 + np.arange(2990, dtype=np.int64) * 10_000_000
    tau = (tau_ns - T0_NS) * 1e-9
    R_WM = _attitude(tau) * R_IM
    amp, w = np.array([2.0, 1.5, 0.5]), np.array([0.4, 0.55, 0.7])
    p = amp * np.sin(w * tau[:, None]) + [0, 0, 1.5]
    v = amp * w * np.cos(w * tau[:, None])
    q = R_WM.as_quat()[:, [3, 0, 1, 2]]
    q *= np.sign(q[:, :1])
    log = Imported(f.t_ns, f.gyro, accel, MASS, G, dict(DEFAULT_IMU_NOISE),
                   t_thrust=f.t_ns + int(round(d_thrust * 1e9)), thrust_n=MASS * thrust,
                   t_gt=tau_ns + int(round(d_mocap * 1e9)), p_WI=p, q_WI_wxyz=q, v_WI=v)
    write_dataset(tmp_path / "seq", log, "test")
    return tmp_path / "seq", f, t


def test_gyro_mocap_offset_and_rotation_are_recovered(tmp_path):
    seq, f, _ = _folder(tmp_path)
    gt = read_table(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv", {17})
    s = gyro_mocap_sync(f.t_ns, f.gyro, gt.t_ns, gt.values[:, 3:7])
    assert abs(s.lag.offset_s - D_MOCAP_S) < 1e-3      # the target: 1 ms
    assert abs(s.lag.offset_s - D_MOCAP_S) < 5e-5      # measured: a few us
    err = np.degrees((s.R_IM * R_IM.inv()).magnitude())
    assert err < 0.1 and err < 0.01


def test_lag_finds_a_pure_shift_between_samples():
    t = np.arange(3000, dtype=np.int64) * 5_000_000
    x = np.sin(2 * np.pi * 0.7 * t * 1e-9) + 0.5 * np.sin(2 * np.pi * 2.3 * t * 1e-9)
    for d in (-0.0123, 0.0, 0.0021, 0.25):
        r = lag(t, x, t + int(d * 1e9), x)
        assert abs(r.offset_s - d) < 1e-5, (d, r)


def test_thrust_offset_is_recovered_with_body_drag(tmp_path):
    """With linear body drag in the accelerometer the plain correlation is biased; the fit with
    the drag term recovers the thrust offset."""
    seq, _, _ = _folder(tmp_path)
    out = tmp_path / "truth.json"
    r = run_eval("mocap-truth", seq, "--json", out)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert abs(doc["thrust_minus_imu_s"] - D_THRUST_S) < 1e-3
    assert abs(doc["thrust_fit_drag_z"] - 0.3) < 0.01
    assert abs(doc["thrust_scale"] - 1.0) < 1e-3
    assert abs(doc["mocap_minus_imu_s"] - D_MOCAP_S) < 1e-3
    assert abs(doc["R_IM_angle_deg"] - 2.0) < 0.1
    assert "thrust stamps - IMU stamps = +30.0" in r.stdout and "mocap stamps - IMU stamps = +7.3" in r.stdout


def test_apply_sync_rewrites_the_ground_truth(tmp_path, cpp_program):
    seq, f, _ = _folder(tmp_path)
    gt_before = read_table(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv", {17})
    r = run_eval("mocap-truth", seq, "--apply-sync", "--apply-thrust-lag")
    assert r.returncode == 0, r.stderr
    assert "applied: state_groundtruth_estimate0" in r.stdout and "applied: thrust0" in r.stdout
    gt = read_table(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv", {17})
    assert np.abs(gt.t_ns - (gt_before.t_ns - int(D_MOCAP_S * 1e9))).max() < 50_000   # within 50 us
    R_WI = Rotation.from_quat(gt.values[:, [4, 5, 6, 3]])
    truth = _attitude((gt_before.t_ns - int(D_MOCAP_S * 1e9) - T0_NS) * 1e-9)
    assert np.degrees((R_WI.inv() * truth).magnitude()).max() < 0.01
    again = tmp_path / "again.json"
    assert run_eval("mocap-truth", seq, "--json", again).returncode == 0
    doc = json.loads(again.read_text())
    assert abs(doc["mocap_minus_imu_s"]) < 5e-5 and doc["R_IM_angle_deg"] < 0.01
    assert abs(doc["thrust_minus_imu_s"]) < 1e-3
    info = subprocess.run([str(cpp_program("vid_info")), str(seq)], capture_output=True, text=True)
    assert info.returncode == 0, info.stderr and "force0" in info.stdout


def test_force_is_exact_on_a_quadratic_flight():
    """Quadratic position (central differences are exact), rotating body, no filter (cutoff at
    Nyquist): F_W = m (a - g) - R [0, 0, T] comes back to rounding."""
    t_ns = T0_NS + np.arange(1000, dtype=np.int64) * 5_000_000
    t = (t_ns - T0_NS) * 1e-9
    a_W = np.array([0.3, -0.2, 0.1])
    p = np.array([1.0, 2.0, 1.5]) + np.outer(t, [0.5, -0.1, 0.2]) + 0.5 * np.outer(t ** 2, a_W)
    R = _attitude(t)
    T = 9.0 + np.sin(t)
    q = R.as_quat()[:, [3, 0, 1, 2]]
    ft = force_truth(t_ns, p, q, t_ns, MASS * T, MASS, G, cutoff_hz=100.0)
    F = MASS * (a_W + [0, 0, G]) - MASS * R.apply(np.column_stack([0 * T, 0 * T, T]))
    kept = np.isin(t_ns, ft.t_ns)
    # no truth within 3 / cutoff = 30 ms of either end (the filter's edges), all rows in between
    assert ft.t_ns[0] - t_ns[0] >= 30_000_000 and t_ns[-1] - ft.t_ns[-1] >= 30_000_000
    assert kept.sum() == len(ft.t_ns) >= len(t_ns) - 2 * 7
    np.testing.assert_allclose(ft.F_W, F[kept], atol=1e-8, rtol=0)


def test_force_truth_of_the_synthetic_flight(tmp_path):
    """The sinusoidal flight through the command (5 Hz default filter): force0 equals the flight's
    external force within 1 mN away from the filter's edges; force0 reads back with the loader."""
    seq, f, _ = _folder(tmp_path, d_mocap=0.0, R_IM=Rotation.identity(), d_thrust=0.0, drag=0.0)
    r = run_eval("mocap-truth", seq)
    assert r.returncode == 0, r.stderr
    F = load_force_gt(seq / "mav0" / "force0" / "data.csv")
    tau = (F.t_ns - T0_NS) * 1e-9
    R = _attitude(tau)
    amp, w = np.array([2.0, 1.5, 0.5]), np.array([0.4, 0.55, 0.7])
    a = -amp * w ** 2 * np.sin(w * tau[:, None])
    thrust = np.interp(F.t_ns - T0_NS, f.t_ns - T0_NS, f.accel[:, 2])  # the folder's thrust: a_z (no drag)
    expect = MASS * (a + [0, 0, G]) - MASS * R.apply(np.column_stack([0 * thrust, 0 * thrust, thrust]))
    inner = slice(200, -200)
    assert np.abs(F.values[inner] - expect[inner]).max() < 1e-3


def test_mocap_truth_errors_are_one_line(tmp_path):
    r = run_eval("mocap-truth", tmp_path / "nothing")
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1
    assert "not a dataset folder" in r.stderr
    r = run_eval("mocap-truth", tmp_path, "--cutoff", "-2")
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("missing", ["thrust0", "state_groundtruth_estimate0"])
def test_missing_stream_names_the_file(tmp_path, missing):
    import shutil

    seq, _, _ = _folder(tmp_path)
    shutil.rmtree(seq / "mav0" / missing)
    r = run_eval("mocap-truth", seq)
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1
    assert ("thrust0/ or rotor0/" if missing == "thrust0" else missing) in r.stderr


def test_stand_in_of_a_simulated_flight_round_trips_and_gives_its_force(tmp_path, cpp_program):
    """A vid_sim flight written as a foreign log (FRD IMU, NED mocap without velocity, thrust from
    the rotor speeds; python -m vid_eval.importer.standin), imported: the IMU and pose equal the
    simulator's; mocap-truth's force0 is within 1 % (RMS) of the simulator's force0."""
    from test_import_synth import run_import
    from vid_eval.importer.standin import write_standin
    from vid_eval.tools.loaders import load_imu

    sim = tmp_path / "sim"
    r = subprocess.run([str(cpp_program("vid_sim")), "--scenario", str(REPO / "config/sim/vid17_like_short.yaml"),
                        "--out", str(sim), "--features-only", "--duration", "8", "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    write_standin(sim, tmp_path / "log")
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", tmp_path / "log" / "source_map.yaml", "--mass", "3.1015",
                   "--imu-frame", "frd", "--world-frame", "ned")
    assert r.returncode == 0, r.stderr
    a, b = load_imu(sim / "mav0/imu0/data.csv"), load_imu(tmp_path / "out/mav0/imu0/data.csv")
    np.testing.assert_array_equal(a.t_ns, b.t_ns)
    np.testing.assert_array_equal(a.gyro, b.gyro)
    np.testing.assert_array_equal(a.accel, b.accel)
    ga = read_table(sim / "mav0/state_groundtruth_estimate0/data.csv", {17}).values
    gb = read_table(tmp_path / "out/mav0/state_groundtruth_estimate0/data.csv", {17}).values
    np.testing.assert_allclose(gb[:, 0:3], ga[:, 0:3], atol=1e-12)
    np.testing.assert_allclose(np.abs((gb[:, 3:7] * ga[:, 3:7]).sum(axis=1)), 1.0, atol=1e-12)
    r = run_eval("mocap-truth", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    F = load_force_gt(tmp_path / "out/mav0/force0/data.csv")
    T = load_force_gt(sim / "mav0/force0/data.csv")
    # force0 leaves out 3 / cutoff = 0.6 s at each end (the filter's edges): the rest, row for row
    assert np.isin(F.t_ns, T.t_ns).all() and len(F.t_ns) == np.sum((T.t_ns >= F.t_ns[0]) & (T.t_ns <= F.t_ns[-1]))
    assert F.t_ns[0] - T.t_ns[0] >= 600_000_000
    T_vals = T.values[np.isin(T.t_ns, F.t_ns)]
    err = np.sqrt(np.mean((F.values - T_vals) ** 2))
    assert err < 0.01 * np.sqrt(np.mean(T_vals ** 2)), err
