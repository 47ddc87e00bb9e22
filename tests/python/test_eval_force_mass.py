"""Force and mass metrics on constructed data with known answers (library and CLI)."""
from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from eval_testdata import run_cli_in_process, write_csv, write_euroc_gt, write_force_estimate, write_state
from vid_eval.core.mass_metrics import rmspe
from plot_checks import assert_plot

MASS = 2.0
C_WORLD = np.array([0.1, -0.2, 0.3])  # constant estimate error in W [m/s^2]


def _vid(*args):
    return run_cli_in_process(*args)


def _force_case(tmp_path, c_body=np.array([0.05, 0.0, -0.04])):
    """Dataset-like folder with force0 (world, N), gt poses; estimate force.csv and state.csv."""
    n = 600
    t_ns = 10**18 + np.arange(n, dtype=np.int64) * 5_000_000  # 200 Hz
    ts = np.arange(n) * 0.005
    f_w = np.c_[3 * np.sin(ts), 2 * np.cos(0.5 * ts), -1 + np.sin(2 * ts)]  # N
    rot = Rotation.from_rotvec(np.c_[0.3 * np.sin(ts), 0.2 * np.cos(ts), 0.8 * ts])
    mav0 = tmp_path / "seq" / "mav0"
    write_csv(mav0 / "force0" / "data.csv", "#timestamp [ns],f_x [N],f_y [N],f_z [N]", t_ns, f_w)
    gt_poses = write_euroc_gt(mav0 / "state_groundtruth_estimate0" / "data.csv", t_ns,
                              np.zeros((n, 3)), rot)
    a_w = f_w / MASS
    R = rot.as_matrix()
    a_b = np.einsum("nji,nj->ni", R, a_w)
    est_t = t_ns[10:-10:2]  # estimate at 100 Hz inside the GT span
    k = np.searchsorted(t_ns, est_t)
    fw_est = a_w[k] + C_WORLD
    fb_est = a_b[k] + c_body
    sigma = np.full((len(k), 3), 0.1)
    force = write_force_estimate(tmp_path / "run" / "force.csv", est_t, fb_est, fw_est, sigma)
    state = write_state(tmp_path / "run" / "state.csv", est_t, np.zeros((len(k), 3)), rot[k], fb_est,
                        sigma_f=sigma)
    return mav0, force, state, gt_poses, c_body


def test_force_world_rmse_known_answer_with_mass_flag(tmp_path):
    mav0, force, _, _, _ = _force_case(tmp_path)
    out = tmp_path / "f.json"
    proc = _vid("force", force, mav0 / "force0" / "data.csv", "--mass", MASS, "--json", out,
                "--plot", tmp_path / "plots")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(out.read_text())["force"]
    assert d["frame"] == "world"
    assert [d["rmse_mps2"][a] for a in "xyz"] == pytest.approx(np.abs(C_WORLD), abs=1e-9)
    assert d["rmse_mps2"]["norm"] == pytest.approx(np.linalg.norm(C_WORLD), abs=1e-9)
    assert d["rmse_N"]["norm"] == pytest.approx(MASS * np.linalg.norm(C_WORLD), abs=1e-9)
    assert d["pairs"] == 290
    # truth and estimate per axis (the error is a constant, drawn under its RMSE line)
    assert_plot(tmp_path / "plots" / "force_world.png", ("black", "tab:blue"), stamp_has=(force.name, "force0"))


@pytest.mark.parametrize("source", ["mass0", "vehicle_mav0", "vehicle_seq"])
def test_force_mass_found_next_to_dataset(tmp_path, source):
    mav0, force, _, _, _ = _force_case(tmp_path)
    if source == "mass0":
        write_csv(mav0 / "mass0" / "data.csv", "#timestamp [ns],mass [kg]",
                  np.array([10**18, 10**18 + 10**10]), np.array([MASS, MASS]))
    else:
        folder = mav0 if source == "vehicle_mav0" else mav0.parent
        (folder / "vehicle.yaml").write_text(f"mass_kg: {MASS}\ngravity: 9.81\n")
    out = tmp_path / "f.json"
    proc = _vid("force", force, mav0 / "force0" / "data.csv", "--json", out)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(out.read_text())
    assert d["force"]["rmse_mps2"]["norm"] == pytest.approx(np.linalg.norm(C_WORLD), abs=1e-9)
    assert d["force_rmse_world_mps2"] == pytest.approx(np.linalg.norm(C_WORLD), abs=1e-9)


def test_force_without_mass_is_a_one_line_error(tmp_path):
    mav0, force, _, _, _ = _force_case(tmp_path)
    proc = _vid("force", force, mav0 / "force0" / "data.csv")
    assert proc.returncode != 0
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "--mass" in proc.stderr


def test_force_body_frame_with_gt_poses(tmp_path):
    mav0, force, _, gt_poses, c_body = _force_case(tmp_path)
    out = tmp_path / "f.json"
    proc = _vid("force", force, mav0 / "force0" / "data.csv", "--mass", MASS, "--frame", "body",
                "--gt-state", gt_poses, "--json", out)
    assert proc.returncode == 0, proc.stderr
    d = json.loads(out.read_text())["force"]
    assert [d["rmse_mps2"][a] for a in "xyz"] == pytest.approx(np.abs(c_body), abs=1e-9)
    assert d["fraction_within_3sigma"] == 1.0


def test_force_from_state_csv_in_world_frame(tmp_path):
    """state.csv has only body force: rotated to W with its own q, error = R c_body."""
    c_body = np.array([0.2, 0.0, 0.0])
    mav0, _, state, _, _ = _force_case(tmp_path, c_body=c_body)
    out = tmp_path / "f.json"
    proc = _vid("force", state, mav0 / "force0" / "data.csv", "--mass", MASS, "--json", out,
                "--plot", tmp_path / "p")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(out.read_text())["force"]
    assert d["rmse_mps2"]["norm"] == pytest.approx(0.2, abs=1e-9)  # rotation keeps the norm
    assert d["rmse_mps2"]["z"] < 0.2 * np.sin(0.31)  # tilt is at most ~0.36 rad


def test_rmspe_equation_48_by_hand():
    m = np.array([2.0, 2.0, 4.0, 4.0])
    m_hat = np.array([2.2, 1.9, 4.0, 4.4])
    # ((0.1)^2 + (-0.05)^2 + 0 + (0.1)^2) / 4 = 0.005625 -> sqrt = 0.075 -> 7.5 %
    assert rmspe(m_hat, m) == pytest.approx(7.5, abs=1e-12)


def test_mass_cli_known_rmspe_and_rmse(tmp_path):
    rng = np.random.default_rng(7)
    t = 10**18 + np.arange(400, dtype=np.int64) * 10_000_000
    m = np.where(np.arange(400) < 200, 1.5, 1.8)  # a mass step
    rel = rng.normal(0, 0.02, 400)
    m_hat = m * (1 + rel)
    gt = write_csv(tmp_path / "mass0.csv", "#timestamp [ns],mass [kg]", t, m)
    est = write_csv(tmp_path / "est.csv", "#timestamp [ns],mass [kg],sigma [kg]", t,
                    np.c_[m_hat, np.full(400, 0.01)])
    out = tmp_path / "m.json"
    proc = _vid("mass", est, gt, "--json", out, "--plot", tmp_path / "plots")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(out.read_text())
    expected = np.sqrt(np.mean(((m_hat - m) / m) ** 2)) * 100.0
    assert d["mass_rmspe_percent"] == pytest.approx(expected, rel=1e-6)
    assert d["mass_rmse_kg"] == pytest.approx(np.sqrt(np.mean((m_hat - m) ** 2)), rel=1e-6)
    assert (tmp_path / "plots" / "mass.png").stat().st_size > 10_000
