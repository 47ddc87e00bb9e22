"""The conversion: resolve the topic map against the bag, stream every message once, write."""
from __future__ import annotations

import pathlib
import sys
import time
from dataclasses import dataclass

import yaml

from .bagio import Bag, short_type
from .calib import DEFAULT_PRESET, Preset, mass_for, write_camera_yaml, write_imu_yaml, write_rotor_yaml, write_vehicle_yaml
from .errors import ConfigError, MissingTopicError, UnknownTypeError, UsageError
from .extract import ForceHandler, ImageHandler, ImuHandler, RotorHandler, ThrustHandler
from .groundtruth import GroundTruthHandler
from .progress import Progress
from . import sinks
from .sinks import PngPool, os_error
from . import topicmap

# what each kind reads: known types, or any type with these top-level fields (duck typing, so
# e.g. a custom IMU message with angular_velocity + linear_acceleration works too)
_ACCEPTED = {
    "image": (("sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage"), ()),
    "imu": (("sensor_msgs/msg/Imu", "djiros/msg/ImuWithHwTimeStamp"), (("angular_velocity", "linear_acceleration"),)),
    "groundtruth": (("geometry_msgs/msg/PoseStamped", "geometry_msgs/msg/PoseWithCovarianceStamped",
                     "geometry_msgs/msg/TransformStamped", "nav_msgs/msg/Odometry"),
                    (("transform",), ("pose",))),
    "force": (("geometry_msgs/msg/WrenchStamped", "geometry_msgs/msg/Wrench", "robotiq_ft_sensor/msg/ft_sensor"),
              (("wrench",), ("force",), ("Fx", "Fy", "Fz"))),
}


@dataclass
class Options:
    bag: pathlib.Path
    out: pathlib.Path
    topics: pathlib.Path | None = None
    start_s: float | None = None
    end_s: float | None = None
    mass_kg: float | None = None
    preset: pathlib.Path | None = None
    png_level: int = 1
    jobs: int = 2
    overwrite: bool = False
    progress: bool | None = None
    allow_no_rotors: bool = False


def _check_types(bag: Bag, resolved) -> None:
    for rs in resolved:
        if rs.spec.kind not in _ACCEPTED:
            continue
        accepted, field_sets = _ACCEPTED[rs.spec.kind]
        for topic in rs.source.topics:
            for conn in bag.connections(topic):
                store = bag.typestore_for(conn)  # raises UnknownTypeError for undefined types
                fields = {name for name, _ in store.fielddefs[conn.msgtype][1]}
                if conn.msgtype not in accepted and not any(set(fs) <= fields for fs in field_sets):
                    raise UnknownTypeError(
                        f"{bag.path}: topic {topic} has type {short_type(conn.msgtype)}, stream "
                        f"{rs.spec.name} (kind {rs.spec.kind}) accepts "
                        f"{', '.join(short_type(a) for a in accepted)}"
                        + "".join(f" or a type with field(s) {'+'.join(fs)}" for fs in field_sets))


def _make_handlers(resolved, mav0, bag_path, opts, mass_kg, preset, pngs):
    handlers = []
    for rs in resolved:
        kind = rs.spec.kind
        if kind == "image":
            h = ImageHandler(rs, mav0, bag_path, pngs)
        elif kind == "imu":
            h = ImuHandler(rs, mav0, bag_path)
        elif kind == "rotor":
            h = RotorHandler(rs, mav0, bag_path, len(preset.vehicle["rotor_thrust_coefficients"]),
                             preset.vehicle_path)
        elif kind == "thrust":
            h = ThrustHandler(rs, mav0, bag_path, mass_kg)
        elif kind == "groundtruth":
            h = GroundTruthHandler(rs, mav0, bag_path)
        else:
            h = ForceHandler(rs, mav0, bag_path)
        handlers.append(h)
    return handlers


def _require_rotors(tmap, profile: str, resolved, bag: Bag, allowed: bool) -> None:
    """A dataset without rotor speeds (or thrust) cannot run in dynamics mode: converting such a
    bag needs --allow-no-rotors; the error names the topics the map looked for."""
    if allowed or any(rs.spec.kind in ("rotor", "thrust") for rs in resolved):
        return
    specs = next(specs for name, specs in tmap.profiles if name == profile)
    wanted = [f"{spec.name} needs " + " or ".join("+".join(src.topics) for src in spec.sources)
              for spec in specs if spec.kind in ("rotor", "thrust")]
    looked = "; ".join(wanted) if wanted else f"the topic map {tmap.path} has no rotor or thrust stream"
    raise MissingTopicError(f"{bag.path}: no rotor speeds in the bag ({looked}; profile '{profile}'): the dataset "
                            f"could only run with vid_run --mode imu; pass --allow-no-rotors to convert it anyway")


def _window(bag: Bag, opts: Options) -> tuple[int | None, int | None]:
    """--start/--end as bag times; negative, empty or outside the bag: a usage error stating
    the bag's span (the rule of the C++ programs' --start/--end, vid::system::check_window)."""
    span_s = (bag.end_ns - bag.start_ns) * 1e-9
    span = f"{bag.path}: the bag spans 0 to {span_s:.3f} s"
    start = stop = None
    if opts.start_s is not None:
        if opts.start_s < 0:
            raise UsageError(f"--start {opts.start_s:g}: negative ({span})")
        if opts.start_s >= span_s:
            raise UsageError(f"--start {opts.start_s:g}: past the end of the bag ({span})")
        start = bag.start_ns + int(round(opts.start_s * 1e9))
    if opts.end_s is not None:
        if opts.end_s <= (opts.start_s or 0.0):
            raise UsageError(f"--end {opts.end_s:g}: not after --start {opts.start_s or 0:g}, the selection is "
                             f"empty ({span})")
        if opts.end_s > span_s + 1.0:  # a margin: --end is often a rounded duration
            raise UsageError(f"--end {opts.end_s:g}: past the end of the bag ({span})")
        stop = bag.start_ns + int(round(opts.end_s * 1e9))
    return start, stop


def convert(opts: Options, log=print) -> dict:
    """Run the conversion; returns the summary also written to OUT/bag2asl.yaml."""
    tmap = topicmap.load(opts.topics)
    preset = Preset(pathlib.Path(opts.preset) if opts.preset else DEFAULT_PRESET)
    mav0 = opts.out / "mav0"
    if mav0.exists() and any(mav0.iterdir()) and not opts.overwrite:
        raise ConfigError(f"{mav0} exists and is not empty (use --overwrite)")
    bag = Bag(opts.bag)
    try:
        topics = bag.topics()
        profile, resolved = topicmap.resolve(tmap, set(topics), bag.topic_list(), bag.path)
        _check_types(bag, resolved)
        _require_rotors(tmap, profile, resolved, bag, opts.allow_no_rotors)
        mass_kg, mass_source = mass_for(opts.bag, opts.mass_kg, preset)
        if mass_source.startswith("preset default"):
            print(f"warning: mass not given and not found in the bag name; using {mass_kg} kg from "
                  f"{preset.vehicle_path} (pass --mass KG)", file=sys.stderr)
        start, stop = _window(bag, opts)
        try:
            mav0.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            raise os_error(mav0, err) from None
        pngs = PngPool(opts.jobs, opts.png_level)
        try:
            handlers = _make_handlers(resolved, mav0, opts.bag, opts, mass_kg, preset, pngs)
            wall, cpu = _stream(bag, handlers, start, stop, opts, pngs)
            reader = bag.reader_summary()
        finally:
            pngs.close()  # idempotent; on errors it still stops the worker threads
    finally:
        bag.close()
    summary = _summary(opts, profile, handlers, mass_kg, mass_source, wall, cpu, tmap, pngs.png_bytes)
    summary["bag_reader"] = reader
    _write_calibration(preset, mav0, handlers, mass_kg, mass_source)
    _write_summary(opts.out / "bag2asl.yaml", summary)
    _log_summary(summary, log)
    return summary


def _stream(bag, handlers, start, stop, opts, pngs):
    """Read the bag once, routing each message to its handlers; returns (wall s, CPU s)."""
    routes = {}
    for h in handlers:
        for index, topic in enumerate(h.rs.source.topics):
            for conn in bag.connections(topic):
                routes.setdefault(conn.id, []).append((h, index, topic, conn.msgtype, bag.deserializer(conn)))
    conns = [c for c in bag.reader.connections if c.id in routes]
    images = [h for h in handlers if isinstance(h, ImageHandler)]
    t0 = start if start is not None else bag.start_ns
    t1 = stop if stop is not None else bag.end_ns
    bar = Progress(bag.progress(t0, t0, t1)[1], opts.progress)  # bytes read (ROS1) or bag time
    wall = time.monotonic()
    cpu = time.process_time()
    try:
        for conn, bag_ns, raw in bag.messages(conns, start, stop):
            for h, index, topic, msgtype, deser in routes[conn.id]:
                h.feed(index, topic, msgtype, deser(raw), bag_ns)
            if bar.enabled:
                bar.update(bag.progress(bag_ns, t0, t1)[0], sum(h.raw_bytes for h in images))
        bar.update(bar.total, sum(h.raw_bytes for h in images), force=True)
    finally:
        bar.close()
    pngs.close()  # wait for the last PNGs (and their errors) before timing and closing the CSVs
    for h in handlers:
        h.finish()
    return time.monotonic() - wall, time.process_time() - cpu


def _write_calibration(preset, mav0, handlers, mass_kg, mass_source) -> None:
    write_vehicle_yaml(preset, mav0, mass_kg, mass_source)
    for h in handlers:
        rate = h.csv.rate_hz() if h.csv is not None else None
        if isinstance(h, ImageHandler):
            if h.name not in preset.cams:
                raise ConfigError(f"{preset.cam_path}: no calibration for camera stream '{h.name}'")
            res = [h.width, h.height] if h.width else None
            write_camera_yaml(preset, h.name, mav0, rate, res, h.rs.source.topics[0])
        elif isinstance(h, ImuHandler):
            write_imu_yaml(preset, mav0, rate, h.rs.source.topics[0])
        elif isinstance(h, RotorHandler) and h.csv is not None:
            write_rotor_yaml(preset, mav0, h.name, h.rs.source.unit or h.rs.spec.options.get("unit"),
                             h.count, rate, h.rs.spec.options.get("noise_density"))


def _summary(opts, profile, handlers, mass_kg, mass_source, wall, cpu, tmap, png_bytes) -> dict:
    streams = {}
    image_raw = 0
    for h in handlers:
        csv = h.csv
        entry = {"kind": h.rs.spec.kind, "topics": list(h.rs.source.topics),
                 "rows": csv.count if csv else 0, "dropped_non_increasing": csv.dropped if csv else 0,
                 "first_ns": csv.first_ns if csv else None, "last_ns": csv.last_ns if csv else None}
        if h.rs.spec.kind == "rotor":
            entry["source"] = h.rs.source.label
            if h.rs.source.per_motor:
                entry["superseded_per_motor_values"] = h.superseded
        if h.bag_stamped:
            entry["stamped_with_bag_time"] = h.bag_stamped
        if isinstance(h, GroundTruthHandler):
            entry["velocity"] = h.velocity_source
            entry["biases"] = "zero (unknown to motion capture)"
        if isinstance(h, ForceHandler):
            entry["frame"] = "rotated by topic-map rotation" if h.R else "sensor frame as recorded"
        if isinstance(h, ImageHandler):
            image_raw += h.raw_bytes
        streams[h.name] = entry
    return {"bag": str(opts.bag), "topic_map": str(tmap.path), "profile": profile,
            "mass_kg": mass_kg, "mass_source": mass_source, "streams": streams,
            "wall_s": round(wall, 3), "cpu_s": round(cpu, 3), "image_input_mb": round(image_raw / 1e6, 3),
            "image_png_mb": round(png_bytes / 1e6, 3), "png_jobs": opts.jobs,
            "image_mb_per_s": round(image_raw / 1e6 / wall, 2) if wall > 0 else None,
            "image_mb_per_cpu_s": round(image_raw / 1e6 / cpu, 2) if cpu > 0 else None}


def _write_summary(path: pathlib.Path, summary: dict) -> None:
    try:
        with sinks._open_out(path, "w") as f:
            yaml.safe_dump(summary, f, sort_keys=False)
    except OSError as err:
        raise os_error(path, err) from None


def _log_summary(s: dict, log) -> None:
    log(f"profile {s['profile']}, mass {s['mass_kg']} kg ({s['mass_source']})")
    for name, e in s["streams"].items():
        extra = f", source {e['source']}" if "source" in e else ""
        extra += f", velocity {e['velocity']}" if "velocity" in e else ""
        drop = f", {e['dropped_non_increasing']} dropped (time not increasing)" if e["dropped_non_increasing"] else ""
        if e.get("superseded_per_motor_values"):
            drop += f", {e['superseded_per_motor_values']} per-motor values superseded before their cycle completed"
        log(f"  {name:<28} {e['rows']:>8} rows from {'+'.join(e['topics'])}{extra}{drop}")
    if s["image_input_mb"]:
        log(f"images: {s['image_input_mb']} MB in {s['wall_s']} s = {s['image_mb_per_s']} MB/s "
            f"({s['image_mb_per_cpu_s']} MB per CPU second)")
