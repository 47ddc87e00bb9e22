"""What ``vid-fit-thrust`` prints and writes: the report lines and the fitted vehicle.yaml
(docs/formats.md §1 keys, read by io's strict loader)."""
from __future__ import annotations

from typing import List, Optional

import numpy as np

from .axis_fit import DRAG_SIGMA_MAX
from .flight_fit import DRAG_RICH_SPEED, FlightFit
from .flight_noise import HIGHPASS_HZ, flight_noise
from .thrust_fit import residuals_with


def _vec(v, fmt: str = "{:+.5f}") -> str:
    return "[" + ", ".join(fmt.format(x) for x in v) + "]"


def _thrust_lines(fit: FlightFit, model: str) -> List[str]:
    k, sig, unit = fit.coefficients, fit.z.sigma, fit.stream.unit
    if fit.stream.kind == "thrust0":
        return [f"  thrust scale s = {k[0]:.5f} +- {sig[0]:.5f} (the thrust the accelerometer sees is s x thrust0)"]
    names = [f"k_{i + 1}" for i in range(len(k))] if model == "per-rotor" else ["k (every rotor)"]
    return [f"  {name} = {c:.6e} N/({unit})^2  +- {s:.2e} ({100 * s / abs(c):.2f} %)"
            for name, c, s in zip(names, k, sig)]


def _axis_lines(fit: FlightFit) -> List[str]:
    a = fit.axis
    if not a.determined:
        return [f"  thrust axis: not determined (tilt {a.tilt_deg:.2f} deg, 1-sigma {a.component_sigma_deg:.2f} deg "
                "per component: too little thrust variation to separate the tilt from the bias)"]
    return [f"  thrust_axis = {_vec(a.axis)} +- {_vec(a.sigma, '{:.5f}')}: {a.tilt_deg:.3f} +- {a.tilt_sigma_deg:.3f} "
            f"deg off z_I towards azimuth {a.azimuth_deg:.1f} deg (accelerometer bias x/y {fit.x.bias:+.4f} / "
            f"{fit.y.bias:+.4f} m/s^2)"]


def _drag_lines(fit: FlightFit) -> List[str]:
    D, s = fit.drag, fit.drag_sigma
    if D is None:
        why = "--no-drag" if fit.motion is not None else "no ground-truth velocity in the log"
        return [f"  linear drag: not fitted ({why})"]
    lines = [f"  linear_drag = {_vec(D, '{:.4f}')} +- {_vec(s, '{:.4f}')} 1/s (F_drag_I = -D v_I per unit mass); "
             f"90 % of the samples below {fit.speed_p90:.2f} m/s; the drag explains {100 * fit.drag_share:.0f} % of "
             "the body force below 5 Hz"]
    k0, tilt0 = fit.no_drag_k, fit.no_drag_tilt_deg
    dk = 100 * (np.mean(k0) / np.mean(fit.coefficients) - 1)
    if fit.drag_rich:
        lines.append(f"  drag-rich log (speeds above {DRAG_RICH_SPEED:g} m/s, the drag a large part of the body force): "
                     f"a hover/steps fit of it (no drag terms, as without ground-truth velocity) is biased: "
                     f"k {dk:+.2f} %, tilt {tilt0:.3f} deg instead of {fit.axis.tilt_deg:.3f}")
    else:
        lines.append(f"  little drag in this log (hover and slow steps): the fit without drag terms differs by k "
                     f"{dk:+.2f} %, tilt {tilt0 - fit.axis.tilt_deg:+.3f} deg")
    undetermined = [ax for ax, ok in zip("xyz", fit.drag_determined) if not ok]
    if undetermined:
        lines.append(f"  linear drag {'/'.join(undetermined)}: not determined (the log hardly moves along that axis: "
                     f"1-sigma above {DRAG_SIGMA_MAX:g} 1/s); written as 0: fit a faster flight for it")
    return lines


def _delay_lines(fit: FlightFit) -> List[str]:
    d = fit.delay
    if d.measured is None:
        return [f"  thrust_delay_s: {d.value_s:.5f}   (estimator.yaml; given with --delay)"]
    m = d.measured
    how = ("a_z = s T/m(t + d) + b - D_z v_z, the drag term in the fit" if np.isfinite(m.drag_z)
           else "a_z = s T/m(t + d) + b (no velocity: the drag is not in the fit)")
    lines = [f"  {fit.stream.kind} stamps - IMU stamps = {m.fitted.text()} (from {how}; plain correlation "
             f"{m.plain.offset_s * 1e3:+.1f} ms)",
             f"  thrust_delay_s: {d.value_s:.5f}   (estimator.yaml: a {fit.stream.kind} sample stamped t is the "
             "thrust at t - thrust_delay_s)"]
    return lines


def report_lines(fit: FlightFit, prog: str, model: str, bias: str, geometry: Optional[str]) -> List[str]:
    mav0 = fit.mav0
    data, z = fit.data, fit.z
    span = (data.t_ns[[0, -1]] - fit.imu.t_ns[0]) * 1e-9
    lines = [f"{prog}: {mav0.parent if mav0.name == 'mav0' else mav0}: {len(data.t_ns)} IMU samples "
             f"{span[0]:.2f}-{span[1]:.2f} s ({int(fit.window.sum()) - len(data.t_ns)} dropped: low thrust or "
             f"thrust-stream gaps), {fit.stream.kind}, mass {fit.mass:g} kg ({fit.mass_source}), model {model}, "
             f"bias {bias}" + (", force0 subtracted" if fit.force0_subtracted else "")
             + (f", {z.torque_windows} torque windows ({geometry})" if z.torque_windows else "")]
    lines += _thrust_lines(fit, model)
    lines.append(f"  accelerometer bias z = {z.bias_z:+.4f} m/s^2"
                 f"{' (fitted)' if bias == 'fit' else ' (ground truth, mean)' if bias == 'groundtruth' else ''}")
    lines += _axis_lines(fit) + _drag_lines(fit) + _delay_lines(fit)
    lines.append(f"  residual RMS {z.rms:.4f} m/s^2 along z (design condition number {z.condition:.3g}); "
                 f"x/y {np.sqrt(np.mean(fit.x.residual ** 2)):.4f} / {np.sqrt(np.mean(fit.y.residual ** 2)):.4f}")
    if z.torque_rms is not None:
        lines.append("  torque-window residual RMS roll/pitch/yaw " + " / ".join(f"{v:.2e}" for v in z.torque_rms)
                     + " N m s")
    veh = fit.vehicle
    if fit.stream.kind == "rotor0" and veh is not None and len(veh.rotor_thrust_coefficients) == data.speed_sq.shape[1]:
        before = residuals_with(data, fit.mass, np.array(veh.rotor_thrust_coefficients), bias)
        lines.append(f"  residual RMS with vehicle.yaml's coefficients: {np.sqrt(np.mean(before ** 2)):.4f} m/s^2")
    if fit.force0_present and not fit.force0_subtracted:
        lines.append("  force0/ not subtracted (--subtract-force0 for a known external force)")
    try:
        noise = flight_noise(fit.residuals, fit.rate_hz)
        lines.append(f"  in-flight accelerometer noise (residual above {HIGHPASS_HZ:g} Hz, vibration included): "
                     f"accel_noise_density {noise.combined:.3e} m/s^2/sqrt(Hz) (x/y/z "
                     + " / ".join(f"{v:.3e}" for v in noise.density) + "; vid-allan --flight for both sensors)")
    except ValueError:
        pass
    return lines


def vehicle_yaml(fit: FlightFit, model: str) -> str:
    """The fitted vehicle.yaml: mass, gravity, coefficients (rotor0), thrust axis (when
    determined) and linear drag (when fitted)."""
    gravity = fit.vehicle.gravity if fit.vehicle is not None else 9.81
    z = fit.z
    lines = [f"# vid-fit-thrust {model} fit of {fit.mav0}: {len(fit.data.t_ns)} samples, residual RMS "
             f"{z.rms:.4f} m/s^2, relative 1-sigma <= {100 * z.relative_sigma.max():.2f} %",
             f"mass_kg: {fit.mass:.6g}", f"gravity: {gravity:.6g}"]
    if fit.stream.kind == "rotor0":
        coeffs = ", ".join(f"{c:.6e}" for c in fit.coefficients)
        lines.append(f"rotor_thrust_coefficients: [{coeffs}]   # N / ({fit.stream.unit})^2, T_i = k_i n_i^2")
    else:
        s = fit.coefficients[0]
        lines.append(f"# thrust0 scale s = {s:.5f}: the estimator reads thrust0 as it is; only T/m enters the "
                     f"dynamics, so mass_kg {fit.mass / s:.6g} (= m / s) applies the scale, or estimate it online "
                     "(thrust_scale_random_walk)")
    a = fit.axis
    if a.determined:
        lines.append(f"thrust_axis: [{a.axis[0]:.6f}, {a.axis[1]:.6f}, {a.axis[2]:.6f}]   # unit vector in I, "
                     f"{a.tilt_deg:.3f} +- {a.tilt_sigma_deg:.3f} deg off z_I")
    else:
        lines.append(f"# thrust_axis not determined by this log (1-sigma {a.component_sigma_deg:.2f} deg)")
    if fit.drag_determined.any():
        D = np.where(fit.drag_determined, np.clip(fit.drag, 0.0, None), 0.0)
        zero = "".join(ax for ax, ok in zip("xyz", fit.drag_determined) if not ok)
        lines.append(f"linear_drag: [{D[0]:.4f}, {D[1]:.4f}, {D[2]:.4f}]   # 1/s, F_drag_I = -D v_I per unit mass"
                     + (f"; {zero}: not determined by this log" if zero else ""))
    if fit.delay.value_s > 0 or fit.delay.measured is not None:
        lines.append(f"# estimator.yaml: thrust_delay_s: {fit.delay.value_s:.5f}")
    return "\n".join(lines) + "\n"
