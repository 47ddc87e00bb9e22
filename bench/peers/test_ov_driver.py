"""Smoke test of bench/peers/openvins/ov_driver (GPL-3 peer benchmark, not part of CI).

Runs only when the peer build exists (bench/peers/openvins/build.sh -> build-peers/bin/ov_driver)
and the project's vid_sim is built; skipped otherwise:

    .venv/bin/python -m pytest bench/peers/test_ov_driver.py -q

Simulates 6 s of the euroc_like preset (stereo images), runs OpenVINS through the driver in
stereo and mono, and checks outputs: exit code 0, initialization from the still start, a
finite trajectory of the right length, summary.json keys, and a sane ATE; and the online
time offset (--est-time-offset: starts from the calibration, writes time_offset.csv).
"""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from driver_test_common import driver, simulate, skip_without

OV = driver("VID_OV_DRIVER", "ov_driver")
pytestmark = skip_without(OV, "ov_driver")


@pytest.fixture(scope="module")
def seq(tmp_path_factory):
    return simulate(tmp_path_factory, "euroc_like", 6)


@pytest.mark.parametrize("cams", [2, 1])
def test_ov_driver_runs(seq, tmp_path, cams):
    from vid_eval.core.ate import compute_ate
    from vid_eval.tools.loaders import load_trajectory

    out = tmp_path / f"ov{cams}"
    r = subprocess.run([str(OV), "--dataset", str(seq), "--out", str(out), "--cams", str(cams),
                        "--num-pts", "150", "--clones", "11", "--max-msckf", "60"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    for f in ("trajectory_tum.txt", "timing.csv", "summary.json", "ov_config/estimator_config.yaml",
              "ov_config/kalibr_imucam_chain.yaml", "ov_config/kalibr_imu_chain.yaml"):
        assert (out / f).exists(), f
    s = json.loads((out / "summary.json").read_text())
    assert s["frames"] in (120, 121) and s["frames_skipped"] == 0
    assert 0 < s["init_after_s"] <= 1.5, "should initialize from the still start (1 s hover)"
    assert s["frames_updated"] > 80
    assert s["peak_rss_kb"] > 0 and s["ms_per_frame"]["median"] > 0
    # features per update are logged, not checked: in 6 s euroc_like mostly hovers and the
    # start-up zero-velocity updates hold the state (no feature updates) until it moves
    assert "mean_msckf_features_per_update" in s and "mean_slam_features" in s
    est = load_trajectory(out / "trajectory_tum.txt", "tum")
    assert np.all(np.isfinite(est.p)) and len(est) == s["frames_updated"]
    gt = load_trajectory(seq / "mav0/state_groundtruth_estimate0/data.csv")
    ate = compute_ate(est, gt, "posyaw").pos_rmse
    assert ate < 0.3, f"ATE {ate:.3f} m"


def test_ov_driver_time_offset(seq, tmp_path):
    """--est-time-offset: OpenVINS estimates t_d from the calibration's timeshift_cam_imu and the
    driver writes time_offset.csv (one row per initialized frame, sigma from its covariance)."""
    import shutil

    cal = tmp_path / "seq"
    shutil.copytree(seq, cal)
    with open(cal / "mav0/cam0/sensor.yaml", "a") as f:
        f.write("timeshift_cam_imu: 0.004\n")
    out = tmp_path / "ov"
    r = subprocess.run([str(OV), "--dataset", str(cal), "--out", str(out), "--cams", "2",
                        "--num-pts", "150", "--clones", "11", "--max-msckf", "60", "--est-time-offset"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert "calib_cam_timeoffset: true" in (out / "ov_config/estimator_config.yaml").read_text()
    assert "timeshift_cam_imu: 0.004" in (out / "ov_config/kalibr_imucam_chain.yaml").read_text()
    v = np.loadtxt(out / "time_offset.csv", delimiter=",", comments="#", ndmin=2)
    timing = np.loadtxt(out / "timing.csv", delimiter=",", comments="#", ndmin=2)
    assert len(v) == int(timing[:, 2].sum())  # one row per initialized frame
    assert np.all(np.isfinite(v)) and np.all(np.diff(v[:, 0]) > 0)
    assert v[0, 1] == pytest.approx(0.004) and v[0, 2] == pytest.approx(0.01)  # start: calibration, sigma 10 ms
    assert np.all(v[:, 2] <= 0.01 + 1e-12) and np.all(v[:, 2] > 0)
    # the trajectory is stamped on the IMU clock: camera stamp + the current estimate
    est = np.loadtxt(out / "trajectory_tum.txt")
    s = json.loads((out / "summary.json").read_text())
    assert len(est) == s["frames_updated"] > 80
    t_imu = v[:, 0] * 1e-9 + v[:, 1]
    assert np.abs(t_imu[None, :] - est[:, :1]).min(axis=1).max() < 2e-6


def test_ov_driver_init_groundtruth(seq, tmp_path):
    """--init-groundtruth: OpenVINS starts from the ground-truth state at the first frame (as its
    ros1_serial_msckf with path_gt) instead of waiting for the still start to be detected."""
    from vid_eval.tools.loaders import load_trajectory

    out = tmp_path / "ovgt"
    r = subprocess.run([str(OV), "--dataset", str(seq), "--out", str(out), "--cams", "2",
                        "--num-pts", "150", "--clones", "11", "--max-msckf", "60", "--init-groundtruth"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["init_after_s"] < 0.1, "initialized at the first frame, not after the 1 s hover"
    est = load_trajectory(out / "trajectory_tum.txt", "tum")
    gt = load_trajectory(seq / "mav0/state_groundtruth_estimate0/data.csv")
    assert len(est) == s["frames_updated"] > 100
    # no alignment: the estimate is in the ground truth's own world from the start
    k = np.searchsorted(gt.t_ns, est.t_ns[:5])
    assert np.abs(est.p[:5] - gt.p[k]).max() < 0.02
