#!/usr/bin/env bash
# The README's demo command: install, build, simulate a short VID-like flight with images that
# starts and ends on the ground with the rotors stopped (take-off, figure-8, landing), estimate
# pose and external force, evaluate against ground truth (per flight phase), print numbers,
# write plots.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${VID_BUILD_DIR:-$ROOT/build}"
OUT="${VID_DEMO_OUT:-$ROOT/demo_out}"
SCENARIO="${VID_DEMO_SCENARIO:-$ROOT/config/sim/takeoff_landing_short.yaml}"
DURATION="${VID_DEMO_DURATION:-22}"

bash "$ROOT/scripts/setup.sh"
bash "$ROOT/scripts/build.sh"
BIN="$BUILD/bin"
mkdir -p "$OUT"

echo "[demo] simulating $DURATION s of $(basename "$SCENARIO") with stereo images into $OUT/seq"
# The ground truth's world starts at a heading drawn from the seed, as a motion-capture world
# would; the estimator starts at its own, and every world-frame score aligns first.
"$BIN/vid_sim" --scenario "$SCENARIO" --out "$OUT/seq" --duration "$DURATION" --seed 1 --initial-heading random
"$BIN/vid_info" "$OUT/seq"
echo "[demo] estimating (dynamics mode)"
"$BIN/vid_run" --dataset "$OUT/seq" --out "$OUT/run" --mode dynamics --config "$ROOT/config/sim"
echo "[demo] evaluating"
GT="$OUT/seq/mav0/state_groundtruth_estimate0/data.csv"
"$ROOT/.venv/bin/vid-eval" traj "$OUT/run/trajectory_tum.txt" "$GT" --align posyaw \
  --json "$OUT/eval_traj.json" --plot "$OUT/plots"
"$ROOT/.venv/bin/vid-eval" force "$OUT/run/force.csv" "$OUT/seq/mav0/force0/data.csv" --frame world \
  --json "$OUT/eval_force.json" --plot "$OUT/plots"
"$ROOT/.venv/bin/python" - "$OUT" <<'PY'
import json, sys, pathlib
out = pathlib.Path(sys.argv[1])
s = json.loads((out / "run" / "summary.json").read_text())
print("[demo] ---------------------------------------------")
for k in ("ate_posyaw_m", "force_rmse_world_mps2", "force_rmse_body_mps2", "real_time_factor"):
    if k in s:
        print(f"[demo] {k:26s} {s[k]:.4f}")
if "force_alignment" in s:
    print(f"[demo] world force scored after the {s['force_alignment']['mode']} alignment "
          f"(heading of the ground truth's world: {s['force_alignment']['yaw_deg']:.1f} deg)")
if "accel" in s:
    a = s["accel"]
    print(f"[demo] accelerometer: {a['rejected']} of {a['samples']} samples rejected, "
          f"{a.get('downweighted', 0)} down-weighted, {a['force_jumps']} force jumps")
if "flight_phase" in s:
    fp = s["flight_phase"]
    events = ", ".join(f"{e['event']} at {(e['t_ns'] - fp['events'][0]['t_ns']) * 1e-9:+.1f} s" for e in fp["events"])
    print(f"[demo] flight phase: {fp['landed_s']:.1f} s landed, {fp['airborne_s']:.1f} s airborne"
          f" ({fp['lift_offs']} lift-off, {fp['touchdowns']} touchdown; {events}); now {fp['final']}")
print(f"[demo] plots in {out / 'plots'}")
PY
