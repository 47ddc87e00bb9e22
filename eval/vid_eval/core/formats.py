"""Column layouts of every file the package reads: the single source of truth.

The C++ writer of ``vid_run`` (docs/formats.md §2) produces ``state.csv`` and ``force.csv`` with the
headers below; :func:`header_line` gives the exact first line. Column *names* are the part of
each header field before the first space; the bracketed unit is documentation. Readers check
the names (when a header is present) and the column count.

state.csv (38 columns, comma separated, one header line starting with ``#``)::

    timestamp [ns]                          int64 nanoseconds
    p_x, p_y, p_z [m]                       p_WI, position of the IMU/body in the world
    q_w, q_x, q_y, q_z []                   q_WI, Hamilton, rotates I-vectors into W
    v_x, v_y, v_z [m s^-1]                  v_WI in W
    bg_x, bg_y, bg_z [rad s^-1]             gyroscope bias
    ba_x, ba_y, ba_z [m s^-2]               accelerometer bias
    f_x, f_y, f_z [m s^-2]                  F_ext, mass-normalized external force, body frame I
    sigma_theta_x.._z [rad]                 1-sigma of the orientation error (right perturbation)
    sigma_p_x.._z [m]                       1-sigma of position
    sigma_v_x.._z [m s^-1]                  1-sigma of velocity
    sigma_bg_x.._z [rad s^-1]               1-sigma of the gyroscope bias
    sigma_ba_x.._z [m s^-2]                 1-sigma of the accelerometer bias
    sigma_f_x.._z [m s^-2]                  1-sigma of F_ext (body)

force.csv (10 columns)::

    timestamp [ns], fb_x, fb_y, fb_z [m s^-2] (body I), fw_x, fw_y, fw_z [m s^-2] (world W),
    sigma_x, sigma_y, sigma_z [m s^-2] (1-sigma, body I)
"""
from __future__ import annotations

from typing import List, Sequence, Tuple

Column = Tuple[str, str]  # (name, unit)


def _xyz(prefix: str, unit: str) -> List[Column]:
    return [(f"{prefix}_{a}", unit) for a in "xyz"]


#: The columns of ``state.csv`` in order (name, unit).
STATE_COLUMNS: List[Column] = (
    [("timestamp", "ns")]
    + _xyz("p", "m")
    + [("q_w", ""), ("q_x", ""), ("q_y", ""), ("q_z", "")]
    + _xyz("v", "m s^-1")
    + _xyz("bg", "rad s^-1")
    + _xyz("ba", "m s^-2")
    + _xyz("f", "m s^-2")
    + _xyz("sigma_theta", "rad")
    + _xyz("sigma_p", "m")
    + _xyz("sigma_v", "m s^-1")
    + _xyz("sigma_bg", "rad s^-1")
    + _xyz("sigma_ba", "m s^-2")
    + _xyz("sigma_f", "m s^-2")
)

#: The columns of ``force.csv`` in order (name, unit).
FORCE_COLUMNS: List[Column] = (
    [("timestamp", "ns")] + _xyz("fb", "m s^-2") + _xyz("fw", "m s^-2") + _xyz("sigma", "m s^-2")
)

#: Ground-truth external force ``force0/data.csv`` (world frame, Newton).
FORCE0_COLUMNS: List[Column] = [("timestamp", "ns")] + _xyz("f", "N")

#: Optional force-rate columns of ``force0/data.csv`` (simulator output since issue #17):
#: ``dFx/dt, dFy/dt, dFz/dt [N s^-1]`` after the force (7 columns in all).
FORCE0_RATE_COLUMNS: List[Column] = [(f"dF{a}/dt", "N s^-1") for a in "xyz"]

#: Ground-truth mass ``mass0/data.csv``; also the format of a mass estimate (optional sigma).
MASS_COLUMNS: List[Column] = [("timestamp", "ns"), ("mass", "kg")]
MASS_SIGMA_COLUMN: Column = ("sigma", "kg")

#: Ground-truth flight phase ``phase0/data.csv`` (issue #29): 0 on the ground, 1 airborne.
PHASE0_COLUMNS: List[Column] = [("timestamp", "ns"), ("phase", "")]
PHASE_ON_GROUND, PHASE_AIRBORNE = 0, 1

#: Tracked features of the KLT frontend (``vid_track --out``, ``vid_run --tracks``): one row
#: per feature and camera of a frame, frames in time order (rows of a frame share its time).
TRACKS_COLUMNS: List[Column] = [("timestamp", "ns"), ("cam_id", ""), ("feature_id", ""), ("u", "px"), ("v", "px")]

#: NEES Monte-Carlo curves (``vio_core_nees*_test`` -> ``<build>/vio_core_nees/nees_*.csv``):
#: this header first, then the comment ``# runs=N band_lo=L band_hi=H`` (the two-sided 95 %
#: band of the mean of N chi2(3) values), then one row per filter time. nees_F is 0 when the
#: state has no F_ext (imu mode).
NEES_COLUMNS: List[Column] = [("t", "s"), ("nees_theta", ""), ("nees_p", ""), ("nees_F", "")]
NEES_DOF = 3

#: EuRoC ``state_groundtruth_estimate0/data.csv``: 17 columns; the pose is the first 8, the
#: accelerometer bias ``b_a_RS_S_x..z`` the last 3 (when all 17 are there).
EUROC_GT_MIN_COLUMNS = 8
EUROC_GT_COLUMNS = 17

#: EuRoC ``imu0/data.csv``: gyroscope [rad/s] then accelerometer [m/s^2], IMU frame.
IMU0_COLUMNS: List[Column] = (
    [("timestamp", "ns")]
    + [(f"w_RS_S_{a}", "rad s^-1") for a in "xyz"]
    + [(f"a_RS_S_{a}", "m s^-2") for a in "xyz"]
)

#: ``rotor0/data.csv``: ``timestamp [ns], n_1, ..., n_k`` in the unit of ``rotor0/sensor.yaml``.
ROTOR0_MAX_ROTORS = 16

#: ``thrust0/data.csv``: collective thrust along body z.
THRUST0_COLUMNS: List[Column] = [("timestamp", "ns"), ("thrust", "N")]

#: Plain ASL pose CSV (e.g. ``vicon0/data.csv`` or ``leica0``): timestamp, p (3), q (w,x,y,z).
ASL_POSE_COLUMNS = 8

#: TUM trajectory: ``timestamp[s] tx ty tz qx qy qz qw``, whitespace separated.
TUM_COLUMNS = 8


def header_line(columns: Sequence[Column]) -> str:
    """Return the exact header line a writer must put first (``#name [unit],...``)."""
    return "#" + ",".join(f"{n} [{u}]" for n, u in columns)


def column_index(columns: Sequence[Column], name: str) -> int:
    """Index of the column called ``name`` (KeyError when absent)."""
    for i, (n, _) in enumerate(columns):
        if n == name:
            return i
    raise KeyError(name)


def header_names(header: str) -> List[str]:
    """Column names of a header line: strip ``#``, split on commas, drop units and spaces."""
    text = header.lstrip().lstrip("#")
    names = []
    for field in text.split(","):
        field = field.strip()
        names.append(field.split(" ")[0].split("[")[0] if field else "")
    return names
