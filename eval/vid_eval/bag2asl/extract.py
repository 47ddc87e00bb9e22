"""Stream handlers: one per output stream, fed deserialized messages, writing rows immediately.

Memory stays constant: images are converted and written one by one; the only buffered state is
the latest value per motor (per-motor rotor rows) and a 3-sample window (ground-truth velocity
by central differences).
"""
from __future__ import annotations

import pathlib

import numpy as np

from . import images
from .bagio import short_type
from .errors import ConfigError, UnknownTypeError
from .sinks import CsvStream, PngPool, os_error
from .topicmap import ResolvedStream

IMU_HEADER = ("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
              "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]")
GT_HEADER = ("#timestamp,p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z [],"
             "v_RS_R_x [m s^-1],v_RS_R_y [m s^-1],v_RS_R_z [m s^-1],b_w_RS_S_x [rad s^-1],"
             "b_w_RS_S_y [rad s^-1],b_w_RS_S_z [rad s^-1],b_a_RS_S_x [m s^-2],b_a_RS_S_y [m s^-2],"
             "b_a_RS_S_z [m s^-2]")
FORCE_HEADER = "#timestamp [ns],f_x [N],f_y [N],f_z [N]"
THRUST_HEADER = "#timestamp [ns],thrust [N]"
CAM_HEADER = "#timestamp [ns],filename"


def get_field(msg, path: str, where: str):
    obj = msg
    for part in path.split("."):
        if not hasattr(obj, part):
            fields = list(getattr(obj, "__dataclass_fields__", {}))
            raise ConfigError(f"{where}: no field '{part}' in '{path}' (fields: {', '.join(fields)})")
        obj = getattr(obj, part)
    return obj


def time_ns(stamp) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


class Handler:
    """Base: owns the stream's CSV, picks each message's timestamp."""

    header = ""
    lazy = False  # True: the CSV is created at the first row (header depends on the data)

    def __init__(self, rs: ResolvedStream, mav0: pathlib.Path, bag_path):
        self.rs = rs
        self.name = rs.spec.name
        self.dir = mav0 / self.name
        self.csv = None if self.lazy else CsvStream(self.dir / "data.csv", self.header)
        self.bag_path = bag_path
        self.bag_stamped = 0  # messages stamped with bag time because the header had none

    def where(self, topic: str, msgtype: str) -> str:
        return f"{self.bag_path}: topic {topic} ({short_type(msgtype)}) -> {self.name}"

    def stamp(self, msg, bag_ns: int, stamp_mode: str, where: str) -> int:
        if stamp_mode == "bag":
            return bag_ns
        if stamp_mode == "header":
            header = getattr(msg, "header", None)
            if header is not None and (header.stamp.sec or header.stamp.nanosec):
                return time_ns(header.stamp)
            self.bag_stamped += 1
            return bag_ns
        return time_ns(get_field(msg, stamp_mode, where))

    def feed(self, index: int, topic: str, msgtype: str, msg, bag_ns: int) -> None:
        raise NotImplementedError

    def finish(self) -> None:
        if self.csv is not None:
            self.csv.close()


class ImageHandler(Handler):
    header = CAM_HEADER

    def __init__(self, rs, mav0, bag_path, pngs: PngPool):
        super().__init__(rs, mav0, bag_path)
        try:
            (self.dir / "data").mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise os_error(self.dir / "data", err) from None
        self.pngs = pngs
        self.raw_bytes = 0
        self.width = self.height = None

    def feed(self, index, topic, msgtype, msg, bag_ns):
        where = self.where(topic, msgtype)
        t = self.stamp(msg, bag_ns, self.rs.source.stamp, where)
        if not self.csv.accepts(t):
            return
        if msgtype.endswith("/CompressedImage"):
            gray = images.compressed_msg_to_gray(msg, where)
            self.raw_bytes += len(msg.data)
        else:
            gray = images.image_msg_to_gray(msg, where)
            self.raw_bytes += len(msg.data)
        self.height, self.width = gray.shape
        name = f"{t}.png"
        # gray may be a view of the message buffer: it is immutable and kept alive by the view
        self.pngs.submit(self.dir / "data" / name, gray)
        self.csv.write_raw(t, f"{t},{name}\n")


class ImuHandler(Handler):
    header = IMU_HEADER

    def feed(self, index, topic, msgtype, msg, bag_ns):
        where = self.where(topic, msgtype)
        t = self.stamp(msg, bag_ns, self.rs.source.stamp, where)
        if not self.csv.accepts(t):
            return
        w = get_field(msg, "angular_velocity", where)
        a = get_field(msg, "linear_acceleration", where)
        gs = self.rs.spec.options.get("gyro_scale", 1.0)
        acs = self.rs.spec.options.get("accel_scale", 1.0)
        if gs == 1.0 and acs == 1.0:
            self.csv.write(t, (w.x, w.y, w.z, a.x, a.y, a.z))
        else:
            self.csv.write(t, (w.x * gs, w.y * gs, w.z * gs, a.x * acs, a.y * acs, a.z * acs))


def _scaled(values, scale: float, order):
    if order is not None:
        values = [values[i] for i in order]
    if scale == 1.0:
        return list(values)
    return [float(v) * scale for v in values]


class RotorHandler(Handler):
    """Rotor speeds from one array topic, or from one topic per motor.

    Per motor (VID's m3508 topics, one message per motor per 10 ms cycle, a few ms apart): a row
    is written once every motor has sent a value since the previous row (a complete cycle), at
    the newest stamp of the cycle (the time the row became complete: no value is from its
    future), never holding a value from an earlier cycle. A motor that reports again before the
    cycle completed (a message of another motor lost) starts a new cycle: the incomplete one's
    values are dropped and counted in `superseded` (bag2asl.yaml). Values are written as the
    sensor gives them.
    """

    lazy = True

    def __init__(self, rs, mav0, bag_path, coefficients: int, vehicle_path):
        super().__init__(rs, mav0, bag_path)
        self.coefficients = coefficients  # rotor_thrust_coefficients in the preset's vehicle.yaml
        self.vehicle_path = vehicle_path
        self.count = None
        self.pending = [None] * len(rs.source.topics)  # (stamp, value) since the last row, per motor
        self.superseded = 0
        self.order = rs.spec.options.get("order")
        if self.order is not None and sorted(self.order) != list(range(len(self.order))):
            raise ConfigError(f"{rs.spec.name}.order: must be a permutation of 0..k-1, got {self.order}")

    def _check_count(self, k: int, where: str) -> None:
        if self.order is not None and len(self.order) != k:
            raise ConfigError(f"{where}: {k} rotor values but order has {len(self.order)} entries")
        if self.csv is None:
            if k != self.coefficients:
                raise ConfigError(f"{where}: {k} rotor speeds per message but {self.vehicle_path} has "
                                  f"{self.coefficients} rotor_thrust_coefficients (pass --preset DIR for this vehicle)")
            self.count = k
            self.csv = CsvStream(self.dir / "data.csv",
                                 "#timestamp [ns]," + ",".join(f"n_{i + 1}" for i in range(k)))
        elif k != self.count:
            raise ConfigError(f"{where}: rotor count changed from {self.count} to {k}")

    def feed(self, index, topic, msgtype, msg, bag_ns):
        src = self.rs.source
        where = self.where(topic, msgtype)
        value = get_field(msg, src.field, where)
        if not src.per_motor:
            t = self.stamp(msg, bag_ns, src.stamp, where)
            values = value.tolist() if isinstance(value, np.ndarray) else list(value)
            self._check_count(len(values), where)
            if self.csv.accepts(t):
                self.csv.write(t, _scaled(values, src.scale, self.order))
            return
        if self.pending[index] is not None:
            # This motor starts a new cycle before the last one completed (another motor's
            # message was lost): the incomplete cycle's values are dropped, not mixed in.
            self.superseded += sum(p is not None for p in self.pending)
            self.pending = [None] * len(self.pending)
        self.pending[index] = (self.stamp(msg, bag_ns, src.stamp, where),
                               value.item() if isinstance(value, np.generic) else value)
        if any(p is None for p in self.pending):
            return
        t = max(stamp for stamp, _ in self.pending)
        values = [v for _, v in self.pending]
        self.pending = [None] * len(self.pending)
        self._check_count(len(values), where)
        if self.csv.accepts(t):
            self.csv.write(t, _scaled(values, src.scale, self.order))


class ThrustHandler(Handler):
    header = THRUST_HEADER

    def __init__(self, rs, mav0, bag_path, mass_kg: float):
        super().__init__(rs, mav0, bag_path)
        self.factor = rs.source.scale * (mass_kg if rs.spec.options.get("mass_normalized") else 1.0)

    def feed(self, index, topic, msgtype, msg, bag_ns):
        where = self.where(topic, msgtype)
        t = self.stamp(msg, bag_ns, self.rs.source.stamp, where)
        value = float(get_field(msg, self.rs.source.field, where))
        if self.csv.accepts(t):
            self.csv.write(t, (value * self.factor if self.factor != 1.0 else value,))


class ForceHandler(Handler):
    """geometry_msgs/WrenchStamped, geometry_msgs/Wrench or robotiq_ft_sensor/ft_sensor (Fx, Fy, Fz).

    Written in the sensor's frame unless the map gives `rotation` (f_out = R f_sensor).
    """
    header = FORCE_HEADER

    def __init__(self, rs, mav0, bag_path):
        super().__init__(rs, mav0, bag_path)
        rot = rs.spec.options.get("rotation")
        self.R = None if rot is None else [[float(v) for v in row] for row in rot]

    def feed(self, index, topic, msgtype, msg, bag_ns):
        where = self.where(topic, msgtype)
        if hasattr(msg, "wrench"):
            f = msg.wrench.force
            fx, fy, fz = f.x, f.y, f.z
        elif hasattr(msg, "force") and hasattr(msg.force, "x"):
            fx, fy, fz = msg.force.x, msg.force.y, msg.force.z
        elif hasattr(msg, "Fx"):
            fx, fy, fz = msg.Fx, msg.Fy, msg.Fz
        else:
            raise UnknownTypeError(f"{where}: not a force message (expected WrenchStamped, Wrench or "
                                   "robotiq_ft_sensor/ft_sensor)")
        t = self.stamp(msg, bag_ns, self.rs.source.stamp, where)
        if not self.csv.accepts(t):
            return
        f = (float(fx), float(fy), float(fz))
        if self.R is not None:
            f = tuple(self.R[i][0] * f[0] + self.R[i][1] * f[1] + self.R[i][2] * f[2] for i in range(3))
        self.csv.write(t, f)
