"""``vid-eval traj EST GT``: ATE and RPE of a trajectory against ground truth, JSON and plots."""
from __future__ import annotations

import argparse

from ..core.alignment import ALIGN_MODES
from ..core.ate import compute_ate, compute_ate_pieces
from ..tools.loaders import TRAJ_FORMATS, load_trajectory, reinit_marks
from ..core.phase_metrics import pose_phase_lines, pose_phase_report
from ..core.rpe import DEFAULT_PERCENTAGES, compute_rpe, default_distances, rpe_as_dict
from .common import (abspath, add_output_args, add_pairing_args, add_phase_args, finish,
                     pairing_from_args, phases_from_args, plot_names)


def _distances(text: str):
    try:
        values = [float(x) for x in text.replace(",", " ").split()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a list of distances in m") from None
    if not values or any(v <= 0 for v in values):
        raise argparse.ArgumentTypeError("RPE distances must be positive numbers")
    return values


def add_parser(sub) -> None:
    """Register the ``traj`` sub-command."""
    p = sub.add_parser("traj", help="ATE / RPE of a trajectory against ground truth",
                       description="Absolute trajectory error (position RMSE [m], rotation RMSE "
                                   "[deg]) after alignment, and relative pose error over "
                                   "sub-trajectory lengths.")
    p.add_argument("est", help="estimated trajectory")
    p.add_argument("gt", help="ground-truth trajectory")
    p.add_argument("--align", choices=ALIGN_MODES, default="posyaw",
                   help="alignment of the estimate to the ground truth (default posyaw)")
    p.add_argument("--align-frames", type=int, default=-1, metavar="N",
                   help="align on the first N associated poses (default: all)")
    p.add_argument("--est-format", choices=TRAJ_FORMATS, default=None,
                   help="format of EST (default: detect; tum = 'ts tx ty tz qx qy qz qw' in s, "
                        "euroc = ns CSV with p, q(w,x,y,z), state = our state.csv)")
    p.add_argument("--gt-format", choices=TRAJ_FORMATS, default=None, help="format of GT (default: detect)")
    p.add_argument("--one-alignment", action="store_true",
                   help="align the whole estimate at once even where vid_run marked a "
                        "re-initialization (default: each piece in its own frame)")
    p.add_argument("--rpe-distances", type=_distances, default=None, metavar="D1,D2,...",
                   help="RPE sub-trajectory lengths [m] (default 10,20,30,40,50%% of the GT length)")
    add_pairing_args(p)
    add_phase_args(p)
    add_output_args(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Compute, print, write JSON/plots."""
    names = plot_names(args, "traj", ("traj_views.png", "traj_errors.png", "traj_rpe.png"))
    est = load_trajectory(args.est, args.est_format)
    gt = load_trajectory(args.gt, args.gt_format)
    phases = phases_from_args(args, args.gt)
    # After a re-initialization vid_run's estimate is in a new world frame (its marker lines):
    # one alignment for the whole file would score the frame change, not the estimator.
    marks = [] if args.one_alignment else reinit_marks(args.est)
    pieces = None
    if len(marks):
        pieces = compute_ate_pieces(est, gt, marks, args.align, args.align_frames,
                                    pairing_from_args(args, min_pairs=3))
        res = pieces.pooled
    else:
        res = compute_ate(est, gt, args.align, args.align_frames, pairing_from_args(args, min_pairs=3))
    pct = None
    if args.rpe_distances is None:
        pct = list(DEFAULT_PERCENTAGES)
        distances = [d for d in default_distances(res.gt, pct) if d > 0]
    else:
        distances = args.rpe_distances
    segments = compute_rpe(res.est_aligned, res.gt, distances)
    out = {
        "command": "traj",
        "est": abspath(args.est),
        "gt": abspath(args.gt),
        "ate_pos_rmse_m": res.pos_rmse,
        "ate_rot_rmse_deg": res.rot_rmse_deg,
        "ate": res.as_dict(),
        "rpe": rpe_as_dict(segments, pct),
        "gt_path_length_m": res.gt.path_length(),
    }
    if pieces is not None:
        out["ate_pieces"] = pieces.as_dict()
        for t, a in zip(pieces.starts_ns, pieces.pieces):
            print(f"piece from {t * 1e-9:.3f} s: {len(a.pos_err)} pairs, ATE pos RMSE {a.pos_rmse:.4f} m "
                  f"(aligned on its own: vid_run re-initialized)")
    print(f"pairs {len(res.pos_err)}  align {args.align}  ATE pos RMSE {res.pos_rmse:.4f} m  "
          f"rot RMSE {res.rot_rmse_deg:.3f} deg")
    for s in segments:
        if len(s.trans_err):
            print(f"RPE {s.distance:8.3f} m: trans RMSE {s.as_dict()['trans_m']['rmse']:.4f} m "
                  f"({s.as_dict()['trans_percent']['mean']:.2f} % mean), rot RMSE "
                  f"{s.as_dict()['rot_deg']['rmse']:.3f} deg  [{len(s.trans_err)} pairs]")
        else:
            print(f"RPE {s.distance:8.3f} m: no sub-trajectory of that length")
    if phases is not None:  # errors of the whole-run alignment, split by phase
        out["phases"] = pose_phase_report(phases, res.gt.t_ns, res.pos_err, res.rot_err_deg)
        print("\n".join(pose_phase_lines(out["phases"])))
    if args.plot:
        from ..plots.trajectory import plot_errors, plot_rpe, plot_views

        stamp = args.plot_stamp
        plot_views(res, args.plot, full_gt=gt, name=names["traj_views.png"], stamp=stamp)
        plot_errors(res, args.plot, phases=phases, name=names["traj_errors.png"], stamp=stamp)
        plot_rpe(segments, args.plot, name=names["traj_rpe.png"], stamp=stamp)
    finish(args, out)
    return 0
