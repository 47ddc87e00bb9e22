"""A stand-in for a log that is not a bag, made from a simulated dataset folder (``vid_sim``
output), for docs/own-vehicle.md: the same flight written the way other rigs log it.

    python -m vid_eval.importer.standin SIM_FOLDER LOG_FOLDER

writes ``imu.csv`` (seconds; FRD IMU: y and z of gyro and accelerometer negated),
``thrust.csv`` (nanoseconds; the collective thrust sum k_i n_i^2 of rotor0 and vehicle.yaml,
mass-normalized, along the FRD z axis, so negative), ``mocap.csv`` (seconds, blank separated;
NED world, quaternion x y z w of the FRD body, no velocity) and ``source_map.yaml`` for them.
Importing it with ``--imu-frame frd --world-frame ned`` gives back the simulator's IMU and
pose (the simulator's world W, z up, is taken as the ENU of the NED conversion).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from ..tools.loaders import load_imu, load_rotor_speeds, load_vehicle
from ..tools.table_reader import read_table

FRD = np.diag([1.0, -1.0, -1.0])
NED_FROM_ENU = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])

MAP = """\
# vid-import source map of the stand-in log (python -m vid_eval.importer.standin)
imu:
  file: imu.csv
  time: t
  time_unit: s
  gyro: [gx, gy, gz]          # rad/s, FRD
  accel: [ax, ay, az]         # m/s^2, FRD
thrust:
  file: thrust.csv
  time: t_ns
  time_unit: ns
  thrust: thrust_z            # collective thrust along the IMU's z (down): negative
  unit: m/s^2
mocap:
  file: mocap.csv
  time: 0                     # no header line: 0-based column numbers
  time_unit: s
  position: [1, 2, 3]         # NED
  quaternion: [4, 5, 6, 7]
  quaternion_order: xyzw
"""


def _seconds(t_ns: np.ndarray) -> list:
    return [f"{int(t) // 10**9}.{int(t) % 10**9:09d}" for t in t_ns]


def write_standin(sim: Path, out: Path) -> None:
    mav0 = sim / "mav0"
    imu = load_imu(mav0 / "imu0" / "data.csv")
    vehicle = load_vehicle(mav0 / "vehicle.yaml")
    rotors = load_rotor_speeds(mav0 / "rotor0" / "data.csv")
    gt = read_table(mav0 / "state_groundtruth_estimate0" / "data.csv", {17})
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "imu.csv", "w", encoding="utf-8") as f:
        f.write("t,gx,gy,gz,ax,ay,az\n")
        for t, g, a in zip(_seconds(imu.t_ns), imu.gyro @ FRD, imu.accel @ FRD):
            f.write(",".join([t, *(repr(float(x)) for x in (*g, *a))]) + "\n")
    thrust = (rotors.values ** 2) @ np.asarray(vehicle.rotor_thrust_coefficients) / vehicle.mass_kg
    with open(out / "thrust.csv", "w", encoding="utf-8") as f:
        f.write("t_ns,thrust_z\n")
        for t, x in zip(rotors.t_ns.tolist(), (-thrust).tolist()):
            f.write(f"{t},{x!r}\n")
    R = Rotation.from_matrix(NED_FROM_ENU) * Rotation.from_quat(gt.values[:, [4, 5, 6, 3]]) * Rotation.from_matrix(FRD)
    p = gt.values[:, 0:3] @ NED_FROM_ENU.T
    with open(out / "mocap.csv", "w", encoding="utf-8") as f:
        for t, pp, q in zip(_seconds(gt.t_ns), p, R.as_quat()):
            f.write(" ".join([t, *(repr(float(x)) for x in (*pp, *q))]) + "\n")
    (out / "source_map.yaml").write_text(MAP, encoding="utf-8")
    print(f"wrote {out}: imu.csv (FRD), thrust.csv, mocap.csv (NED), source_map.yaml; mass {vehicle.mass_kg:g} kg")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print("usage: python -m vid_eval.importer.standin SIM_FOLDER LOG_FOLDER", file=sys.stderr)
        sys.exit(2)
    write_standin(Path(sys.argv[1]), Path(sys.argv[2]))
