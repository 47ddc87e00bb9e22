"""``vid-allan --flight``: the IMU noise in flight from a dataset folder with no static part
(ground truth or mocap for the gyro, the thrust stream for the accelerometer), in Kalibr's keys
and the estimator's (:mod:`vid_eval.calib.flight_noise`). The random walks need hours of
static log: the ones of ``imu0/sensor.yaml`` are kept."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Dict, List, Optional

import numpy as np

from ..errors import VidEvalError
from ..tools.loaders import load_yaml_mapping
from . import dataset as ds
from .flight_fit import FitOptions, fit_flight
from .flight_noise import FlightNoise, flight_noise
from .truth_motion import truth_motion

KEYS = {"gyroscope": "gyro_noise_density", "accelerometer": "accel_noise_density"}
UNITS = {"gyroscope": "rad/s/sqrt(Hz)", "accelerometer": "m/s^2/sqrt(Hz)"}


def _static(mav0: Path) -> Dict[str, float]:
    """The noise keys of imu0/sensor.yaml (what a static calibration says), those present."""
    path = mav0 / "imu0" / "sensor.yaml"
    if not path.is_file():
        return {}
    data = load_yaml_mapping(path, "imu0/sensor.yaml")
    return {k: float(v) for k, v in data.items() if k.endswith(("_noise_density", "_random_walk"))
            and isinstance(v, (int, float)) and not isinstance(v, bool)}


def _gyro(mav0: Path, start: float, end: Optional[float], cutoff: float) -> tuple[Optional[FlightNoise], str]:
    imu = ds.imu(mav0)
    gt = ds.groundtruth(mav0)
    if gt is None:
        return None, "no ground truth (mocap): the gyro's in-flight noise needs the true body rate"
    t = (imu.t_ns - imu.t_ns[0]) * 1e-9
    window = (t >= start) & (t <= (end if end is not None else np.inf))
    t_ns = imu.t_ns[window]
    rate = 1.0 / float(np.median(np.diff(t_ns) * 1e-9))
    res = imu.gyro[window] - truth_motion(gt, t_ns).w_I
    return flight_noise(res, rate, cutoff), f"gyro - ground-truth body rate ({gt.path})"


def _accel(mav0: Path, start: float, end: Optional[float], cutoff: float) -> tuple[Optional[FlightNoise], str]:
    try:
        fit = fit_flight(mav0, FitOptions(start=start, end=end))
    except VidEvalError as exc:
        return None, f"no thrust model ({exc})"
    latency = f"thrust latency {fit.delay.value_s * 1e3:.1f} ms" + (f": {fit.delay.note}" if fit.delay.note else "")
    how = f"accelerometer - fitted thrust{' + drag' if fit.drag is not None else ''} model ({fit.stream.kind}, {latency})"
    return flight_noise(fit.residuals, fit.rate_hz, cutoff), how


def run_flight(args: argparse.Namespace, prog: str, kalibr_yaml) -> int:
    """Print (and with --out write) the in-flight noise densities of args.input."""
    mav0 = ds.find_mav0(args.input)
    static = _static(mav0)
    results = {"gyroscope": _gyro(mav0, args.start, args.end, args.highpass),
               "accelerometer": _accel(mav0, args.start, args.end, args.highpass)}
    if all(r[0] is None for r in results.values()):
        raise VidEvalError(f"{mav0}: nothing to measure: " + "; ".join(r[1] for r in results.values()))
    rate = float(ds.imu(mav0).t_ns.size / max((ds.imu(mav0).t_ns[-1] - ds.imu(mav0).t_ns[0]) * 1e-9, 1e-9))
    print(f"{prog} --flight: {mav0}: residuals high-passed at {args.highpass:g} Hz; density = RMS / sqrt(rate)")
    values: Dict[str, float] = {}
    for sensor, (noise, how) in results.items():
        key = f"{sensor}_noise_density"
        if noise is None:
            print(f"  {sensor}: not measured: {how}")
            continue
        values[key] = noise.combined
        ratio = f"; {noise.combined / static[key]:.1f} x imu0/sensor.yaml's {static[key]:.3g} (static)" \
            if static.get(key) else ""
        print(f"  {sensor}: {how}: RMS x/y/z " + " / ".join(f"{v:.4f}" for v in noise.rms)
              + f" over {noise.samples} samples -> {noise.combined:.3e} {UNITS[sensor]} (x/y/z "
              + " / ".join(f"{v:.3e}" for v in noise.density) + f"){ratio}")
    print("Kalibr imu.yaml (in flight, vibration included; random walks: a static log's, here imu0/sensor.yaml's):")
    for key, v in values.items():
        print(f"  {key}: {v:.4e}")
    print("estimator.yaml (the estimator's own keys, which a preset's imu.yaml sets):")
    for sensor, key in KEYS.items():
        name = f"{sensor}_noise_density"
        if name in values:
            what = ("the gyro noise that propagation integrates" if sensor == "gyroscope" else
                    "the dynamics-mode accelerometer update's noise: what the thrust + drag model leaves")
            print(f"  {key}: {values[name]:.4e}   # {what}")
    louder = [k for k, v in values.items() if static.get(k) and v > 3.0 * static[k]]
    if louder:
        print(f"{prog}: warning: in flight {', '.join(louder)} is more than 3x imu0/sensor.yaml's (a static "
              "calibration or a default): give the estimator the flight values", file=sys.stderr)
    if args.out:
        merged = {**{k: static.get(k, float("nan")) for k in ("accelerometer_noise_density", "accelerometer_random_walk",
                                                             "gyroscope_noise_density", "gyroscope_random_walk")},
                  **values}
        missing = [k for k, v in merged.items() if not np.isfinite(v)]
        if missing:
            raise VidEvalError(f"{mav0}: --out: no value for {', '.join(missing)} (not measured and not in "
                               "imu0/sensor.yaml)")
        comment = (f"vid-allan --flight on {mav0}: noise densities in flight (high-pass {args.highpass:g} Hz); "
                   "random walks from imu0/sensor.yaml")
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(kalibr_yaml(merged, rate, args.rostopic, comment), encoding="utf-8")
        print(f"  wrote {args.out}")
    return 0


def flight_flags(p: argparse.ArgumentParser) -> List[str]:
    """Add --flight and --highpass to vid-allan's parser."""
    from .flight_noise import HIGHPASS_HZ
    p.add_argument("--flight", action="store_true",
                   help="a flight log with no static part: gyro noise from the gyro minus the ground-truth body "
                        "rate, accelerometer noise from the residual of the fitted thrust + drag model")
    p.add_argument("--highpass", type=float, default=HIGHPASS_HZ, metavar="HZ",
                   help=f"--flight: high-pass of the residuals (default {HIGHPASS_HZ:g} Hz)")
    return ["--flight", "--highpass"]
