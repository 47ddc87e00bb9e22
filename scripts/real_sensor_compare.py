#!/usr/bin/env python3
"""A real flight next to simulated ones: IMU spectra, thrust-model error, drag, latency.

  scripts/real_sensor_compare.py --blackbird ../shared/realdata/blackbird_clover \\
      --sim fast_drag=/tmp/fast_drag --sim vid17_real_sensors=/tmp/vid17_real_sensors \\
      --out docs/results/real_sensors

Real flight: the Blackbird "clover" HDF5 pieces (README there: 100 Hz IMU in a z-down IMU
frame, `thrust` = mass-normalized collective thrust along -z, motion-capture pose/velocity).
Simulated: vid_sim folders (docs/formats.md §1); their thrust is what an estimator computes,
sum(k_i n_i^2) / m from rotor0 and the written vehicle.yaml, at the IMU stamps. Per data set:

* IMU spectrum: Welch one-sided PSD (2 s segments, Hann) of accelerometer and gyro; the level
  is the rms of sqrt(PSD) over 10-45 Hz (below the real IMU's 50 Hz Nyquist, above the motion).
* thrust-model error: accelerometer along the thrust axis minus the thrust (mean, std; and std
  after a 5 Hz low-pass of both).
* latency: the shift of the thrust that best matches the accelerometer along the thrust axis
  (both band-passed, 1 ms steps by linear interpolation), in two bands: 0.3-10 Hz (dominated
  by the slow motion, where vertical drag, in quadrature with the acceleration, shifts the
  phase too) and 2-20 Hz (the thrust's fast changes).
* drag: body force after thrust r = accel - thrust (5 Hz low-passed), per axis rms, the
  least-squares D of r = -D v_I + c, the residual rms after it.
* accel minus the motion-capture specific force R^T (dv/dt - g), both 5 Hz low-passed: std.

Writes OUT/imu_psd.png and OUT/summary.json and prints a Markdown table.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys

import numpy as np
from scipy import signal
from scipy.spatial.transform import Rotation

from vid_eval.tools.loaders import load_imu, load_rotor_speeds, load_vehicle
from vid_eval.tools.table_reader import read_table

BAND_HZ = (10.0, 45.0)
LOWPASS_HZ = 5.0


class Flight:
    """One flight on the IMU clock: accel/gyro [N,3] in I, thrust vector [N,3] in I
    (mass-normalized), body velocity v_I [N,3], specific force from the motion capture [N,3]."""

    def __init__(self, name, t, accel, gyro, thrust, v_I, sf_mocap):
        self.name, self.t, self.accel, self.gyro, self.thrust = name, t, accel, gyro, thrust
        self.v_I, self.sf_mocap = v_I, sf_mocap
        self.fs = (len(t) - 1) / (t[-1] - t[0])  # mean rate (stamps may jitter)
        axis = np.mean(thrust, axis=0)
        self.axis = axis / np.linalg.norm(axis)  # thrust direction in I (+z or -z)


def _specific_force(t, R_WI, v_W):
    a_W = np.gradient(v_W, t, axis=0)
    return np.einsum("nji,nj->ni", R_WI, a_W + np.array([0.0, 0.0, 9.81]))


def load_blackbird(root: pathlib.Path) -> Flight:
    import h5py  # only needed for the real flight

    parts = []
    for sub in ("test", "val", "train"):
        with h5py.File(root / sub / "data.hdf5", "r") as f:
            parts.append({k: np.asarray(f[k]) for k in ("ts", "accel_raw", "gyro_raw", "thrust")})
        gt = np.loadtxt(root / sub / "stamped_groundtruth_imu.txt")
        parts[-1]["gt"] = gt
    parts.sort(key=lambda p: p["ts"][0])
    cat = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    gt = cat["gt"]
    if np.max(np.abs(gt[:, 0] - cat["ts"])) > 1e-6:
        sys.exit("blackbird: ground truth is not on the IMU times")
    R_WI = Rotation.from_quat(gt[:, 4:8]).as_matrix()  # qx qy qz qw
    v_W = gt[:, 8:11]
    v_I = np.einsum("nji,nj->ni", R_WI, v_W)
    return Flight("Blackbird clover (real)", cat["ts"], cat["accel_raw"], cat["gyro_raw"], cat["thrust"], v_I,
                  _specific_force(cat["ts"], R_WI, v_W))


def load_sim(name: str, root: pathlib.Path) -> Flight:
    mav = root / "mav0"
    imu = load_imu(mav / "imu0" / "data.csv")
    veh = load_vehicle(mav / "vehicle.yaml")
    rot = load_rotor_speeds(mav / "rotor0" / "data.csv", len(veh.rotor_thrust_coefficients))
    t = imu.t_ns.astype(np.float64) * 1e-9
    T = rot.values ** 2 @ np.asarray(veh.rotor_thrust_coefficients) / veh.mass_kg
    thrust_z = np.interp(t, rot.t_ns.astype(np.float64) * 1e-9, T)
    thrust = np.zeros((len(t), 3))
    thrust[:, 2] = thrust_z
    gt = read_table(mav / "state_groundtruth_estimate0" / "data.csv", {17}, what="ground truth")
    tg = gt.t_ns.astype(np.float64) * 1e-9
    R_WI = Rotation.from_quat(gt.values[:, [4, 5, 6, 3]]).as_matrix()  # file: qw qx qy qz
    v_W = gt.values[:, 7:10]
    sf = _specific_force(tg, R_WI, v_W)
    v_I = np.einsum("nji,nj->ni", R_WI, v_W)
    interp = lambda x: np.stack([np.interp(t, tg, x[:, i]) for i in range(3)], axis=1)  # noqa: E731
    keep = (t > tg[0] + 0.5) & (t < tg[-1] - 0.5) & (t > t[0] + 3.0)  # skip the hover start
    return Flight(name, t[keep], imu.accel[keep], imu.gyro[keep], thrust[keep], interp(v_I)[keep],
                  interp(sf)[keep])


def lowpass(x, fs, hz=LOWPASS_HZ):
    sos = signal.butter(4, hz, fs=fs, output="sos")
    return signal.sosfiltfilt(sos, x, axis=0)


def psd(x, fs):
    f, P = signal.welch(x, fs=fs, nperseg=int(round(2.0 * fs)), axis=0)
    return f, P


def band_level(f, P):
    m = (f >= BAND_HZ[0]) & (f <= BAND_HZ[1])
    return np.sqrt(np.mean(P[m], axis=0))


def latency_s(fl: Flight, band) -> float:
    sos = signal.butter(2, list(band), btype="band", fs=fl.fs, output="sos")
    a = signal.sosfiltfilt(sos, fl.accel @ fl.axis)
    th = signal.sosfiltfilt(sos, fl.thrust @ fl.axis)
    best, best_c = 0.0, -np.inf
    for lag in np.arange(-0.12, 0.1201, 0.001):  # thrust(t + lag) against accel(t)
        c = np.corrcoef(a, np.interp(fl.t + lag, fl.t, th))[0, 1]
        if c > best_c:
            best, best_c = lag, c
    return float(best)


def analyse(fl: Flight) -> dict:
    out = {"name": fl.name, "rate_hz": round(fl.fs, 1), "duration_s": round(fl.t[-1] - fl.t[0], 1)}
    f, Pa = psd(fl.accel, fl.fs)
    _, Pg = psd(fl.gyro, fl.fs)
    out["accel_psd_10_45"] = band_level(f, Pa).tolist()
    out["gyro_psd_10_45"] = band_level(f, Pg).tolist()
    err = fl.accel @ fl.axis - fl.thrust @ fl.axis
    out["thrust_err_mean"] = float(np.mean(err))
    out["thrust_err_std"] = float(np.std(err))
    out["thrust_err_std_45hz"] = float(np.std(lowpass(err, fl.fs, min(BAND_HZ[1], 0.45 * fl.fs))))
    out["thrust_err_std_lp"] = float(np.std(lowpass(err, fl.fs)))
    out["latency_s"] = latency_s(fl, (0.3, 10.0))
    out["latency_fast_s"] = latency_s(fl, (2.0, 20.0))
    r = lowpass(fl.accel - fl.thrust, fl.fs)
    v = lowpass(fl.v_I, fl.fs)
    D, resid = [], []
    for i in range(3):
        A = np.stack([-v[:, i], np.ones(len(v))], axis=1)
        sol, *_ = np.linalg.lstsq(A, r[:, i], rcond=None)
        D.append(float(sol[0]))
        resid.append(float(np.std(r[:, i] - A @ sol)))
    out["body_force_rms"] = np.sqrt(np.mean((r - r.mean(0)) ** 2, axis=0)).tolist()
    out["drag_D"] = D
    out["drag_residual_rms"] = resid
    out["speed_median"] = float(np.median(np.linalg.norm(fl.v_I, axis=1)))
    out["accel_minus_mocap_std_lp"] = np.std(lowpass(fl.accel, fl.fs) - lowpass(fl.sf_mocap, fl.fs), axis=0).tolist()
    out["_psd"] = (f, Pa, Pg)
    return out


def plot(results, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 3, figsize=(14, 7), sharex=True)
    for res in results:
        f, Pa, Pg = res["_psd"]
        for i in range(3):
            axes[0, i].semilogy(f[1:], np.sqrt(Pa[1:, i]), lw=0.8, label=res["name"])
            axes[1, i].semilogy(f[1:], np.sqrt(Pg[1:, i]), lw=0.8, label=res["name"])
    for i, a in enumerate("xyz"):
        axes[0, i].set_title(f"accelerometer {a}")
        axes[1, i].set_title(f"gyroscope {a}")
        axes[1, i].set_xlabel("frequency [Hz]")
        for row in range(2):
            axes[row, i].axvspan(*BAND_HZ, color="0.9", zorder=0)
            axes[row, i].grid(True, which="both", lw=0.3)
    axes[0, 0].set_ylabel("sqrt(PSD) [m/s²/√Hz]")
    axes[1, 0].set_ylabel("sqrt(PSD) [rad/s/√Hz]")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle("IMU spectra, one-sided Welch (grey: the 10-45 Hz band of the table)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def fmt3(v, p=3):
    return " / ".join(f"{x:.{p}g}" for x in v)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--blackbird", type=pathlib.Path, required=True, help="blackbird_clover folder")
    ap.add_argument("--sim", action="append", default=[], help="NAME=vid_sim output folder (repeatable)")
    ap.add_argument("--out", type=pathlib.Path, required=True)
    args = ap.parse_args()
    flights = [load_blackbird(args.blackbird)]
    for s in args.sim:
        if "=" not in s:
            ap.error(f"--sim: expected NAME=FOLDER, got '{s}'")
        name, folder = s.split("=", 1)
        flights.append(load_sim(name, pathlib.Path(folder)))
    results = [analyse(f) for f in flights]
    args.out.mkdir(parents=True, exist_ok=True)
    plot(results, args.out / "imu_psd.png")
    with open(args.out / "summary.json", "w") as fh:
        json.dump([{k: v for k, v in r.items() if not k.startswith("_")} for r in results], fh, indent=1)
    print("| data | rate | accel sqrt(PSD) 10-45 Hz x/y/z | gyro sqrt(PSD) | thrust err mean / std / <45 Hz / <5 Hz "
          "| latency 0.3-10 / 2-20 Hz | body force rms x/y/z | drag D x/y/z | residual rms | accel - mocap std (5 Hz) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        print(f"| {r['name']} | {r['rate_hz']:.0f} Hz | {fmt3(r['accel_psd_10_45'])} | {fmt3(r['gyro_psd_10_45'])} | "
              f"{r['thrust_err_mean']:.2f} / {r['thrust_err_std']:.2f} / {r['thrust_err_std_45hz']:.2f} / "
              f"{r['thrust_err_std_lp']:.2f} | {r['latency_s'] * 1e3:.0f} / {r['latency_fast_s'] * 1e3:.0f} ms | {fmt3(r['body_force_rms'], 2)} | {fmt3(r['drag_D'], 2)} | "
              f"{fmt3(r['drag_residual_rms'], 2)} | {fmt3(r['accel_minus_mocap_std_lp'], 2)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
