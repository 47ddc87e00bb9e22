"""Issue 49 step 2: hover initialization under rotor vibration. The real-sensor presets (2 s of
hover first) initialize within 1 s of the hover's start, also with the vibration raised to what a
real 400 Hz IMU shows in hover (0.08 rad/s per gyro axis, 0.02 m/s^2/sqrt(Hz) accelerometer);
the still test judges 0.1 s moving averages (init_lowpass_s), and the same flight judged sample
by sample (init_lowpass_s 0) does not initialize in that second."""
import shutil

import numpy as np
import pytest

from test_vid_run_helpers import REPO, simulate, simulate_cached, summary, vid_run

CONFIG = REPO / "config" / "sim"
PRESETS = ["vid17_real_sensors_short.yaml", "rotor_dip_short.yaml", "vibration_burst_short.yaml",
           "fast_drag_short.yaml"]


def init_delay_s(seq, out) -> float:
    """First estimate's time after the first IMU sample [s]."""
    t_imu = np.loadtxt(seq / "mav0" / "imu0" / "data.csv", delimiter=",", comments="#", max_rows=1, skiprows=1, ndmin=2)[0, 0]
    t_est = np.loadtxt(out / "state.csv", delimiter=",", comments="#", max_rows=1, skiprows=1, ndmin=2)[0, 0]
    return (t_est - t_imu) * 1e-9


@pytest.mark.parametrize("preset", PRESETS)
def test_real_sensor_preset_initializes_within_1s(preset, tmp_path):
    seq = simulate_cached(preset, 4.0, 1, True)
    r = vid_run(seq, tmp_path / "run", "--config", str(CONFIG), "--init", "static")
    assert r.returncode == 0, r.stderr
    assert summary(tmp_path / "run")["status"] == "ok"
    # Measured 0.50-0.64 s (the 0.5 s window, then the rotor telemetry's 30 ms latency and gaps).
    assert init_delay_s(seq, tmp_path / "run") <= 1.0


@pytest.fixture(scope="module")
def strong_vibration(tmp_path_factory):
    """vid17_real_sensors_short with the broadband vibration of a real hover: gyro 0.004
    rad/s/sqrt(Hz) (0.08 rad/s per sample at 400 Hz: the simulator draws density * sqrt(rate)), accelerometer 0.02 m/s^2/sqrt(Hz)."""
    d = tmp_path_factory.mktemp("strong_vibration")
    text = (CONFIG / "vid17_real_sensors_short.yaml").read_text()
    for old, new in [("accel_noise_density: 0.013", "accel_noise_density: 0.02"),
                     ("gyro_noise_density: 1.2e-3", "gyro_noise_density: 4.0e-3")]:
        assert old in text
        text = text.replace(old, new)
    scenario = d / "strong_vibration.yaml"
    scenario.write_text(text)
    for f in CONFIG.glob("*.yaml"):  # the scene and files the scenario may name
        if not (d / f.name).exists():
            shutil.copy(f, d / f.name)
    seq = simulate(d / "seq", str(scenario), 4.0, 1, True)
    gyro = np.loadtxt(seq / "mav0" / "imu0" / "data.csv", delimiter=",", comments="#")[:800, 1:4]
    assert 0.06 < float(np.mean(np.std(gyro, axis=0))) < 0.1  # what the fixture claims
    return seq


def test_strong_vibration_hover_initializes_within_1s(strong_vibration, tmp_path):
    r = vid_run(strong_vibration, tmp_path / "run", "--config", str(CONFIG), "--init", "static")
    assert r.returncode == 0, r.stderr
    assert init_delay_s(strong_vibration, tmp_path / "run") <= 1.0


def test_strong_vibration_sample_by_sample_is_not_still(strong_vibration, tmp_path):
    cfg = tmp_path / "config"
    shutil.copytree(CONFIG, cfg)
    est = cfg / "estimator.yaml"
    assert "init_lowpass_s: 0.1" in est.read_text()
    est.write_text(est.read_text().replace("init_lowpass_s: 0.1", "init_lowpass_s: 0"))
    r = vid_run(strong_vibration, tmp_path / "run", "--config", str(cfg), "--init", "static", "--end", "1.5")
    assert r.returncode == 4, r.stderr
    assert "not still" in r.stderr
