"""Camera-IMU time offset (issue #23, README "Camera-IMU time offset"): the simulator stamps
images t_imu - t_d (cameras.time_offset_s), the estimator places frames at t_cam + t_d, with t_d
from the calibration (timeshift_cam_imu) or estimated online (init_sigma_time_offset > 0)."""
import re
import shutil

import numpy as np
import pytest

from test_vid_run_helpers import REPO, simulate, summary, vid_run


def scenario(tmp_path, preset: str, camera_keys: str, timeshift: float = None) -> str:
    """config/sim/<preset>.yaml with keys added under `cameras:` (and every camera's calibrated
    timeshift_cam_imu set), as an absolute path."""
    text = (REPO / "config" / "sim" / f"{preset}.yaml").read_text()
    text = text.replace("cameras:\n", "cameras:\n" + camera_keys, 1)
    if timeshift is not None:
        text = re.sub(r"(?m)^(\s*)(T_imu_cam: .*)$", rf"\1\2\n\1timeshift_cam_imu: {timeshift}", text)
    path = tmp_path / f"{preset}_clock.yaml"
    path.write_text(text)
    return str(path)


def config(tmp_path, sigma: float):
    cfg = tmp_path / "cfg"
    shutil.copytree(REPO / "config" / "sim", cfg)
    with open(cfg / "estimator.yaml", "a") as f:
        f.write(f"\ninit_sigma_time_offset: {sigma}\n")
    return cfg


def offset_series(out):
    v = np.loadtxt(out / "time_offset.csv", delimiter=",", comments="#")
    return (v[:, 0] - v[0, 0]) * 1e-9, v[:, 1], v[:, 2]


@pytest.mark.parametrize("offset", [0.010, -0.010])
def test_calibrated_offset_is_applied(tmp_path, offset):
    """A sequence whose camera runs t_d behind/ahead of the IMU, with t_d in its calibration,
    is estimated as well as the same flight without an offset (a negative t_d means frames
    arrive after the IMU samples they precede: the pipeline holds the IMU for them)."""
    clean = simulate(tmp_path / "clean", "vid17_like.yaml", 20.0, 1, True)
    seq = simulate(tmp_path / "seq", scenario(tmp_path, "vid17_like", f"  time_offset_s: {offset}\n", offset),
                   20.0, 1, True)
    for s, out in ((clean, tmp_path / "o_clean"), (seq, tmp_path / "o_seq")):
        r = vid_run(s, out, "--config", str(REPO / "config" / "sim"))
        assert r.returncode == 0, r.stderr
    a, b = summary(tmp_path / "o_clean"), summary(tmp_path / "o_seq")
    assert b["ate_posyaw_m"] <= 1.1 * a["ate_posyaw_m"], (a["ate_posyaw_m"], b["ate_posyaw_m"])
    assert b["force_rmse_world_mps2"] <= 1.1 * a["force_rmse_world_mps2"]


@pytest.mark.parametrize("preset", ["vid18_like", "fast_yaw"])
def test_offset_estimated_online_noise_free(tmp_path, preset):
    """From t_d = 0 with sigma 20 ms, a true 10 ms offset (noise-free sensors): within 0.5 ms from
    10 s on, and the estimate's sigma covers its error. On fast_yaw (3 rad/s) the fresh clone's
    exact copy of the IMU pose once made the covariance check call P non-PD at 1.4 s."""
    seq = simulate(tmp_path / "seq", scenario(tmp_path, preset, "  time_offset_s: 0.010\n"), 20.0, 1, True,
                   noise_free=True)
    out = tmp_path / "out"
    r = vid_run(seq, out, "--config", str(config(tmp_path, 0.02)))
    assert r.returncode == 0, r.stderr
    t, td, sigma = offset_series(out)
    late = t >= 10.0
    assert np.abs(td[late] - 0.010).max() <= 0.0005, f"max error {np.abs(td[late] - 0.010).max() * 1e3:.2f} ms"
    assert np.all(np.abs(td[late] - 0.010) <= 3 * sigma[late])


@pytest.mark.xfail(strict=True, reason="issue #23: with sensor noise the estimate stays ms away from a true "
                                       "10 ms (fast_yaw 7.8 ms) with a sigma of 0.2 ms (README)")
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_offset_estimated_online(tmp_path, seed):
    """The issue's criterion: from a true 10 ms offset (0.5 ms jitter), within 0.5 ms after 10 s."""
    seq = simulate(tmp_path / "seq", scenario(tmp_path, "vid18_like",
                                              "  time_offset_s: 0.010\n  time_offset_jitter_s: 0.0005\n"),
                   20.0, seed, True)
    out = tmp_path / "out"
    r = vid_run(seq, out, "--config", str(config(tmp_path, 0.02)))
    assert r.returncode == 0, r.stderr
    t, td, _ = offset_series(out)
    assert np.abs(td[t >= 10.0] - 0.010).max() <= 0.0005
