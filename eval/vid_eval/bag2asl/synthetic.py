"""Synthetic VID-Dataset-like bags for tests and the memory/throughput measurement.

The custom message types are registered from their .msg text (as the VID-Dataset packages
define them) so the written connections embed those definitions, exactly like recorded bags.

  python -m vid_eval.bag2asl.synthetic OUT.bag --seconds 60 [--compression none|bz2|lz4] [--ros2]
writes a raw-profile VID bag: 2 x 640x480 mono8 at 30 Hz, djiros IMU at 400 Hz, 4 x m3508 at
100 Hz, target rpm, vicon TransformStamped at 100 Hz, Robotiq ft_sensor at 100 Hz.
"""
from __future__ import annotations

import argparse
import pathlib

import numpy as np
from rosbags.rosbag1 import Writer as Writer1
from rosbags.rosbag2 import Writer as Writer2
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from ..usage import OneLineParser

MSG_DEFS = {
    "uavmotor/msg/motordata": "Header header\ntime hwts\nint16[4] data\n",
    "uavmotor/msg/m3508": "Header header\ntime hwts\nuint8 id\nint16 current\nint16 rpm\n",
    "djiros/msg/ImuWithHwTimeStamp": (
        "Header header\nuint16 index\nuint8 flag\ntime hwts\n"
        "geometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\n"
        "geometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\n"
        "geometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n"),
    "mav_msgs/msg/Actuators": "Header header\nfloat64[] angles\nfloat64[] angular_velocities\nfloat64[] normalized\n",
    "quadrotor_msgs/msg/ControlCommand": (
        "uint8 NONE=0\nuint8 ATTITUDE=1\nuint8 BODY_RATES=2\n"
        "Header header\nuint8 control_mode\nbool armed\ntime expected_execution_time\n"
        "geometry_msgs/Quaternion orientation\ngeometry_msgs/Vector3 bodyrates\n"
        "geometry_msgs/Vector3 angular_accelerations\nfloat64 collective_thrust\nfloat64[] rotor_thrusts\n"),
    "robotiq_ft_sensor/msg/ft_sensor": "float32 Fx\nfloat32 Fy\nfloat32 Fz\nfloat32 Mx\nfloat32 My\nfloat32 Mz\n",
}


def typestore(ros2: bool = False):
    """Stock ROS1 Noetic / ROS2 Humble store plus the custom VID types parsed from MSG_DEFS."""
    store = get_typestore(Stores.ROS2_HUMBLE if ros2 else Stores.ROS1_NOETIC)
    types = {}
    for name, text in MSG_DEFS.items():
        types.update(get_types_from_msg(text, name))
    store.register(types)
    return store


class BagWriter:
    """Same calls for ROS1 (compression none/bz2/lz4) and ROS2 (sqlite3) bags."""

    def __init__(self, path: pathlib.Path, ros2: bool = False, compression: str = "none"):
        self.ros2 = ros2
        self.ts = typestore(ros2)
        if ros2:
            self.w = Writer2(path, version=9)
        else:
            self.w = Writer1(path)
            if compression != "none":
                self.w.set_compression(getattr(Writer1.CompressionFormat, compression.upper()))
        self.w.open()
        self.conns = {}

    def connection(self, topic: str, msgtype: str):
        if topic not in self.conns:
            self.conns[topic] = self.w.add_connection(topic, msgtype, typestore=self.ts)
        return self.conns[topic]

    def write(self, topic: str, msgtype: str, bag_ns: int, msg) -> None:
        conn = self.connection(topic, msgtype)
        data = self.ts.serialize_cdr(msg, msgtype) if self.ros2 else self.ts.serialize_ros1(msg, msgtype)
        self.w.write(conn, bag_ns, data)

    def close(self) -> None:
        self.w.close()

    # -- message constructors ---------------------------------------------------------------
    def T(self, name):
        return self.ts.types[name]

    def stamp(self, t_ns: int):
        return self.T("builtin_interfaces/msg/Time")(sec=t_ns // 1_000_000_000, nanosec=t_ns % 1_000_000_000)

    def header(self, t_ns: int, frame: str = ""):
        H = self.T("std_msgs/msg/Header")
        if self.ros2:
            return H(stamp=self.stamp(t_ns), frame_id=frame)
        return H(seq=0, stamp=self.stamp(t_ns), frame_id=frame)

    def vec3(self, v):
        return self.T("geometry_msgs/msg/Vector3")(x=float(v[0]), y=float(v[1]), z=float(v[2]))

    def quat(self, q):  # (w, x, y, z)
        return self.T("geometry_msgs/msg/Quaternion")(x=float(q[1]), y=float(q[2]), z=float(q[3]), w=float(q[0]))

    def image(self, t_ns, encoding, pixels: np.ndarray, step=None, bigendian=0):
        h, w = pixels.shape[:2]
        raw = pixels.tobytes() if step is None else _pad_rows(pixels, step)
        step = step if step is not None else len(raw) // h
        return self.T("sensor_msgs/msg/Image")(header=self.header(t_ns), height=h, width=w, encoding=encoding,
                                               is_bigendian=bigendian, step=step,
                                               data=np.frombuffer(raw, np.uint8).copy())

    def imu(self, t_ns, gyro, acc):
        zero9 = np.zeros(9)
        return self.T("sensor_msgs/msg/Imu")(
            header=self.header(t_ns), orientation=self.quat((1, 0, 0, 0)), orientation_covariance=zero9,
            angular_velocity=self.vec3(gyro), angular_velocity_covariance=zero9,
            linear_acceleration=self.vec3(acc), linear_acceleration_covariance=zero9)

    def dji_imu(self, t_ns, hw_ns, gyro, acc, index=0):
        zero9 = np.zeros(9)
        return self.T("djiros/msg/ImuWithHwTimeStamp")(
            header=self.header(t_ns), index=index, flag=0, hwts=self.stamp(hw_ns),
            orientation=self.quat((1, 0, 0, 0)), orientation_covariance=zero9,
            angular_velocity=self.vec3(gyro), angular_velocity_covariance=zero9,
            linear_acceleration=self.vec3(acc), linear_acceleration_covariance=zero9)

    def m3508(self, t_ns, hw_ns, motor_id, current, rpm):
        return self.T("uavmotor/msg/m3508")(header=self.header(t_ns), hwts=self.stamp(hw_ns), id=motor_id,
                                            current=current, rpm=rpm)

    def motordata(self, t_ns, hw_ns, data):
        return self.T("uavmotor/msg/motordata")(header=self.header(t_ns), hwts=self.stamp(hw_ns),
                                                data=np.array(data, dtype=np.int16))

    def actuators(self, t_ns, speeds):
        return self.T("mav_msgs/msg/Actuators")(header=self.header(t_ns), angles=np.zeros(0),
                                                angular_velocities=np.array(speeds, dtype=np.float64),
                                                normalized=np.zeros(0))

    def control_command(self, t_ns, thrust):
        return self.T("quadrotor_msgs/msg/ControlCommand")(
            header=self.header(t_ns), control_mode=2, armed=True, expected_execution_time=self.stamp(t_ns),
            orientation=self.quat((1, 0, 0, 0)), bodyrates=self.vec3((0, 0, 0)),
            angular_accelerations=self.vec3((0, 0, 0)), collective_thrust=float(thrust),
            rotor_thrusts=np.zeros(0))

    def transform(self, t_ns, p, q):
        tf = self.T("geometry_msgs/msg/Transform")(translation=self.vec3(p), rotation=self.quat(q))
        return self.T("geometry_msgs/msg/TransformStamped")(header=self.header(t_ns, "world"),
                                                            child_frame_id="m100", transform=tf)

    def pose_stamped(self, t_ns, p, q):
        pose = self.T("geometry_msgs/msg/Pose")(position=self.T("geometry_msgs/msg/Point")(
            x=float(p[0]), y=float(p[1]), z=float(p[2])), orientation=self.quat(q))
        return self.T("geometry_msgs/msg/PoseStamped")(header=self.header(t_ns, "world"), pose=pose)

    def odometry(self, t_ns, p, q, v_body):
        pose = self.T("geometry_msgs/msg/Pose")(position=self.T("geometry_msgs/msg/Point")(
            x=float(p[0]), y=float(p[1]), z=float(p[2])), orientation=self.quat(q))
        twist = self.T("geometry_msgs/msg/Twist")(linear=self.vec3(v_body), angular=self.vec3((0, 0, 0)))
        return self.T("nav_msgs/msg/Odometry")(
            header=self.header(t_ns, "world"), child_frame_id="m100",
            pose=self.T("geometry_msgs/msg/PoseWithCovariance")(pose=pose, covariance=np.zeros(36)),
            twist=self.T("geometry_msgs/msg/TwistWithCovariance")(twist=twist, covariance=np.zeros(36)))

    def wrench(self, t_ns, f, torque=(0, 0, 0)):
        return self.T("geometry_msgs/msg/WrenchStamped")(
            header=self.header(t_ns), wrench=self.T("geometry_msgs/msg/Wrench")(force=self.vec3(f),
                                                                                torque=self.vec3(torque)))

    def ft_sensor(self, f, torque=(0, 0, 0)):
        return self.T("robotiq_ft_sensor/msg/ft_sensor")(Fx=float(f[0]), Fy=float(f[1]), Fz=float(f[2]),
                                                         Mx=float(torque[0]), My=float(torque[1]),
                                                         Mz=float(torque[2]))


def _pad_rows(pixels: np.ndarray, step: int) -> bytes:
    h = pixels.shape[0]
    rows = pixels.reshape(h, -1).view(np.uint8)
    out = np.zeros((h, step), np.uint8)
    out[:, : rows.shape[1]] = rows
    return out.tobytes()


def write_vid_bag(path: pathlib.Path, seconds: float, compression: str = "none", ros2: bool = False,
                  width: int = 640, height: int = 480, seed: int = 7) -> None:
    """A raw-profile VID bag with realistic rates (used for the memory/throughput measurement)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:height, 0:width]
    base = ((xx * 3 + yy * 2) % 256).astype(np.uint8)
    frames = [np.clip(base.astype(int) + rng.integers(-20, 21, base.shape), 0, 255).astype(np.uint8)
              for _ in range(4)]
    w = BagWriter(path, ros2=ros2, compression=compression)
    t0 = 1_600_000_000_000_000_000
    end = t0 + int(seconds * 1e9)
    period = {"cam": 33_333_333, "imu": 2_500_000, "motor": 10_000_000}
    t_cam, t_imu, t_mot = t0, t0, t0
    k = 0
    while min(t_cam, t_imu, t_mot) < end:
        t = min(t_cam, t_imu, t_mot)
        if t == t_cam:
            img = np.roll(frames[k % 4], k, axis=1)
            w.write("/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image", t, w.image(t, "mono8", img))
            w.write("/camera/infra2/image_rect_raw", "sensor_msgs/msg/Image", t, w.image(t, "mono8", img))
            k += 1
            t_cam += period["cam"]
        if t == t_imu:
            w.write("/djiros/imu_hwts", "djiros/msg/ImuWithHwTimeStamp", t,
                    w.dji_imu(t, t, (0.01, -0.02, 0.03), (0.1, 0.2, 9.81)))
            t_imu += period["imu"]
        if t == t_mot:
            for m in range(4):
                w.write(f"/m100withm3508/m3508_m{m + 1}", "uavmotor/msg/m3508", t,
                        w.m3508(t, t, m + 1, 100, 3000 + m))
            w.write("/m100withm3508/target_rpm", "uavmotor/msg/motordata", t, w.motordata(t, t, [3000] * 4))
            w.write("/vicon/m100/m100", "geometry_msgs/msg/TransformStamped", t,
                    w.transform(t, ((t - t0) * 1e-9, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0)))
            w.write("/robotiq_ft_sensor", "robotiq_ft_sensor/msg/ft_sensor", t, w.ft_sensor((0.5, -0.25, 1.0)))
            t_mot += period["motor"]
    w.close()


def main(argv=None) -> int:
    p = OneLineParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out", type=pathlib.Path)
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--compression", choices=["none", "bz2", "lz4"], default="none")
    p.add_argument("--ros2", action="store_true")
    args = p.parse_args(argv)
    write_vid_bag(args.out, args.seconds, args.compression, args.ros2)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
