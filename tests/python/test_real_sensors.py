"""Issue 48: the estimator on the real-sensor presets (docs/real_sensors.md): rotor drag, a
tilted thrust axis, thrust-coefficient error, late quantized rotor telemetry, IMU vibration,
one-rotor dips and vibration bursts.

Each preset runs as a user would fly it: after calibrating the vehicle (vehicle.yaml: the thrust
coefficients, the thrust axis and the linear drag that vid-fit-thrust measures; the rotor
telemetry latency as thrust_delay_s; the in-flight accelerometer noise, vibration included, that
vid-allan --flight / vid-fit-thrust's residual measures) - here the simulator's true values, so
the test holds the estimator, not the calibration tools (tested in test_calib_thrust.py). And as
it is flown uncalibrated (the folder's own files), where the force error is the calibration's.

Feature level, seeds 1-3 (25 s each), config/sim.
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


SEEDS = (1, 2, 3)


def run(tmp_path_factory, preset: str, calibrated: bool, mode: str, seed: int = 1) -> dict:
    key = (preset, calibrated, mode, seed)
    if key not in _RUNS:
        scenario = REPO / "config" / "sim" / f"{preset}.yaml"
        seq = simulate_cached(f"{preset}.yaml", 25.0, seed, True)
        base = tmp_path_factory.getbasetemp() / "real_sensors"
        cfg = REPO / "config" / "sim"
        if calibrated:
            seq = calibrate(seq, scenario, base / f"{preset}_s{seed}_cal")
            latency = yaml.safe_load(scenario.read_text()).get("sensor_faults", {}).get(
                "rotor_telemetry", {}).get("latency_s", 0.0)
            cfg = base / f"cfg_{preset}"
            if not cfg.exists():
                shutil.copytree(REPO / "config" / "sim", cfg)
                with open(cfg / "estimator.yaml", "a") as fh:
                    fh.write(f"\nthrust_delay_s: {latency}\n")
        out = base / f"run_{preset}_s{seed}_{'cal' if calibrated else 'raw'}_{mode}"
        r = vid_run(seq, out, "--config", str(cfg), "--mode", mode)
        assert r.returncode == 0, r.stderr
        _RUNS[key] = summary(out)
    return _RUNS[key]


def over_seeds(tmp_path_factory, preset: str) -> list:
    """Calibrated runs of seeds 1-3: [(dynamics summary, imu summary)]."""
    return [(run(tmp_path_factory, preset, True, "dynamics", s), run(tmp_path_factory, preset, True, "imu", s))
            for s in SEEDS]


# Calibrated, seeds 1-3, measured with the vibration-aware accelerometer noise (0.25 s window,
# innovation power above 10 Hz, 3-sigma clipped). Ratchets at 1.2x the worst seed (three seeds
# are too few for a spread; docs/testing.md).
#                             body force [m/s^2]     jumps      ATE dynamics / imu
#   fast_drag_short           0.094 0.106 0.101      0  0  0    1.072 0.983 1.009 (mean 1.021)
#   vid17_real_sensors_short  0.103 0.104 0.115      0  0  0    1.015 0.986 1.085 (mean 1.029)
#   rotor_dip_short           0.115 0.165 0.129      0  0  0    0.865 0.944 0.964 (mean 0.924)
#   vibration_burst_short     0.189 0.181 0.195     19 26 28    0.895 0.980 0.993 (mean 0.956)
# vibration_burst_short with the detector counting vibration as white (before the coloured excess
# of docs/model.md eq. (22)): 0.301 0.255 0.279 m/s^2, 57 58 52 jumps (half a cycle of a burst
# read as a step); the jumps left are the bursts' first 0.1-0.4 s, before the noise estimate has
# seen them.
# vibration_burst_short seed 1 was 0.286 / 45 jumps with the first estimator (the plain window
# variance), which read every slow innovation as noise: it also hid touchdowns (the vehicle sank
# 0.4 m through the floor on takeoff_landing_short, ATE 0.076 m). With no adaptation: 0.341 / 88.
# A fast-attack estimate (the same power over 8 samples) took the bursts to 0.165 / 12 jumps but
# impacts_short's force from 0.90 to 1.20 and takeoff_landing_short's from 0.66 to 0.93 m/s^2:
# within 20 ms a burst's onset and an impact look alike (docs/notes/real-sensors.md).
WORST_FORCE = {"fast_drag_short": 0.106, "vid17_real_sensors_short": 0.115, "rotor_dip_short": 0.165,
               "vibration_burst_short": 0.195}
MOST_JUMPS = {"fast_drag_short": 0, "vid17_real_sensors_short": 0, "rotor_dip_short": 0, "vibration_burst_short": 28}
ATE_RATIO = {"fast_drag_short": 1.021, "vid17_real_sensors_short": 1.029, "rotor_dip_short": 0.924,
             "vibration_burst_short": 0.956}  # mean over the seeds
SMOOTH = ["fast_drag_short", "vid17_real_sensors_short", "rotor_dip_short"]
# Issue 48: body force <= 0.15 m/s^2 on every seed; dynamics ATE <= imu ATE on the mean and on
# 2 of the 3 seeds. Where not met, a strict xfail.
FORCE_MET = ["fast_drag_short", "vid17_real_sensors_short"]
ATE_MET = ["rotor_dip_short", "vibration_burst_short"]


def jumps_per_minute_limit(s: dict) -> float:
    """At most one force jump per minute where the force is smooth (no preset here has a step)."""
    return max(1.0, s.get("data_duration_s", 25.0) / 60.0)


def report(preset: str, runs: list) -> None:
    for seed, (d, i) in zip(SEEDS, runs):
        print(f"{preset} seed {seed}: body force {d['force_rmse_body_mps2']:.3f} m/s^2, "
              f"jumps {d['counts']['force_jumps']}, ATE dynamics {d['ate_posyaw_m']:.4f} / imu {i['ate_posyaw_m']:.4f} m")


@pytest.mark.parametrize("preset", PRESETS)
def test_calibrated_force_ratchet(tmp_path_factory, preset):
    runs = over_seeds(tmp_path_factory, preset)
    report(preset, runs)
    assert all(d["status"] == "ok" for d, _ in runs)
    worst = max(d["force_rmse_body_mps2"] for d, _ in runs)
    ratchet(f"{preset} body force RMSE, worst seed", worst, 1.2 * WORST_FORCE[preset],
            measured=WORST_FORCE[preset], unit=" m/s^2")
    most = max(d["counts"]["force_jumps"] for d, _ in runs)
    ratchet(f"{preset} force jumps, most of a seed", most, max(1, round(1.2 * MOST_JUMPS[preset])),
            measured=MOST_JUMPS[preset])


@pytest.mark.parametrize("preset", SMOOTH)
def test_calibrated_no_false_jumps_where_the_force_is_smooth(tmp_path_factory, preset):
    for d, _ in over_seeds(tmp_path_factory, preset):
        assert d["counts"]["force_jumps"] <= jumps_per_minute_limit(d), d["accel"]["force_jump_events"][:5]


@pytest.mark.parametrize("preset", [p if p in FORCE_MET else pytest.param(p, marks=target_not_met(
    f"{p}: body force above 0.15 m/s^2 on a seed")) for p in SMOOTH])
def test_calibrated_force_target(tmp_path_factory, preset):
    for seed, (d, _) in zip(SEEDS, over_seeds(tmp_path_factory, preset)):
        target(f"{preset} seed {seed} body force RMSE", d["force_rmse_body_mps2"], 0.15, unit=" m/s^2")


@target_not_met("vibration bursts (0.4-1 m/s^2 rms at 10-40 Hz for 1-3 s) still read as force steps "
                "in their first 0.1-0.4 s, before the noise estimate has seen them "
                "(docs/notes/real-sensors.md)")
def test_vibration_burst_force_target(tmp_path_factory):
    for d, _ in over_seeds(tmp_path_factory, "vibration_burst_short"):
        target("vibration_burst_short body force RMSE", d["force_rmse_body_mps2"], 0.15, unit=" m/s^2")
        target("vibration_burst_short force jumps", d["counts"]["force_jumps"], jumps_per_minute_limit(d))


def ate_ratios(runs: list) -> list:
    return [d["ate_posyaw_m"] / i["ate_posyaw_m"] for d, i in runs]


@pytest.mark.parametrize("preset", PRESETS)
def test_calibrated_dynamics_ate_ratchet(tmp_path_factory, preset):
    ratios = ate_ratios(over_seeds(tmp_path_factory, preset))
    print(f"{preset}: ATE dynamics / imu per seed {[round(r, 3) for r in ratios]}")
    mean = sum(ratios) / len(ratios)
    ratchet(f"{preset} ATE dynamics / imu, mean of 3 seeds", mean, 1.2 * ATE_RATIO[preset], measured=ATE_RATIO[preset])


@pytest.mark.parametrize("preset", [p if p in ATE_MET else pytest.param(p, marks=target_not_met(
    f"{p}: dynamics ATE above imu mode (mean or 2 of 3 seeds)")) for p in PRESETS])
def test_calibrated_dynamics_is_no_worse_than_imu(tmp_path_factory, preset):
    ratios = ate_ratios(over_seeds(tmp_path_factory, preset))
    target(f"{preset} ATE dynamics / imu, mean of 3 seeds", sum(ratios) / len(ratios), 1.0)
    target(f"{preset} seeds with dynamics ATE <= imu", sum(r <= 1.0 for r in ratios), 2, higher_is_better=True)


@pytest.mark.parametrize("preset", ["fast_drag_short", "vid17_real_sensors_short"])
def test_uncalibrated_vehicle_is_reported_by_the_noise_fit(tmp_path_factory, preset):
    """The folder's own files (chip accelerometer noise 0.003, k 3 % low, thrust axis = z): the
    force carries the calibration's error, and the noise fit says which key is off."""
    s = run(tmp_path_factory, preset, False, "dynamics")
    nis = s["noise_fit"]["accel_nis_per_axis"]
    print(f"{preset} uncalibrated: body force {s['force_rmse_body_mps2']:.3f}, accel NIS {nis}")
    assert min(nis) > 3.0, "the vibrating accelerometer's innovations are far above the chip noise"
    assert any("accel_noise_density" in w for w in s["noise_fit"]["warnings"])
