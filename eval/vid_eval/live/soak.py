"""``vid-soak``: vid_replay at real time into vid_live for an hour, with faults injected.

  vid-soak --dataset SEQ --out DIR [--minutes 60 | --loops N] [--transport udpm|log]

The dataset is looped (``vid_replay --loop``): pass k is shifted by k times the sequence's
IMU span, so a sequence that ends where it started (``takeoff_landing_short``: on the ground,
same pose, rotors stopped) flies the same hop again and again. Every pass injects its own
faults (dropped images, duplicated IMU messages, reordering, late and malformed messages, a
camera stall). Meanwhile vid_live's resident memory is sampled; at the end vid_live's
counters are compared with what vid_replay injected (:mod:`vid_eval.live.fault_counts`).

Transports: ``udpm`` (default) publishes at real time on UDP multicast confined to this host
(``ttl=0``) with a 4 MB receive buffer; ``log`` writes an LCM event log first and lets vid_live
read it as fast as it can (``file://LOG?speed=0``; deterministic, what the tests use).

Writes ``DIR/soak.json`` (RSS samples, growth, counters, mismatches, ATE) and exits 0 when
vid_live ran to the end, counted every fault exactly and its RSS grew by at most
``--max-growth`` after the first pass; 1 otherwise; 2 on usage errors.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import pathlib
import subprocess
import sys
import time
from typing import List, Optional

import numpy as np

from ..errors import InputFormatError
from ..tools.sim_runs import REPO
from ..usage import OneLineParser
from .fault_counts import fault_mismatches

UDPM_URL = "udpm://239.255.76.67:{port}?ttl=0&recv_buf_size=4194304"
# Per pass (22 s of takeoff_landing_short): ~2 % of images dropped, duplicates, 20 ms
# reordering inside vid_live's 30 ms window, late messages beyond it, malformed payloads and
# one 0.5 s camera stall in the middle of the flight.
DEFAULT_FAULTS = ["--drop-images", "0.02", "--duplicate-imu", "0.002", "--reorder", "0.01",
                  "--reorder-max-ms", "20", "--late", "0.0005", "--malformed", "4",
                  "--camera-stall", "12", "0.5"]


def _imu_range_ns(dataset: pathlib.Path) -> tuple:
    """First and last IMU time [ns]; their difference is the shift between two passes of
    vid_replay --loop."""
    csv = dataset / "mav0" / "imu0" / "data.csv"
    if not csv.is_file():
        csv = dataset / "imu0" / "data.csv"
    if not csv.is_file():
        raise InputFormatError(str(dataset), "no imu0/data.csv (not a dataset folder)")
    stamps = [int(line.split(",", 1)[0]) for line in csv.read_text().splitlines()
              if line and not line.startswith("#")]
    if len(stamps) < 2:
        raise InputFormatError(str(csv), "fewer than two IMU samples")
    return stamps[0], stamps[-1]


def _rss_kb(pid: int) -> Optional[int]:
    """VmRSS of a running process [kB], None once it has gone."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def _looped_ground_truth(dataset: pathlib.Path, loops: int, span_ns: int):
    """The ground truth of the looped replay: pass k shifted by k * span, [first, first+span)
    for all passes but the last (as vid_replay publishes)."""
    from ..tools.loaders import load_euroc_pose_csv
    from ..core.series import Trajectory
    gt = load_euroc_pose_csv(dataset / "mav0" / "state_groundtruth_estimate0" / "data.csv")
    inner = gt.t_ns < gt.t_ns[0] + span_ns
    t, p, q = [], [], []
    for k in range(loops):
        sel = inner if k + 1 < loops else np.ones(len(gt), bool)
        t.append(gt.t_ns[sel] + k * span_ns)
        p.append(gt.p[sel])
        q.append(gt.q[sel])
    return Trajectory(np.concatenate(t), np.concatenate(p), np.concatenate(q), gt.source)


def _ate(out: pathlib.Path, dataset: pathlib.Path, loops: int, span_ns: int) -> dict:
    """posyaw ATE over the whole run and over the last pass [m]."""
    from ..core.ate import compute_ate
    from ..tools.loaders import load_trajectory
    est = load_trajectory(out / "trajectory_tum.txt")
    gt = _looped_ground_truth(dataset, loops, span_ns)
    whole = compute_ate(est, gt, "posyaw")
    last = est.subset(np.flatnonzero(est.t_ns >= gt.t_ns[0] + (loops - 1) * span_ns))
    res = {"whole_m": float(whole.pos_rmse)}
    if len(last) > 10:
        res["last_pass_m"] = float(compute_ate(last, gt, "posyaw").pos_rmse)
    return res


def _udp_rcvbuf_errors() -> Optional[int]:
    """Datagrams the kernel dropped since boot because a UDP socket's receive buffer was full
    (Linux /proc/net/snmp ``Udp: RcvbufErrors``); None where that file does not exist."""
    try:
        rows = [ln.split() for ln in pathlib.Path("/proc/net/snmp").read_text().splitlines() if ln.startswith("Udp:")]
        return int(rows[1][rows[0].index("RcvbufErrors")])
    except (OSError, IndexError, ValueError):
        return None


def _estimated_until_ns(trajectory: pathlib.Path) -> Optional[int]:
    """Data time [ns] of the last whole line vid_live has written to its TUM trajectory so far
    (the file grows while it runs; buffered, so a few lines behind); None before the first."""
    try:
        with open(trajectory, "rb") as f:
            f.seek(0, os.SEEK_END)
            size = f.tell()
            f.seek(max(0, size - 1024))
            tail = f.read().decode("ascii", "replace")
    except OSError:
        return None
    lines = [ln for ln in tail.split("\n")[:-1] if ln and not ln.startswith("#")]  # last one may be partial
    if not lines:
        return None
    try:
        sec, _, frac = lines[-1].split(" ", 1)[0].partition(".")
        return int(sec) * 1_000_000_000 + int((frac + "000000000")[:9])
    except ValueError:
        return None


def _growth(samples: List[dict], warmup_s: float) -> dict:
    """RSS after warm-up (the first sample whose data time is at or after ``warmup_s``) and the
    largest later growth relative to it."""
    after = [s for s in samples if s["data_s"] is not None and s["data_s"] >= warmup_s and s["vid_live_kb"]]
    if not after:
        return {"baseline_kb": None, "max_kb": None, "growth": None, "samples": 0}
    base = after[0]["vid_live_kb"]
    peak = max(s["vid_live_kb"] for s in after)
    return {"baseline_kb": base, "max_kb": peak, "last_kb": after[-1]["vid_live_kb"],
            "growth": (peak - base) / base, "samples": len(after)}


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of vid-soak."""
    p = OneLineParser(prog="vid-soak", description=__doc__,
                      formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dataset", type=pathlib.Path, required=True, help="dataset folder to loop")
    p.add_argument("--out", type=pathlib.Path, required=True, help="output folder")
    length = p.add_mutually_exclusive_group()
    length.add_argument("--minutes", type=float, default=60.0, help="soak length (default 60)")
    length.add_argument("--loops", type=int, default=None, help="passes over the dataset instead")
    p.add_argument("--transport", choices=["udpm", "log"], default="udpm")
    p.add_argument("--port", type=int, default=7667, help="udpm port (default 7667)")
    p.add_argument("--config", type=pathlib.Path, default=REPO / "config" / "sim")
    p.add_argument("--build-dir", type=pathlib.Path,
                   default=pathlib.Path(os.environ.get("VID_BUILD_DIR", str(REPO / "build"))))
    p.add_argument("--sample-s", type=float, default=60.0, help="RSS sampling period (default 60 s)")
    p.add_argument("--max-growth", type=float, default=0.05, help="allowed RSS growth (default 0.05)")
    p.add_argument("--warmup-s", type=float, default=None,
                   help="growth is measured from the first sample after this much data time [s] "
                        "(default: two passes)")
    p.add_argument("--live-out", type=pathlib.Path, default=None,
                   help="vid_live's output folder (default OUT/live); a tmpfs such as /dev/shm keeps "
                        "the disk writeback stalls of a busy machine out of the hour")
    p.add_argument("--fault-seed", type=int, default=1)
    p.add_argument("--no-faults", action="store_true", help="replay without injected faults")
    p.add_argument("--lag", type=float, default=None, metavar="S",
                   help="run vid_live with --lag S (fixed-lag smoothing on: its memory is in the soak too)")
    return p


def main(argv: Optional[List[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    if args.loops is not None and args.loops < 1:
        print("vid-soak: error: --loops must be >= 1", file=sys.stderr)
        return 2
    if args.minutes <= 0 or args.sample_s <= 0:
        print("vid-soak: error: --minutes and --sample-s must be > 0", file=sys.stderr)
        return 2
    if args.lag is not None and not args.lag > 0:
        print(f"vid-soak: error: --lag must be > 0 s, got {args.lag:g}", file=sys.stderr)
        return 2
    bins = {n: args.build_dir / "bin" / n for n in ("vid_replay", "vid_live")}
    for n, b in bins.items():
        if not b.exists():
            print(f"vid-soak: error: {b} not built (run scripts/build.sh or pass --build-dir)",
                  file=sys.stderr)
            return 2
    try:
        t_first_ns, t_last_ns = _imu_range_ns(args.dataset)
        span_ns = t_last_ns - t_first_ns
    except InputFormatError as exc:
        print(f"vid-soak: error: {exc}", file=sys.stderr)
        return 2
    loops = args.loops or max(1, math.ceil(args.minutes * 60e9 / span_ns))
    warmup_s = args.warmup_s if args.warmup_s is not None else 2 * span_ns * 1e-9
    out = args.out
    out.mkdir(parents=True, exist_ok=True)
    faults = [] if args.no_faults else DEFAULT_FAULTS + ["--fault-seed", str(args.fault_seed)]
    report_path = out / "replay_report.json"
    live_out = args.live_out or out / "live"
    (live_out / "trajectory_tum.txt").unlink(missing_ok=True)  # an old run's would fake progress
    udp_drops_before = _udp_rcvbuf_errors()
    replay_cmd = [str(bins["vid_replay"]), "--dataset", str(args.dataset), "--loop", str(loops),
                  "--report", str(report_path), "--quiet", *faults]
    live_cmd = [str(bins["vid_live"]), "--sensors", str(args.dataset), "--config", str(args.config),
                "--out", str(live_out), "--quiet", *(["--lag", f"{args.lag:g}"] if args.lag else [])]
    log_path = out / "soak.log"
    print(f"[soak] {loops} passes of {span_ns * 1e-9:.3f} s ({loops * span_ns / 60e9:.1f} min of data) "
          f"over {args.transport}", flush=True)
    replay_err = open(out / "vid_replay.stderr", "w")
    live_err = open(out / "vid_live.stderr", "w")
    replay = None
    if args.transport == "udpm":
        url = UDPM_URL.format(port=args.port)
        live = subprocess.Popen(live_cmd + ["--lcm-url", url, "--idle-timeout", "10"], stderr=live_err)
        time.sleep(1.0)  # subscribed before the first message
        replay = subprocess.Popen(replay_cmd + ["--lcm-url", url], stderr=replay_err)
    else:
        rc = subprocess.run(replay_cmd + ["--lcm-url", "memq://", "--fast", "--log", str(log_path)],
                            stderr=replay_err).returncode
        if rc != 0:
            print(f"vid-soak: error: vid_replay exited with {rc} (see {out / 'vid_replay.stderr'})",
                  file=sys.stderr)
            return 1
        live = subprocess.Popen(live_cmd + ["--lcm-url", f"file://{log_path}?speed=0"], stderr=live_err)
    samples: List[dict] = []
    t0 = time.monotonic()
    next_sample = 0.0
    while True:
        pid, status, usage = os.wait4(live.pid, os.WNOHANG)
        if pid:  # exited; wait4 also gives its peak RSS
            live.returncode = live_rc = os.waitstatus_to_exitcode(status)
            break
        now = time.monotonic() - t0
        if now >= next_sample:
            # Warm-up is data time (how far vid_live has estimated), not wall time: a log is read
            # as fast as vid_live can.
            until_ns = _estimated_until_ns(live_out / "trajectory_tum.txt")
            data_s = None if until_ns is None else (until_ns - t_first_ns) * 1e-9
            s = {"t_s": round(now, 3), "data_s": None if data_s is None else round(data_s, 3),
                 "vid_live_kb": _rss_kb(live.pid), "vid_replay_kb": _rss_kb(replay.pid) if replay else None}
            samples.append(s)
            if s["vid_live_kb"]:
                d = "" if data_s is None else f" (data {data_s / 60:6.2f} min)"
                print(f"[soak] {now / 60:6.1f} min{d}  vid_live RSS {s['vid_live_kb'] / 1024:.1f} MB",
                      flush=True)
            next_sample += args.sample_s
        time.sleep(min(0.2, args.sample_s))
    if replay and replay.poll() is None and live_rc != 0:
        replay.terminate()  # vid_live stopped early: no point publishing the rest of the hour
    replay_rc = replay.wait() if replay else 0
    replay_err.close()
    live_err.close()
    if args.transport == "log" and log_path.exists():
        log_path.unlink()  # ~20 MB per second of stereo images
    result = {"transport": args.transport, "loops": loops, "pass_s": span_ns * 1e-9,
              "wall_s": time.monotonic() - t0, "vid_live_rc": live_rc, "vid_replay_rc": replay_rc,
              "rss_samples": samples, "vid_live_peak_rss_kb": usage.ru_maxrss,
              "rss": _growth(samples, warmup_s), "live_out": str(live_out), "lag_s": args.lag}
    udp_drops_after = _udp_rcvbuf_errors()
    if args.transport == "udpm" and udp_drops_before is not None and udp_drops_after is not None:
        # every UDP socket of the machine: an upper bound of what vid_live's socket lost
        result["udp_rcvbuf_errors"] = udp_drops_after - udp_drops_before
    ok = live_rc == 0 and replay_rc == 0
    summary_path = live_out / "summary.json"
    if report_path.exists() and summary_path.exists():
        report = json.loads(report_path.read_text())
        summary = json.loads(summary_path.read_text())
        result["injected"] = report["faults"]
        result["counted"] = summary["faults"]
        result["mismatches"] = fault_mismatches(report, summary)
        result["health"] = summary.get("health")
        result["lift_offs"] = summary.get("flight_phase", {}).get("lift_offs")
        ok &= not result["mismatches"]
        try:
            result["ate_posyaw"] = _ate(live_out, args.dataset, loops, span_ns)
        except (InputFormatError, OSError, ValueError) as exc:
            result["ate_posyaw"] = {"error": str(exc)}
    else:
        ok = False
    growth = result["rss"]["growth"]
    ok &= growth is not None and growth <= args.max_growth
    result["ok"] = bool(ok)
    (out / "soak.json").write_text(json.dumps(result, indent=2) + "\n")
    g = "n/a" if growth is None else f"{100 * growth:+.2f} %"
    print(f"[soak] {'ok' if ok else 'FAILED'}: {loops} passes in {result['wall_s'] / 60:.1f} min, "
          f"vid_live exit {live_rc}, RSS growth after warm-up {g}, "
          f"{len(result.get('mismatches', []))} counter mismatches; {out / 'soak.json'}", flush=True)
    for m in result.get("mismatches", []):
        print(f"[soak]   {m}", flush=True)
    if result.get("udp_rcvbuf_errors"):
        print(f"[soak]   the kernel dropped {result['udp_rcvbuf_errors']} UDP datagrams for full receive "
              f"buffers during the run (/proc/net/snmp RcvbufErrors)", flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
