"""Writers of small synthetic files for the vid-eval tests (TUM, EuRoC CSV, force, mass, state)."""
from __future__ import annotations

import pathlib
from typing import Optional

import numpy as np
from scipy.spatial.transform import Rotation

from vid_eval.core import formats


def smooth_trajectory(t_s: np.ndarray, seed: int = 0):
    """A smooth 3-D flight (positions [m], quaternions x,y,z,w) with a seed-dependent shape."""
    rng = np.random.default_rng(seed)
    a, b, c = rng.uniform(0.2, 0.6, 3)
    p = np.c_[3 * np.cos(a * t_s), 2 * np.sin(b * t_s), 1 + 0.5 * np.sin(c * t_s)]
    rv = np.c_[0.2 * np.sin(0.7 * t_s), 0.15 * np.cos(0.5 * t_s), 0.3 * t_s]
    return p, Rotation.from_rotvec(rv)


def write_tum(path: pathlib.Path, t_s: np.ndarray, p: np.ndarray, rot: Rotation) -> pathlib.Path:
    """TUM file: 'ts tx ty tz qx qy qz qw' with 9 decimals."""
    q = rot.as_quat()
    with open(path, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for i in range(len(t_s)):
            f.write(f"{t_s[i]:.9f} " + " ".join(f"{x:.9f}" for x in (*p[i], *q[i])) + "\n")
    return path


def write_euroc_gt(path: pathlib.Path, t_ns: np.ndarray, p: np.ndarray, rot: Rotation) -> pathlib.Path:
    """EuRoC state_groundtruth_estimate0/data.csv with 17 columns (v and biases zero)."""
    q = rot.as_quat()[:, [3, 0, 1, 2]]
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as f:
        f.write("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
                "q_RS_y [], q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], "
                "b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], "
                "b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n")
        for i in range(len(t_ns)):
            vals = [*p[i], *q[i]] + [0.0] * 9
            f.write(f"{int(t_ns[i])}," + ",".join(f"{x:.12g}" for x in vals) + "\n")
    return path


def write_csv(path: pathlib.Path, header: str, t_ns: np.ndarray, cols: np.ndarray) -> pathlib.Path:
    """Generic '#header' + 'ns,v1,v2,...' CSV."""
    path.parent.mkdir(parents=True, exist_ok=True)
    cols = np.asarray(cols, dtype=float).reshape(len(t_ns), -1)
    with open(path, "w") as f:
        f.write(header + "\n")
        for i in range(len(t_ns)):
            f.write(f"{int(t_ns[i])}," + ",".join(f"{x:.12g}" for x in cols[i]) + "\n")
    return path


def write_force_estimate(path: pathlib.Path, t_ns, f_body, f_world, sigma) -> pathlib.Path:
    """Our force.csv with the contract header."""
    return write_csv(path, formats.header_line(formats.FORCE_COLUMNS), t_ns,
                     np.hstack([f_body, f_world, sigma]))


def write_state(path: pathlib.Path, t_ns, p, rot: Rotation, f_body,
                sigma_f: Optional[np.ndarray] = None) -> pathlib.Path:
    """Our state.csv with the contract header (v, biases zero; sigmas 0.01 except sigma_f)."""
    n = len(t_ns)
    q = rot.as_quat()[:, [3, 0, 1, 2]]
    sig = np.full((n, 18), 0.01)
    if sigma_f is not None:
        sig[:, 15:18] = sigma_f
    cols = np.hstack([p, q, np.zeros((n, 9)), f_body, sig])
    return write_csv(path, formats.header_line(formats.STATE_COLUMNS), t_ns, cols)


class CliResult:
    """Outcome of an in-process ``vid-eval`` call (same fields as subprocess.CompletedProcess)."""

    def __init__(self, returncode: int, stdout: str, stderr: str) -> None:
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


def run_cli_in_process(*args) -> CliResult:
    """Run ``vid_eval.cli.main`` in this process (fast; the bad-input tests use a subprocess)."""
    import contextlib
    import io

    from vid_eval.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main([str(a) for a in args])
        except SystemExit as exc:  # argparse usage errors
            rc = int(exc.code or 0)
    return CliResult(rc, out.getvalue(), err.getvalue())
