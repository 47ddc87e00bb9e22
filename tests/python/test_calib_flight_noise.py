"""vid-allan --flight (issue #48 item 2): the IMU noise in flight from a log with no static part.

The log is config/sim/vid17_real_sensors_short.yaml: its imu0/sensor.yaml holds the chip's
static noise (what a static calibration gives), while in flight the rotors add vibration far
above it (sensor_faults.vibration). The expected in-flight level is computed here from the
scenario's vibration keys and the log's rotor speeds, independently of the tool (the model of
config/sim/README.md "Real-sensor effects"): per axis and sample, the rotor and blade-pass lines
(amplitude A (n/n_hover)^2, variance A^2/2 each), the broadband noise (density times the rotors'
mean (n/n_hover)^2) and the chip's white noise, plus the bursts (rms^2 over 0.75 of their
window: raised-cosine ramps of a fifth). The density is the per-sample sigma over sqrt(rate).

Measured over seeds 1-5 (and fast_drag_short seeds 1-3): the gyro within -0.8/+0.7 % of that
level, the accelerometer within -1.2/+2.2 %; the bound is 5 %.
"""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
import yaml

from test_vid_run_helpers import REPO, program
from vid_eval.tools.loaders import load_imu, load_rotor_speeds

PRESET = REPO / "config" / "sim" / "vid17_real_sensors_short.yaml"
TOL = 0.05


@pytest.fixture(scope="module")
def flight(tmp_path_factory):
    out = tmp_path_factory.mktemp("flight_noise") / "real"
    subprocess.run([str(program("vid_sim")), "--scenario", str(PRESET), "--out", str(out), "--features-only",
                    "--quiet"], check=True, capture_output=True, text=True, timeout=900)
    return out


def _allan(*args):
    return subprocess.run([sys.executable, "-m", "vid_eval.calib.allan_cli", *map(str, args)],
                          capture_output=True, text=True)


def expected_density(folder, scenario) -> dict:
    """In-flight density per sensor (root mean square over the axes) of the module docstring."""
    sc = yaml.safe_load(scenario.read_text())
    vib, imu, veh = sc["sensor_faults"]["vibration"], sc["imu"], sc["vehicle"]
    k = np.array(veh["thrust_coefficients"])
    n_hover = np.sqrt(veh["mass_kg"] * veh["gravity"] / k.sum())
    s = (load_rotor_speeds(folder / "mav0" / "rotor0" / "data.csv").values / n_hover) ** vib["speed_exponent"]
    t = load_imu(folder / "mav0" / "imu0" / "data.csv").t_ns
    span = (t[-1] - t[0]) * 1e-9
    rate = imu["rate_hz"]
    out = {}
    for sensor, chip, pre in (("accelerometer", imu["accelerometer_noise_density"], "accel"),
                              ("gyroscope", imu["gyroscope_noise_density"], "gyro")):
        lines = (s ** 2).sum(axis=1).mean() * (np.array(vib[f"{pre}_rotor_amplitude"]) ** 2
                                               + np.array(vib[f"{pre}_blade_amplitude"]) ** 2) / 2
        broadband = (vib[f"{pre}_noise_density"] * s.mean(axis=1)) ** 2
        bursts = sum(b[f"{pre}_rms"] ** 2 * 0.75 * b["duration_s"] for b in vib.get("bursts", []) if b["t_s"] < span)
        var = lines + (chip ** 2 + broadband.mean()) * rate + bursts / span
        out[sensor] = float(np.sqrt(np.mean(var / rate)))
    return out


def test_flight_noise_matches_the_vibration(flight, tmp_path):
    out = tmp_path / "imu.yaml"
    r = _allan("--flight", flight, "--out", out)
    assert r.returncode == 0, r.stderr
    got = yaml.safe_load(out.read_text())["imu0"]
    want = expected_density(flight, PRESET)
    static = yaml.safe_load(PRESET.read_text())["imu"]
    for sensor in ("gyroscope", "accelerometer"):
        key = f"{sensor}_noise_density"
        print(f"[tolerance] {key}: {got[key]:.4e} vs {want[sensor]:.4e} ({got[key] / want[sensor] - 1:+.2%}; "
              f"static {static[key]:g})")
        assert got[key] == pytest.approx(want[sensor], rel=TOL)
        assert got[key] > 4.0 * static[key]   # the point: the static value is far too optimistic
        random_walk = f"{sensor}_random_walk"
        assert got[random_walk] == pytest.approx(static[random_walk])   # kept from imu0/sensor.yaml
    # The estimator's keys with their explanation, and the warning that says the static values
    # are too low.
    assert "gyro_noise_density:" in r.stdout and "accel_noise_density:" in r.stdout
    assert "more than 3x imu0/sensor.yaml's" in r.stderr


def test_vid_fit_thrust_prints_the_same_accelerometer_level(flight):
    r = subprocess.run([sys.executable, "-m", "vid_eval.calib.fit_thrust_cli", flight],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    density = float(r.stdout.split("accel_noise_density ")[1].split()[0])
    assert density == pytest.approx(expected_density(flight, PRESET)["accelerometer"], rel=TOL)


def test_without_ground_truth_and_thrust_nothing_to_measure(flight, tmp_path):
    import shutil
    copy = tmp_path / "imu_only"
    shutil.copytree(flight / "mav0" / "imu0", copy / "mav0" / "imu0")
    r = _allan("--flight", copy)
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1
    assert "nothing to measure" in r.stderr and "no ground truth" in r.stderr


def test_flight_flags_are_checked(flight, tmp_path):
    r = _allan("--flight", flight, "--plot", tmp_path / "a.png")
    assert r.returncode == 2 and "not with --flight" in r.stderr
    r = _allan("--flight", flight, "--highpass", "0")
    assert r.returncode == 2 and "--highpass" in r.stderr
