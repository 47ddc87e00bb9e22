"""vid-import --sync: the mocap clock offset and the IMU-mocap rotation (vid-eval mocap-truth's
measurement, imported from it) are applied before the ground truth and the synthetic features are
written, so that the synthetic camera is rigidly attached to the IMU, as a calibrated camera is,
not to the mocap body (0.74 deg off the IMU on the Blackbird flight)."""
from __future__ import annotations

import numpy as np
import yaml
from scipy.spatial.transform import Rotation

from test_import_synth import MASS, _attitude, csv_map, flight, run_import, time_column
from vid_eval.core.geometry import lerp, rot_from_wxyz, slerp_wxyz
from vid_eval.tools.table_reader import read_table

D_MOCAP_S = 0.0073   # mocap stamps late by 7.3 ms
R_IM = Rotation.from_rotvec(np.radians(2.0) * np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]))


def _log(folder, seconds=12.0):
    """imu.csv of the synthetic flight (FLU, ENU) and mocap.csv of a body M with R_WM = R_WI R_IM,
    stamped D_MOCAP_S late (100 Hz, off the IMU grid)."""
    f = flight(seconds=seconds)
    folder.mkdir(parents=True)
    tt = time_column(f.t_ns, "ns")
    with open(folder / "imu.csv", "w") as fh:
        fh.write("# t,wx,wy,wz,ax,ay,az,thrust\n")
        for i in range(f.t_ns.size):
            fh.write(",".join([tt[i], *map(repr, f.gyro[i].tolist()), *map(repr, f.accel[i].tolist()),
                               repr(float(f.thrust[i]))]) + "\n")
    t0 = int(f.t_ns[0])
    tau_ns = t0 + 1_700_000 + np.arange(int(seconds * 100) - 2, dtype=np.int64) * 10_000_000
    tau = (tau_ns - t0) * 1e-9
    R_WM = _attitude(tau) * R_IM
    amp, w = np.array([2.0, 1.5, 0.5]), np.array([0.4, 0.55, 0.7])
    p = amp * np.sin(w * tau[:, None]) + [0, 0, 1.5]
    v = amp * w * np.cos(w * tau[:, None])
    q = R_WM.as_quat()[:, [3, 0, 1, 2]]
    stamps = time_column(tau_ns + int(round(D_MOCAP_S * 1e9)), "ns")
    with open(folder / "mocap.csv", "w") as fh:
        fh.write("time x y z qw qx qy qz vx vy vz\n")
        for i in range(tau.size):
            fh.write(" ".join([stamps[i], *map(repr, np.concatenate([p[i], q[i], v[i]]).tolist())]) + "\n")
    return csv_map(folder / "map.yaml", unit="ns")


def _reprojection_px(mav0, t_gt, p_W, q_wxyz):
    """|observed - projected| of every cam0 feature with the poses given (interpolated to the
    frame times) and cam0's sensor.yaml."""
    cam = yaml.safe_load((mav0 / "cam0" / "sensor.yaml").read_text())
    T_IC = np.array(cam["T_BS"]["data"], float).reshape(4, 4)
    fu, fv, cu, cv = cam["intrinsics"]
    feat = read_table(mav0 / "feat0" / "data.csv", {5}, repeated_times=True)
    lm = np.loadtxt(mav0 / "landmarks.csv", delimiter=",", comments="#")
    where = {int(i): row for i, row in zip(lm[:, 0], lm[:, 1:])}
    sel = (feat.values[:, 0] == 0) & (feat.t_ns >= t_gt[0]) & (feat.t_ns <= t_gt[-1])
    t = feat.t_ns[sel]
    ids, uv = feat.values[sel, 1].astype(int), feat.values[sel, 2:4]
    R_WI = rot_from_wxyz(slerp_wxyz(t_gt, q_wxyz, t))
    p_I = R_WI.inv().apply(np.array([where[i] for i in ids]) - lerp(t_gt, p_W, t))
    p_C = (p_I - T_IC[:3, 3]) @ T_IC[:3, :3]
    proj = np.column_stack([fu * p_C[:, 0] / p_C[:, 2] + cu, fv * p_C[:, 1] / p_C[:, 2] + cv])
    return np.linalg.norm(proj - uv, axis=1)


def test_sync_puts_the_features_on_the_imu(tmp_path, cpp_program):
    smap = _log(tmp_path / "log")
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", smap, "--mass", MASS, "--sync",
                   "--synthetic-features", "--vid-sim", cpp_program("vid_sim"))
    assert r.returncode == 0, r.stderr
    assert "applied: state_groundtruth_estimate0: stamps -7.3" in r.stdout
    mav0 = tmp_path / "out" / "mav0"
    gt = read_table(mav0 / "state_groundtruth_estimate0" / "data.csv", {17})
    # The written ground truth is the IMU's: R_WI = R_WM R_IM^T, mocap stamps - offset.
    t_true = (gt.t_ns - gt.t_ns[0]) * 1e-9 + (gt.t_ns[0] - int(flight(seconds=0.01).t_ns[0])) * 1e-9
    err = np.degrees((rot_from_wxyz(gt.values[:, 3:7]) * _attitude(t_true).inv()).magnitude())
    assert err.max() < 0.02, err.max()
    synced = _reprojection_px(mav0, gt.t_ns, gt.values[:, 0:3], gt.values[:, 3:7])
    assert synced.size > 1000
    # pixel noise 0.5 px per axis: the median of |e| is 0.5 * 1.18 = 0.59 px
    print(f"[sync] reprojection with the synced poses: median {np.median(synced):.3f} px, "
          f"95 % {np.percentile(synced, 95):.3f} px")
    assert np.median(synced) < 0.75 and np.percentile(synced, 95) < 1.5
    # The same features against the mocap body's poses are off by the 2 deg rotation: the check
    # above can fail.
    q_WM = (rot_from_wxyz(gt.values[:, 3:7]) * R_IM).as_quat()[:, [3, 0, 1, 2]]
    assert np.median(_reprojection_px(mav0, gt.t_ns, gt.values[:, 0:3], q_WM)) > 5.0


def test_without_sync_the_features_follow_the_mocap_body(tmp_path, cpp_program):
    """What --sync fixes: without it the ground truth and the camera are the mocap body's, 2 deg
    off the IMU whose gyro the estimator integrates."""
    smap = _log(tmp_path / "log", seconds=6.0)
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", smap, "--mass", MASS, "--synthetic-features",
                   "--vid-sim", cpp_program("vid_sim"))
    assert r.returncode == 0, r.stderr
    assert "applied:" not in r.stdout
    gt = read_table(tmp_path / "out" / "mav0" / "state_groundtruth_estimate0" / "data.csv", {17})
    t_true = (gt.t_ns - int(flight(seconds=0.01).t_ns[0])) * 1e-9 - D_MOCAP_S
    err = np.degrees((rot_from_wxyz(gt.values[:, 3:7]) * _attitude(t_true).inv()).magnitude())
    assert np.median(err) > 1.9


def test_sync_needs_the_mocap(tmp_path):
    f = flight(seconds=2.0)
    (tmp_path / "log").mkdir()
    tt = time_column(f.t_ns, "s")
    with open(tmp_path / "log" / "imu.csv", "w") as fh:
        fh.write("# t,wx,wy,wz,ax,ay,az\n")
        for i in range(f.t_ns.size):
            fh.write(",".join([tt[i], *map(repr, f.gyro[i].tolist()), *map(repr, f.accel[i].tolist())]) + "\n")
    (tmp_path / "m.yaml").write_text("imu: {file: imu.csv, time: t, time_unit: s, gyro: [wx, wy, wz], "
                                     "accel: [ax, ay, az]}\n")
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", tmp_path / "m.yaml", "--mass", MASS, "--sync")
    assert r.returncode == 2 and r.stderr.strip() == ("vid-import: error: --sync needs the mocap poses "
                                                      "(a 'mocap' stream in the map)")
