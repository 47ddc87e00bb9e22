"""vid-bag2asl end to end: synthetic VID-like bags (ROS1 none/bz2/lz4, ROS2) with the VID topic
names and custom message definitions, converted and checked value by value and stamp by stamp."""
from __future__ import annotations

import pathlib

import numpy as np
import pytest
import yaml

from test_bag2asl_helpers import f32, numeric, png, rows
from vid_eval.bag2asl.cli import main
from vid_eval.bag2asl.synthetic import BagWriter

T0 = 1_650_000_000_123_456_789
RNG_SEED = 42


def luma(r, g, b):
    return np.clip(np.rint(0.299 * r.astype(float) + 0.587 * g + 0.114 * b), 0, 255).astype(np.uint8)


def write_raw_vid_bag(path: pathlib.Path, compression: str) -> dict:
    """Raw-profile VID bag; returns every expected output row."""
    rng = np.random.default_rng(RNG_SEED)
    w = BagWriter(path, compression=compression)
    exp = {"cam0": [], "cam1": [], "imu0": [], "rotor0": [], "gt": [], "force0": []}
    h, wd = 6, 8
    encodings = ["mono8", "mono16", "bgr8", "rgb8", "bgra8", "rgba8", "mono8-padded", "mono16-be"]
    for k in range(8):  # camera 20 Hz
        t = T0 + k * 50_000_000
        enc = encodings[k]
        if enc in ("mono8", "mono8-padded"):
            px = rng.integers(0, 256, (h, wd), dtype=np.uint8)
            msg = w.image(t, "mono8", px, step=wd + 3 if enc == "mono8-padded" else None)
            gray = px
        elif enc.startswith("mono16"):
            px = rng.integers(0, 65536, (h, wd), dtype=np.uint16)
            big = enc.endswith("be")
            msg = w.image(t, "mono16", px.astype(">u2" if big else "<u2"), bigendian=int(big))
            gray = (px >> 8).astype(np.uint8)
        else:
            ch = 4 if enc.endswith("a8") else 3
            px = rng.integers(0, 256, (h, wd, ch), dtype=np.uint8)
            msg = w.image(t, enc, px)
            r, g, b = (px[..., 2], px[..., 1], px[..., 0]) if enc.startswith("bgr") else (
                px[..., 0], px[..., 1], px[..., 2])
            gray = luma(r, g, b)
        w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t + 1000, msg)
        exp["cam0"].append((t, gray))
        px2 = rng.integers(0, 256, (h, wd), dtype=np.uint8)
        t2 = t + 7  # right camera stamped 7 ns later
        w.write("/camera/infra2/image_rect_raw", "sensor_msgs/msg/Image", t2 + 1000, w.image(t2, "mono8", px2))
        exp["cam1"].append((t2, px2))
    for k in range(160):  # IMU 400 Hz, custom djiros type
        t = T0 + k * 2_500_000
        gyro, acc = rng.normal(size=3), rng.normal(size=3) + [0, 0, 9.81]
        w.write("/djiros/imu_hwts", "djiros/msg/ImuWithHwTimeStamp", t + 500, w.dji_imu(t, t + 99, gyro, acc, k))
        exp["imu0"].append((t, [*gyro, *acc]))
    for k in range(40):  # motors 100 Hz, m1 first then m2..m4 at +1..3 ms
        cycle = []
        for m in range(4):
            t = T0 + k * 10_000_000 + m * 1_000_000
            rpm = int(rng.integers(-3000, 9000))
            w.write(f"/m100withm3508/m3508_m{m + 1}", "uavmotor/msg/m3508", t + 200,
                    w.m3508(t, t + 5, m + 1, int(rng.integers(-500, 500)), rpm))
            cycle.append(rpm)
        # one row per complete cycle, at its newest stamp (m4's), never a value of the last cycle
        exp["rotor0"].append((T0 + k * 10_000_000 + 3_000_000, cycle))
        w.write("/m100withm3508/target_rpm", "uavmotor/msg/motordata", T0 + k * 10_000_000 + 300,
                w.motordata(T0 + k * 10_000_000, T0, [1, 2, 3, 4]))
    for k in range(30):  # vicon TransformStamped 100 Hz, jittered stamps
        t = T0 + k * 10_000_000 + int(rng.integers(0, 1000))
        p = rng.normal(size=3)
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        w.write("/vicon/m100/m100", "geometry_msgs/msg/TransformStamped", t + 100, w.transform(t, p, q))
        exp["gt"].append((t, p, q))
    for k in range(25):  # Robotiq ft_sensor: no header -> bag time
        t = T0 + k * 10_000_000 + 400
        f = rng.normal(size=3) * 5
        w.write("/robotiq_ft_sensor", "robotiq_ft_sensor/msg/ft_sensor", t, w.ft_sensor(f, (1, 2, 3)))
        exp["force0"].append((t, [f32(v) for v in f]))
    w.close()
    return exp


def expected_gt(samples):
    out = []
    n = len(samples)
    for i, (t, p, q) in enumerate(samples):
        a, b = (max(i - 1, 0), min(i + 1, n - 1))
        ta, pa = samples[a][0], samples[a][1]
        tb, pb = samples[b][0], samples[b][1]
        dt = (tb - ta) * 1e-9
        v = [(pb[j] - pa[j]) / dt for j in range(3)]
        out.append((t, [*p, *q, *v, 0, 0, 0, 0, 0, 0]))
    return out


def check_images(mav0: pathlib.Path, cam: str, expected) -> None:
    got = rows(mav0 / cam / "data.csv")
    assert [int(r[0]) for r in got] == [t for t, _ in expected]
    for (t, gray), r in zip(expected, got):
        assert r[1] == f"{t}.png"
        np.testing.assert_array_equal(png(mav0 / cam / "data" / r[1]), gray)


@pytest.mark.parametrize("compression", ["none", "bz2", "lz4"])
def test_ros1_raw_vid_bag_every_value(tmp_path, compression, capsys):
    bag = tmp_path / "indoor_sensor_fast_3101.5g_126.53s.bag"
    exp = write_raw_vid_bag(bag, compression)
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--no-progress"]) == 0
    mav0 = out / "mav0"
    check_images(mav0, "cam0", exp["cam0"])
    check_images(mav0, "cam1", exp["cam1"])
    assert numeric(mav0 / "imu0" / "data.csv") == exp["imu0"]
    assert numeric(mav0 / "rotor0" / "data.csv") == [(t, [float(v) for v in r]) for t, r in exp["rotor0"]]
    assert rows(mav0 / "rotor0" / "data.csv")[0][1:] == [str(v) for v in exp["rotor0"][0][1]]  # ints stay ints
    assert numeric(mav0 / "state_groundtruth_estimate0" / "data.csv") == expected_gt(exp["gt"])
    assert numeric(mav0 / "force0" / "data.csv") == exp["force0"]
    summary = yaml.safe_load((out / "bag2asl.yaml").read_text())
    assert summary["profile"] == "raw"
    assert summary["streams"]["rotor0"]["source"] == "measured_per_motor"
    assert summary["streams"]["state_groundtruth_estimate0"]["velocity"] == "central_finite_difference"
    assert summary["mass_source"].startswith("VID sequence 17")
    assert summary["bag_reader"]["reader"].startswith("sequential")  # constant-memory ROS1 path
    assert "measured_per_motor" in capsys.readouterr().out
    vehicle = yaml.safe_load((mav0 / "vehicle.yaml").read_text())
    assert vehicle == {"mass_kg": 3.1015, "gravity": 9.81,
                       "rotor_thrust_coefficients": [2.6890e-7, 2.8190e-7, 2.7263e-7, 2.7741e-7]}
    cam0 = yaml.safe_load((mav0 / "cam0" / "sensor.yaml").read_text())
    assert cam0["T_BS"]["data"] == [0, 0, 1, 0.18875, -1, 0, 0, 0.00175, 0, -1, 0, 0.0555, 0, 0, 0, 1]
    assert cam0["intrinsics"] == [382.59014892578125, 382.59014892578125, 323.421142578125, 242.06617736816406]
    assert cam0["resolution"] == [8, 6] and cam0["rate_hz"] == 20.0
    cam1 = yaml.safe_load((mav0 / "cam1" / "sensor.yaml").read_text())
    assert cam1["T_BS"]["data"][3] == 0.18875 and cam1["T_BS"]["data"][7] == pytest.approx(0.00175 - 0.05)
    imu = yaml.safe_load((mav0 / "imu0" / "sensor.yaml").read_text())
    assert imu["rate_hz"] == 400.0 and imu["gyroscope_noise_density"] == 0.001
    assert imu["accelerometer_random_walk"] == 0.004
    rotor = yaml.safe_load((mav0 / "rotor0" / "sensor.yaml").read_text())
    assert rotor == {"sensor_type": "rotor_speed", "unit": "rpm", "count": 4, "rate_hz": 100.0,
                     "noise_density": 1.459}


def write_synced_ros2_bag(path: pathlib.Path, rotor: str) -> dict:
    """Synced-profile ROS2 bag: sensor_msgs/Imu, one combined rotor topic, PoseStamped, WrenchStamped."""
    rng = np.random.default_rng(RNG_SEED + 1)
    w = BagWriter(path, ros2=True)
    exp = {"cam0": [], "imu0": [], "rotor0": [], "gt": [], "force0": []}
    for k in range(5):
        t = T0 + k * 33_333_333
        px = rng.integers(0, 256, (4, 5), dtype=np.uint8)
        w.write("/synced/infra1", "sensor_msgs/msg/Image", t, w.image(t, "mono8", px))
        exp["cam0"].append((t, px))
    for k in range(50):
        t = T0 + k * 2_500_000
        gyro, acc = rng.normal(size=3), rng.normal(size=3)
        w.write("/synced/imu", "sensor_msgs/msg/Imu", t, w.imu(t, gyro, acc))
        exp["imu0"].append((t, [*gyro, *acc]))
    for k in range(12):
        t = T0 + k * 10_000_000
        if rotor == "allrpm":
            data = [int(v) for v in rng.integers(0, 9000, 4)]
            w.write("/synced/allrpm", "uavmotor/msg/motordata", t, w.motordata(t, t, data))
        else:
            data = [float(v) for v in rng.uniform(0, 9000, 4)]
            w.write("/synced/vidrpm", "mav_msgs/msg/Actuators", t, w.actuators(t, data))
        w.write("/synced/target_rpm", "uavmotor/msg/motordata", t, w.motordata(t, t, [9, 9, 9, 9]))
        exp["rotor0"].append((t, [float(v) for v in data]))
        p, q = rng.normal(size=3), np.array([0.5, 0.5, -0.5, 0.5])
        w.write("/vicon/m100/m100", "geometry_msgs/msg/PoseStamped", t, w.pose_stamped(t, p, q))
        exp["gt"].append((t, p, q))
        f = rng.normal(size=3)
        w.write("/robotiq_ft_wrench", "geometry_msgs/msg/WrenchStamped", t + 3, w.wrench(t + 3, f))
        exp["force0"].append((t + 3, list(f)))
    w.close()
    return exp


@pytest.mark.parametrize("rotor", ["allrpm", "vidrpm"])
def test_ros2_synced_bag_every_value(tmp_path, rotor):
    bag = tmp_path / "vid17"
    exp = write_synced_ros2_bag(bag, rotor)
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--no-progress"]) == 0
    mav0 = out / "mav0"
    check_images(mav0, "cam0", exp["cam0"])
    assert not (mav0 / "cam1").exists()
    assert numeric(mav0 / "imu0" / "data.csv") == exp["imu0"]
    assert numeric(mav0 / "rotor0" / "data.csv") == exp["rotor0"]
    assert numeric(mav0 / "state_groundtruth_estimate0" / "data.csv") == expected_gt(exp["gt"])
    assert numeric(mav0 / "force0" / "data.csv") == exp["force0"]
    summary = yaml.safe_load((out / "bag2asl.yaml").read_text())
    assert summary["profile"] == "synced"
    assert summary["streams"]["rotor0"]["source"] == f"measured_{rotor}"
    assert summary["mass_kg"] == 3.1015 and "number" in summary["mass_source"]


def test_target_rpm_fallback_and_time_window(tmp_path):
    bag = tmp_path / "indoor_loaded_8_3103.2g_load269.0g_138.41s_copy.bag"
    w = BagWriter(bag)
    for k in range(100):  # 1 s at 100 Hz
        t = T0 + k * 10_000_000
        w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t,
                w.image(t, "mono8", np.full((2, 2), k, np.uint8)))
        w.write("/djiros/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (k, 0, 0), (0, 0, k)))
        w.write("/m100withm3508/target_rpm", "uavmotor/msg/motordata", t, w.motordata(t, t, [k, -k, 2 * k, 3]))
    w.close()
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--start", "0.2", "--end", "0.5", "--no-progress"]) == 0
    got = numeric(out / "mav0" / "rotor0" / "data.csv")
    assert got == [(T0 + k * 10_000_000, [k, -k, 2 * k, 3]) for k in range(20, 50)]
    assert [t for t, _ in numeric(out / "mav0" / "imu0" / "data.csv")] == [T0 + k * 10_000_000 for k in range(20, 50)]
    summary = yaml.safe_load((out / "bag2asl.yaml").read_text())
    assert summary["streams"]["rotor0"]["source"] == "target_rpm"
    assert summary["mass_kg"] == 3.3722  # 3103.2 g + load 269.0 g from the file name
    assert not (out / "mav0" / "state_groundtruth_estimate0").exists()


def test_non_increasing_stamps_dropped_and_counted(tmp_path):
    bag = tmp_path / "b.bag"
    w = BagWriter(bag)
    stamps = [T0, T0 + 10, T0 + 10, T0 + 5, T0 + 20]
    for i, t in enumerate(stamps):
        w.write("/djiros/imu", "sensor_msgs/msg/Imu", T0 + i, w.imu(t, (i, 0, 0), (0, 0, 0)))
        w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", T0 + i,
                w.image(t, "mono8", np.full((2, 2), i, np.uint8)))
    w.close()
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--mass", "2.5", "--no-progress", "--allow-no-rotors"]) == 0
    assert [t for t, _ in numeric(out / "mav0" / "imu0" / "data.csv")] == [T0, T0 + 10, T0 + 20]
    assert [v[0] for _, v in numeric(out / "mav0" / "imu0" / "data.csv")] == [0.0, 1.0, 4.0]
    summary = yaml.safe_load((out / "bag2asl.yaml").read_text())
    assert summary["streams"]["imu0"]["dropped_non_increasing"] == 2
    assert summary["mass_kg"] == 2.5 and summary["mass_source"] == "--mass"
    assert len(list((out / "mav0" / "cam0" / "data").iterdir())) == 3


def _vid_info(cpp_program, out: pathlib.Path) -> dict:
    import json
    import subprocess

    res = subprocess.run([str(cpp_program("vid_info")), str(out), "--json"], capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stderr
    return {s["name"]: s for s in json.loads(res.stdout)["streams"]}


def test_output_loads_in_cpp_reader(tmp_path, cpp_program):
    """The dataset summary (C++ DatasetReader) reads every converted stream with the same counts."""
    bag1 = tmp_path / "vid17.bag"
    exp1 = write_raw_vid_bag(bag1, "lz4")
    bag2 = tmp_path / "vid18"
    exp2 = write_synced_ros2_bag(bag2, "allrpm")
    for bag, exp in ((bag1, exp1), (bag2, exp2)):
        out = tmp_path / (bag.stem + "_out")
        assert main([str(bag), str(out), "--no-progress"]) == 0
        streams = _vid_info(cpp_program, out)
        expected = {"cam0": len(exp["cam0"]), "imu0": len(exp["imu0"]), "rotor0": len(exp["rotor0"]),
                    "state_groundtruth_estimate0": len(exp["gt"]), "force0": len(exp["force0"])}
        if "cam1" in exp:
            expected["cam1"] = len(exp["cam1"])
        assert {name: s["count"] for name, s in streams.items()} == expected
        for name, s in streams.items():
            assert s["dropped"] == 0 and s.get("skipped_missing_images", 0) == 0, name
        assert streams["imu0"]["first_ns"] == exp["imu0"][0][0]
        assert streams["imu0"]["last_ns"] == exp["imu0"][-1][0]
        assert streams["cam0"]["last_ns"] == exp["cam0"][-1][0]


def test_rest_with_rotors_stopped_is_kept(tmp_path):
    """Issue 29: a recording starts on the ground with the rotors stopped; the converter keeps it
    whole (no trimming to the airborne part): zero-rpm rows from the first message on."""
    bag = tmp_path / "ground.bag"
    w = BagWriter(bag)
    rpm = []
    for k in range(200):  # 2 s at 100 Hz: 1 s at rest (0 rpm), then a spin-up ramp
        t = T0 + k * 10_000_000
        r = 0 if k < 100 else 50 * (k - 99)
        rpm.append(r)
        w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t,
                w.image(t, "mono8", np.full((2, 2), k % 256, np.uint8)))
        w.write("/djiros/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (0, 0, 0), (0, 0, 9.81)))
        w.write("/m100withm3508/target_rpm", "uavmotor/msg/motordata", t, w.motordata(t, t, [r] * 4))
    w.close()
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--no-progress"]) == 0
    got = numeric(out / "mav0" / "rotor0" / "data.csv")
    assert got == [(T0 + k * 10_000_000, [r] * 4) for k, r in enumerate(rpm)]
    assert sum(1 for _, v in got if v == [0, 0, 0, 0]) == 100
    imu = numeric(out / "mav0" / "imu0" / "data.csv")
    assert [t for t, _ in imu] == [T0 + k * 10_000_000 for k in range(200)]


def test_per_motor_rows_wait_for_the_whole_cycle(tmp_path):
    """Issue 26: motors that arrive out of order within a cycle, one cycle with a message of
    motor 3 lost: every row holds the four values of one cycle at its newest stamp; the
    incomplete cycle is dropped (its values counted as superseded), nothing stale is held."""
    bag = tmp_path / "motors.bag"
    w = BagWriter(bag)
    orders = [[2, 0, 3, 1], [0, 1, 2, 3], [3, 2, 1, 0], [1, 3, 0, 2]]
    expected = []
    for k in range(12):
        base = T0 + k * 10_000_000
        order = orders[k % 4]
        values, stamps = {}, {}
        for j, m in enumerate(order):
            if k == 5 and m == 2:
                continue  # motor 3's message of cycle 5 lost
            t = base + j * 1_000_000
            rpm = 1000 * (k + 1) + m
            w.write(f"/m100withm3508/m3508_m{m + 1}", "uavmotor/msg/m3508", t, w.m3508(t, t, m + 1, 0, rpm))
            values[m], stamps[m] = rpm, t
        if k == 5:
            continue  # incomplete: dropped when cycle 6 starts (3 values superseded)
        expected.append((max(stamps.values()), [values[m] for m in range(4)]))
    for k in range(12):
        t = T0 + k * 10_000_000
        w.write("/djiros/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (0, 0, 0), (0, 0, 9.81)))
        w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t, w.image(t, "mono8", np.zeros((2, 2), np.uint8)))
    w.close()
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--no-progress"]) == 0
    got = numeric(out / "mav0" / "rotor0" / "data.csv")
    assert got == expected
    summary = yaml.safe_load((out / "bag2asl.yaml").read_text())
    assert summary["streams"]["rotor0"]["superseded_per_motor_values"] == 3
