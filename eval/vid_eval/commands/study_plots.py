"""``vid-eval massid-plots`` and ``vid-eval elm-plots``: the mass-identification study's figures
(vid_eval.plots.massid_study, vid_eval.plots.elm_study), which ``vid_massid report`` and
``vid_massid elm-study --plots`` run."""
from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import VidEvalError
from ..plots import elm_study, massid_study


def add_parser(sub) -> None:
    """Register ``massid-plots`` and ``elm-plots``."""
    p = sub.add_parser("massid-plots", help="figures of a `vid_massid run` output folder",
                       description="Per trajectory, the true mass under each method's estimate (a row per "
                                   "mass profile, a column per method), and the commanded inputs "
                                   "(inputs.png), from RESULTS/runs.csv and RESULTS/estimates/.")
    p.add_argument("--results", required=True, type=Path, help="output folder of `vid_massid run`")
    p.add_argument("--out", required=True, type=Path, help="folder for the PNG files")
    p.set_defaults(run=run_massid)
    p = sub.add_parser("elm-plots", help="figures of a `vid_massid elm-study` output folder",
                       description="OUT/figures/elm_<trajectory>.png from OUT/series/, and "
                                   "elm_hidden_nodes.png from table1_hidden_nodes.csv if present.")
    p.add_argument("out", type=Path, help="output folder of `vid_massid elm-study`")
    p.set_defaults(run=run_elm)


def run_massid(args: argparse.Namespace) -> int:
    runs = massid_study.find_runs(args.results)  # a bad file: ValueError, one line from cli.main
    args.out.mkdir(parents=True, exist_ok=True)
    trajectories = massid_study.ordered({t for (t, _) in runs}, massid_study.TRAJ_ORDER)
    written = [massid_study.plot_trajectory(t, runs, args.out) for t in trajectories]
    written.append(massid_study.plot_inputs(runs, args.out))
    for path in written:
        print(path)
    return 0


def run_elm(args: argparse.Namespace) -> int:
    if not (args.out / "series").is_dir() and not (args.out / "table1_hidden_nodes.csv").exists():
        raise VidEvalError(f"{args.out}: no series/ folder or table1_hidden_nodes.csv (vid_massid elm-study output)")
    for path in elm_study.plot_trajectories(args.out) + elm_study.plot_hidden_nodes(args.out):
        print(path)
    return 0
