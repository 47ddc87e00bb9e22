"""``vid-eval force-bound DATASET``: idealized force-estimation bound of a sequence.

Runs :mod:`vid_eval.core.force_bound` on the sequence's force0 (divided by the mass) with the
accelerometer noise and rates of its imu0 / cam0 sensor.yaml, for several camera position
noises, and prints the best causal-filter RMSE (and the smoother's) per sigma_p.
"""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, Dict, Optional

import numpy as np
import yaml

from ..errors import ConfigurationError, InputFormatError
from ..core.force_bound import BoundSetup, force_bound, split_by_time_scale
from ..core.force_frames import mass_at
from ..tools.gauge import find_estimate_trajectory, find_gt_trajectory, rotate_world, world_gauge_from_files
from ..core.geometry import lerp
from ..tools.loaders import (find_mass_source, load_force_estimate, load_force_gt, load_mass,
                       load_vehicle_mass)
from .common import abspath, finish


def add_parser(sub) -> None:
    """Register the ``force-bound`` sub-command."""
    p = sub.add_parser(
        "force-bound", help="idealized bound of the external-force RMSE of a sequence",
        description="Best RMSE any linear filter could reach on the sequence's force0 if "
                    "attitude, thrust and accelerometer bias were known and the camera gave "
                    "absolute position with noise sigma_p (docs/notes/force-accuracy.md).")
    p.add_argument("dataset", help="dataset folder (with mav0/force0/data.csv)")
    p.add_argument("--sigma-p-mm", type=float, nargs="+", default=[0.25, 0.5, 1.0, 2.0],
                   metavar="MM", help="camera position noise per frame [mm] (default 0.25 0.5 1 2)")
    p.add_argument("--accel-noise-density", type=float, default=None, metavar="D",
                   help="[m/s^2/sqrt(Hz)]; default: imu0/sensor.yaml, else 0.1")
    p.add_argument("--imu-rate", type=float, default=None, metavar="HZ",
                   help="default: imu0/sensor.yaml rate_hz, else 400")
    p.add_argument("--camera-rate", type=float, default=None, metavar="HZ",
                   help="default: cam0/sensor.yaml rate_hz, else 30")
    p.add_argument("--skip", type=float, default=5.0, metavar="S",
                   help="RMSE after the first S seconds (default 5, as the estimator tests)")
    p.add_argument("--seed", type=int, default=1, help="noise seed (default 1)")
    p.add_argument("--jump-oracle", type=float, default=0.0, metavar="MPS2",
                   help="tell the filter when the true force changes by more than MPS2 between "
                        "two IMU samples (a perfect jump detector; 0 = off, e.g. 0.2)")
    p.add_argument("--estimate", metavar="FORCE_CSV", default=None,
                   help="also split this force.csv's world error (after the posyaw alignment of "
                        "the trajectory next to it, as `vid-eval force`) into slow (2 s moving "
                        "average) and fast parts, for comparison with the bound")
    p.add_argument("--json", metavar="OUT", help="write the results as JSON to OUT")
    p.set_defaults(run=run)


def _sensor_value(path: Path, key: str) -> Optional[float]:
    """A number from a EuRoC-style sensor.yaml, or None when the file or key is absent."""
    if not path.is_file():
        return None
    text = path.read_text(encoding="utf-8")
    if text.startswith("%YAML"):
        text = text.split("\n", 1)[1] if "\n" in text else ""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError:
        raise InputFormatError(str(path), "invalid YAML") from None
    if not isinstance(data, dict) or key not in data:
        return None
    try:
        return float(data[key])
    except (TypeError, ValueError):
        raise InputFormatError(str(path), f"key '{key}' is not a number") from None


def run(args: argparse.Namespace) -> int:
    mav0 = Path(args.dataset) / "mav0"
    force_path = mav0 / "force0" / "data.csv"
    if not force_path.is_file():
        raise ConfigurationError(f"{force_path}: no force ground truth in this dataset")
    gt = load_force_gt(force_path)
    mass_src = find_mass_source(force_path)
    if mass_src is None:
        raise ConfigurationError(f"{mav0}: no mass0/data.csv or vehicle.yaml for the mass")
    mass = load_mass(mass_src) if mass_src.suffix == ".csv" else load_vehicle_mass(mass_src)
    force = gt.values / mass_at(mass, gt.t_ns)[:, None]

    def pick(flag, path, key, default):
        if flag is not None:
            return flag
        value = _sensor_value(path, key)
        return default if value is None else value

    setup = BoundSetup(
        imu_rate_hz=pick(args.imu_rate, mav0 / "imu0" / "sensor.yaml", "rate_hz", 400.0),
        camera_rate_hz=pick(args.camera_rate, mav0 / "cam0" / "sensor.yaml", "rate_hz", 30.0),
        accel_noise_density=pick(args.accel_noise_density, mav0 / "imu0" / "sensor.yaml",
                                 "accelerometer_noise_density", 0.1),
        skip_s=args.skip, seed=args.seed)
    if args.jump_oracle < 0:
        raise ConfigurationError(f"--jump-oracle must be >= 0, got {args.jump_oracle}")
    results = force_bound(gt.t_ns * 1e-9, force, [s * 1e-3 for s in args.sigma_p_mm],
                          setup=setup, jump_min=args.jump_oracle)
    oracle = f", jump oracle at {args.jump_oracle:g} m/s^2 per sample" if args.jump_oracle > 0 else ""
    print(f"force bound of {args.dataset}: accelerometer {setup.accel_noise_density} "
          f"m/s^2/sqrt(Hz) at {setup.imu_rate_hz:g} Hz, camera {setup.camera_rate_hz:g} Hz"
          f"{oracle}, RMSE of |F_err| after {setup.skip_s:g} s [m/s^2]")
    print(f"{'sigma_p [mm]':>12} {'best q':>7} {'filter':>8} {'smoother':>9}")
    for r in results:
        print(f"{r.sigma_p_m * 1e3:12.2f} {r.q:7.2f} {r.filter_rmse:8.4f} {r.smoother_rmse:9.4f}")
    out: Dict[str, Any] = {
        "dataset": abspath(args.dataset),
        "accel_noise_density": setup.accel_noise_density,
        "imu_rate_hz": setup.imu_rate_hz,
        "camera_rate_hz": setup.camera_rate_hz,
        "skip_s": setup.skip_s,
        "jump_oracle_mps2": args.jump_oracle,
        "results": [{"sigma_p_m": r.sigma_p_m, "q": r.q, "filter_rmse": r.filter_rmse,
                     "filter_rmse_axes": list(r.filter_rmse_axes),
                     "smoother_rmse": r.smoother_rmse} for r in results],
    }
    if args.estimate:
        _, est = load_force_estimate(args.estimate)
        # The estimate's world has its own heading: rotate it into the ground truth's first.
        gauge = world_gauge_from_files(find_estimate_trajectory(args.estimate),
                                       find_gt_trajectory(force_path), "posyaw")
        est = rotate_world(est, gauge)
        keep = (est.t_ns >= gt.t_ns[0] + int(setup.skip_s * 1e9)) & (est.t_ns <= gt.t_ns[-1])
        if keep.sum() < 10:
            raise ConfigurationError(f"{args.estimate}: too few samples inside the ground truth")
        t = est.t_ns[keep]
        truth = np.stack([lerp(gt.t_ns, force[:, k], t) for k in range(3)], axis=1)
        total, slow, fast = split_by_time_scale(t * 1e-9, est.values[keep] - truth, 2.0)
        print(f"estimate {args.estimate}: RMSE {total:.4f} = slow (2 s average) {slow:.4f} "
              f"+ fast {fast:.4f} (in quadrature, approximately)")
        out["estimate"] = {"path": abspath(args.estimate), "rmse": total, "slow_rmse": slow,
                           "fast_rmse": fast, "window_s": 2.0, "alignment": gauge.as_dict()}
    finish(args, out)
    return 0
