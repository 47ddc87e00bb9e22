"""The conversion: read every stream of the map from every piece, join, convert to the project's
frames (frames.py), check the thrust and accelerometer point up, and collect the report lines."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Tuple

import numpy as np

from ..core.geometry import wxyz_from_rot
from .errors import DataError
from .frames import check_up, check_world, imu_vectors, mocap_orientation, quat_to_xyzw, world_vectors
from .pieces import Stream, find_pieces, gaps, read_joined
from .smoothing import derivatives
from .sourcemap import SourceMap
from .writer import Imported, rate_hz

#: Cutoff of the position low-pass when the velocity is differentiated from mocap positions:
#: a multirotor's velocity has little above ~5 Hz; 10 Hz keeps it and removes most of the noise
#: that one differentiation amplifies.
VELOCITY_CUTOFF_HZ = 10.0


@dataclass
class Options:
    mass_kg: float
    gravity: float = 9.81
    imu_frame: str = "flu"
    world_frame: str = "enu"
    negate_thrust: bool = False
    imu_noise: Dict[str, float] = field(default_factory=dict)
    rotor_noise: float = 1.0
    rotor_coefficients: List[float] = field(default_factory=list)
    velocity_cutoff_hz: float = VELOCITY_CUTOFF_HZ


def describe(name: str, s: Stream, what: str = "samples") -> str:
    """``imu0: 15100 samples, 100.000 Hz, span 151.000 s, 3 files, gaps: none``."""
    g = gaps(s.t_ns)
    gap = (f"gaps: {g.count} longer than 1.5 x {g.median_dt_s * 1e3:.3g} ms (largest {g.largest_s * 1e3:.3g} ms)"
           if g.count else "gaps: none")
    dup = f", {s.duplicates} duplicate rows dropped" if s.duplicates else ""
    return (f"{name}: {s.t_ns.size} {what}, {rate_hz(s.t_ns):.3f} Hz, span {(s.t_ns[-1] - s.t_ns[0]) * 1e-9:.3f} s "
            f"from {len(s.files)} file(s){dup}, {gap}")


def _thrust(s: Stream, unit: str, opts: Options, accel_flu: np.ndarray, lines: List[str]) -> np.ndarray:
    raw = s.values["thrust"]
    vec = raw if raw.shape[1] == 3 else np.hstack([np.zeros((raw.shape[0], 2)), raw])
    vec = imu_vectors(vec, opts.imu_frame) * (-1.0 if opts.negate_thrust else 1.0)
    check_up(accel_flu, vec[:, 2], opts.imu_frame, unit)
    thrust_n = vec[:, 2] * (opts.mass_kg if unit == "m/s^2" else 1.0)
    side = float(np.abs(vec[:, :2]).max())
    note = f"; x/y components dropped (largest {side:.3g} {unit})" if side > 0 else ""
    how = f"= {opts.mass_kg:g} kg x m/s^2" if unit == "m/s^2" else "in N as given"
    lines.append(f"thrust0: collective thrust along body z {how}, median {np.median(thrust_n):.4g} N{note}")
    return thrust_n


def _mocap(s: Stream, opts: Options, lines: List[str], order: str, t_imu: np.ndarray, accel: np.ndarray):
    R_WI = mocap_orientation(quat_to_xyzw(s.values["quaternion"], order), opts.imu_frame, opts.world_frame)
    angle = check_world(t_imu, accel, s.t_ns, R_WI, opts.world_frame)
    q = wxyz_from_rot(R_WI)
    p = world_vectors(s.values["position"], opts.world_frame)
    if "velocity" in s.values:
        v = world_vectors(s.values["velocity"], opts.world_frame)
        how = "from the mocap (rotated into W)"
    else:
        v = derivatives(s.t_ns, p, opts.velocity_cutoff_hz).v
        how = (f"differentiated from the position (zero-phase Butterworth low-pass at "
               f"{opts.velocity_cutoff_hz:g} Hz)")
    lines.append(f"ground truth: quaternion order {order}, velocity {how}; biases 0 (unknown to mocap); the "
                 f"accelerometer rotated into W averages {angle:.1f} deg from +z")
    return p, q, v


def _overlap(a: np.ndarray, b: np.ndarray, what: str) -> None:
    lo, hi = max(a[0], b[0]), min(a[-1], b[-1])
    if hi <= lo:
        raise DataError(f"{what}: the streams do not overlap in time (IMU {a[0] * 1e-9:.3f}..{a[-1] * 1e-9:.3f} s, "
                        f"other {b[0] * 1e-9:.3f}..{b[-1] * 1e-9:.3f} s): check time_unit / --time-unit")


def convert(smap: SourceMap, root: Path, opts: Options) -> Tuple[Imported, List[str]]:
    """Everything but the writing; returns the converted log and the report lines."""
    pieces = find_pieces(smap, root)
    names = ", ".join(p.name for p in pieces)
    lines = [f"map {smap.path}: {len(pieces)} piece(s) ({names}; joined in time order)"]
    imu = read_joined(smap.streams["imu"], smap, pieces, root)
    gyro = imu_vectors(imu.values["gyro"], opts.imu_frame)
    accel = imu_vectors(imu.values["accel"], opts.imu_frame)
    lines.append(describe("imu0", imu))
    frd = opts.imu_frame == "frd"
    lines.append(f"frames: IMU {opts.imu_frame} -> flu" + (" (diag(1,-1,-1) on gyro, accel, thrust and the mocap "
                                                           "body orientation)" if frd else " (unchanged)")
                 + f"; mocap world {opts.world_frame} -> enu" + ("" if opts.world_frame == "enu" else
                                                                 " (positions, velocities, orientations rotated)"))
    log = Imported(imu.t_ns, gyro, accel, opts.mass_kg, opts.gravity, dict(opts.imu_noise))
    if "thrust" in smap.streams:
        spec = smap.streams["thrust"]
        s = read_joined(spec, smap, pieces, root)
        _overlap(imu.t_ns, s.t_ns, "thrust")
        lines.append(describe("thrust0", s))
        log.t_thrust, log.thrust_n = s.t_ns, _thrust(s, spec.options["unit"], opts, accel, lines)
    elif "rotors" in smap.streams:
        spec = smap.streams["rotors"]
        s = read_joined(spec, smap, pieces, root)
        _overlap(imu.t_ns, s.t_ns, "rotors")
        speeds = s.values["speeds"]
        if (speeds < 0).any():
            raise DataError(f"rotors: negative rotor speed {speeds.min():g} (rotor0 holds speeds >= 0)")
        check_up(accel, None, opts.imu_frame, "")
        if opts.rotor_coefficients and len(opts.rotor_coefficients) != speeds.shape[1]:
            raise DataError(f"--rotor-coefficients: {len(opts.rotor_coefficients)} values for "
                            f"{speeds.shape[1]} rotors")
        lines.append(describe("rotor0", s) + f", {speeds.shape[1]} rotors in {spec.options['unit']}")
        log.t_rotor, log.rotor_speeds, log.rotor_unit = s.t_ns, speeds, spec.options["unit"]
        log.rotor_noise, log.rotor_coefficients = opts.rotor_noise, list(opts.rotor_coefficients)
    else:
        check_up(accel, None, opts.imu_frame, "")
        lines.append("no thrust or rotor stream: the folder runs with vid_run --mode imu only")
    if "mocap" in smap.streams:
        spec = smap.streams["mocap"]
        s = read_joined(spec, smap, pieces, root)
        _overlap(imu.t_ns, s.t_ns, "mocap")
        lines.append(describe("state_groundtruth_estimate0", s, "poses"))
        log.t_gt = s.t_ns
        log.p_WI, log.q_WI_wxyz, log.v_WI = _mocap(s, opts, lines, spec.options["quaternion_order"], imu.t_ns, accel)
    return log, lines
