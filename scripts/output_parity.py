#!/usr/bin/env python3
"""Outputs of every program on fixed seeds, and their comparison: the check of a refactor.

  scripts/output_parity.py run --build build --out /tmp/parity/before
  ... refactor, rebuild ...
  scripts/output_parity.py run --build build --out /tmp/parity/after
  scripts/output_parity.py compare /tmp/parity/before /tmp/parity/after

`run` drives vid_sim (three presets), vid_run (feat0 and images, decode threads 0 and 1),
vid_track, vid_info, vid_replay -> vid_live (file:// LCM log), sim_render_preview and
vid_massid (generate, run, report, elm-study) with fixed seeds into OUT.

`compare` walks both trees and reports per file: `identical` (bytes), `equal to 1e-12`
(numbers compared with |a-b| <= 1e-12 * max(1, |a|)), or the first difference. Measured
timings are not outputs of the computation and are left out: JSON keys and CSV columns whose
names say time was measured (`*_ms`, `cpu*`, `wall*`, ...), and timing.csv's values. The
outputs name their inputs' paths: `run` works in OUT/../work, records that path and the
repository's in OUT/steps.json, and `compare` reads each side's text with them replaced by
<WORK> and <REPO> (so a checkout elsewhere compares equal).
Exit 1 on any difference.
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys

REPO = pathlib.Path(__file__).resolve().parents[1]
# Names of measured (wall / CPU) times and of things derived from them, and the build's git id.
VOLATILE = re.compile(r"(^|_|\s)(ms|cpu|wall|timing|elapsed|realtime|real_time|seconds_taken|per_frame|"
                      r"fps|speed|hz_achieved|duration_wall|throughput|time_s|time_ms|train_s|decode|memory|rss|time|wait|git)(_|\s|$)",
                      re.IGNORECASE)
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|nan|inf", re.IGNORECASE)


def _run(cmd: list, **kw) -> None:
    cmd = [str(c) for c in cmd]
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"output_parity: error: {' '.join(cmd)} exited {r.returncode}:\n{r.stderr[-2000:]}")


def run(build: pathlib.Path, out: pathlib.Path) -> None:
    b = build.resolve() / "bin"
    work = out.resolve().parent / "work"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    sim = REPO / "config" / "sim"
    steps = []

    def step(name, cmd, **kw):
        print(f"[parity] {name}", flush=True)
        _run(cmd, **kw)
        steps.append(name)

    seqs = {"vid17": ("vid17_like_short.yaml", 6, []), "rope": ("rope_snap_short.yaml", 8, ["--features-only"]),
            "img": ("vid17_like_short.yaml", 3, [])}
    for name, (preset, dur, extra) in seqs.items():
        step(f"vid_sim {name}", [b / "vid_sim", "--scenario", sim / preset, "--out", work / f"seq_{name}",
                                 "--seed", 7, "--duration", dur, "--quiet", *extra])
    step("vid_run vid17 feat0", [b / "vid_run", "--dataset", work / "seq_vid17", "--out", work / "run_vid17_feat0",
                                 "--config", sim, "--features", "feat0", "--quiet"])
    step("vid_run rope", [b / "vid_run", "--dataset", work / "seq_rope", "--out", work / "run_rope",
                          "--config", sim, "--quiet"])
    step("vid_run rope imu", [b / "vid_run", "--dataset", work / "seq_rope", "--out", work / "run_rope_imu",
                              "--config", sim, "--mode", "imu", "--init", "groundtruth", "--quiet"])
    for threads in (0, 1):
        step(f"vid_run img decode {threads}",
             [b / "vid_run", "--dataset", work / "seq_img", "--out", work / f"run_img_d{threads}", "--config", sim,
              "--decode-threads", threads, "--quiet"])
    (work / "track").mkdir()
    step("vid_track", [b / "vid_track", "--dataset", work / "seq_img", "--config", sim / "frontend.yaml",
                       "--out", work / "track" / "tracks.csv"])
    with open(work / "vid_info.json", "w") as f:
        print("[parity] vid_info", flush=True)
        r = subprocess.run([str(b / "vid_info"), "--json", str(work / "seq_vid17")], stdout=f, text=True)
        if r.returncode != 0:
            sys.exit("output_parity: error: vid_info failed")
    step("vid_replay", [b / "vid_replay", "--dataset", work / "seq_img", "--lcm-url", "memq://", "--fast",
                        "--log", work / "replay.log", "--report", work / "replay_report.json", "--quiet"])
    step("vid_live", [b / "vid_live", "--lcm-url", f"file://{work}/replay.log?speed=0", "--sensors",
                      work / "seq_img", "--config", sim, "--out", work / "live", "--quiet"])
    step("sim_render_preview", [b / "sim_render_preview", sim / "checkerboard.yaml", work / "preview" / "p"])
    cfg = work / "study.yaml"
    cfg.write_text("duration_s: 4\n")
    step("vid_massid generate", [b / "vid_massid", "generate", "--config", cfg, "--out", work / "massid_data",
                                 "--runs", 3, "--trajectories", "loop,lemniscate", "--profiles",
                                 "constant,step_drop", "--threads", 1, "--quiet"])
    step("vid_massid run", [b / "vid_massid", "run", "--data", work / "massid_data", "--out", work / "massid_out",
                            "--runs-per-case", 1, "--threads", 1,
                            "--methods", "ekf,ukf,msckf,swls,elm,relm,oselm"])
    step("vid_massid elm-study", [b / "vid_massid", "elm-study", "--dataset", work / "massid_data",
                                  "--out", work / "elm_study", "--n-train", 1, "--max-train", 1,
                                  "--test-per-profile", 1, "--test-first", 2, "--hidden", 10, 20, "--repeats", 1])
    shutil.rmtree(out, ignore_errors=True)
    out.parent.mkdir(parents=True, exist_ok=True)
    # The LCM event log carries wall-clock receive times: keep only what vid_live made of it.
    (work / "replay.log").unlink()
    shutil.copytree(work, out)
    (out / "steps.json").write_text(json.dumps({"work": str(work), "repo": str(REPO), "steps": steps}, indent=1))
    print(f"[parity] {len(steps)} steps -> {out}")


def _strip_json(x):
    if isinstance(x, dict):
        return {k: _strip_json(v) for k, v in x.items() if not VOLATILE.search(k)}
    if isinstance(x, list):
        return [_strip_json(v) for v in x]
    return x


def _numbers_equal(a: str, b: str, tol: float) -> bool:
    ta, tb = NUMBER.split(a), NUMBER.split(b)
    if ta != tb:
        return False
    na, nb = NUMBER.findall(a), NUMBER.findall(b)
    if len(na) != len(nb):
        return False
    for x, y in zip(na, nb):
        fx, fy = float(x), float(y)
        if fx != fy and not abs(fx - fy) <= tol * max(1.0, abs(fx)):
            return False
    return True


def _max_diff(a: str, b: str) -> str:
    """Largest |a-b| / max(1, |a|) over the numbers of two texts with the same number count."""
    na, nb = NUMBER.findall(a), NUMBER.findall(b)
    if len(na) != len(nb):
        return f"{len(na)} vs {len(nb)} numbers"
    worst = max((abs(float(x) - float(y)) / max(1.0, abs(float(x))) for x, y in zip(na, nb)
                 if float(x) != float(y)), default=0.0)
    return f"max relative difference {worst:.2g} over {len(na)} numbers"


def _csv_text(text: str, name: str) -> str:
    lines = text.splitlines()
    if name == "timing.csv":
        return "\n".join(lines[:1] + [l.split(",")[0] for l in lines[1:]])
    if not lines:
        return ""
    header = lines[0].split(",")
    keep = [i for i, h in enumerate(header) if not VOLATILE.search(h.strip().lstrip("#").strip())]
    return "\n".join(",".join(c for i, c in enumerate(l.split(",")) if i in keep) for l in lines)


def _md_text(text: str, name: str) -> str:
    """Markdown tables without the columns of measured times (header names them)."""
    out, keep = [], None
    for line in text.splitlines():
        if not line.startswith("|"):
            keep = None
            out.append(line)
            continue
        cells = line.strip().strip("|").split("|")
        if keep is None:
            keep = [i for i, h in enumerate(cells) if not VOLATILE.search(h.strip())]
        out.append("|".join(c for i, c in enumerate(cells) if i in keep))
    return "\n".join(out)


def _compare_file(a: pathlib.Path, b: pathlib.Path, paths_a: tuple, paths_b: tuple) -> tuple[bool, str]:
    """paths_*: (work folder, repository) of each side, replaced by <WORK> / <REPO> in the text."""
    ba = a.read_bytes().replace(paths_a[0], b"<WORK>").replace(paths_a[1], b"<REPO>")
    bb = b.read_bytes().replace(paths_b[0], b"<WORK>").replace(paths_b[1], b"<REPO>")
    if ba == bb:
        return True, "identical"
    if a.suffix == ".json":
        ja, jb = _strip_json(json.loads(ba.decode(errors="replace"))), _strip_json(json.loads(bb.decode(errors="replace")))
        sa, sb = json.dumps(ja, sort_keys=True, indent=0), json.dumps(jb, sort_keys=True, indent=0)
        if sa == sb:
            return True, "identical without measured times"
        if _numbers_equal(sa, sb, 1e-12):
            return True, "equal to 1e-12 without measured times"
        for la, lb in zip(sa.splitlines(), sb.splitlines()):
            if la != lb and not _numbers_equal(la, lb, 1e-12):
                return False, f"differs ({_max_diff(sa, sb)}): {la.strip()} | {lb.strip()}"
        return False, "differs in length"
    if a.suffix in (".csv", ".txt", ".md", ".yaml"):
        text = {".csv": _csv_text, ".md": _md_text}.get(a.suffix, lambda t, name: t)
        ta, tb = text(ba.decode(), a.name), text(bb.decode(), b.name)
        if ta == tb:
            return True, "identical without measured times"
        la, lb = ta.splitlines(), tb.splitlines()
        if len(la) != len(lb):
            return False, f"{len(la)} vs {len(lb)} lines"
        for i, (x, y) in enumerate(zip(la, lb)):
            if x != y and not _numbers_equal(x, y, 1e-12):
                return False, f"{_max_diff(ta, tb)}; first at line {i + 1}: {x[:80]} | {y[:80]}"
        return True, "equal to 1e-12"
    return False, "binary files differ"


def compare(a: pathlib.Path, b: pathlib.Path) -> int:
    fa = {p.relative_to(a) for p in a.rglob("*") if p.is_file()}
    fb = {p.relative_to(b) for p in b.rglob("*") if p.is_file()}
    bad = 0
    counts: dict[str, int] = {}
    sa, sb = (json.loads((d / "steps.json").read_text()) for d in (a, b))
    wa, wb = sa["work"].encode(), sb["work"].encode()
    ra, rb = sa.get("repo", str(REPO)).encode(), sb.get("repo", str(REPO)).encode()
    for rel in sorted(fa | fb):
        if rel not in fa or rel not in fb:
            print(f"MISSING in {'after' if rel in fa else 'before'}: {rel}")
            bad += 1
            continue
        if rel.name == "steps.json":
            continue
        ok, how = _compare_file(a / rel, b / rel, (wa, ra), (wb, rb))
        counts[how if ok else "different"] = counts.get(how if ok else "different", 0) + 1
        if not ok:
            print(f"DIFFERENT {rel}: {how}")
            bad += 1
        elif how != "identical":
            print(f"{how:40s} {rel}")
    print(f"[parity] {len(fa | fb)} files: " + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
    return 1 if bad else 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="run every program into OUT")
    r.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    r.add_argument("--out", type=pathlib.Path, required=True)
    c = sub.add_parser("compare", help="compare two `run` outputs")
    c.add_argument("before", type=pathlib.Path)
    c.add_argument("after", type=pathlib.Path)
    args = ap.parse_args()
    if args.cmd == "run":
        run(args.build, args.out)
        return 0
    return compare(args.before, args.after)


if __name__ == "__main__":
    sys.exit(main())
