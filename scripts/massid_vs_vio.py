#!/usr/bin/env python3
"""Mass identification on the same flights: the study's filters on pose/velocity measurements
versus the VIO (camera + IMU + rotor speeds) with its mass state (issue #21, item 4).

For each preset and seed, vid_sim writes the sequence (features only, 60 s); then

* VIO: ``vid_run --config config/sim`` with ``thrust_scale_random_walk: 0.02`` and
  ``force_rate_random_walk: 0`` (docs/notes/mass-state.md: the setting that makes the mass
  observable) -> ``mass.csv``;
* study: ``vid_massid from-sequence`` turns every sequence into a study run (true pose and
  velocity plus the study's noise, 0.005 rad / 0.01 m / 0.02 m/s at 100 Hz; thrust from the
  measured rotor speeds; initial guess = vehicle.yaml mass, as the VIO's), and
  ``vid_massid run --methods ekf,ukf,msckf,swls`` estimates it.

Every estimate is scored by the same code (vid_eval.core.mass_metrics): RMSPE after the first 5 s
and, after each change of the true mass, the time until the estimate stays within 5 %.

  .venv/bin/python scripts/massid_vs_vio.py --presets vid_loaded spraying payload_heavy \\
      --seeds 1 2 3 --out /tmp/massid_vs_vio

Writes OUT/table.md and OUT/results.json and prints the table.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import subprocess
import sys

import numpy as np
import yaml

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "eval"))

from vid_eval.tools.loaders import load_mass  # noqa: E402
from vid_eval.core.mass_metrics import MassResult  # noqa: E402
from vid_eval.core.pairing import PairingOptions, pair_scalars  # noqa: E402
from vid_eval.core.series import ScalarSeries  # noqa: E402
from vid_eval.tools.sim_runs import config_with_overrides, simulate  # noqa: E402

METHODS = ("ekf", "ukf", "msckf", "swls")
SKIP_NS = 5_000_000_000  # RMSPE after the first 5 s


def _bin(build: pathlib.Path, name: str) -> str:
    path = build / "bin" / name
    if not path.exists():
        sys.exit(f"massid_vs_vio: error: {path} not built (run scripts/build.sh)")
    return str(path)


def _run(cmd: list) -> None:
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"massid_vs_vio: error: {' '.join(cmd[:2])} ... exited {r.returncode}: "
                 f"{r.stderr.strip().splitlines()[-1] if r.stderr.strip() else ''}")


def score(est: ScalarSeries, gt: ScalarSeries) -> dict:
    """RMSPE after 5 s and settling after each change (same pairing as `vid-eval mass`)."""
    keep = np.flatnonzero(est.t_ns >= est.t_ns[0] + SKIP_NS)
    pe, pg = pair_scalars(est.subset(keep), gt, PairingOptions())
    d = MassResult(pe, pg, t0_ns=int(gt.t_ns[0])).as_dict()
    return {"rmspe_pct": d["rmspe_percent"], "settle_s": [s["settle_s"] for s in d["settle_5pct"]]}


def _fmt_settle(values: list) -> str:
    return " / ".join("never" if v is None else f"{v:.2f}" for v in values) or "-"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--presets", nargs="+", default=["vid_loaded", "spraying", "payload_heavy"])
    ap.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3])
    ap.add_argument("--out", required=True, type=pathlib.Path)
    ap.add_argument("--build-dir", type=pathlib.Path, default=REPO / "build")
    a = ap.parse_args()
    vid_sim, vid_run, vid_massid = (_bin(a.build_dir, n) for n in ("vid_sim", "vid_run", "vid_massid"))
    a.out.mkdir(parents=True, exist_ok=True)
    config = config_with_overrides(REPO / "config" / "sim",
                                   {"force_rate_random_walk": 0.0, "thrust_scale_random_walk": 0.02},
                                   a.out / "config_mass")
    cases = [(p, s) for p in a.presets for s in a.seeds]
    results = {}
    for i, (preset, seed) in enumerate(cases):
        name = f"{preset}_s{seed}"
        seq = a.out / "seq" / name
        print(f"[{i + 1}/{len(cases)}] {name}: simulate, vid_run", file=sys.stderr, flush=True)
        simulate(vid_sim, preset, seed, seq, duration=60.0)
        vio = a.out / "vio" / name
        _run([vid_run, "--dataset", str(seq), "--out", str(vio), "--quiet", "--config", str(config)])
        gt = load_mass(seq / "mav0" / "mass0" / "data.csv")
        results[name] = {"preset": preset, "seed": seed, "gt": gt,
                         "vio": score(load_mass(vio / "mass.csv"), gt)}
    print("study filters on the same flights", file=sys.stderr, flush=True)
    data, study = a.out / "study_data", a.out / "study_out"
    _run([vid_massid, "from-sequence", "--out", str(data), "--name", ",".join(results)]
         + [x for name in results for x in ("--sequence", str(a.out / "seq" / name))])
    _run([vid_massid, "run", "--data", str(data), "--out", str(study), "--methods", ",".join(METHODS),
          "--runs-per-case", "1"])
    manifest = yaml.safe_load((data / "manifest.yaml").read_text())
    t0 = {s["name"]: int(s["t0_ns"]) for s in manifest["generator"]["sequences"]}
    for name, r in results.items():
        est = np.genfromtxt(study / "estimates" / name / "sequence" / "run_000.csv", delimiter=",", names=True)
        t_ns = t0[name] + np.round(est["t"] * 1e9).astype(np.int64)
        for m in METHODS:
            r[m] = score(ScalarSeries(t_ns, np.asarray(est[m], dtype=float), None, m), r["gt"])

    rows = ["| flight | seed | " + " | ".join(f"{m.upper()} (pose+vel)" for m in METHODS)
            + " | VIO (cam+IMU+rotors) |",
            "|---|---|" + "---|" * (len(METHODS) + 1)]
    for name, r in results.items():
        cells = [f"{r[k]['rmspe_pct']:.2f} % ({_fmt_settle(r[k]['settle_s'])})" for k in (*METHODS, "vio")]
        rows.append(f"| {r['preset']} | {r['seed']} | " + " | ".join(cells) + " |")
    table = ("Mass RMSPE after the first 5 s (in brackets: seconds until within 5 % for good after "
             "each mass change)\n\n" + "\n".join(rows) + "\n")
    (a.out / "table.md").write_text(table)
    (a.out / "results.json").write_text(json.dumps(
        {n: {k: v for k, v in r.items() if k != "gt"} for n, r in results.items()}, indent=1))
    print(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
