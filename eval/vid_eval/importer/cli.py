"""``vid-import INPUT OUT --map MAP --mass KG``: a flight log in CSV / HDF5 columns -> the dataset
folder of docs/formats.md §1 in the project's frames (docs/own-vehicle.md, "Importing a log that
is not a bag"). One line per thing done on stdout; errors are one line on stderr: exit 2 for
usage (flags, map, a column that is not there), 1 for data that contradicts them.
"""
from __future__ import annotations

import argparse
import math
import shutil
import sys
from pathlib import Path
from typing import List, Optional

from ..errors import VidEvalError
from ..usage import OneLineParser, positive_float
from . import convert
from .errors import MapError
from .features import DEFAULT_SCENE, find_vid_sim, synthesize
from .sourcemap import QUAT_ORDERS, TIME_UNITS, load_map, preset_names
from .sync import DEFAULT_MAX_LAG_S, gyro_mocap_sync
from .truth import applied_sync_line, gyro_sync_lines, synced_groundtruth
from .writer import DEFAULT_IMU_NOISE, DEFAULT_ROTOR_NOISE, write_dataset

EXIT_USAGE, EXIT_DATA = 2, 1


def _coefficients(text: str) -> List[float]:
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a comma-separated list of numbers") from None
    if not all(v > 0 and math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"coefficients must be positive, got {text}")
    return values


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog="vid-import",
        description="Convert a flight log given as CSV or HDF5 columns (IMU, thrust or rotor speeds, "
                    "motion-capture pose) into the dataset folder of docs/formats.md §1, in the project's "
                    "frames (world z up, IMU frame FLU).")
    p.add_argument("input", help="the log: a folder (with the map's 'pieces', a folder of pieces) or one file")
    p.add_argument("out", help="output dataset folder (OUT/mav0/...)")
    p.add_argument("--map", required=True, metavar="NAME|FILE",
                   help=f"source map: a preset ({', '.join(preset_names())}) or a YAML file")
    p.add_argument("--mass", type=positive_float, required=True, metavar="KG", help="vehicle mass [kg] (vehicle.yaml)")
    p.add_argument("--gravity", type=positive_float, default=9.81, metavar="G", help="gravity magnitude (default 9.81)")
    p.add_argument("--imu-frame", choices=("flu", "frd"), default="flu",
                   help="axes of the IMU (and of the thrust and the mocap body): flu (z up, default) or "
                        "frd (z down: rotated by diag(1,-1,-1))")
    p.add_argument("--world-frame", choices=("enu", "nwu", "ned"), default="enu",
                   help="axes of the mocap world (written as ENU, z up)")
    p.add_argument("--time-unit", choices=tuple(TIME_UNITS), help="override the map's time_unit of every stream")
    p.add_argument("--quaternion-order", choices=QUAT_ORDERS, help="override the map's mocap quaternion_order")
    p.add_argument("--negate-thrust", action="store_true",
                   help="the thrust column counts positive downwards along its body z")
    g = p.add_argument_group("noise written to imu0/sensor.yaml and rotor0/sensor.yaml (defaults stated in the output)")
    for flag, key in (("--gyro-noise", "gyroscope_noise_density"), ("--gyro-walk", "gyroscope_random_walk"),
                      ("--accel-noise", "accelerometer_noise_density"), ("--accel-walk", "accelerometer_random_walk")):
        g.add_argument(flag, type=positive_float, dest=key, metavar="X", help=f"{key} (default {DEFAULT_IMU_NOISE[key]:g})")
    g.add_argument("--rotor-noise", type=positive_float, default=None, metavar="X",
                   help=f"rotor speed noise density (default {DEFAULT_ROTOR_NOISE:g})")
    g.add_argument("--rotor-coefficients", type=_coefficients, default=None, metavar="K1,K2,...",
                   help="rotor thrust coefficients [N/unit^2] for vehicle.yaml (vid-fit-thrust finds them)")
    p.add_argument("--velocity-cutoff", type=positive_float, default=convert.VELOCITY_CUTOFF_HZ, metavar="HZ",
                   help="low-pass cutoff of the position before differentiating, when the mocap has no "
                        f"velocity (default {convert.VELOCITY_CUTOFF_HZ:g})")
    p.add_argument("--sync", action="store_true",
                   help="measure the mocap clock offset and the IMU-mocap rotation (as vid-eval mocap-truth) and "
                        "write the ground truth in the IMU's clock and frame (R_WI = R_WM R_IM^T); the synthetic "
                        "features then follow the IMU, as a calibrated camera does")
    f = p.add_argument_group("synthetic features (a log without cameras)")
    f.add_argument("--synthetic-features", action="store_true",
                   help="simulate stereo feature tracks (feat0, cam0/cam1 sensor.yaml, landmarks.csv) along "
                        "the mocap poses with vid_sim --camera-along")
    f.add_argument("--vid-sim", metavar="PATH", help="vid_sim program (default $VID_BUILD_DIR/bin, then PATH)")
    f.add_argument("--scene", metavar="FILE", default=None,
                   help=f"vid_sim scenario giving the room and cameras (default {DEFAULT_SCENE.name} of config/sim)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing OUT/mav0")
    return p


def run(args: argparse.Namespace) -> int:
    overrides = {k: v for k, v in (("time_unit", args.time_unit), ("quaternion_order", args.quaternion_order)) if v}
    smap = load_map(args.map, overrides)
    out = Path(args.out)
    mav0 = out / "mav0"
    if mav0.exists() and any(mav0.iterdir()) and not args.overwrite:
        raise MapError(f"{mav0} exists and is not empty (pass --overwrite)")
    vid_sim = find_vid_sim(args.vid_sim) if args.synthetic_features else None
    noise = {k: getattr(args, k) if getattr(args, k) is not None else v for k, v in DEFAULT_IMU_NOISE.items()}
    defaulted = [k for k in DEFAULT_IMU_NOISE if getattr(args, k) is None]
    opts = convert.Options(mass_kg=args.mass, gravity=args.gravity, imu_frame=args.imu_frame,
                           world_frame=args.world_frame, negate_thrust=args.negate_thrust, imu_noise=noise,
                           rotor_noise=args.rotor_noise or DEFAULT_ROTOR_NOISE,
                           rotor_coefficients=args.rotor_coefficients or [],
                           velocity_cutoff_hz=args.velocity_cutoff)
    log, lines = convert.convert(smap, Path(args.input), opts)
    if args.sync:
        if log.t_gt is None:
            raise MapError("--sync needs the mocap poses (a 'mocap' stream in the map)")
        sync = gyro_mocap_sync(log.t_imu, log.gyro, log.t_gt, log.q_WI_wxyz, DEFAULT_MAX_LAG_S)
        log.t_gt, log.q_WI_wxyz = synced_groundtruth(log.t_gt, log.q_WI_wxyz, sync)
        lines += gyro_sync_lines(sync) + [f"applied: {applied_sync_line(sync)}"]
    if mav0.exists():
        shutil.rmtree(mav0)
    write_dataset(out, log, f"{args.input} (map {smap.path})")
    for line in lines:
        print(line)
    if defaulted:
        print("imu0/sensor.yaml noise: " + ", ".join(f"{k} {noise[k]:g}" for k in DEFAULT_IMU_NOISE)
              + f" ({', '.join(defaulted)} defaulted to EuRoC's ADIS16448 values: measure yours with vid-allan)")
    if args.synthetic_features:
        if log.t_gt is None:
            raise MapError("--synthetic-features needs the mocap poses (a 'mocap' stream in the map)")
        scene = Path(args.scene) if args.scene else DEFAULT_SCENE
        moved = synthesize(out, log.t_gt, log.p_WI, log.q_WI_wxyz, vid_sim, scene)
        print(f"synthetic features: {vid_sim} --camera-along (scene {scene}) wrote {', '.join(moved)}")
    print(f"wrote {out}")
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return run(args)
    except MapError as exc:
        print(f"vid-import: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except VidEvalError as exc:
        print(f"vid-import: error: {exc}", file=sys.stderr)
        return EXIT_DATA
    except OSError as exc:
        print(f"vid-import: error: {exc.filename or ''}: {exc.strerror}", file=sys.stderr)
        return EXIT_DATA


if __name__ == "__main__":
    sys.exit(main())
