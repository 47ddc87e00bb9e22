"""One known flight in the project's frames (world ENU z up, IMU FLU), and the same flight written
as a log in any convention (IMU FLU/FRD, world ENU/NWU/NED, quaternion order, time unit, CSV or
HDF5, in pieces), for the vid-import and mocap-truth tests. The frame maps here are written out
axis by axis, independently of vid_eval.importer.frames."""
from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from conftest import REPO

G = 9.81
MASS = 1.3
T0_NS = 1_700_000_000_123_456_000   # on a microsecond grid: exact in every time unit
F_EXT_W = np.array([0.4, -0.25, 0.15])  # N, a constant wind in W

# v_src = M v_flu / M v_enu, axis by axis
BODY = {"flu": np.eye(3), "frd": np.array([[1, 0, 0], [0, -1, 0], [0, 0, -1]], float)}
WORLD = {"enu": np.eye(3),
         "nwu": np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1]], float),   # north = y_enu, west = -x_enu
         "ned": np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1]], float)}   # north, east, down


@dataclass
class Flight:
    t_ns: np.ndarray
    p: np.ndarray       # p_WI
    R: Rotation         # R_WI
    v: np.ndarray
    a: np.ndarray       # a_W
    gyro: np.ndarray    # w_I
    accel: np.ndarray   # R^T (a - g)
    thrust: np.ndarray  # mass-normalized, along body z
    force_W: np.ndarray  # the external force that results, m (a - g) - m R [0, 0, thrust]  [N]

    def q_wxyz(self) -> np.ndarray:
        q = self.R.as_quat()[:, [3, 0, 1, 2]]
        return q * np.sign(q[:, :1])


def _attitude(t):
    return Rotation.from_euler("ZYX", np.column_stack([0.8 * np.sin(0.31 * t) + 0.2 * t,
                                                       0.35 * np.sin(1.3 * t + 0.4),
                                                       0.3 * np.sin(1.7 * t)]))


def flight(seconds: float = 20.0, rate_hz: float = 200.0, t0_ns: int = T0_NS) -> Flight:
    """Smooth sinusoidal flight; body rates by a tiny central difference of the attitude (error
    ~1e-10 rad/s); the thrust balances the body-z part of the motion against a wind F_EXT_W, and
    the external force is what thrust and gravity leave (the wind plus the lateral remainder)."""
    n = int(seconds * rate_hz)
    t_ns = t0_ns + np.arange(n, dtype=np.int64) * int(round(1e9 / rate_hz))
    t = (t_ns - t0_ns) * 1e-9
    w = np.array([0.4, 0.55, 0.7])
    amp = np.array([2.0, 1.5, 0.5])
    p = amp * np.sin(w * t[:, None]) + np.array([0.0, 0.0, 1.5])
    v = amp * w * np.cos(w * t[:, None])
    a = -amp * w ** 2 * np.sin(w * t[:, None])
    R = _attitude(t)
    h = 1e-5
    gyro = (_attitude(t - h).inv() * _attitude(t + h)).as_rotvec() / (2 * h)
    spec_W = a - np.array([0.0, 0.0, -G])
    accel = R.inv().apply(spec_W)
    # F = m (a - g) - R [0, 0, T]: thrust = body-z component of (a - g) - F/m
    thrust = R.inv().apply(spec_W - F_EXT_W / MASS)[:, 2]
    force_W = MASS * spec_W - MASS * R.apply(np.column_stack([0 * thrust, 0 * thrust, thrust]))
    return Flight(t_ns, p, R, v, a, gyro, accel, thrust, force_W)


def time_column(t_ns: np.ndarray, unit: str):
    """Text of the stamps in a unit (exact: the stamps are on a microsecond grid)."""
    if unit == "ns":
        return [str(int(x)) for x in t_ns]
    if unit == "us":
        return [str(int(x) // 1000) for x in t_ns]
    return [f"{int(x) // 10**9}.{int(x) % 10**9:09d}" for x in t_ns]


def source_arrays(f: Flight, imu: str, world: str, order: str):
    """The flight as the log would hold it."""
    B, W = BODY[imu], WORLD[world]
    R_src = Rotation.from_matrix(W) * f.R * Rotation.from_matrix(B.T)
    q = R_src.as_quat()
    q = q[:, [3, 0, 1, 2]] if order == "wxyz" else q
    thrust_vec = np.column_stack([np.zeros_like(f.thrust), np.zeros_like(f.thrust), f.thrust]) @ B.T
    return {"gyro": f.gyro @ B.T, "accel": f.accel @ B.T, "thrust": thrust_vec[:, 2],
            "pos": f.p @ W.T, "vel": f.v @ W.T, "quat": q}


def write_csv_log(folder: Path, f: Flight, imu="flu", world="enu", order="wxyz", unit="s",
                  rows=slice(None), with_velocity=True) -> None:
    """imu.csv (t, gyro, accel, thrust) and mocap.csv (t, p, q[, v]) with headers."""
    folder.mkdir(parents=True, exist_ok=True)
    s = source_arrays(f, imu, world, order)
    tt = time_column(f.t_ns, unit)
    idx = np.arange(f.t_ns.size)[rows]
    with open(folder / "imu.csv", "w") as fh:
        fh.write("# t,wx,wy,wz,ax,ay,az,thrust\n")
        for i in idx:
            fh.write(",".join([tt[i], *(repr(float(x)) for x in s["gyro"][i]), *(repr(float(x)) for x in s["accel"][i]),
                               repr(float(s["thrust"][i]))]) + "\n")
    qn = ["qw", "qx", "qy", "qz"] if order == "wxyz" else ["qx", "qy", "qz", "qw"]
    with open(folder / "mocap.csv", "w") as fh:
        fh.write("time x y z " + " ".join(qn) + (" vx vy vz" if with_velocity else "") + "\n")
        for i in idx:
            vals = [*s["pos"][i], *s["quat"][i], *(s["vel"][i] if with_velocity else [])]
            fh.write(" ".join([tt[i], *(repr(float(x)) for x in vals)]) + "\n")


def csv_map(path: Path, order="wxyz", unit="s", pieces=None, with_velocity=True, thrust_unit="m/s^2") -> Path:
    qn = ["qw", "qx", "qy", "qz"] if order == "wxyz" else ["qx", "qy", "qz", "qw"]
    text = (f"pieces: {pieces!r}\n" if pieces else "") + (
        f"imu: {{file: imu.csv, time: t, time_unit: {unit}, gyro: [wx, wy, wz], accel: [ax, ay, az]}}\n"
        f"thrust: {{file: imu.csv, time: t, time_unit: {unit}, thrust: thrust, unit: {thrust_unit!r}}}\n"
        f"mocap: {{file: mocap.csv, time: time, time_unit: {unit}, position: [x, y, z], "
        f"quaternion: [{', '.join(qn)}], quaternion_order: {order}"
        + (", velocity: [vx, vy, vz]" if with_velocity else "") + "}\n")
    path.write_text(text)
    return path


def write_hdf5_log(folder: Path, f: Flight, imu="frd", world="enu", order="xyzw", int_ns=False) -> Path:
    """data.h5 with 2-D datasets (as Blackbird's) and float seconds or int64 ns."""
    import h5py

    folder.mkdir(parents=True, exist_ok=True)
    s = source_arrays(f, imu, world, order)
    with h5py.File(folder / "data.h5", "w") as h:
        h["t"] = f.t_ns if int_ns else f.t_ns * 1e-9
        h["imu/gyro"] = s["gyro"]
        h["imu/accel"] = s["accel"]
        h["thrust"] = np.column_stack([np.zeros((f.t_ns.size, 2)), s["thrust"]])
        h["mocap/p"] = s["pos"]
        h["mocap/q"] = s["quat"]
    return folder / "data.h5"


def hdf5_map(path: Path, order="xyzw", unit="s") -> Path:
    path.write_text(
        f"imu: {{file: data.h5, time: t, time_unit: {unit}, gyro: imu/gyro, accel: imu/accel}}\n"
        f"thrust: {{file: data.h5, time: t, time_unit: {unit}, thrust: thrust}}\n"
        f"mocap: {{file: data.h5, time: t, time_unit: {unit}, position: mocap/p, quaternion: mocap/q, "
        f"quaternion_order: {order}}}\n")
    return path


def run_import(*args, cwd=None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": f"{REPO / 'eval'}:{os.environ.get('PYTHONPATH', '')}"}
    return subprocess.run([sys.executable, "-m", "vid_eval.importer", *map(str, args)], capture_output=True,
                          text=True, env=env, cwd=cwd)


def run_eval(*args) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": f"{REPO / 'eval'}:{os.environ.get('PYTHONPATH', '')}"}
    return subprocess.run([sys.executable, "-m", "vid_eval.cli", *map(str, args)], capture_output=True,
                          text=True, env=env)


def test_the_synthetic_flight_is_consistent():
    """The helper's own check: gyro integrates to the attitude, thrust leaves F_EXT_W."""
    f = flight(seconds=4.0)
    dt = 5e-3
    R_next = f.R[:-1] * Rotation.from_rotvec(0.5 * (f.gyro[:-1] + f.gyro[1:]) * dt)
    assert np.degrees((R_next.inv() * f.R[1:]).magnitude()).max() < 1e-3
    F_I = f.R.inv().apply(f.force_W)
    assert np.abs(F_I[:, 2] - f.R.inv().apply(np.tile(F_EXT_W, (len(F_I), 1)))[:, 2]).max() < 1e-9
    assert np.abs(f.accel[:, 2] - f.thrust - F_I[:, 2] / MASS).max() < 1e-9
    assert f.thrust.min() > 5.0
