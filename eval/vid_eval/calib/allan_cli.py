"""``vid-allan``: IMU noise densities and random walks from a static IMU log, in the keys of
Kalibr's imu.yaml (which ``vid_run --config`` reads as it is); with ``--flight`` the in-flight
noise densities of a flight log with no static part (:mod:`vid_eval.calib.allan_flight`).

Reads ``imu0/data.csv`` (a dataset folder or the CSV itself), takes ``--start``/``--end``
(the part where the IMU stands still), computes each axis' overlapping Allan deviation with
allantools and fits white noise N, random walk K and bias instability B to it
(:mod:`vid_eval.calib.allan`). Prints per-axis values and, per sensor, the mean over the
three axes in Kalibr's keys; ``--out`` writes a Kalibr imu.yaml, ``--plot`` the curves.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import List, Optional

import numpy as np

from ..errors import VidEvalError
from ..tools.loaders import load_imu
from ..usage import OneLineParser
from .cli_errors import run_reporting_errors
from .allan import analyse
from .allan_flight import flight_flags, run_flight
from .dataset import find_mav0

PROG = "vid-allan"
SENSORS = (("gyroscope", "rad/s", "gyro"), ("accelerometer", "m/s^2", "accel"))


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog=PROG,
        description="IMU noise from a static log (Allan deviation): noise densities and random walks "
                    "in Kalibr's imu.yaml keys.")
    p.add_argument("input", help="dataset folder (SEQ or SEQ/mav0) or an imu0 data.csv")
    p.add_argument("--start", type=float, default=0.0, metavar="S",
                   help="use samples from S seconds after the first one (default 0)")
    p.add_argument("--end", type=float, metavar="S", help="... up to S seconds (default: the end)")
    p.add_argument("--out", metavar="FILE", help="write a Kalibr imu.yaml (imu0: ...) here")
    p.add_argument("--plot", metavar="FILE.png", help="write the Allan deviation plot here")
    p.add_argument("--rostopic", default="/imu0", help="rostopic written into --out (default /imu0)")
    flight_flags(p)
    return p


def _check_flags(p: argparse.ArgumentParser, a: argparse.Namespace) -> None:
    if not (a.start >= 0 and np.isfinite(a.start)):
        p.error(f"--start: expected seconds >= 0, got {a.start:g}")
    if a.end is not None and not (a.end > a.start and np.isfinite(a.end)):
        p.error(f"--end: expected seconds after --start ({a.start:g}), got {a.end:g}")
    if a.plot is not None and not a.plot.lower().endswith(".png"):
        p.error(f"--plot: expected a .png file name, got '{a.plot}'")
    if a.flight and a.plot is not None:
        p.error("--plot: the Allan deviation of a static log; not with --flight")
    if not (a.highpass > 0 and np.isfinite(a.highpass)):
        p.error(f"--highpass: expected a positive frequency in Hz, got {a.highpass:g}")


def kalibr_imu_yaml(values: dict, rate_hz: float, rostopic: str, comment: str) -> str:
    """Kalibr's imu chain (imu0: T_i_b identity, the four noise keys, model calibrated)."""
    eye = "\n".join(f"    - [{', '.join('1.0' if r == c else '0.0' for c in range(4))}]" for r in range(4))
    return (f"# {comment}\n"
            "imu0:\n"
            f"  T_i_b:\n{eye}\n"
            f"  accelerometer_noise_density: {values['accelerometer_noise_density']:.4e}   # m/s^2/sqrt(Hz)\n"
            f"  accelerometer_random_walk: {values['accelerometer_random_walk']:.4e}     # m/s^3/sqrt(Hz)\n"
            f"  gyroscope_noise_density: {values['gyroscope_noise_density']:.4e}       # rad/s/sqrt(Hz)\n"
            f"  gyroscope_random_walk: {values['gyroscope_random_walk']:.4e}         # rad/s^2/sqrt(Hz)\n"
            "  model: calibrated\n"
            f"  rostopic: {rostopic}\n"
            "  time_offset: 0.0\n"
            f"  update_rate: {rate_hz:.1f}\n")


def run(args: argparse.Namespace) -> int:
    if args.flight:
        return run_flight(args, PROG, kalibr_imu_yaml)
    src = Path(args.input)
    csv = src if src.is_file() else find_mav0(src) / "imu0" / "data.csv"
    imu = load_imu(csv)
    t = (imu.t_ns - imu.t_ns[0]) * 1e-9
    keep = (t >= args.start) & (t <= (args.end if args.end is not None else np.inf))
    if keep.sum() < 100:
        raise VidEvalError(f"{csv}: {int(keep.sum())} samples between --start {args.start:g} s and --end "
                           f"{args.end if args.end is not None else 'the end'} (log spans {t[-1]:.3f} s); "
                           "need at least 100")
    dt = np.diff(imu.t_ns[keep]) * 1e-9
    rate = 1.0 / float(np.median(dt))
    if np.max(dt) > 5.0 / rate:
        raise VidEvalError(f"{csv}: gap of {np.max(dt):.3f} s in the static window (rate {rate:.1f} Hz): the "
                           "Allan deviation needs evenly spaced samples; choose --start/--end around it")
    span = t[keep][-1] - t[keep][0]
    print(f"{PROG}: {csv}: {int(keep.sum())} samples over {span:.1f} s at {rate:.1f} Hz")
    if span < 600:
        print(f"{PROG}: warning: a {span:.0f} s log pins the noise densities, but the random walks need the "
              "Allan curve well past its minimum: record hours for them", file=sys.stderr)
    values, taus, adevs, models = {}, {}, {}, {}
    for sensor, unit, _ in SENSORS:
        data = imu.gyro[keep] if sensor == "gyroscope" else imu.accel[keep]
        fits = []
        for a, axis in enumerate("xyz"):
            f = analyse(data[:, a], rate)
            fits.append(f)
            key = f"{sensor}_{axis}"
            taus[key], adevs[key], models[key] = f.taus, f.adev, f.model(f.taus)
            print(f"  {sensor} {axis}: noise density {f.noise_density:.4e} {unit}/sqrt(Hz), random walk "
                  f"{f.random_walk:.4e} {unit}/s/sqrt(Hz), bias instability {f.bias_instability:.3e} {unit}")
        values[f"{sensor}_noise_density"] = float(np.mean([f.noise_density for f in fits]))
        values[f"{sensor}_random_walk"] = float(np.mean([f.random_walk for f in fits]))
    print("Kalibr imu.yaml (mean over the axes):")
    for key in ("accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density",
                "gyroscope_random_walk"):
        print(f"  {key}: {values[key]:.4e}")
    print(f"  update_rate: {rate:.1f}")
    if args.out:
        comment = f"vid-allan on {csv}, {span:.1f} s static ({args.start:g} s on); Allan-deviation fit"
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(kalibr_imu_yaml(values, rate, args.rostopic, comment), encoding="utf-8")
        print(f"  wrote {args.out}")
    if args.plot:
        from .plots import plot_allan
        print(f"  wrote {plot_allan(taus, adevs, models, Path(args.plot))}")
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    _check_flags(parser, args)
    return run_reporting_errors(PROG, run, args)


if __name__ == "__main__":
    sys.exit(main())
