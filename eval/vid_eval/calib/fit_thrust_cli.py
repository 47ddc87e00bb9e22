"""``vid-fit-thrust``: fit the rotor thrust coefficients of vehicle.yaml from a flight log.

Reads a dataset folder (docs/formats.md §1; a rosbag converted with vid-bag2asl is one):
``imu0`` (the body-z specific force), ``rotor0`` (speeds and their unit), ``vehicle.yaml``
(the mass the estimator divides by), and when present the ground truth (accelerometer bias
for ``--bias groundtruth``) and ``force0`` (an external force, subtracted); for per-rotor
coefficients also ``--geometry`` (rotor layout and inertia: the gyroscope's torque balance
separates the rotors, :mod:`vid_eval.calib.torque_rows`). Prints the
coefficients with their 1-sigma and the residual RMS, writes a vehicle.yaml (``--out``) and a
residual plot (``--plot``). The model and solver: :mod:`vid_eval.calib.thrust_fit`.

Errors: one line ``vid-fit-thrust: error: ...`` naming the file or flag; exit 2 for usage
errors, 1 for bad data.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import List, Optional

import numpy as np

from ..errors import VidEvalError
from ..usage import OneLineParser
from .cli_errors import run_reporting_errors
from . import dataset as ds
from .thrust_fit import BIAS_MODES, MODELS, FitInput, fit_thrust, regressors, residuals_with
from .torque_rows import WINDOW_S, load_geometry, torque_rows

PROG = "vid-fit-thrust"


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog=PROG,
        description="Fit the rotor thrust coefficients k_i (T_i = k_i n_i^2) of vehicle.yaml from a "
                    "hover / vertical-step log: the estimator's model a_z = sum k_i n_i^2 / m + b_z.")
    p.add_argument("dataset", help="dataset folder (SEQ or SEQ/mav0) with imu0, rotor0 and vehicle.yaml")
    p.add_argument("--model", choices=MODELS, default="collective",
                   help="one k for all rotors, or one per rotor (needs --geometry, or roll/pitch/yaw "
                        "accelerations in the log; default: collective)")
    p.add_argument("--geometry", metavar="FILE.yaml",
                   help="per-rotor: the vehicle's layout (x/plus), arm_length_m, rotor_directions, "
                        "torque_to_thrust_m and inertia_diag, top level or under vehicle: (a vid_sim "
                        "scenario is one); adds the gyroscope's torque balance to the fit")
    p.add_argument("--bias", choices=BIAS_MODES, default="fit",
                   help="accelerometer bias along z: fit a constant (default), take the ground truth's, or none")
    p.add_argument("--mass", type=float, metavar="KG", help="vehicle mass [kg] (default: vehicle.yaml mass_kg)")
    p.add_argument("--start", type=float, default=0.0, metavar="S",
                   help="use data from S seconds after the first IMU sample (default 0)")
    p.add_argument("--end", type=float, metavar="S", help="... up to S seconds (default: the end)")
    p.add_argument("--min-thrust-fraction", type=float, default=0.25, metavar="F",
                   help="drop samples whose sum n_i^2 is below F times its median (ground, idle, "
                        "spin-up; default 0.25)")
    p.add_argument("--out", metavar="FILE", help="write the fitted vehicle.yaml here")
    p.add_argument("--plot", metavar="FILE.png", help="write the residual plot here")
    return p


def _check_flags(p: argparse.ArgumentParser, a: argparse.Namespace) -> None:
    if a.mass is not None and not (a.mass > 0 and np.isfinite(a.mass)):
        p.error(f"--mass: expected a positive mass in kg, got {a.mass:g}")
    if not (a.start >= 0 and np.isfinite(a.start)):
        p.error(f"--start: expected seconds >= 0, got {a.start:g}")
    if a.end is not None and not (a.end > a.start and np.isfinite(a.end)):
        p.error(f"--end: expected seconds after --start ({a.start:g}), got {a.end:g}")
    if not 0.0 <= a.min_thrust_fraction < 1.0:
        p.error(f"--min-thrust-fraction: expected a fraction in [0, 1), got {a.min_thrust_fraction:g}")
    if a.geometry is not None and a.model != "per-rotor":
        p.error("--geometry: only used with --model per-rotor")
    if a.plot is not None and not a.plot.lower().endswith(".png"):
        p.error(f"--plot: expected a .png file name, got '{a.plot}'")


def vehicle_yaml(k: np.ndarray, mass: float, gravity: float, unit: str, comment: List[str]) -> str:
    """The fitted vehicle.yaml (docs/formats.md §1 keys; io's strict loader reads it)."""
    coeffs = ", ".join(f"{c:.6e}" for c in k)
    lines = [f"# {c}" for c in comment]
    lines += [f"mass_kg: {mass:.6g}", f"gravity: {gravity:.6g}",
              f"rotor_thrust_coefficients: [{coeffs}]   # N / ({unit})^2, T_i = k_i n_i^2"]
    return "\n".join(lines) + "\n"


def run(args: argparse.Namespace) -> int:
    mav0 = ds.find_mav0(args.dataset)
    imu = ds.imu(mav0)
    rotors, unit = ds.rotor_speeds(mav0)
    veh, mass, mass_src = ds.vehicle(mav0, args.mass)
    gt = ds.groundtruth(mav0)
    t_rel = (imu.t_ns - imu.t_ns[0]) * 1e-9
    window = (t_rel >= args.start) & (t_rel <= (args.end if args.end is not None else np.inf))
    if not window.any():
        raise VidEvalError(f"{mav0 / 'imu0' / 'data.csv'}: no IMU sample between --start {args.start:g} s and "
                           f"--end {args.end if args.end is not None else 'the end'} (log spans {t_rel[-1]:.3f} s)")
    t_ns, accel_z = imu.t_ns[window], imu.accel[window, 2]
    force_z = ds.external_force_z(mav0, gt, t_ns, mass)
    if force_z is not None:  # the log's known external force (force0) is no thrust
        accel_z = accel_z - force_z
    keep, speed_sq = regressors(t_ns, accel_z, rotors.t_ns, rotors.values, args.min_thrust_fraction)
    if keep.sum() == 0:
        raise VidEvalError(f"{rotors.path}: no IMU sample inside the rotor stream with thrust in the window")
    bias_z = ds.groundtruth_accel_bias_z(gt, t_ns[keep]) if args.bias == "groundtruth" and gt is not None else None
    if args.bias == "groundtruth" and gt is None:
        raise VidEvalError(f"{mav0}: --bias groundtruth needs state_groundtruth_estimate0/data.csv")
    data = FitInput(t_ns[keep], accel_z[keep], speed_sq[keep], bias_z)
    torque = None
    if args.geometry is not None:
        geometry = load_geometry(Path(args.geometry), speed_sq.shape[1])
        torque = torque_rows(t_ns, imu.gyro[window], speed_sq, keep, geometry)
        if torque is None:
            raise VidEvalError(f"{mav0}: no {1000 * WINDOW_S:g} ms window with thrust and rotor data for the torque rows")
    try:
        fit = fit_thrust(data, mass, args.model, args.bias, torque)
    except ValueError as exc:
        raise VidEvalError(f"{mav0}: {exc}") from None

    span = (data.t_ns[[0, -1]] - imu.t_ns[0]) * 1e-9
    print(f"{PROG}: {mav0.parent if mav0.name == 'mav0' else mav0}: {len(data.t_ns)} IMU samples "
          f"{span[0]:.2f}-{span[1]:.2f} s ({int(window.sum()) - len(data.t_ns)} dropped: low thrust or rotor gaps), "
          f"mass {mass:g} kg ({mass_src}), model {args.model}, bias {args.bias}"
          + (", force0 subtracted" if force_z is not None else "")
          + (f", {fit.torque_windows} torque windows ({args.geometry})" if fit.torque_windows else ""))
    names = [f"k_{i + 1}" for i in range(len(fit.coefficients))] if args.model == "per-rotor" else ["k (every rotor)"]
    for name, k, s in zip(names, fit.coefficients, fit.sigma):
        print(f"  {name} = {k:.6e} N/({unit})^2  +- {s:.2e} ({100 * s / abs(k):.2f} %)")
    print(f"  accelerometer bias z = {fit.bias_z:+.4f} m/s^2"
          f"{' (fitted)' if args.bias == 'fit' else ' (ground truth, mean)' if args.bias == 'groundtruth' else ''}")
    print(f"  residual RMS {fit.rms:.4f} m/s^2 (design condition number {fit.condition:.3g})")
    if fit.torque_rms is not None:
        print("  torque-window residual RMS roll/pitch/yaw " + " / ".join(f"{v:.2e}" for v in fit.torque_rms) + " N m s")
    if veh is not None and len(veh.rotor_thrust_coefficients) == data.speed_sq.shape[1]:
        before = residuals_with(data, mass, np.array(veh.rotor_thrust_coefficients), args.bias)
        print(f"  residual RMS with vehicle.yaml's coefficients: {np.sqrt(np.mean(before ** 2)):.4f} m/s^2")
    for w in fit.warnings:
        print(f"{PROG}: warning: {w}", file=sys.stderr)
    if args.out:
        gravity = veh.gravity if veh is not None else 9.81
        comment = [f"vid-fit-thrust {args.model} fit of {mav0}: {len(data.t_ns)} samples, "
                   f"residual RMS {fit.rms:.4f} m/s^2, relative 1-sigma <= {100 * fit.relative_sigma.max():.2f} %"]
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(vehicle_yaml(fit.coefficients, mass, gravity, unit, comment), encoding="utf-8")
        print(f"  wrote {args.out}")
    if args.plot:
        from .plots import plot_thrust_residuals
        path = plot_thrust_residuals(data, fit, Path(args.plot), imu.t_ns[0], unit)
        print(f"  wrote {path}")
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    _check_flags(parser, args)
    return run_reporting_errors(PROG, run, args)


if __name__ == "__main__":
    sys.exit(main())
