"""`vid-eval force` and `vid-eval traj` per flight phase on a synthetic take-off and landing
(phase_testdata: known force, position and attitude errors per phase)."""
from __future__ import annotations

import json
import subprocess
import sys

import matplotlib.pyplot as plt
import numpy as np
import pytest

from eval_testdata import run_cli_in_process
from phase_testdata import (EST_K, F_ERR, G, LIFTOFF_K, MASS, ROT_ERR_DEG, TOUCHDOWN_K, Z_ERR,
                            region, truth_mps2, write_flight)
from test_eval_phases_unchanged import GOLDEN, TMP, _same, strip_added
from plot_checks import assert_plot

SEGMENTS = ["landed", "airborne", "lift-off 1", "touchdown 1"]


def _expected_pairs() -> dict:
    reg = region(EST_K)
    air = (EST_K >= LIFTOFF_K) & (EST_K < TOUCHDOWN_K)
    return {"landed": int(np.sum((reg != "window") & ~air)),
            "airborne": int(np.sum((reg != "window") & air)),
            "lift-off 1": int(np.sum(np.abs(EST_K - LIFTOFF_K) <= 100)),
            "touchdown 1": int(np.sum(np.abs(EST_K - TOUCHDOWN_K) <= 100))}


def _run(tmp_path, command, *extra, phases=True):
    paths = write_flight(tmp_path, phases=phases)
    out = tmp_path / f"{command}.json"
    if command == "force":
        args = ("force", paths["force"], paths["force0"], "--mass", MASS)
    else:
        args = ("traj", paths["state"], paths["gt"])
    proc = run_cli_in_process(*args, "--json", out, *extra)
    assert proc.returncode == 0, proc.stderr
    return json.loads(out.read_text()), proc.stdout, paths


def test_force_rmse_per_phase_by_hand(tmp_path):
    d, _, _ = _run(tmp_path, "force")
    ph = d["phases"]
    assert ph["frames"] == ["world", "body"] and "skipped_frames" not in ph
    pairs = _expected_pairs()
    segs = {s["name"]: s for s in ph["segments"]}
    assert list(segs) == SEGMENTS
    for name, s in segs.items():
        want = np.linalg.norm(F_ERR["window" if " " in name else name])
        for frame in ("world", "body"):  # body: R_gt^T e, the same norm
            assert s[frame]["pairs"] == pairs[name]
            assert s[frame]["rmse_mps2"]["norm"] == pytest.approx(want, rel=1e-9)
            assert s[frame]["rmse_N"]["norm"] == pytest.approx(MASS * want, rel=1e-9)
    assert segs["landed"]["duration_s"] == pytest.approx(4.5 + 4.495)
    assert segs["lift-off 1"]["duration_s"] == 1.0
    # the whole-run RMSE is unchanged by the split: the pairs add up
    assert sum(pairs.values()) == d["force"]["pairs"]


def test_force_settling_and_landed_error(tmp_path):
    d, stdout, _ = _run(tmp_path, "force")
    st = d["phases"]["settling"]
    assert (st["frame"], st["tol"], st["hold_s"], st["window_s"]) == ("world", 0.1, 0.3, 2.0)
    ts = EST_K * 0.005
    on_ground = np.array([0.0, 0.0, G])
    for r, te in zip(st["events"], (5.0, 15.0)):
        # levels: the truth's median over the 0.3 s just outside the 1 s window
        pre = (ts >= te - 0.8 - 1e-9) & (ts < te - 0.5 - 1e-9)
        post = (ts > te + 0.5 + 1e-9) & (ts <= te + 0.8 + 1e-9)
        l0 = np.median(truth_mps2(ts[pre], EST_K[pre]), axis=0)
        l1 = np.median(truth_mps2(ts[post], EST_K[post]), axis=0)
        assert r["step_mps2"] == pytest.approx(np.linalg.norm(l1 - l0), rel=1e-9)
        assert (l0 if r["kind"] == "lift-off" else l1) == pytest.approx(on_ground)
        # 1.5 m/s^2 inside the window (> 10 % of ~9.6), 0.2 after it: settled one 10 ms
        # estimate sample after the window's end
        assert r["peak_error_mps2"] == pytest.approx(1.5)
        assert r["settling_s"] == pytest.approx(0.51, abs=1e-6)
    la = d["phases"]["landed_after"]
    assert la["skip_s"] == 1.0
    assert [iv["from_s"] for iv in la["intervals"]] == [1.0, 16.0]
    assert [iv["pairs"] for iv in la["intervals"]] == [350, 395]  # 1.0-4.5 s, 16.0-19.98 s
    for iv in la["intervals"]:
        assert iv["error_mps2"]["max"] == pytest.approx(0.05, rel=1e-9)
    assert "  lift-off 1    step " in stdout and "settling 0.510 s" in stdout


def test_traj_errors_per_phase_use_the_whole_run_alignment(tmp_path):
    d, _, _ = _run(tmp_path, "traj")
    # posyaw fits the heading on x-y (exact here) and takes out the mean z error of all pairs
    reg = region(EST_K)
    z = np.array([Z_ERR[r] for r in reg])
    segs = {s["name"]: s for s in d["phases"]["segments"]}
    assert list(segs) == SEGMENTS
    for name, s in segs.items():
        key = "window" if " " in name else name
        assert s["pairs"] == _expected_pairs()[name]
        assert s["pos_m"]["rmse"] == pytest.approx(abs(Z_ERR[key] - z.mean()), abs=1e-8)
        assert s["rot_deg"]["max"] == pytest.approx(ROT_ERR_DEG[key], abs=1e-6)
    assert d["ate"]["alignment"]["yaw_deg"] == pytest.approx(140.0, abs=1e-6)


@pytest.mark.parametrize("command", ["traj", "force"])
def test_with_phase0_the_output_only_gains_the_phase_block(tmp_path, command):
    d, stdout, _ = _run(tmp_path, command)
    golden_text = (GOLDEN / f"phases_absent_{command}.txt").read_text()
    assert stdout.startswith(golden_text)
    block = stdout[len(golden_text):].splitlines()
    assert block[0] == ("phases: 2 landed, 1 airborne intervals; lift-off 1 at 5.000 s, "
                        "touchdown 1 at 15.000 s; window 1 s")
    assert [ln.split()[0] + (" " + ln.split()[1] if ln.split()[1] == "1" else "")
            for ln in block[1:5]] == SEGMENTS
    ph = d.pop("phases")
    want = json.loads((GOLDEN / f"phases_absent_{command}.json").read_text())
    got = strip_added(command, json.loads(json.dumps(d).replace(str(tmp_path.resolve()), TMP)), want)
    assert list(got) == list(want) and _same(got, want)
    keys = {"source", "window_s", "t0_ns", "t1_ns", "intervals", "events", "segments"}
    if command == "force":
        keys |= {"frames", "settling", "landed_after"}
    assert set(ph) == keys
    assert ph["source"].endswith("mav0/phase0/data.csv")
    assert [e["name"] for e in ph["events"]] == ["lift-off 1", "touchdown 1"]


def test_phases_option_and_window(tmp_path):
    paths = write_flight(tmp_path)
    moved = tmp_path / "phases.csv"
    (paths["mav0"] / "phase0" / "data.csv").rename(moved)
    out = tmp_path / "t.json"
    proc = run_cli_in_process("traj", paths["state"], paths["gt"], "--json", out,
                              "--phases", moved, "--phase-window", "0.5")
    assert proc.returncode == 0, proc.stderr
    ph = json.loads(out.read_text())["phases"]
    assert ph["source"] == str(moved) and ph["window_s"] == 0.5
    assert [(e["window_t0_s"], e["window_t1_s"]) for e in ph["events"]] == [(4.75, 5.25),
                                                                           (14.75, 15.25)]
    segs = {s["name"]: s for s in ph["segments"]}
    assert segs["lift-off 1"]["pairs"] == 51  # estimate samples (even) within +-50 of 1000
    assert segs["lift-off 1"]["duration_s"] == 0.5
    for bad in ("0", "inf"):
        proc = run_cli_in_process("traj", paths["state"], paths["gt"], "--phase-window", bad)
        assert proc.returncode == 2 and "must be positive" in proc.stderr


def test_body_frame_without_a_trajectory_scores_body_only(tmp_path):
    paths = write_flight(tmp_path)
    paths["state"].unlink()  # the world frame's gauge has no estimated trajectory now
    out = tmp_path / "f.json"
    proc = run_cli_in_process("force", paths["force"], paths["force0"], "--mass", MASS,
                              "--frame", "body", "--json", out)
    assert proc.returncode == 0, proc.stderr
    ph = json.loads(out.read_text())["phases"]
    assert ph["frames"] == ["body"] and "trajectory" in ph["skipped_frames"]["world"]
    assert all("world" not in s for s in ph["segments"])
    assert "(world frame not scored: " in proc.stdout


def test_a_bad_phase0_is_one_line_naming_file_line_and_column(tmp_path):
    paths = write_flight(tmp_path)
    bad = paths["mav0"] / "phase0" / "data.csv"
    lines = bad.read_text().splitlines()
    lines[7] = lines[7].split(",")[0] + ",3"
    bad.write_text("\n".join(lines) + "\n")
    proc = subprocess.run([sys.executable, "-m", "vid_eval.cli", "traj", str(paths["state"]),
                           str(paths["gt"])], capture_output=True, text=True)
    assert proc.returncode == 1
    assert proc.stderr.splitlines() == [
        f"vid-eval: error: {bad.resolve()}:8: phase0 CSV: column 2 'phase': expected 0 "
        f"(on the ground) or 1 (airborne), got 3"]


def test_plots_shade_landed_intervals_and_mark_events(tmp_path):
    from vid_eval.tools.loaders import load_phases
    from vid_eval.core.phases import segment_phases
    from vid_eval.plots.phases import shade_phases
    from vid_eval.plots.style import new_figure

    paths = write_flight(tmp_path)
    for command in ("traj", "force"):
        _run(tmp_path / command, command, "--plot", tmp_path / "plots")
    # truth and estimate per axis, the error; position (red) and rotation (purple) errors
    assert_plot(tmp_path / "plots" / "force_world.png", ("black", "tab:blue", "tab:red"))
    assert_plot(tmp_path / "plots" / "traj_errors.png", ("tab:red", "tab:purple"))
    seg = segment_phases(load_phases(paths["mav0"] / "phase0" / "data.csv"))
    fig, ax = new_figure()
    ax.plot([1.0, 19.0], [0.0, 1.0])
    xlim = ax.get_xlim()
    shade_phases(ax, seg, seg.t0_ns, label=True)
    assert len(ax.patches) == 2  # the two landed intervals
    assert sorted(ln.get_xdata()[0] for ln in ax.lines[1:]) == pytest.approx([5.0, 15.0])
    assert [ln.get_label() for ln in ax.lines[1:]] == ["lift-off", "touchdown"]
    assert ax.get_xlim() == xlim  # the 0-20 s phases do not widen the plotted range
    plt.close(fig)
