"""vid_run end to end (issue 6): accuracy on a short rendered VID17-like sequence in dynamics
mode, evo accepts the trajectory, summary.json metrics equal vid-eval's, --start/--end,
--features feat0 vs images, --mode imu on the EuRoC-like preset, every preset loads, images
decoded ahead on other threads give byte-identical outputs to inline decoding (also on SIGINT
the summary is written and its decoding CPU time is accounted).

Accuracy figures are ratchets at today's value (a regression fails) next to strict xfails at
the issue's targets (docs/testing.md).
"""
import json
import subprocess

import pytest

from ratchets import ratchet, target, target_not_met
from test_vid_run_helpers import (REPO, VENV_BIN, first_timestamp_ns, interrupt_vid_run, simulate_cached, summary,
                                  tum_rows, vid_run)

SEQ_S = 12.0  # rendered seconds of vid17_like_short (seed 1)

# Known gap (issues 4 and 6): the world-frame force error on these 12 s is 0.12-0.13 m/s^2, not
# <= 0.08: in the first seconds roll/pitch, the accelerometer bias and F_ext are only separated by
# yaw turns (docs/notes/force-accuracy.md; analysis in tests/vio_core/test_sim_accuracy.cpp).
# The strict xfails hold the target and expect only TargetNotMet; the ratchets below hold
# today's value.
FORCE_GAP = target_not_met("open: world-frame force RMSE 0.12-0.13 m/s^2 > 0.08 (issues 4, 6)")

# Measured on vid17_like_short 12 s, config/sim, seeds 1-3 (seed 1 is the test's), 182d56e:
#   force RMSE images 0.131 / 0.197 / 0.150, feat0 0.121 / 0.196 / 0.136 m/s^2 (the seed spread
#   is wide: 1.2 x seed 1 is the tighter bound);
#   ATE images 0.00470 / 0.00491 / 0.00483 m (mean + 3 sd = 0.00513 is tighter than 1.2 x),
#   feat0 0.00368 / 0.00585 / 0.00412 m (1.2 x seed 1 = 0.00441).
FORCE_IMAGES, FORCE_FEAT0 = 0.131, 0.121
ATE_IMAGES, ATE_FEAT0 = 0.00470, 0.00368


@pytest.fixture(scope="session")
def rendered17():
    """12 s of config/sim/vid17_like_short.yaml with stereo images and feat0 (seed 1)."""
    return simulate_cached("vid17_like_short.yaml", SEQ_S, 1, features_only=False)


@pytest.fixture(scope="session")
def euroc_feat():
    """10 s of config/sim/euroc_like_short.yaml, features only (no rotor stream)."""
    return simulate_cached("euroc_like_short.yaml", 10.0, 2, features_only=True)


@pytest.fixture(scope="session")
def dyn_images(rendered17, tmp_path_factory):
    """Dynamics mode (auto: rotor0 present) on the rendered images with the sim preset."""
    out = tmp_path_factory.mktemp("run") / "dyn_images"
    r = vid_run(rendered17, out, "--config", str(REPO / "config" / "sim"))
    assert r.returncode == 0, r.stderr
    assert summary(out)["force_pairs"] > 0.9 * 200 * SEQ_S  # compared against every force0 sample
    return rendered17, out, r


@pytest.fixture(scope="session")
def dyn_feat0(rendered17, tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "dyn_feat0"
    r = vid_run(rendered17, out, "--config", str(REPO / "config" / "sim"), "--features", "feat0")
    assert r.returncode == 0, r.stderr
    assert summary(out)["force_pairs"] > 0.9 * 200 * SEQ_S
    return rendered17, out, r


def test_rendered_dynamics_ate(dyn_images):
    seq, out, r = dyn_images
    assert r.returncode == 0, r.stderr
    s = summary(out)
    assert s["mode"] == "dynamics"
    assert s["mode_source"].startswith("auto")
    assert s["features"] == "images"
    assert s["status"] == "ok"
    assert s["counts"]["camera_frames"] >= 0.9 * SEQ_S * 30
    assert s["counts"]["frames_skipped_bad_image"] == 0
    assert s["counts"]["visual_updates"] > 0
    # Issue 6 acceptance (<= 0.05 m) is met by a factor 10: the ratchet holds today's value.
    ratchet("rendered ATE posyaw [m]", s["ate_posyaw_m"], 0.00513, ATE_IMAGES)


def test_rendered_dynamics_force_ratchet(dyn_images):
    ratchet("rendered force RMSE [m/s^2]", summary(dyn_images[1])["force_rmse_world_mps2"], FORCE_IMAGES * 1.2,
            FORCE_IMAGES)


@FORCE_GAP
def test_rendered_dynamics_force(dyn_images):
    """Issue 6 acceptance: external-force RMSE (world, mass-normalized) <= 0.08 m/s^2."""
    target("rendered force RMSE [m/s^2]", summary(dyn_images[1])["force_rmse_world_mps2"], 0.08)


def test_summary_has_stage_times_and_run_facts(dyn_images):
    _, out, r = dyn_images
    s = summary(out)
    frames = s["counts"]["frames_processed"]
    for stage in ("tracking", "propagation", "accel_updates", "msckf_update", "marginalization", "total"):
        st = s["timing"][stage]
        assert st["count"] > 0.8 * frames
        assert 0.0 <= st["median_ms"] <= st["p99_ms"] <= st["max_ms"]
    assert s["timing"]["image_decoding"]["count"] == s["counts"]["camera_frames"]
    assert s["timing"]["total"]["median_ms"] >= s["timing"]["tracking"]["median_ms"]
    assert s["real_time_factor"] > 0.0
    cpu = s["cpu"]
    # every decoded frame is tracked (also those before the filter initializes)
    assert cpu["tracking_cpu"]["count"] == s["counts"]["camera_frames"] - s["counts"]["frames_skipped_bad_image"]
    assert 0.0 < cpu["image_decoding_cpu_s"] < cpu["process_cpu_s"]
    assert cpu["real_time_factor_cpu"] == pytest.approx(s["data_duration_s"] / cpu["process_cpu_s"])
    assert cpu["mean_cpu_ms_per_frame_excluding_decoding"] > 0.0
    # The real-time factor is over the whole run (wall clock, decoding included).
    assert s["real_time_factor"] == pytest.approx(s["data_duration_s"] / s["wall_time_s"])
    # Default: images decoded ahead on a second thread; every frame decoded once and used.
    da = s["decode_ahead"]
    assert da["decode_threads"] == 1
    assert da["frames_ahead"] >= 2
    assert da["frames_decoded"] == s["counts"]["camera_frames"]
    assert 0.0 <= da["main_thread_wait_s"] < s["wall_time_s"]
    assert s["peak_memory_mib"] > 1.0
    assert abs(s["data_duration_s"] - SEQ_S) < 0.5
    # the configuration as a JSON object (numbers as numbers), and as the YAML text
    assert s["config"]["estimator"]["imu_rate_hz"] == 400.0 and s["config"]["imu"]["rate_hz"] == 400.0
    assert "thrust_noise_density" in s["config"]["estimator"]
    assert "thrust_noise_density: " in s["config_yaml"]
    assert s["config_sources"]["estimator"].endswith("config/sim/estimator.yaml")
    timing_rows = (out / "timing.csv").read_text().splitlines()[1:]
    assert len(timing_rows) == s["timing"]["total"]["count"]


@pytest.fixture(scope="session")
def dyn_images_inline(rendered17, tmp_path_factory):
    """dyn_images with the images decoded inline on the estimator thread."""
    out = tmp_path_factory.mktemp("run") / "dyn_images_inline"
    r = vid_run(rendered17, out, "--config", str(REPO / "config" / "sim"), "--decode-threads", "0")
    return rendered17, out, r


ESTIMATE_FILES = ("trajectory_tum.txt", "state.csv", "force.csv")


def test_decode_ahead_outputs_equal_inline_decoding(dyn_images, dyn_images_inline):
    """Decode-ahead only moves work to another thread: the estimator sees the same
    measurements in the same order, so the outputs are byte-identical."""
    _, out, r = dyn_images
    _, out0, r0 = dyn_images_inline
    assert r.returncode == 0, r.stderr
    assert r0.returncode == 0, r0.stderr
    for name in ESTIMATE_FILES:
        assert (out / name).read_bytes() == (out0 / name).read_bytes(), name
    s, s0 = summary(out), summary(out0)
    assert s0["decode_ahead"]["decode_threads"] == 0
    assert s0["decode_ahead"]["frames_ahead"] == 0
    assert s0["decode_ahead"]["frames_decoded"] == s0["counts"]["camera_frames"]
    assert s["counts"] == s0["counts"]
    assert s["timing"]["image_decoding"]["count"] == s0["timing"]["image_decoding"]["count"]
    assert 0.0 < s0["cpu"]["image_decoding_cpu_s"] < s0["cpu"]["process_cpu_s"]


def test_several_decode_threads_equal_inline(rendered17, tmp_path):
    outs = {}
    for threads in ("0", "3"):
        outs[threads] = tmp_path / f"threads{threads}"
        r = vid_run(rendered17, outs[threads], "--config", str(REPO / "config" / "sim"), "--end", "4",
                    "--decode-threads", threads)
        assert r.returncode == 0, r.stderr
    assert len(tum_rows(outs["0"] / "trajectory_tum.txt")) > 500
    for name in ESTIMATE_FILES:
        assert (outs["3"] / name).read_bytes() == (outs["0"] / name).read_bytes(), name
    assert summary(outs["3"])["decode_ahead"]["decode_threads"] == 3


def test_sigint_during_decode_ahead_writes_summary(rendered17, tmp_path):
    """SIGINT while images are decoded ahead: the decoders stop, the summary says
    "interrupted", and decoding CPU time (also of frames decoded but never used) stays out of
    the per-frame CPU time."""
    out = tmp_path / "run"
    traj = out / "trajectory_tum.txt"
    returncode, err = interrupt_vid_run(rendered17, out, 400, poll_s=0.01)  # 1 s of 400 Hz estimates
    assert returncode == 130, err
    s = summary(out)
    assert s["status"] == "interrupted"
    assert s["data_duration_s"] < SEQ_S - 1.0
    assert s["counts"]["estimates"] == len(tum_rows(traj))
    da = s["decode_ahead"]
    assert da["decode_threads"] == 1
    # frames read ahead may be decoded but not used, never the other way round
    assert s["counts"]["camera_frames"] <= da["frames_decoded"] <= s["counts"]["camera_frames"] + da["frames_ahead"] + 1
    assert s["timing"]["image_decoding"]["count"] == s["counts"]["camera_frames"]
    assert 0.0 < s["cpu"]["image_decoding_cpu_s"] < s["cpu"]["process_cpu_s"]
    assert s["cpu"]["mean_cpu_ms_per_frame_excluding_decoding"] > 0.0


def test_evo_accepts_trajectory(dyn_images, tmp_path):
    seq, out, _ = dyn_images
    from evo.tools import file_interface

    traj = file_interface.read_tum_trajectory_file(str(out / "trajectory_tum.txt"))
    assert traj.num_poses == len(tum_rows(out / "trajectory_tum.txt"))
    assert traj.num_poses > 300 * SEQ_S  # IMU-rate estimates (400 Hz)
    gt = seq / "mav0" / "state_groundtruth_estimate0" / "data.csv"
    r = subprocess.run([str(VENV_BIN / "evo_ape"), "euroc", str(gt), str(out / "trajectory_tum.txt"), "-a",
                        "--save_results", str(tmp_path / "ape.zip")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    res = file_interface.load_res_file(str(tmp_path / "ape.zip"))
    # evo associated (almost) every estimate with ground truth and found a small error.
    assert res.stats["rmse"] < 0.1
    assert len(res.np_arrays["error_array"]) > 0.9 * 200 * SEQ_S


def test_summary_metrics_equal_vid_eval(dyn_images, tmp_path):
    seq, out, _ = dyn_images
    s = summary(out)
    mav0 = seq / "mav0"
    subprocess.run([str(VENV_BIN / "vid-eval"), "traj", str(out / "trajectory_tum.txt"),
                    str(mav0 / "state_groundtruth_estimate0" / "data.csv"), "--json", str(tmp_path / "traj.json")],
                   check=True, capture_output=True, timeout=120)
    subprocess.run([str(VENV_BIN / "vid-eval"), "force", str(out / "force.csv"), str(mav0 / "force0" / "data.csv"),
                    "--json", str(tmp_path / "force.json")], check=True, capture_output=True, timeout=120)
    traj = json.loads((tmp_path / "traj.json").read_text())
    force = json.loads((tmp_path / "force.json").read_text())
    assert abs(traj["ate_pos_rmse_m"] - s["ate_posyaw_m"]) < 1e-6
    assert abs(force["force_rmse_world_mps2"] - s["force_rmse_world_mps2"]) < 1e-6


def test_features_feat0_vs_images(dyn_images, dyn_feat0):
    _, out_img, _ = dyn_images
    _, out_feat, r = dyn_feat0
    assert r.returncode == 0, r.stderr
    si, sf = summary(out_img), summary(out_feat)
    assert sf["features"] == "feat0" and si["features"] == "images"
    assert sf["counts"]["feature_frames"] >= 0.9 * SEQ_S * 30
    assert sf["counts"]["camera_frames"] == 0
    assert sf["timing"]["image_decoding"]["count"] == 0
    assert sf["counts"]["visual_updates"] > 0
    # Both feature sources see the same scene; issue 6's 0.05 m is met by a factor 10.
    ratchet("feat0 ATE posyaw [m]", sf["ate_posyaw_m"], ATE_FEAT0 * 1.2, ATE_FEAT0)


def test_feat0_dynamics_force_ratchet(dyn_feat0):
    ratchet("feat0 force RMSE [m/s^2]", summary(dyn_feat0[1])["force_rmse_world_mps2"], FORCE_FEAT0 * 1.2,
            FORCE_FEAT0)


@FORCE_GAP
def test_feat0_dynamics_force(dyn_feat0):
    target("feat0 force RMSE [m/s^2]", summary(dyn_feat0[1])["force_rmse_world_mps2"], 0.08)


# Fixed-lag smoothing (--smooth 0.3, docs/results.md): the smoothed force RMSE on the same 12 s,
# feat0, measured at 182d56e over seeds 1 / 2 / 3: 0.0869 / 0.167 / 0.0916 m/s^2 (causal 0.121 /
# 0.196 / 0.136); 1.2 x seed 1 = 0.104 is the tighter bound. Target 0.05 (issue of the smoother).
SMOOTHED_FORCE = 0.0869


@pytest.fixture(scope="session")
def smoothed_feat0_rmse(rendered17, tmp_path_factory):
    """World force RMSE of force_smoothed.csv (vid_run --smooth 0.3, feat0), by vid-eval force."""
    out = tmp_path_factory.mktemp("run") / "smooth_feat0"
    r = vid_run(rendered17, out, "--config", str(REPO / "config" / "sim"), "--features", "feat0", "--smooth", "0.3")
    assert r.returncode == 0, r.stderr
    js = out / "force_smoothed_eval.json"
    subprocess.run([str(VENV_BIN / "vid-eval"), "force", str(out / "force_smoothed.csv"),
                    str(rendered17 / "mav0" / "force0" / "data.csv"), "--json", str(js)],
                   check=True, capture_output=True, timeout=120)
    d = json.loads(js.read_text())
    assert d["alignment"]["est_trajectory"].endswith("trajectory_smoothed_tum.txt")
    return d["force_rmse_world_mps2"]


def test_smoothed_force_ratchet(smoothed_feat0_rmse):
    ratchet("feat0 smoothed force RMSE [m/s^2]", smoothed_feat0_rmse, 1.2 * SMOOTHED_FORCE, SMOOTHED_FORCE)


@target_not_met("open: smoothed (0.3 s lag) world force RMSE 0.087 m/s^2 > 0.05 (docs/results.md)")
def test_smoothed_force_target(smoothed_feat0_rmse):
    target("feat0 smoothed force RMSE [m/s^2]", smoothed_feat0_rmse, 0.05)


def test_start_end_window(rendered17, tmp_path):
    out = tmp_path / "window"
    r = vid_run(rendered17, out, "--config", str(REPO / "config" / "sim"), "--features", "feat0",
                "--start", "3", "--end", "8")
    assert r.returncode == 0, r.stderr
    t0 = first_timestamp_ns(rendered17) * 1e-9
    rows = tum_rows(out / "trajectory_tum.txt")
    assert len(rows) > 100
    first, last = float(rows[0][0]) - t0, float(rows[-1][0]) - t0
    assert 3.0 - 1e-6 <= first < 3.6  # static init waits for its 0.5 s window
    assert 7.8 < last <= 8.0 + 1e-6
    s = summary(out)
    assert abs(s["data_duration_s"] - 5.0) < 0.05
    # Ground truth is read only inside the window too: every estimate has a partner.
    assert s["ate_pairs"] <= len(rows)


def test_imu_mode_on_euroc_like(euroc_feat, tmp_path):
    out = tmp_path / "imu"
    r = vid_run(euroc_feat, out)  # no --mode, no rotor0: imu mode
    assert r.returncode == 0, r.stderr
    s = summary(out)
    assert s["mode"] == "imu"
    assert s["mode_source"] == "auto (no rotor/thrust data)"
    assert s["status"] == "ok"
    assert "force_rmse_world_mps2" not in s
    assert len((out / "force.csv").read_text().splitlines()) == 1  # header only
    assert len(tum_rows(out / "trajectory_tum.txt")) > 150 * 9
    assert s["ate_posyaw_m"] < 0.1


def test_mode_flag_overrides_preset(rendered17, tmp_path):
    out = tmp_path / "imu_on_vid"
    r = vid_run(rendered17, out, "--config", str(REPO / "config" / "vid_dataset"), "--features", "feat0",
                "--mode", "imu", "--end", "4")
    assert r.returncode == 0, r.stderr
    assert summary(out)["mode"] == "imu"
    assert summary(out)["mode_source"] == "flag --mode"


@pytest.mark.parametrize("preset", ["sim", "vid_dataset"])
def test_vid_like_presets_run(preset, rendered17, tmp_path):
    """The VID-like simulator uses VID-Dataset's published calibration, so both presets fit."""
    out = tmp_path / preset
    r = vid_run(rendered17, out, "--config", str(REPO / "config" / preset), "--features", "feat0", "--end", "6")
    assert r.returncode == 0, r.stderr
    s = summary(out)
    assert s["mode"] == "dynamics"
    assert s["status"] == "ok"
    assert s["config_sources"]["estimator"].endswith(f"config/{preset}/estimator.yaml")
    assert s["config_sources"]["frontend"].endswith(f"config/{preset}/frontend.yaml")
    if preset == "vid_dataset":
        assert s["mode_source"].endswith("config/vid_dataset/estimator.yaml")
        assert s["config_sources"]["cameras"].endswith("camchain-imucam.yaml")
        assert s["config_sources"]["vehicle"].endswith("config/vid_dataset/vehicle.yaml")
    assert len(tum_rows(out / "trajectory_tum.txt")) > 1000


def test_euroc_preset_on_euroc_layout_folder(tmp_path):
    """config/euroc on the EuRoC-layout sample (tests/data): the preset's calibration replaces
    the folder's, its mode (imu) is used, and the sample's 64x48 images are refused as the
    wrong size for EuRoC's 752x480 cameras (skipped, counted, run completes). The sample is too
    short for the 1 s still window: the run says it never initialized (exit 4)."""
    out = tmp_path / "euroc"
    r = vid_run(REPO / "tests" / "data" / "euroc_sample", out, "--config", str(REPO / "config" / "euroc"))
    assert r.returncode == 4 and "never initialized" in r.stderr, r.stderr
    s = summary(out)
    assert s["mode"] == "imu"
    assert s["mode_source"].endswith("config/euroc/estimator.yaml")
    assert s["config_sources"]["cameras"].endswith("config/euroc/camchain-imucam.yaml")
    assert s["config_sources"]["imu"].endswith("config/euroc/imu.yaml")
    assert s["counts"]["images_wrong_size"] == s["counts"]["camera_frames"] == 2
    assert "752x480" in r.stderr


def test_missing_preset_is_one_line_error(rendered17, tmp_path):
    r = vid_run(rendered17, tmp_path / "x", "--config", str(REPO / "config" / "no_such_preset"))
    assert r.returncode == 1
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "no_such_preset" in lines[0]
