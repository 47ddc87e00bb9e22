"""``vid-eval view``: a run in the Rerun viewer - a finished vid_run / vid_live folder, or
vid_live's LCM output as it comes (see :mod:`vid_eval.view.scene` for what is shown)."""
from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import ConfigurationError


def add_parser(sub) -> None:
    """Register the ``view`` sub-command."""
    p = sub.add_parser("view", help="a run in the Rerun viewer (.rrd file or a spawned viewer)",
                       description="Log a run to Rerun: trajectory, force arrows, tracked features, "
                                   "camera images. Offline from RUN_DIR (+ --dataset), or live from "
                                   "vid_live's LCM channels (--lcm URL).")
    p.add_argument("run_dir", nargs="?", metavar="RUN_DIR", help="vid_run / vid_live --out folder (state.csv, force.csv, "
                                          "tracks.csv when written with --tracks)")
    p.add_argument("--dataset", help="the run's dataset folder: camera images, ground-truth path")
    p.add_argument("--tracks", help="tracked features CSV (default RUN/tracks.csv; vid_track --out)")
    p.add_argument("--image-every", type=int, default=1, metavar="N", help="log every N-th image (default 1)")
    p.add_argument("--lcm", metavar="URL", help="follow vid_live's output on this LCM URL instead of RUN")
    p.add_argument("--lcm-types", metavar="DIR", help="lcm-gen's Python output (default BUILD/python)")
    p.add_argument("--idle-timeout", type=float, default=3.0, metavar="S",
                   help="--lcm: stop after S seconds without a message (default 3)")
    out = p.add_mutually_exclusive_group(required=True)
    out.add_argument("--rrd", metavar="OUT.rrd", help="write a Rerun recording (open with `rerun OUT.rrd`)")
    out.add_argument("--spawn", action="store_true", help="start the Rerun viewer and stream to it")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ..view import live, offline, scene

    if (args.run_dir is None) == (args.lcm is None):
        raise ConfigurationError("give either RUN_DIR or --lcm URL")
    if args.image_every < 1:
        raise ConfigurationError(f"--image-every must be >= 1, got {args.image_every}")
    if args.run_dir is not None and not Path(args.run_dir).is_dir():
        raise ConfigurationError(f"{args.run_dir}: no such run folder")
    rec = scene.open_recording(args.rrd, args.spawn, Path(args.run_dir).name if args.run_dir else "live")
    sc = scene.Scene(rec)
    if args.run_dir is not None:
        counts = offline.log_run(sc, Path(args.run_dir), Path(args.dataset) if args.dataset else None,
                                 Path(args.tracks) if args.tracks else None, args.image_every)
    else:
        counts = live.follow(sc, args.lcm, live.DEFAULT_CHANNELS, args.lcm_types, args.idle_timeout)
    rec.flush()
    rec.disconnect()
    print("logged " + ", ".join(f"{k} {v}" for k, v in counts.items())
          + (f" -> {args.rrd}" if args.rrd else " -> viewer"))
    return 0
