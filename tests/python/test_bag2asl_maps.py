"""vid-bag2asl: the example topic maps (rad/s rotor topic, collective thrust, rotated force,
Odometry ground truth) and the small pieces (PNG encoder, mass rule, encodings)."""
from __future__ import annotations

import io
import json
import pathlib
import shutil
import subprocess

import numpy as np
import pytest
import yaml
from PIL import Image

from test_bag2asl_helpers import numeric, png, rows
from vid_eval.bag2asl import calib, images, png as pngenc, topicmap
from vid_eval.bag2asl.cli import main
from vid_eval.bag2asl.errors import UnknownTypeError, UsageError
from vid_eval.bag2asl.groundtruth import quat_rotate
from vid_eval.bag2asl.synthetic import BagWriter

T0 = 1_700_000_000_000_000_000
MAPS = pathlib.Path(topicmap.__file__).parent / "topic_maps"


def rotation_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def hexacopter_preset(tmp_path) -> pathlib.Path:
    """The VID preset with a 6-rotor vehicle.yaml (k in N/(rad/s)^2), as a user would pass with --preset."""
    preset = tmp_path / "preset"
    shutil.copytree(calib.DEFAULT_PRESET, preset)
    (preset / "vehicle.yaml").write_text("mass_kg: 1.5\ngravity: 9.81\nrotor_thrust_coefficients: [8.5e-6, 8.5e-6, "
                                         "8.5e-6, 8.5e-6, 8.5e-6, 8.5e-6]\n")
    return preset


def test_vid_fusion_map_rad_s_rotors_and_odometry(tmp_path, cpp_program):
    rng = np.random.default_rng(5)
    bag = tmp_path / "iris.bag"
    w = BagWriter(bag)
    exp_rot, exp_gt = [], []
    for k in range(10):
        t = T0 + k * 5_000_000
        w.write("/iris/vi_sensor/left/image_raw", "sensor_msgs/msg/Image", t,
                w.image(t, "mono8", np.full((3, 3), k, np.uint8)))
        w.write("/iris/vi_sensor/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (0, 0, k), (0, 0, 9.8)))
        speeds = list(rng.uniform(400, 900, 6))  # hexacopter: 6 rotors
        w.write("/iris/motor_speed", "mav_msgs/msg/Actuators", t, w.actuators(t, speeds))
        exp_rot.append((t, speeds))
        p, q, vb = rng.normal(size=3), rng.normal(size=4), rng.normal(size=3)
        q /= np.linalg.norm(q)
        w.write("/iris/ground_truth/odometry", "nav_msgs/msg/Odometry", t, w.odometry(t, p, q, vb))
        exp_gt.append((t, p, q, rotation_matrix(q) @ vb))
    w.close()
    out = tmp_path / "out"
    argv = [str(bag), str(out), "--topics", str(MAPS / "vid_fusion_iris.yaml"), "--mass", "1.5", "--no-progress"]
    assert main(argv) == 1  # the default (VID, 4-rotor) preset does not fit a hexacopter
    assert main(argv + ["--overwrite", "--preset", str(hexacopter_preset(tmp_path))]) == 0
    mav0 = out / "mav0"
    assert numeric(mav0 / "rotor0" / "data.csv") == exp_rot
    sensor = yaml.safe_load((mav0 / "rotor0" / "sensor.yaml").read_text())
    assert sensor["unit"] == "rad/s" and sensor["count"] == 6 and sensor["noise_density"] == 1.0
    assert sensor["rate_hz"] == 200.0
    gt = numeric(mav0 / "state_groundtruth_estimate0" / "data.csv")
    assert [t for t, _ in gt] == [t for t, *_ in exp_gt]
    for (t, vals), (_, p, q, vw) in zip(gt, exp_gt):
        assert vals[:7] == [*p, *q]
        np.testing.assert_allclose(vals[7:10], vw, rtol=0, atol=1e-12)
        assert vals[10:] == [0.0] * 6
    summary = yaml.safe_load((out / "bag2asl.yaml").read_text())
    assert summary["streams"]["state_groundtruth_estimate0"]["velocity"] == "odometry_twist_rotated_to_world"
    counts = vid_info_counts(cpp_program, out)
    assert counts == {"cam0": 10, "imu0": 10, "rotor0": 10, "state_groundtruth_estimate0": 10}


def vid_info_counts(cpp_program, out: pathlib.Path) -> dict:
    res = subprocess.run([str(cpp_program("vid_info")), str(out), "--json"], capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stderr
    return {s["name"]: s["count"] for s in json.loads(res.stdout)["streams"]}


def test_collective_thrust_map_and_rotated_force(tmp_path, cpp_program):
    rng = np.random.default_rng(6)
    bag = tmp_path / "cmd.bag"
    w = BagWriter(bag)
    exp_thrust, exp_force = [], []
    for k in range(8):
        t = T0 + k * 20_000_000
        w.write("/cam0/image_raw", "sensor_msgs/msg/Image", t, w.image(t, "mono8", np.zeros((2, 2), np.uint8)))
        w.write("/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (0, 0, 0), (0, 0, 9.8)))
        c = float(rng.uniform(5, 15))
        w.write("/control_command", "quadrotor_msgs/msg/ControlCommand", t, w.control_command(t, c))
        exp_thrust.append((t, [c * 0.75]))
        f = rng.normal(size=3)
        w.write("/ft_sensor/wrench", "geometry_msgs/msg/WrenchStamped", t, w.wrench(t, f))
        exp_force.append((t, [f[1], f[0], -f[2]]))
    w.close()
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--topics", str(MAPS / "collective_thrust.yaml"), "--mass", "0.75",
                 "--no-progress"]) == 0
    assert numeric(out / "mav0" / "thrust0" / "data.csv") == exp_thrust
    assert numeric(out / "mav0" / "force0" / "data.csv") == exp_force
    assert rows(out / "mav0" / "thrust0" / "data.csv")  # header checked inside rows()
    assert (out / "mav0" / "thrust0" / "data.csv").read_text().startswith("#timestamp [ns],thrust [N]\n")
    assert vid_info_counts(cpp_program, out) == {"cam0": 8, "imu0": 8, "thrust0": 8, "force0": 8}


def test_compressed_image_and_bag_time_stamp(tmp_path):
    bag = tmp_path / "c.bag"
    w = BagWriter(bag)
    px = np.arange(12, dtype=np.uint8).reshape(3, 4) * 20
    buf = io.BytesIO()
    Image.fromarray(px).save(buf, format="PNG")
    msg = w.T("sensor_msgs/msg/CompressedImage")(header=w.header(T0), format="mono8; png compressed",
                                                 data=np.frombuffer(buf.getvalue(), np.uint8).copy())
    w.write("/cam0/image_raw", "sensor_msgs/msg/CompressedImage", T0 + 55, msg)
    w.write("/imu", "sensor_msgs/msg/Imu", T0 + 77, w.imu(T0, (1, 2, 3), (4, 5, 6)))
    w.close()
    tmap = tmp_path / "map.yaml"
    tmap.write_text("streams:\n"
                    "  cam0: {kind: image, topic: /cam0/image_raw}\n"
                    "  imu0: {kind: imu, topic: /imu, stamp: bag, accel_scale: 2.0}\n")
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--topics", str(tmap), "--mass", "1", "--no-progress", "--allow-no-rotors"]) == 0
    np.testing.assert_array_equal(png(out / "mav0" / "cam0" / "data" / f"{T0}.png"), px)
    assert numeric(out / "mav0" / "imu0" / "data.csv") == [(T0 + 77, [1.0, 2.0, 3.0, 8.0, 10.0, 12.0])]


@pytest.mark.parametrize("shape", [(1, 1), (1, 7), (9, 1), (480, 640), (5, 300)])
def test_png_encoder_round_trip(shape):
    rng = np.random.default_rng(shape[0] * 1000 + shape[1])
    img = rng.integers(0, 256, shape, dtype=np.uint8)
    for level in (0, 1, 9):
        with Image.open(io.BytesIO(pngenc.encode_gray8(img, level))) as decoded:
            assert decoded.mode == "L" and decoded.size == (shape[1], shape[0])
            np.testing.assert_array_equal(np.asarray(decoded), img)


def test_encodings():
    v = np.array([[0x1234, 0xFFEE]], dtype=np.uint16)
    le = images.raw_to_gray("mono16", 1, 2, 4, 0, np.frombuffer(v.astype("<u2").tobytes(), np.uint8), "w")
    be = images.raw_to_gray("16UC1", 1, 2, 4, 1, np.frombuffer(v.astype(">u2").tobytes(), np.uint8), "w")
    assert le.tolist() == [[0x12, 0xFF]] and be.tolist() == [[0x12, 0xFF]]
    rgb = np.array([[[255, 0, 0], [0, 255, 0], [0, 0, 255], [10, 20, 30]]], np.uint8)
    got = images.raw_to_gray("rgb8", 1, 4, 12, 0, rgb.reshape(-1), "w")
    assert got.tolist() == [[76, 150, 29, 18]]  # rint(0.299*255)=76, rint(0.587*255)=150, rint(0.114*255)=29
    got_bgr = images.raw_to_gray("bgr8", 1, 4, 12, 0, rgb[..., ::-1].reshape(-1).copy(), "w")
    assert got_bgr.tolist() == got.tolist()
    with pytest.raises(UnknownTypeError, match="too short"):
        images.raw_to_gray("mono8", 4, 4, 4, 0, np.zeros(10, np.uint8), "w")


def test_mass_rule(tmp_path):
    preset = calib.Preset(calib.DEFAULT_PRESET)
    m = lambda name, flag=None: calib.mass_for(pathlib.Path(name), flag, preset)  # noqa: E731
    assert m("x.bag", 2.0) == (2.0, "--mass")
    assert m("indoor_sensor_slow_3101.5g_155.38s.bag")[0] == 3.1015
    assert m("vid14.bag")[0] == 3.3722 and m("seq_07.bag")[0] == 3.46 and m("18.bag")[0] == 3.1015
    assert m("my_flight_1234.5g_load100g_10s.bag") == (1.3345, "file name (1234.5g+load100g)")
    mass, source = m("channel_1.bag")
    assert mass == 3.1015 and source.startswith("preset default")
    with pytest.raises(UsageError):  # a command-line value: exit 2
        m("x.bag", -1.0)


def test_quat_rotate_matches_matrix():
    rng = np.random.default_rng(9)
    for _ in range(20):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        v = rng.normal(size=3)
        np.testing.assert_allclose(quat_rotate(q, v), rotation_matrix(q) @ v, atol=1e-12)


def test_custom_imu_type_read_by_its_fields(tmp_path):
    """A vendor IMU type known only from the bag's embedded definition is read by field names."""
    from rosbags.typesys import get_types_from_msg

    bag = tmp_path / "v.bag"
    w = BagWriter(bag)
    w.ts.register(get_types_from_msg("Header header\ngeometry_msgs/Vector3 angular_velocity\n"
                                     "geometry_msgs/Vector3 linear_acceleration\nfloat32 temperature\n",
                                     "vendor_msgs/msg/RawImu"))
    vals = []
    for k in range(4):
        t = T0 + k * 1_000_000
        msg = w.T("vendor_msgs/msg/RawImu")(header=w.header(t), angular_velocity=w.vec3((k, 0.5, -k)),
                                            linear_acceleration=w.vec3((0.25, k, 9.75)), temperature=30.0)
        w.write("/vendor/imu", "vendor_msgs/msg/RawImu", t, msg)
        w.write("/cam0/image_raw", "sensor_msgs/msg/Image", t, w.image(t, "mono8", np.zeros((2, 2), np.uint8)))
        vals.append((t, [k, 0.5, -k, 0.25, k, 9.75]))
    w.close()
    tmap = tmp_path / "map.yaml"
    tmap.write_text("streams:\n  cam0: {kind: image, topic: /cam0/image_raw}\n  imu0: {kind: imu, topic: /vendor/imu}\n")
    out = tmp_path / "out"
    assert main([str(bag), str(out), "--topics", str(tmap), "--mass", "1", "--no-progress", "--allow-no-rotors"]) == 0
    assert numeric(out / "mav0" / "imu0" / "data.csv") == vals
