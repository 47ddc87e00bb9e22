"""``vid-eval mocap-truth FOLDER``: clock offsets, the IMU-to-mocap rotation and the external-force
truth force0 of a dataset folder with motion capture (vid_eval.importer.truth)."""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..importer.force_truth import FORCE_CUTOFF_HZ
from ..importer.sync import DEFAULT_MAX_LAG_S
from ..importer.truth import mocap_truth, report_lines
from ..usage import positive_float


def add_parser(sub) -> None:
    """Register the ``mocap-truth`` sub-command."""
    p = sub.add_parser("mocap-truth", help="force truth, clock offsets and IMU-mocap rotation from motion capture",
                       description="From a dataset folder with imu0, thrust0 (or rotor0 + coefficients), "
                                   "vehicle.yaml and mocap ground truth: the mocap clock offset and the rotation "
                                   "between the IMU and the mocap body (gyro vs mocap rate), the thrust stream's "
                                   "offset against the accelerometer, and force0/data.csv = m (a_W - g_W) - R_WI "
                                   "[0, 0, T] from the smoothed, twice differentiated mocap position.")
    p.add_argument("folder", help="dataset folder (SEQ or SEQ/mav0)")
    p.add_argument("--cutoff", type=positive_float, default=FORCE_CUTOFF_HZ, metavar="HZ",
                   help=f"zero-phase Butterworth cutoff of the position and thrust (default {FORCE_CUTOFF_HZ:g})")
    p.add_argument("--max-lag", type=positive_float, default=DEFAULT_MAX_LAG_S, metavar="S",
                   help=f"largest clock offset searched (default {DEFAULT_MAX_LAG_S:g} s)")
    p.add_argument("--apply-sync", action="store_true",
                   help="rewrite the ground truth with the mocap offset removed and the orientation rotated "
                        "into the IMU frame (R_WI = R_WM R_IM^T) before deriving the force")
    p.add_argument("--apply-thrust-lag", action="store_true",
                   help="rewrite thrust0 with the measured thrust offset removed")
    p.add_argument("--force-out", metavar="CSV", help="write the force truth here (default FOLDER/mav0/force0/data.csv)")
    p.add_argument("--json", metavar="OUT", help="write the numbers as JSON")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    rep = mocap_truth(Path(args.folder), args.cutoff, args.max_lag, args.apply_sync, args.apply_thrust_lag,
                      Path(args.force_out) if args.force_out else None)
    for line in report_lines(rep, args.cutoff):
        print(line)
    out = args.force_out or str(Path(args.folder) / ("mav0" if (Path(args.folder) / "mav0").is_dir() else "")
                                / "force0" / "data.csv")
    print(f"wrote {out}")
    if args.json:
        Path(args.json).write_text(json.dumps({"command": "mocap-truth", "folder": str(Path(args.folder).resolve()),
                                               "cutoff_hz": args.cutoff, **rep.as_dict()}, indent=2) + "\n")
    return 0
