"""``vid-eval force EST GT``: external-force RMSE per axis and of the norm, JSON and plot.

A world-frame comparison first rotates the estimate into the ground truth's world with the
trajectory alignment (:mod:`vid_eval.tools.gauge`): the estimator's world frame has its own heading.
"""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Optional, Tuple

import numpy as np

from ..errors import AssociationError, ConfigurationError, InputFormatError
from ..core.alignment import ALIGN_MODES
from ..core.force_frames import Mass, mass_at, newton_to_accel, rotate_series
from ..core.force_metrics import force_errors
from ..core.force_response import force_response
from ..tools.gauge import (WorldGauge, find_estimate_trajectory, find_gt_trajectory, rotate_orientations,
                     rotate_world, world_gauge_from_files)
from ..tools.loaders import (find_mass_source, load_force_estimate, load_force_gt, load_mass,
                       load_state, load_trajectory, load_vehicle_mass)
from ..core.pairing import pair_vectors
from ..core.phase_metrics import force_phase_lines, force_phase_report
from ..core.phases import PhaseSegmentation
from ..core.series import Trajectory, VectorSeries
from .common import (abspath, add_output_args, add_pairing_args, add_phase_args, finish,
                     pairing_from_args, phases_from_args, plot_names)


def add_parser(sub) -> None:
    """Register the ``force`` sub-command."""
    p = sub.add_parser("force", help="external-force errors against force0 ground truth",
                       description="RMSE per axis and of the error norm of the mass-normalized "
                                   "external force [m/s^2] (and [N] when the mass is known).")
    p.add_argument("est", help="our force.csv or state.csv")
    p.add_argument("gt", help="ground-truth force CSV (force0/data.csv: world frame, N)")
    p.add_argument("--frame", choices=("world", "body"), default="world",
                   help="frame of the comparison (default world: the estimate is rotated into "
                        "the ground truth's world by the trajectory alignment, see --align)")
    p.add_argument("--align", choices=ALIGN_MODES, default="posyaw",
                   help="world frame: alignment of the estimate's trajectory to the ground "
                        "truth's whose rotation is applied to the force (default posyaw, as "
                        "`vid-eval traj`; none = the two share one world frame)")
    p.add_argument("--align-frames", type=int, default=-1, metavar="N",
                   help="fit the alignment on the first N associated poses (default: all)")
    p.add_argument("--traj", default=None, metavar="EST_TRAJ",
                   help="the estimate's trajectory for the alignment (TUM / EuRoC / state.csv; "
                        "default: --state, else state.csv or trajectory_tum.txt next to EST)")
    p.add_argument("--est-format", choices=("force", "state"), default=None,
                   help="EST is force.csv or state.csv (default: detect by column count)")
    p.add_argument("--mass", type=float, default=None, metavar="KG",
                   help="vehicle mass; default: mav0/mass0/data.csv, else vehicle.yaml next to GT")
    p.add_argument("--mass-file", default=None, metavar="CSV|YAML",
                   help="mass0-style CSV or vehicle.yaml to take the mass from")
    p.add_argument("--gt-frame", choices=("world", "body"), default="world",
                   help="frame of GT (default world, as force0)")
    p.add_argument("--gt-unit", choices=("N", "m/s^2"), default="N",
                   help="unit of GT (default N, as force0)")
    p.add_argument("--state", default=None, metavar="STATE_CSV",
                   help="our state.csv: estimated q_WI for frame changes and the world 3-sigma band")
    p.add_argument("--gt-state", default=None, metavar="POSES",
                   help="ground-truth poses (EuRoC CSV / TUM) for the alignment and to rotate GT "
                        "between frames (default: mav0/state_groundtruth_estimate0 next to GT)")
    add_pairing_args(p)
    add_phase_args(p)
    add_output_args(p)
    p.set_defaults(run=run)


def _detect_est_format(path: str) -> str:
    with open(path, "r", encoding="utf-8") as fh:
        for raw in fh:
            t = raw.strip()
            if t and not t.startswith("#"):
                return "state" if len(t.split(",")) > 20 else "force"
    raise InputFormatError(path, "no data rows (empty file)")


def _resolve_mass(args: argparse.Namespace) -> Tuple[Optional[Mass], str]:
    """Mass from --mass, --mass-file, or next to the ground truth; (None, '') when absent."""
    if args.mass is not None:
        if not args.mass > 0:
            raise ConfigurationError(f"--mass must be positive, got {args.mass}")
        return float(args.mass), "--mass"
    src = Path(args.mass_file) if args.mass_file else find_mass_source(args.gt)
    if src is None:
        return None, ""
    if src.suffix in (".yaml", ".yml"):
        return load_vehicle_mass(src), str(src)
    return load_mass(src), str(src)


def _load_estimate(args) -> Tuple[VectorSeries, Optional[VectorSeries], Optional[Trajectory], str]:
    """Body series, world series (force.csv only), estimated orientations and the format."""
    fmt = args.est_format or _detect_est_format(args.est)
    orient = load_state(args.state).trajectory() if args.state else None
    if fmt == "state":
        st = load_state(args.est)
        return st.force_body(), None, orient or st.trajectory(), fmt
    body, world = load_force_estimate(args.est)
    return body, world, orient, fmt


def band_orientation(est_path: str, orient: Optional[Trajectory]) -> Optional[Trajectory]:
    """Orientations for the world 3-sigma band of a force.csv: ``--state`` when given, else
    the run's own state.csv / trajectory_tum.txt next to it (force.csv's sigma is body-frame,
    so without orientations the world plot would have no band, issue #25)."""
    if orient is not None:
        return orient
    found = find_estimate_trajectory(est_path)
    return None if found is None else load_trajectory(str(found))


def _estimate_in(frame: str, body: VectorSeries, world: Optional[VectorSeries],
                 orient: Optional[Trajectory], gauge: Optional[WorldGauge] = None) -> VectorSeries:
    """The estimate in ``frame``; in the ground truth's world when ``gauge`` is given, else the
    estimator's own. World values come from force.csv's fw columns when present; the world
    3-sigma band from rotating the body sigma with the orientations, in one step (q_GI) when
    there is a gauge. Samples without an orientation at their time drop."""
    if frame == "body":
        return body
    if gauge is not None and orient is not None:
        orient = rotate_orientations(orient, gauge)
    if world is None:
        if orient is None:
            raise ConfigurationError("EST has only body-frame force: give --state for the world frame")
        return rotate_series(body, orient, "world")
    if gauge is not None:
        world = rotate_world(world, gauge)  # fw columns carry no sigma: values only
    if orient is None:
        return world
    rot = rotate_series(body, orient, "world")
    idx = np.minimum(np.searchsorted(world.t_ns, rot.t_ns), len(world.t_ns) - 1)
    same = world.t_ns[idx] == rot.t_ns
    if not np.any(same):
        raise AssociationError(f"{world.source}: no force row at the times of the orientations")
    return VectorSeries(rot.t_ns[same], world.values[idx[same]], "world", "m/s^2",
                        rot.sigma[same], world.source)


def _gt_poses_path(args) -> Optional[str]:
    """--gt-state, else the dataset's ground-truth poses next to GT, else None."""
    if args.gt_state:
        return args.gt_state
    found = find_gt_trajectory(args.gt)
    return None if found is None else str(found)


def _world_gauge(args, est_fmt: str) -> WorldGauge:
    """The alignment of the estimator's world to the ground truth's (``--align``)."""
    est_traj = args.traj or args.state or (args.est if est_fmt == "state" else None)
    if est_traj is None:
        found = find_estimate_trajectory(args.est)
        est_traj = None if found is None else str(found)
    return world_gauge_from_files(est_traj, _gt_poses_path(args), args.align, args.align_frames,
                                  pairing_from_args(args, min_pairs=3))


def _paired(args, frame: str, loaded) -> Tuple[VectorSeries, VectorSeries, Optional[WorldGauge]]:
    """Estimate and truth in ``frame`` (the world one after the gauge), paired; the gauge."""
    body, world, orient_est, est_fmt, gt = loaded
    gauge = _world_gauge(args, est_fmt) if frame == "world" else None
    band = band_orientation(args.est, orient_est) if world is not None and frame == "world" else orient_est
    est = _estimate_in(frame, body, world, band, gauge)
    if gt.frame != frame:
        gt = rotate_series(gt, _gt_orientation(args, orient_est, frame), frame)
    pe, pg = pair_vectors(est, gt, pairing_from_args(args))
    return pe, pg, gauge


def run(args: argparse.Namespace) -> int:
    """Compute, print, write JSON/plot."""
    names = plot_names(args, "force", (f"force_{args.frame}.png", f"force_response_{args.frame}.png"))
    body, world, orient_est, est_fmt = _load_estimate(args)
    gt = load_force_gt(args.gt)
    gt.frame = args.gt_frame
    gt.unit = args.gt_unit
    mass, mass_src = _resolve_mass(args)
    if gt.unit == "N":
        if mass is None:
            raise ConfigurationError(
                f"{args.gt}: ground truth is in N but no mass found: give --mass KG "
                f"(or mav0/mass0/data.csv or vehicle.yaml next to the dataset)")
        gt = newton_to_accel(gt, mass)
    phases = phases_from_args(args, args.gt)
    loaded = (body, world, orient_est, est_fmt, gt)
    pe, pg, gauge = _paired(args, args.frame, loaded)
    popt = pairing_from_args(args)
    m = None if mass is None else mass_at(mass, pg.t_ns)
    res = force_errors(pe, pg, m)
    out = {"command": "force", "est": abspath(args.est), "gt": abspath(args.gt),
           "mass_source": mass_src or None, "frame": args.frame, "force": res.as_dict(),
           f"force_rmse_{args.frame}_mps2": res.rmse_norm}
    if gauge is not None:
        out["alignment"] = gauge.as_dict()
    resp = force_response(pe, pg, offset_ns=popt.offset_ns)  # lag, steps, pulses
    out["response"] = resp.as_dict()
    ax = res.rmse_axis
    frame = args.frame if gauge is None else f"world {gauge.describe()}"
    line = (f"pairs {len(res.err)}  frame {frame}  RMSE x {ax[0]:.4f} y {ax[1]:.4f} "
            f"z {ax[2]:.4f} norm {res.rmse_norm:.4f} m/s^2")
    if m is not None:
        line += f"  norm {out['force']['rmse_N']['norm']:.4f} N"
    print(line)
    print(resp.summary_line())
    if phases is not None:
        out["phases"] = _phase_report(args, phases, loaded, (pe, pg, m), mass, resp)
        print("\n".join(force_phase_lines(out["phases"])))
    if args.plot:
        from ..plots.force import plot_force

        if pe.sigma is None:  # say why the plot has no band rather than leave it out silently
            print(f"note: no ±3σ band in the {args.frame} frame: force.csv's sigma is body-frame and "
                  f"no orientations were found (give --state STATE_CSV)")
        from ..plots.force_response import plot_force_response

        plot_force(res, args.plot, names[f"force_{args.frame}.png"], phases=phases,
                   stamp=args.plot_stamp)
        plot_force_response(resp, args.plot, names[f"force_response_{args.frame}.png"],
                            stamp=args.plot_stamp)
    finish(args, out)
    return 0


def _phase_report(args, phases: PhaseSegmentation, loaded, main, mass, resp) -> dict:
    """Errors per flight phase in the command's frame and, when its inputs are there, in the
    other one (world: the gauge's trajectories; body: ground-truth orientations)."""
    frames = {args.frame: main}
    other = "body" if args.frame == "world" else "world"
    skipped = {}
    try:
        oe, og, _ = _paired(args, other, loaded)
        frames[other] = (oe, og, None if mass is None else mass_at(mass, og.t_ns))
    except (ConfigurationError, AssociationError) as exc:  # that frame's inputs are missing
        skipped[other] = str(exc)
    return force_phase_report(phases, frames, resp, skipped)


def _gt_orientation(args, orient_est: Optional[Trajectory], frame: str) -> Trajectory:
    """Orientations ``q_WI`` to rotate GT between frames: the ground-truth poses; the
    estimate's own orientations only with ``--align none`` (they are in the estimator's world,
    which is the ground truth's only when the two are known to share one)."""
    gt_poses = _gt_poses_path(args)
    if gt_poses is not None:
        return load_trajectory(gt_poses)
    if orient_est is not None and args.align == "none":
        return orient_est
    raise ConfigurationError(
        f"ground truth is in the {args.gt_frame} frame: give --gt-state (ground-truth poses) to "
        f"rotate it into the {frame} frame (or --state with --align none when the "
        f"estimate shares the ground truth's world frame)")
