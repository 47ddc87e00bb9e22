"""``vid-eval mass EST GT``: RMSPE (docs/model.md eq. (56)) and RMSE of a mass estimate, JSON and plot."""
from __future__ import annotations

import argparse

from ..tools.loaders import load_mass
from ..core.mass_metrics import MassResult
from ..core.pairing import pair_scalars
from .common import (abspath, add_output_args, add_pairing_args, finish, pairing_from_args,
                     plot_names)


def add_parser(sub) -> None:
    """Register the ``mass`` sub-command."""
    p = sub.add_parser("mass", help="mass-identification errors (RMSPE, RMSE)",
                       description="RMSPE = sqrt(mean(((m_hat - m)/m)^2)) * 100 % (docs/model.md eq. (56)) "
                                   "and RMSE [kg] of a mass estimate against ground truth; after every change of "
                                   "the true mass, the time until the estimate stays within 5 %; "
                                   "with a sigma column, the NEES.")
    p.add_argument("est", help="mass estimate CSV: timestamp [ns], mass [kg] [, sigma [kg]]")
    p.add_argument("gt", help="ground-truth mass CSV (mass0/data.csv)")
    p.add_argument("--skip", type=float, default=0.0, metavar="S",
                   help="ignore the first S seconds of the estimate (convergence)")
    add_pairing_args(p)
    add_output_args(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Compute, print, write JSON/plot."""
    names = plot_names(args, "mass", ("mass.png",))
    est = load_mass(args.est)
    gt = load_mass(args.gt)
    if args.skip > 0:
        keep = est.t_ns >= est.t_ns[0] + int(round(args.skip * 1e9))
        est = est.subset(keep.nonzero()[0])
    pe, pg = pair_scalars(est, gt, pairing_from_args(args, min_pairs=1))
    res = MassResult(pe, pg, t0_ns=int(gt.t_ns[0]))
    d = res.as_dict()
    out = {"command": "mass", "est": abspath(args.est), "gt": abspath(args.gt),
           "mass_rmspe_percent": res.rmspe, "mass_rmse_kg": res.rmse, "mass": d}
    print(f"pairs {len(pe)}  RMSPE {res.rmspe:.3f} %  RMSE {res.rmse:.5f} kg")
    for ev in d["settle_5pct"]:
        s = "never within 5 %" if ev["settle_s"] is None else f"within 5 % after {ev['settle_s']:.2f} s"
        print(f"  mass change ending at {ev['t_s']:.2f} s (after the truth's start): {s}")
    if "nees_mean" in d:
        print(f"  NEES mean {d['nees_mean']:.2f}, in the 95 % band {100 * d['nees_in_95pct_band']:.0f} % of the time")
    if args.plot:
        from ..plots.mass import plot_mass

        plot_mass(res, args.plot, names["mass.png"], stamp=args.plot_stamp)
    finish(args, out)
    return 0
