"""The estimator's dynamics model fitted to a flight log (what ``vid-fit-thrust`` prints and
``vid-allan --flight`` takes its accelerometer residual from).

Steps, on the IMU samples of the window:

1. thrust stream: ``rotor0`` (k n^2, the coefficients fitted) or ``thrust0`` (a measured thrust
   T; its scale s fitted);
2. the thrust stream's latency against the IMU (``thrust_delay_s``): given, or measured by
   :func:`vid_eval.importer.sync.thrust_offset` (the code of ``vid-eval mocap-truth``), with the
   drag term -D_z v_z as a regressor when the ground truth gives the velocity, because the drag
   correlates with the velocity and fakes a lag at low frequency;
3. body z: :func:`vid_eval.calib.thrust_fit.fit_thrust` with -v_z as an extra regressor (D_z);
4. body x, y and the thrust axis: :mod:`vid_eval.calib.axis_fit`;
5. with the velocity: the same fit without the drag terms, to say what a hover/steps fit of
   k and the tilt would be on this log; without it: the lateral force the thrust model leaves.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import List, Optional

import numpy as np

from ..errors import VidEvalError
from ..importer.errors import DataError
from ..importer.sync import ThrustOffset, thrust_offset
from ..tools.loaders import ImuSeries, Vehicle
from . import dataset as ds
from .axis_fit import AXIS_SIGMA_MAX_DEG, DRAG_SIGMA_MAX, FORCE_BAND_HZ, LateralFit, ThrustAxis, drag_share, fit_lateral, low_pass, thrust_axis
from .thrust_fit import FitInput, ThrustFit, fit_thrust, regressors
from .torque_rows import WINDOW_S, load_geometry, torque_rows
from .truth_motion import TruthMotion, truth_motion

#: Largest thrust latency searched [s]: rotor telemetry runs 10-50 ms late; the search costs
#: in proportion to its range.
MAX_LAG_S = 0.2
#: A measured latency whose standard error (spread over five parts of the log) exceeds this [s]
#: is not used (0 is, with a warning): the thrust does not vary enough to time it.
DELAY_STDERR_MAX_S = 0.02
#: Drag-rich flight: 90 % of the samples slower than this [m/s] is hover and steps ...
DRAG_RICH_SPEED = 1.0
#: ... and the drag explains at least this share of the low-passed body force.
DRAG_RICH_SHARE = 0.5
#: Without the velocity: lateral force beyond the thrust model (low-passed RMS) [m/s^2] that
#: says the log is not hover and steps in still air.
LATERAL_FORCE_WARN = 0.3


@dataclass
class FitOptions:
    model: str = "collective"
    bias: str = "fit"
    mass: Optional[float] = None
    start: float = 0.0
    end: Optional[float] = None
    min_thrust_fraction: float = 0.25
    geometry: Optional[Path] = None
    source: str = "auto"
    delay: Optional[float] = None       # None: measure it
    max_lag: float = MAX_LAG_S
    drag: bool = True                   # fit D when the ground truth gives the velocity
    subtract_force0: bool = False


@dataclass
class Delay:
    value_s: float                       # the latency used (thrust_delay_s)
    measured: Optional[ThrustOffset]     # None when given with --delay
    note: str = ""                       # why the measured value was not used


@dataclass
class FlightFit:
    mav0: Path
    imu: ImuSeries
    stream: ds.ThrustStream
    vehicle: Optional[Vehicle]
    mass: float
    mass_source: str
    window: np.ndarray             # IMU samples inside --start/--end
    data: FitInput                 # the samples fitted (z row)
    z: ThrustFit
    x: LateralFit
    y: LateralFit
    axis: ThrustAxis
    delay: Delay
    motion: Optional[TruthMotion]  # ground truth at the IMU times of the window
    rate_hz: float
    force0_subtracted: bool
    force0_present: bool
    speed_p90: float = float("nan")
    drag_share: float = float("nan")
    no_drag_k: Optional[np.ndarray] = None     # k (or s) of the same fit without drag terms
    no_drag_tilt_deg: float = float("nan")
    lateral_force_rms: float = float("nan")    # without velocity: low-passed lateral residual
    drag_fitted: bool = False                  # the velocity was given to the fit (some axes may be NaN)
    warnings: List[str] = field(default_factory=list)

    @property
    def drag(self) -> Optional[np.ndarray]:
        """[D_x, D_y, D_z] [1/s], or None when not fitted."""
        if not self.drag_fitted:
            return None
        return np.array([self.x.drag, self.y.drag, self.z.extra[0]])

    @property
    def drag_sigma(self) -> Optional[np.ndarray]:
        return None if not self.drag_fitted else np.array([self.x.drag_sigma, self.y.drag_sigma, self.z.extra_sigma[0]])

    @property
    def drag_determined(self) -> np.ndarray:
        """Per axis: the log determines D (1-sigma at most DRAG_SIGMA_MAX)."""
        return np.zeros(3, bool) if self.drag is None else self.drag_sigma <= DRAG_SIGMA_MAX

    @property
    def coefficients(self) -> np.ndarray:
        """k_i (or the thrust scale) of the thrust along the fitted axis: the z fit's / t_z when the
        axis is determined (the estimator applies the unit axis to the whole thrust)."""
        return self.z.coefficients * (self.axis.norm_factor if self.axis.determined else 1.0)

    @property
    def residuals(self) -> np.ndarray:
        """(N, 3) accelerometer minus the fitted model at ``data.t_ns``."""
        return np.column_stack([self.x.residual, self.y.residual, self.z.residuals])

    @property
    def drag_rich(self) -> bool:
        return self.speed_p90 > DRAG_RICH_SPEED and self.drag_share > DRAG_RICH_SHARE


def _thrust_proxy(stream: ds.ThrustStream, veh: Optional[Vehicle], mass: float) -> np.ndarray:
    """T/m at the stream's stamps for the latency search (its scale does not matter there)."""
    if stream.kind == "thrust0":
        return stream.values[:, 0] / mass
    sq = stream.values ** 2
    k = np.asarray(veh.rotor_thrust_coefficients) if veh is not None else np.zeros(0)
    return (sq @ k if k.size == sq.shape[1] else sq.sum(axis=1) * np.median(1.0 / np.maximum(sq.sum(axis=1), 1e-300))
            ) / mass


def _delay(opts: FitOptions, t_ns, accel_z, usable, v_z, stream, veh, mass) -> Delay:
    if opts.delay is not None:
        return Delay(opts.delay, None)
    sel = usable & (np.isfinite(v_z) if v_z is not None else True)
    try:
        off = thrust_offset(t_ns[sel], accel_z[sel], stream.t_ns, _thrust_proxy(stream, veh, mass),
                            None if v_z is None else v_z[sel], opts.max_lag)
    except DataError as exc:
        return Delay(0.0, None, f"not measured ({exc}); 0 used")
    d = off.fitted
    if d.at_limit or not d.stderr_s <= DELAY_STDERR_MAX_S:
        return Delay(0.0, off, f"not determined ({d.text()}): 0 used; the thrust must vary (steps)")
    if d.offset_s < 0:  # a latency of zero measures slightly negative half the time: say so only when it is not
        significant = -d.offset_s > max(2.0 * d.stderr_s, 0.001)
        return Delay(0.0, off, f"the thrust stream leads the IMU ({d.text()}); thrust_delay_s cannot be negative: "
                               "0 used (shift the IMU or thrust stamps if it is real)" if significant else "")
    return Delay(d.offset_s, off)


def _z_fit(data: FitInput, mass: float, opts: FitOptions, torque) -> ThrustFit:
    try:
        return fit_thrust(data, mass, opts.model, opts.bias, torque)
    except ValueError as exc:
        raise VidEvalError(str(exc)) from None


def fit_flight(mav0: Path, opts: FitOptions) -> FlightFit:
    """The whole fit (module docstring) on ``mav0``; VidEvalError on data that cannot be fitted."""
    imu = ds.imu(mav0)
    stream = ds.thrust_stream(mav0, opts.source)
    if stream.kind == "thrust0" and opts.model != "collective":
        raise VidEvalError(f"{stream.path}: a measured collective thrust has no per-rotor coefficients "
                           "(--model collective)")
    veh, mass, mass_src = ds.vehicle(mav0, opts.mass)
    gt = ds.groundtruth(mav0)
    t_rel = (imu.t_ns - imu.t_ns[0]) * 1e-9
    window = (t_rel >= opts.start) & (t_rel <= (opts.end if opts.end is not None else np.inf))
    if not window.any():
        raise VidEvalError(f"{mav0 / 'imu0' / 'data.csv'}: no IMU sample between --start {opts.start:g} s and "
                           f"--end {opts.end if opts.end is not None else 'the end'} (log spans {t_rel[-1]:.3f} s)")
    t_ns, accel = imu.t_ns[window], imu.accel[window].copy()
    rate = 1.0 / float(np.median(np.diff(t_ns) * 1e-9))
    force_present = (mav0 / "force0" / "data.csv").is_file()
    force_I = ds.external_force_I(mav0, gt, t_ns, mass) if opts.subtract_force0 else None
    if opts.subtract_force0 and force_I is None:
        raise VidEvalError(f"{mav0}: --subtract-force0 needs force0/data.csv and the ground truth")
    if force_I is not None:
        accel -= force_I
    motion = truth_motion(gt, t_ns) if gt is not None else None
    v_I = motion.v_I if (motion is not None and opts.drag) else None
    usable0, _ = regressors(t_ns, accel[:, 2], stream.t_ns, stream.values, opts.min_thrust_fraction, stream.squared)
    delay = _delay(opts, t_ns, accel[:, 2], usable0, None if v_I is None else v_I[:, 2], stream, veh, mass)
    t_stream = stream.t_ns - int(round(delay.value_s * 1e9))
    keep, speed_sq = regressors(t_ns, accel[:, 2], t_stream, stream.values, opts.min_thrust_fraction, stream.squared)
    if v_I is not None:
        keep &= np.isfinite(v_I).all(axis=1)
    if keep.sum() == 0:
        raise VidEvalError(f"{stream.path}: no IMU sample inside the thrust stream with thrust in the window")
    bias_z = None
    if opts.bias == "groundtruth":
        if gt is None:
            raise VidEvalError(f"{mav0}: --bias groundtruth needs state_groundtruth_estimate0/data.csv")
        bias_z = ds.groundtruth_accel_bias_z(gt, t_ns[keep])
    v = None if v_I is None else v_I[keep]
    data = FitInput(t_ns[keep], accel[keep, 2], speed_sq[keep], bias_z, None if v is None else -v[:, 2:3])
    torque = None
    if opts.geometry is not None:
        geometry = load_geometry(Path(opts.geometry), speed_sq.shape[1])
        torque = torque_rows(t_ns, imu.gyro[window], speed_sq, keep, geometry)
        if torque is None:
            raise VidEvalError(f"{mav0}: no {1000 * WINDOW_S:g} ms window with thrust and rotor data for the torque rows")
    z = _z_fit(data, mass, opts, torque)
    ax, ay = accel[keep, 0], accel[keep, 1]
    fx = fit_lateral(ax, z.thrust_per_m, None if v is None else v[:, 0])
    fy = fit_lateral(ay, z.thrust_per_m, None if v is None else v[:, 1])
    fit = FlightFit(mav0, imu, stream, veh, mass, mass_src, window, data, z, fx, fy, thrust_axis(fx, fy), delay,
                    motion, rate, force_I is not None, force_present)
    if v is not None:
        fit.drag_fitted = True
        _drag_diagnostics(fit, accel[keep], v, opts, torque)
    else:
        lateral = np.column_stack([fx.residual, fy.residual])
        fit.lateral_force_rms = float(np.sqrt(np.mean(low_pass(lateral, rate) ** 2)))
        if fit.lateral_force_rms > LATERAL_FORCE_WARN:
            fit.warnings.append(
                f"the body x/y force beyond the thrust model is {fit.lateral_force_rms:.2f} m/s^2 RMS below "
                f"{FORCE_BAND_HZ:g} Hz: not a hover/steps log in still air (the drag of a fast flight, wind, a "
                "tether); k and the tilt fitted without the drag are biased: give the ground truth (mocap) "
                "velocity for a joint drag fit, or cut the log to hover and steps (--start/--end)")
    if not fit.axis.determined:
        fit.warnings.append(
            f"the thrust axis is not determined (1-sigma {fit.axis.component_sigma_deg:.2f} deg per component > "
            f"{AXIS_SIGMA_MAX_DEG:g} deg): the log does not separate the tilt from the accelerometer bias; the thrust must vary "
            "(vertical steps); thrust_axis is not written")
    if delay.note:
        fit.warnings.append(f"thrust latency {delay.note}")
    return fit


def _drag_diagnostics(fit: FlightFit, accel: np.ndarray, v: np.ndarray, opts: FitOptions, torque) -> None:
    """Speed, drag share of the body force, and what the fit without drag gives on this log."""
    z = fit.z
    fit.speed_p90 = float(np.percentile(np.linalg.norm(v, axis=1), 90))
    D = np.nan_to_num(fit.drag)
    thrust = np.column_stack([fit.x.c * z.thrust_per_m, fit.y.c * z.thrust_per_m, z.thrust_per_m])
    body = accel - thrust - np.array([fit.x.bias, fit.y.bias, z.bias_z])
    fit.drag_share = drag_share(body, -D * v, fit.rate_hz)
    plain = FitInput(fit.data.t_ns, fit.data.accel_z, fit.data.speed_sq, fit.data.bias_z)
    z0 = _z_fit(plain, fit.mass, opts, torque)
    ax0 = thrust_axis(fit_lateral(accel[:, 0], z0.thrust_per_m), fit_lateral(accel[:, 1], z0.thrust_per_m))
    fit.no_drag_k = z0.coefficients * ax0.norm_factor
    fit.no_drag_tilt_deg = ax0.tilt_deg
