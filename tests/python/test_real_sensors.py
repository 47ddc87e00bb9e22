"""Issue 48: the estimator on the real-sensor presets (docs/real_sensors.md): rotor drag, a
tilted thrust axis, thrust-coefficient error, late quantized rotor telemetry, IMU vibration,
one-rotor dips and vibration bursts.

Each preset runs as a user would fly it: after calibrating the vehicle (vehicle.yaml: the thrust
coefficients, the thrust axis and the linear drag that vid-fit-thrust measures; the rotor
telemetry latency as thrust_delay_s; the in-flight accelerometer noise, vibration included, that
vid-allan --flight / vid-fit-thrust's residual measures) - here the simulator's true values, so
the test holds the estimator, not the calibration tools (tested in test_calib_thrust.py). And as
it is flown uncalibrated (the folder's own files), where the force error is the calibration's.

Feature level, seed 1 (the spread over seeds 1-3 is in the comments), config/sim.
"""
import json
import math
import pathlib
import shutil

import pytest
import yaml

from ratchets import ratchet, target, target_not_met
from test_vid_run_helpers import REPO, simulate_cached, summary, vid_run

PRESETS = ["fast_drag_short", "vid17_real_sensors_short", "rotor_dip_short", "vibration_burst_short"]
# In-flight accelerometer noise density of the vibrating presets (rotor lines + broadband: 0.022
# m/s^2/sqrt(Hz) at 10-45 Hz, docs/real_sensors.md); their imu0/sensor.yaml holds the chip's 0.003.
IN_FLIGHT_ACCEL_NOISE = 0.025


def calibrate(seq: pathlib.Path, scenario: pathlib.Path, out: pathlib.Path) -> pathlib.Path:
    """A copy of the folder (links) with the vehicle calibrated to the scenario's truth."""
    sc = yaml.safe_load(scenario.read_text())
    veh, faults = sc["vehicle"], sc.get("sensor_faults", {})
    shutil.rmtree(out, ignore_errors=True)
    (out / "mav0").mkdir(parents=True)
    for d in (seq / "mav0").iterdir():
        if d.name not in ("vehicle.yaml", "imu0"):
            (out / "mav0" / d.name).symlink_to(d.resolve())
    (out / "mav0" / "imu0").mkdir()
    (out / "mav0" / "imu0" / "data.csv").symlink_to((seq / "mav0" / "imu0" / "data.csv").resolve())
    imu = (seq / "mav0" / "imu0" / "sensor.yaml").read_text()
    if "vibration" in faults:
        imu = "\n".join(f"accelerometer_noise_density: {IN_FLIGHT_ACCEL_NOISE}"
                        if line.startswith("accelerometer_noise_density:") else line for line in imu.splitlines())
    (out / "mav0" / "imu0" / "sensor.yaml").write_text(imu + "\n")
    lines = [f"mass_kg: {veh['mass_kg']}", "gravity: 9.81",
             f"rotor_thrust_coefficients: {list(veh['thrust_coefficients'])}"]
    if "thrust_axis" in faults:
        tilt, az = math.radians(faults["thrust_axis"]["tilt_deg"]), math.radians(faults["thrust_axis"]["azimuth_deg"])
        lines.append(f"thrust_axis: [{math.sin(tilt) * math.cos(az)}, {math.sin(tilt) * math.sin(az)}, {math.cos(tilt)}]")
    if "rotor_drag_per_s" in veh:
        lines.append(f"linear_drag: {list(veh['rotor_drag_per_s'])}")
    (out / "mav0" / "vehicle.yaml").write_text("\n".join(lines) + "\n")
    return out


_RUNS = {}


def run(tmp_path_factory, preset: str, calibrated: bool, mode: str) -> dict:
    key = (preset, calibrated, mode)
    if key not in _RUNS:
        scenario = REPO / "config" / "sim" / f"{preset}.yaml"
        seq = simulate_cached(f"{preset}.yaml", 25.0, 1, True)
        base = tmp_path_factory.getbasetemp() / "real_sensors"
        cfg = REPO / "config" / "sim"
        if calibrated:
            seq = calibrate(seq, scenario, base / f"{preset}_cal")
            latency = yaml.safe_load(scenario.read_text()).get("sensor_faults", {}).get(
                "rotor_telemetry", {}).get("latency_s", 0.0)
            cfg = base / f"cfg_{preset}"
            shutil.rmtree(cfg, ignore_errors=True)
            shutil.copytree(REPO / "config" / "sim", cfg)
            with open(cfg / "estimator.yaml", "a") as fh:
                fh.write(f"\nthrust_delay_s: {latency}\n")
        out = base / f"run_{preset}_{'cal' if calibrated else 'raw'}_{mode}"
        r = vid_run(seq, out, "--config", str(cfg), "--mode", mode)
        assert r.returncode == 0, r.stderr
        _RUNS[key] = summary(out)
    return _RUNS[key]


# Calibrated, seed 1, measured with the vibration-aware accelerometer noise (0.25 s window,
# innovation power above 10 Hz, 3-sigma clipped): body force RMSE [m/s^2], force jumps, ATE
# dynamics / imu [m]. Ratchets at 1.2x (one seed: the margin docs/testing.md gives a figure
# without a measured spread).
#   fast_drag_short           0.094   0   0.0245 / 0.0229  (dynamics 7 % worse: target not met)
#   vid17_real_sensors_short  0.103   0   0.0071 / 0.0070
#   rotor_dip_short           0.115   0   0.0053 / 0.0061
#   vibration_burst_short     0.301  57   0.0079 / 0.0097  (bursts: force and jumps not met)
# vibration_burst_short was 0.286 / 45 jumps with the first estimator (the plain window
# variance), which read every slow innovation as noise: it also hid touchdowns (the vehicle sank
# 0.4 m through the floor on takeoff_landing_short, ATE 0.076 m). With no adaptation: 0.341 / 88.
FORCE = {"fast_drag_short": 0.094, "vid17_real_sensors_short": 0.103, "rotor_dip_short": 0.115,
         "vibration_burst_short": 0.301}
ATE_RATIO = {"fast_drag_short": 1.072, "vid17_real_sensors_short": 1.015, "rotor_dip_short": 0.865,
             "vibration_burst_short": 0.814}
SMOOTH = ["fast_drag_short", "vid17_real_sensors_short", "rotor_dip_short"]


def jumps_per_minute_limit(s: dict) -> float:
    """At most one force jump per minute where the force is smooth (no preset here has a step)."""
    return max(1.0, s.get("data_duration_s", 25.0) / 60.0)


@pytest.mark.parametrize("preset", PRESETS)
def test_calibrated_force_ratchet(tmp_path_factory, preset):
    s = run(tmp_path_factory, preset, True, "dynamics")
    assert s["status"] == "ok"
    force = s["force_rmse_body_mps2"]
    print(f"{preset}: body force {force:.3f} m/s^2, ATE {s['ate_posyaw_m']:.4f} m, jumps {s['counts']['force_jumps']}")
    ratchet(f"{preset} body force RMSE", force, 1.2 * FORCE[preset], measured=FORCE[preset], unit=" m/s^2")


@pytest.mark.parametrize("preset", SMOOTH)
def test_calibrated_force_target_and_no_false_jumps(tmp_path_factory, preset):
    s = run(tmp_path_factory, preset, True, "dynamics")
    assert s["force_rmse_body_mps2"] <= 0.15, s["force_rmse_body_mps2"]
    assert s["counts"]["force_jumps"] <= jumps_per_minute_limit(s), s["accel"]["force_jump_events"][:5]


@target_not_met("vibration bursts (0.4-1 m/s^2 rms at 10-40 Hz for 1-3 s) still read as force steps "
                "before the vibration-aware noise has caught up (README 'Real sensors')")
def test_vibration_burst_force_target(tmp_path_factory):
    s = run(tmp_path_factory, "vibration_burst_short", True, "dynamics")
    jumps = s["counts"]["force_jumps"]
    ratchet("vibration_burst_short force jumps", jumps, 68, measured=57)
    target("vibration_burst_short body force RMSE", s["force_rmse_body_mps2"], 0.15, unit=" m/s^2")
    target("vibration_burst_short force jumps", jumps, jumps_per_minute_limit(s))


@pytest.mark.parametrize("preset", PRESETS)
def test_calibrated_dynamics_ate_ratchet(tmp_path_factory, preset):
    dyn = run(tmp_path_factory, preset, True, "dynamics")["ate_posyaw_m"]
    imu = run(tmp_path_factory, preset, True, "imu")["ate_posyaw_m"]
    print(f"{preset}: ATE dynamics {dyn:.4f} m, imu {imu:.4f} m")
    ratchet(f"{preset} ATE dynamics / imu", dyn / imu, 1.2 * ATE_RATIO[preset], measured=ATE_RATIO[preset])


@pytest.mark.parametrize("preset", [p for p in PRESETS if ATE_RATIO[p] <= 1.0])
def test_calibrated_dynamics_is_no_worse_than_imu(tmp_path_factory, preset):
    dyn = run(tmp_path_factory, preset, True, "dynamics")["ate_posyaw_m"]
    imu = run(tmp_path_factory, preset, True, "imu")["ate_posyaw_m"]
    assert dyn <= imu * 1.01, (dyn, imu)  # 1 %: the two modes' ATE agree to ~0.5 % on the ideal presets


@target_not_met("fast_drag_short: dynamics ATE 7 % above imu mode (seed 1)")
def test_fast_drag_dynamics_is_no_worse_than_imu(tmp_path_factory):
    dyn = run(tmp_path_factory, "fast_drag_short", True, "dynamics")["ate_posyaw_m"]
    imu = run(tmp_path_factory, "fast_drag_short", True, "imu")["ate_posyaw_m"]
    target("fast_drag_short ATE dynamics / imu", dyn / imu, 1.0)


@pytest.mark.parametrize("preset", ["fast_drag_short", "vid17_real_sensors_short"])
def test_uncalibrated_vehicle_is_reported_by_the_noise_fit(tmp_path_factory, preset):
    """The folder's own files (chip accelerometer noise 0.003, k 3 % low, thrust axis = z): the
    force carries the calibration's error, and the noise fit says which key is off."""
    s = run(tmp_path_factory, preset, False, "dynamics")
    nis = s["noise_fit"]["accel_nis_per_axis"]
    print(f"{preset} uncalibrated: body force {s['force_rmse_body_mps2']:.3f}, accel NIS {nis}")
    assert min(nis) > 3.0, "the vibrating accelerometer's innovations are far above the chip noise"
    assert any("accel_noise_density" in w for w in s["noise_fit"]["warnings"])
