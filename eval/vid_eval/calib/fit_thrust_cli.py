"""``vid-fit-thrust``: fit the estimator's dynamics model of vehicle.yaml from a flight log.

Reads a dataset folder (docs/formats.md §1; a rosbag converted with vid-bag2asl is one):
``imu0``, ``rotor0`` (speeds and their unit: the coefficients k_i are fitted) or ``thrust0``
(a measured collective thrust: its scale is fitted), ``vehicle.yaml`` (the mass the estimator
divides by), and when present the ground truth (body velocity for the drag, accelerometer bias
for ``--bias groundtruth``); for per-rotor coefficients also ``--geometry`` (rotor layout and
inertia: the gyroscope's torque balance separates the rotors, :mod:`vid_eval.calib.torque_rows`).
Prints the coefficients, the thrust axis, the linear drag and the thrust latency with their
1-sigma, and the in-flight accelerometer noise; writes a vehicle.yaml (``--out``) and a residual
plot (``--plot``). The model and solvers: :mod:`vid_eval.calib.flight_fit`.

Errors: one line ``vid-fit-thrust: error: ...`` naming the file or flag; exit 2 for usage
errors, 1 for bad data.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import List, Optional

import numpy as np

from ..usage import OneLineParser
from . import dataset as ds
from .cli_errors import run_reporting_errors
from .fit_report import report_lines, vehicle_yaml
from .flight_fit import MAX_LAG_S, FitOptions, fit_flight
from .thrust_fit import BIAS_MODES, MODELS

PROG = "vid-fit-thrust"


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog=PROG,
        description="Fit the estimator's dynamics model of vehicle.yaml from a flight log: the rotor thrust "
                    "coefficients k_i (T_i = k_i n_i^2) or the scale of a measured thrust, the thrust axis, "
                    "the linear drag (with ground-truth velocity) and the thrust latency: "
                    "a_I = (T/m) t_I - D v_I + b.")
    p.add_argument("dataset", help="dataset folder (SEQ or SEQ/mav0) with imu0, rotor0 or thrust0, and vehicle.yaml")
    p.add_argument("--model", choices=MODELS, default="collective",
                   help="one k for all rotors, or one per rotor (needs --geometry, or roll/pitch/yaw "
                        "accelerations in the log; default: collective)")
    p.add_argument("--geometry", metavar="FILE.yaml",
                   help="per-rotor: the vehicle's layout (x/plus), arm_length_m, rotor_directions, "
                        "torque_to_thrust_m and inertia_diag, top level or under vehicle: (a vid_sim "
                        "scenario is one); adds the gyroscope's torque balance to the fit")
    p.add_argument("--source", choices=ds.SOURCES, default="auto",
                   help="thrust stream: rotor0 (fit k), thrust0 (fit the scale of the measured thrust); "
                        "auto: rotor0 when present (default)")
    p.add_argument("--bias", choices=BIAS_MODES, default="fit",
                   help="accelerometer bias along z: fit a constant (default), take the ground truth's, or none")
    p.add_argument("--mass", type=float, metavar="KG", help="vehicle mass [kg] (default: vehicle.yaml mass_kg)")
    p.add_argument("--delay", metavar="S|auto", default="auto",
                   help="thrust/rotor stream latency against the IMU [s] (a sample stamped t is the thrust at "
                        "t - S), or auto: measured (default)")
    p.add_argument("--max-lag", type=float, default=MAX_LAG_S, metavar="S",
                   help=f"largest latency searched with --delay auto (default {MAX_LAG_S:g} s)")
    p.add_argument("--no-drag", action="store_true",
                   help="no drag terms even when the ground truth gives the velocity (a hover/steps fit)")
    p.add_argument("--subtract-force0", action="store_true",
                   help="subtract a known external force (force0/, e.g. a simulated tether) from the "
                        "accelerometer; not the force0 of vid-eval mocap-truth, which is derived from the "
                        "thrust model itself")
    p.add_argument("--start", type=float, default=0.0, metavar="S",
                   help="use data from S seconds after the first IMU sample (default 0)")
    p.add_argument("--end", type=float, metavar="S", help="... up to S seconds (default: the end)")
    p.add_argument("--min-thrust-fraction", type=float, default=0.25, metavar="F",
                   help="drop samples whose thrust is below F times its median (ground, idle, spin-up; default 0.25)")
    p.add_argument("--out", metavar="FILE", help="write the fitted vehicle.yaml here")
    p.add_argument("--plot", metavar="FILE.png", help="write the residual plot here")
    return p


def _delay(text: str) -> Optional[float]:
    if text == "auto":
        return None
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    return value


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
    d = _delay(a.delay)
    if d is not None and not (d >= 0 and np.isfinite(d)):
        p.error(f"--delay: expected seconds >= 0 or auto, got '{a.delay}'")
    if not (a.max_lag > 0 and np.isfinite(a.max_lag)):
        p.error(f"--max-lag: expected positive seconds, got {a.max_lag:g}")


def options(a: argparse.Namespace) -> FitOptions:
    return FitOptions(model=a.model, bias=a.bias, mass=a.mass, start=a.start, end=a.end,
                      min_thrust_fraction=a.min_thrust_fraction,
                      geometry=Path(a.geometry) if a.geometry else None, source=a.source,
                      delay=_delay(a.delay), max_lag=a.max_lag, drag=not a.no_drag,
                      subtract_force0=a.subtract_force0)


def run(args: argparse.Namespace) -> int:
    mav0 = ds.find_mav0(args.dataset)
    fit = fit_flight(mav0, options(args))
    for line in report_lines(fit, PROG, args.model, args.bias, args.geometry):
        print(line)
    for w in fit.z.warnings + fit.warnings:
        print(f"{PROG}: warning: {w}", file=sys.stderr)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(vehicle_yaml(fit, args.model), encoding="utf-8")
        print(f"  wrote {args.out}")
    if args.plot:
        from .plots import plot_thrust_residuals
        path = plot_thrust_residuals(fit.data, fit.z, Path(args.plot), fit.imu.t_ns[0], fit.stream.unit)
        print(f"  wrote {path}")
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    _check_flags(parser, args)
    return run_reporting_errors(PROG, run, args)


if __name__ == "__main__":
    sys.exit(main())
