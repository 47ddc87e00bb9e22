"""IMU noise in flight, from a log with no static part: what the estimator's noise keys should
say, vibration included.

* gyroscope: the gyro minus the ground-truth (mocap) body rate at the IMU times
  (:mod:`vid_eval.calib.truth_motion`);
* accelerometer: the residual of the fitted thrust + drag model (:mod:`vid_eval.calib.flight_fit`),
  which is what the dynamics-mode accelerometer update compares against.

Both are high-passed (zero-phase 4th-order Butterworth, scipy ``sosfiltfilt``) to remove the slow
mismatch (bias, drift, unmodelled slow forces such as a tether or wind, the truth's own
low-frequency error), and the estimator's sense of a noise density is the per-sample standard
deviation over sqrt(rate) (white noise of Kalibr density N has per-sample sigma N sqrt(rate)):

    density = RMS(high-passed residual) / sqrt(rate * kept)

with ``kept`` the share of a white noise's power that the high-pass keeps (its |H|^2 averaged
over 0..Nyquist; 0.97 at 5 Hz and 400 Hz). Rotor vibration lines lie far above the cutoff and
are kept whole; they are not white, but the estimator treats them as if they were, so their
power belongs in the density it is given. A mocap whose differentiated orientation is noisier
than the gyro adds its own noise: the gyro value is then an upper bound.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import butter, sosfiltfilt, sosfreqz

#: Default high-pass [Hz]: above the flight's motion and aerodynamic forces, below the vibration.
HIGHPASS_HZ = 5.0


@dataclass
class FlightNoise:
    rms: np.ndarray        # (3,) per-axis RMS of the high-passed residual
    density: np.ndarray    # (3,) per-axis density [unit/sqrt(Hz)]
    samples: int

    @property
    def combined(self) -> float:
        """One density for all axes with the same per-sample variance (root mean square)."""
        return float(np.sqrt(np.mean(self.density ** 2)))


def _highpass(rate_hz: float, cutoff_hz: float):
    return butter(4, cutoff_hz, "highpass", fs=rate_hz, output="sos")


def kept_white_power(rate_hz: float, cutoff_hz: float) -> float:
    """Share of a white noise's power that the zero-phase high-pass keeps (|H|^4 of the single
    pass, averaged over 0..Nyquist)."""
    _, h = sosfreqz(_highpass(rate_hz, cutoff_hz), worN=8192, fs=rate_hz)
    return float(np.mean(np.abs(h) ** 4))


def flight_noise(residual: np.ndarray, rate_hz: float, cutoff_hz: float = HIGHPASS_HZ) -> FlightNoise:
    """Per-axis density of a (N, 3) residual at ``rate_hz`` (module docstring). Rows with a NaN
    are dropped (the runs between them are filtered as one series: the gaps are short)."""
    r = np.asarray(residual, dtype=float)
    r = r[np.isfinite(r).all(axis=1)]
    if len(r) < 200:
        raise ValueError(f"{len(r)} samples: too few for an in-flight noise (need at least 200)")
    hp = sosfiltfilt(_highpass(rate_hz, cutoff_hz), r - r.mean(axis=0), axis=0)
    edge = min(len(hp) // 10, int(round(rate_hz / cutoff_hz)))  # filter start-up at both ends
    hp = hp[edge:len(hp) - edge]
    rms = np.sqrt(np.mean(hp ** 2, axis=0))
    return FlightNoise(rms, rms / np.sqrt(rate_hz * kept_white_power(rate_hz, cutoff_hz)), len(hp))
