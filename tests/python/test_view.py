"""vid-eval view (issue #25): a run logged to a Rerun recording and read back with Rerun's own
reader (rerun.chunk.RrdReader): entity paths and row counts equal what the run folder holds.

* synthetic: a run folder and dataset written here (no C++ build);
* simulated: vid_sim -> vid_run --rerun (tracked features from vid_run --tracks, equal to
  vid_track's), and vid_replay -> vid_live --publish-url log -> vid-eval view --lcm.
"""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest
from PIL import Image
from scipy.spatial.transform import Rotation

from eval_testdata import run_cli_in_process, smooth_trajectory, write_euroc_gt, write_force_estimate, write_state
from test_vid_run_helpers import REPO, build_dir, program, simulate_cached, vid_run
from vid_eval.core import formats

import rerun.chunk as rerun_chunk  # noqa: E402  (rerun-sdk: the view extra, scripts/setup.sh installs it)


def rows_per_entity(rrd) -> dict:
    """Rows logged per entity path (static and temporal), read back from the file."""
    counts = {}
    for chunk in rerun_chunk.RrdReader(rrd).stream():
        counts[chunk.entity_path] = counts.get(chunk.entity_path, 0) + chunk.num_rows
    return counts


def _synthetic(tmp_path, frames=6):
    n = 200
    t_ns = 10**18 + np.arange(n, dtype=np.int64) * 5_000_000
    p, rot = smooth_trajectory(np.arange(n) * 0.005, 4)
    run = tmp_path / "run"
    f_w = np.c_[np.sin(np.arange(n) * 0.01), np.zeros(n), np.full(n, 9.81)]
    write_force_estimate(run / "force.csv", t_ns, rot.inv().apply(f_w), f_w, np.full((n, 3), 0.1))
    write_state(run / "state.csv", t_ns, p, rot, rot.inv().apply(f_w))
    mav0 = tmp_path / "seq" / "mav0"
    write_euroc_gt(mav0 / "state_groundtruth_estimate0" / "data.csv", t_ns, p + 1.0, Rotation.identity(n) * rot)
    (mav0 / "imu0").mkdir(parents=True)
    (mav0 / "cam0" / "data").mkdir(parents=True)
    cam_t = t_ns[::40][:frames]
    rows = ["#timestamp [ns],filename"]
    rng = np.random.default_rng(5)
    for t in cam_t:
        Image.fromarray(rng.integers(0, 255, (24, 32), dtype=np.uint8)).save(mav0 / "cam0" / "data" / f"{t}.png")
        rows.append(f"{t},{t}.png")
    (mav0 / "cam0" / "data.csv").write_text("\n".join(rows) + "\n")
    lines = [formats.header_line(formats.TRACKS_COLUMNS)]
    for k, t in enumerate(cam_t):
        lines += [f"{t},0,{i},{5 + i + k:.4f},{7.5:.4f}" for i in range(3 + k % 2)]
    (run / "tracks.csv").write_text("\n".join(lines) + "\n")
    return run, tmp_path / "seq", len(cam_t)


def test_synthetic_run_reads_back_with_every_entity(tmp_path):
    run, seq, frames = _synthetic(tmp_path)
    rrd = tmp_path / "run.rrd"
    proc = run_cli_in_process("view", run, "--dataset", seq, "--rrd", rrd)
    assert proc.returncode == 0, proc.stderr
    got = rows_per_entity(rrd)
    assert got["/world/vehicle"] == 200 + 1        # a pose per state row, and the axes (static)
    assert got["/world/force"] == 200 + 1          # an arrow per force row, and its style
    assert got["/world/trajectory"] == 1 and got["/world/groundtruth"] == 1
    assert got["/cam0/image"] == frames
    assert got["/cam0/image/tracks"] == frames and got["/cam0/image/trails"] == frames
    for axis in "xyz":
        assert got[f"/plots/force/{axis}"] == 200 and got[f"/plots/force_sigma/{axis}"] == 200
    assert f"cam0/image {frames}," in proc.stdout


def test_view_errors_are_one_line(tmp_path):
    proc = run_cli_in_process("view", tmp_path / "nothing", "--rrd", tmp_path / "x.rrd")
    assert proc.returncode == 1 and proc.stderr.count("\n") == 1 and "no such run folder" in proc.stderr
    (tmp_path / "empty").mkdir()
    proc = run_cli_in_process("view", tmp_path / "empty", "--rrd", tmp_path / "x.rrd")
    assert proc.returncode == 1 and "state.csv" in proc.stderr
    proc = run_cli_in_process("view", tmp_path / "empty")
    assert proc.returncode == 2  # neither --rrd nor --spawn: usage


def _tracks_by_frame(path):
    return [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]


@pytest.fixture(scope="module")
def short_seq():
    return simulate_cached("vid17_like_short.yaml", 4.0, 2, features_only=False)


def test_vid_run_rerun_recording_of_a_simulated_run(short_seq, tmp_path):
    """vid_run --rerun: the recording holds every state, force row, image and tracked frame;
    vid_run's tracks.csv is vid_track's on the same images."""
    out, rrd = tmp_path / "run", tmp_path / "run.rrd"
    r = vid_run(short_seq, out, "--config", str(REPO / "config" / "sim"), "--rerun", str(rrd),
                "--decode-threads", "0")
    assert r.returncode == 0, r.stderr
    got = rows_per_entity(rrd)
    states = len((out / "state.csv").read_text().splitlines()) - 1
    assert got["/world/vehicle"] == states + 1 and got["/world/force"] == states + 1
    track_times = {ln.split(",")[0] for ln in _tracks_by_frame(out / "tracks.csv") if ln.split(",")[1] == "0"}
    assert got["/cam0/image/tracks"] == len(track_times) > 0
    frames = json.loads((out / "summary.json").read_text())["counts"]["camera_frames"]
    assert got["/cam0/image"] == frames and got["/cam1/image"] == frames
    t = subprocess.run([program("vid_track"), "--dataset", short_seq, "--config", REPO / "config" / "sim" / "frontend.yaml",
                        "--out", tmp_path / "tracks.csv"], capture_output=True, text=True, timeout=300)
    assert t.returncode == 0, t.stderr
    assert _tracks_by_frame(out / "tracks.csv") == _tracks_by_frame(tmp_path / "tracks.csv")


def test_vid_eval_view_follows_vid_live_over_lcm(short_seq, tmp_path):
    """vid_replay -> event log -> vid_live (publishing into a second log) -> vid-eval view --lcm:
    one pose per VID_STATE message (= a state.csv row of vid_live's --out) and one arrow per
    VID_FORCE message; the status log arrives too."""
    from test_live import live

    log, pub = tmp_path / "sensors.log", tmp_path / "published.log"
    r = subprocess.run([program("vid_replay"), "--dataset", short_seq, "--lcm-url", "memq://", "--fast", "--end", "3",
                        "--log", log, "--quiet"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "live"
    live(short_seq, log, out, "--publish-url", f"file://{pub}?mode=w")
    rrd = tmp_path / "live.rrd"
    proc = run_cli_in_process("view", "--lcm", f"file://{pub}?speed=0", "--lcm-types", build_dir() / "python",
                              "--idle-timeout", "2", "--rrd", rrd)
    assert proc.returncode == 0, proc.stderr
    got = rows_per_entity(rrd)
    states = len((out / "state.csv").read_text().splitlines()) - 1
    assert got["/world/vehicle"] == states + 1 > 1  # a pose per message, the axes (static)
    assert got["/world/force"] == states + 1
    assert got["/status"] >= 1
    log.unlink()


def test_vid_live_rerun_logs_its_out_folder(short_seq, tmp_path):
    """vid_live --out DIR --rerun OUT.rrd: tracks.csv written, and the recording holds every
    state, the tracked frames and (with a dataset as --sensors) the images of the window."""
    from test_live import live

    log = tmp_path / "sensors.log"
    r = subprocess.run([program("vid_replay"), "--dataset", short_seq, "--lcm-url", "memq://", "--fast", "--end", "2",
                        "--log", log, "--quiet"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    out, rrd = tmp_path / "live", tmp_path / "live.rrd"
    live(short_seq, log, out, "--rerun", rrd)
    got = rows_per_entity(rrd)
    assert got["/world/vehicle"] == len((out / "state.csv").read_text().splitlines()) - 1 + 1
    cam0_frames = {ln.split(",")[0] for ln in _tracks_by_frame(out / "tracks.csv") if ln.split(",")[1] == "0"}
    assert got["/cam0/image/tracks"] == len(cam0_frames) > 0
    assert got["/cam0/image"] >= len(cam0_frames)
    log.unlink()
