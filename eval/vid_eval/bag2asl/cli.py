"""vid-bag2asl BAG OUT [--topics FILE] [--start S] [--end S] [--mass KG] ...

Errors print one line on stderr ("vid-bag2asl: error: ...") and exit with status 1
(2 for command-line usage errors, also --start/--end outside the bag or --mass <= 0; 130 on
Ctrl-C).
"""
from __future__ import annotations

import argparse
import pathlib
import sys

from .convert import Options, convert
from .errors import Bag2AslError, UsageError
from ..usage import OneLineParser


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got '{text}'") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {n}")
    return n


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog="vid-bag2asl",
        description="Convert a ROS1 bag (bz2/lz4/uncompressed) or ROS2 bag to the VID-MSCKF "
                    "dataset folder (EuRoC/ASL + rotor0, force0, thrust0, vehicle.yaml). "
                    "Default topic map: VID-Dataset. See eval/vid_eval/bag2asl/README.md.")
    p.add_argument("bag", type=pathlib.Path, help="ROS1 .bag file or ROS2 bag directory")
    p.add_argument("out", type=pathlib.Path, help="output folder (OUT/mav0/... is written)")
    p.add_argument("--topics", type=pathlib.Path, metavar="FILE",
                   help="topic map YAML (default: topic_maps/vid_dataset.yaml)")
    p.add_argument("--start", type=float, metavar="S", help="skip the first S seconds (bag time)")
    p.add_argument("--end", type=float, metavar="S", help="stop S seconds after the bag start")
    p.add_argument("--mass", type=float, metavar="KG", help="vehicle mass (else the mass rule)")
    p.add_argument("--preset", type=pathlib.Path, metavar="DIR",
                   help="calibration preset folder (default: config/vid_dataset)")
    p.add_argument("--png-level", type=int, default=1, choices=range(0, 10), metavar="0-9",
                   help="PNG zlib compression level (default 1: fast)")
    p.add_argument("--jobs", type=_positive_int, default=2, metavar="N",
                   help="threads encoding PNGs (default 2; 1 = encode inline)")
    p.add_argument("--overwrite", action="store_true", help="write into a non-empty OUT/mav0")
    p.add_argument("--allow-no-rotors", action="store_true",
                   help="convert a bag without rotor-speed (or thrust) topics; the dataset then runs only with "
                        "vid_run --mode imu")
    p.add_argument("--no-progress", action="store_true", help="never draw the progress bar")
    return p


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    opts = Options(bag=args.bag, out=args.out, topics=args.topics, start_s=args.start, end_s=args.end,
                   mass_kg=args.mass, preset=args.preset, png_level=args.png_level, jobs=args.jobs,
                   overwrite=args.overwrite, progress=False if args.no_progress else None,
                   allow_no_rotors=args.allow_no_rotors)
    try:
        convert(opts)
    except Bag2AslError as err:
        print(f"vid-bag2asl: error: {err}", file=sys.stderr)
        return 2 if isinstance(err, UsageError) else 1
    except KeyboardInterrupt:
        print("vid-bag2asl: interrupted", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
