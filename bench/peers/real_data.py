"""The real Blackbird flight as a dataset folder with rendered stereo images (compare_real.py):
import, mocap sync, rendering along the synced mocap path, and time windows cut from it.

Steps (each a project tool; the folder is made once and stamped with the commands in
``.complete``):

1. ``vid-import --map blackbird_lio DATA SEQ --mass 0.915 --imu-frame frd --world-frame enu``
   with the IMU noise measured on this flight (docs/real_sensors.md) instead of the importer's
   EuRoC defaults: every estimator reads it from ``imu0/sensor.yaml``;
2. ``vid-eval mocap-truth SEQ --apply-sync``: the mocap clock offset (-0.47 ms) and the 0.74 deg
   rotation between the mocap body and the IMU frame are removed from the ground truth, and
   ``force0`` (force truth = mocap acceleration minus thrust) is derived from it;
3. ``vid_sim --camera-along GT.tum --scenario config/sim/recorded_room.yaml --out SEQ``: stereo
   images (640x480, 30 Hz, the vid17_like camera pair) rendered along the *synced* ground truth,
   so the cameras sit where the IMU is.
"""
from __future__ import annotations

import os
import pathlib
import shutil
import subprocess
import sys

from peers_common import ROOT, trim_rows

sys.path.insert(0, str(ROOT / "eval"))
from vid_eval.importer.features import write_tum  # noqa: E402
from vid_eval.tools.loaders import load_trajectory  # noqa: E402

SCENE = ROOT / "config" / "sim" / "recorded_room.yaml"
# Measured on this flight in flight by `vid-allan --flight` (the same figures as
# scripts/bench_realdata.py: gyro minus mocap rate 5.7e-3 rad/s/sqrt(Hz), accelerometer minus the
# thrust + drag model 0.014 m/s^2/sqrt(Hz); the 10-45 Hz band of docs/real_sensors.md alone,
# 0.002 / 0.025, left the slow part out and made every estimator's gyro overconfident); the bias
# walks keep the importer's defaults (EuRoC's ADIS16448).
IMU_NOISE = ["--accel-noise", "0.014", "--gyro-noise", "5.7e-3"]
# Streams cut to a window (data.csv rows by time); the rest is copied or linked.
CUT = ("imu0", "thrust0", "cam0", "cam1", "state_groundtruth_estimate0", "force0")


def _run(cmd, log: pathlib.Path, env=None) -> None:
    print("[real] " + " ".join(map(str, cmd)), flush=True)
    with open(log, "a") as f:
        f.write("$ " + " ".join(map(str, cmd)) + "\n")
        f.flush()
        r = subprocess.run(["nice", "-n", "15"] + [str(c) for c in cmd], stdout=f, stderr=subprocess.STDOUT, env=env)
    if r.returncode != 0:
        raise SystemExit(f"[real] failed (exit {r.returncode}): {' '.join(map(str, cmd))}; see {log}")


def prepare(data: pathlib.Path, seq: pathlib.Path, vid_sim: pathlib.Path, mass: float = 0.915) -> pathlib.Path:
    """The whole flight with rendered images in ``seq`` (made once; ``.complete`` holds the commands)."""
    if (seq / ".complete").exists():
        return seq
    if not (data / "test" / "data.hdf5").exists():
        raise SystemExit(f"{data}: not the Blackbird clover folder (no test/data.hdf5); pass --data")
    if seq.exists():
        shutil.rmtree(seq)
    seq.parent.mkdir(parents=True, exist_ok=True)
    log = seq.parent / (seq.name + ".prepare.log")
    log.write_text("")
    py = sys.executable
    env = dict(os.environ, PYTHONPATH=str(ROOT / "eval") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    cmds = [[py, "-m", "vid_eval.importer", "--map", "blackbird_lio", data, seq, "--mass", str(mass),
             "--imu-frame", "frd", "--world-frame", "enu"] + IMU_NOISE,
            [py, "-m", "vid_eval.cli", "mocap-truth", seq, "--apply-sync", "--json", seq / "mocap_truth.json"]]
    for c in cmds:
        _run(c, log, env)
    gt = load_trajectory(seq / "mav0" / "state_groundtruth_estimate0" / "data.csv")
    tum = seq / "gt_synced_tum.txt"
    write_tum(tum, gt.t_ns, gt.p, gt.q)
    render = [vid_sim, "--camera-along", tum, "--scenario", SCENE, "--out", seq, "--quiet"]
    _run(render, log)
    (seq / ".complete").write_text("\n".join(" ".join(map(str, c)) for c in cmds + [render]) + "\n")
    return seq


def window(seq: pathlib.Path, out: pathlib.Path, start_s: float, length_s: float) -> pathlib.Path:
    """A folder holding [start, start + length] s after the first IMU sample of ``seq``: the
    data.csv of every stream cut by time, sensor files copied, image folders linked."""
    stamp = out / ".complete"
    key = f"{seq.resolve()} {start_s} {length_s}\n"
    if stamp.exists() and stamp.read_text() == key:
        return out
    if out.exists():
        shutil.rmtree(out)
    src, dst = seq / "mav0", out / "mav0"
    dst.mkdir(parents=True)
    with open(src / "imu0" / "data.csv") as f:
        first = next(int(ln.split(",", 1)[0]) for ln in f if ln.strip() and not ln.startswith("#"))
    t0 = first + int(round(start_s * 1e9))
    t1 = t0 + int(round(length_s * 1e9))
    for item in src.iterdir():
        if item.is_file():
            shutil.copy2(item, dst / item.name)
        elif item.name in CUT:
            (dst / item.name).mkdir()
            for f in item.iterdir():
                if f.name == "data.csv":
                    if trim_rows(f, dst / item.name / "data.csv", t0, t1) == 0:
                        raise SystemExit(f"{f}: no rows in the window {start_s}-{start_s + length_s} s")
                elif f.is_dir():
                    (dst / item.name / f.name).symlink_to(f.resolve())
                else:
                    shutil.copy2(f, dst / item.name / f.name)
    stamp.write_text(key)
    return out
