"""Python bindings (python/, module vid_msckf._core built by CMake into <build>/python).

run_dataset writes the same files as vid_run; pushing the same measurements from numpy (the
example script python/examples/push_samples.py) gives the same estimates; latest() and
history() agree with each other and with state.csv; bad arguments raise one clear exception.
"""
import importlib.util
import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import build_dir
from test_vid_run_helpers import REPO, VENV_BIN, simulate_cached, vid_run

SIM_CONFIG = REPO / "config" / "sim"


def _import_bindings():
    path = build_dir() / "python"
    if not (path / "vid_msckf" / "__init__.py").exists():
        pytest.fail(f"{path}/vid_msckf not built: run scripts/build.sh first")
    sys.path.insert(0, str(path))
    import vid_msckf  # noqa: E402

    return vid_msckf


vm = _import_bindings()


def _example():
    spec = importlib.util.spec_from_file_location("push_samples", REPO / "python" / "examples" / "push_samples.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def seq():
    # The 12 s rendered sequence test_vid_run.py uses (simulated once per pytest process).
    return simulate_cached("vid17_like_short.yaml", 12.0, 1, features_only=False)


@pytest.fixture(scope="module")
def reference(seq, tmp_path_factory):
    out = tmp_path_factory.mktemp("bind") / "vid_run"
    r = vid_run(seq, out, "--config", str(SIM_CONFIG))
    assert r.returncode == 0, r.stderr
    return out


def _state_csv(path):
    """state.csv with exact int64 timestamps."""
    t = np.loadtxt(path, delimiter=",", comments="#", usecols=0, dtype=np.int64)
    x = np.loadtxt(path, delimiter=",", comments="#")[:, 1:]
    return t, x


def test_version_matches_programs(cpp_program):
    line = subprocess.run([str(cpp_program("vid_run")), "--version"], capture_output=True, text=True).stdout
    assert f"{vm.__version__} (git {vm.git_sha})" in line


def test_run_dataset_writes_what_vid_run_writes(seq, reference, tmp_path):
    s = vm.run_dataset(seq, tmp_path / "py", config=SIM_CONFIG)
    assert s == json.loads((tmp_path / "py" / "summary.json").read_text())
    assert s["status"] == "ok" and s["mode"] == "dynamics"
    for name in ("trajectory_tum.txt", "state.csv", "force.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (reference / name).read_bytes(), name
    ref = json.loads((reference / "summary.json").read_text())
    assert s["ate_posyaw_m"] == ref["ate_posyaw_m"]
    assert s["force_rmse_world_mps2"] == ref["force_rmse_world_mps2"]


def test_push_from_numpy_equals_vid_run(seq, reference):
    system = vm.System(dataset=seq, config=SIM_CONFIG)
    assert system.dynamics
    _example().push_dataset(system, seq / "mav0")
    h = system.history()
    t_ref, x_ref = _state_csv(reference / "state.csv")
    np.testing.assert_array_equal(h["t_ns"], t_ref)
    x = np.hstack([h[k] for k in ("p_WI", "q_WI", "v_WI", "b_g", "b_a")])
    # state.csv prints 9 significant digits: equal to that precision
    np.testing.assert_allclose(x, x_ref[:, :16], rtol=1e-8, atol=1e-9)
    # sigma of theta, p, v, b_g, b_a (state.csv prints 6 digits, and the force sigma in the body frame)
    np.testing.assert_allclose(h["sigma"][:, :15], x_ref[:, 19:34], rtol=1e-5, atol=1e-12)  # 6 digits printed
    assert system.status == "ok"
    assert system.estimates == len(t_ref)


def test_latest_is_last_history_row_with_consistent_covariances(seq):
    system = vm.System(dataset=seq, config=SIM_CONFIG)
    assert system.latest() is None  # nothing pushed yet
    _example().push_dataset(system, seq / "mav0")
    e, h = system.latest(), system.history()
    assert e["t_ns"] == h["t_ns"][-1]
    for k in ("p_WI", "q_WI", "v_WI", "F_ext_I", "F_ext_W"):
        np.testing.assert_array_equal(e[k], h[k][-1], err_msg=k)
    np.testing.assert_allclose(e["R_WI"] @ e["F_ext_I"], e["F_ext_W"], atol=1e-12)
    for k in ("cov_F_I", "cov_F_W", "cov_theta", "cov_p"):
        c = e[k]
        np.testing.assert_allclose(c, c.T, atol=1e-15, err_msg=k)
        assert np.linalg.eigvalsh(c).min() > 0.0, k
    # sigma's force block is the diagonal of the force covariance in the state's force frame
    assert e["force_frame"] == system.force_frame == "world"  # config/sim/estimator.yaml
    np.testing.assert_allclose(e["sigma"][15:18] ** 2, np.diag(e["cov_F_W"]), rtol=1e-9)


def test_example_script_runs(seq, tmp_path):
    out = tmp_path / "est.npz"
    r = subprocess.run([str(VENV_BIN / "python"), str(REPO / "python" / "examples" / "push_samples.py"), str(seq),
                        "--config", str(SIM_CONFIG), "--out", str(out)],
                       capture_output=True, text=True, timeout=300,
                       env={"PYTHONPATH": str(build_dir() / "python"), "PATH": "/usr/bin:/bin"})
    assert r.returncode == 0, r.stderr
    assert "status ok" in r.stdout and out.exists()
    assert len(np.load(out)["t_ns"]) > 1000


def test_bad_arguments_raise_one_clear_error(seq, tmp_path):
    with pytest.raises(ValueError, match="dataset folder"):
        vm.System()
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "estimator.yaml").write_text("window_size: [1, 2\n")
    with pytest.raises(vm.ConfigError, match="estimator.yaml"):
        vm.System(dataset=seq, config=bad)
    with pytest.raises(vm.DatasetError):
        vm.System(dataset=tmp_path / "missing")
    system = vm.System(dataset=seq, config=SIM_CONFIG)
    with pytest.raises(ValueError, match="gyro must have 3 elements"):
        system.push_imu(0, [0.0, 0.0], [0.0, 0.0, 9.81])
    with pytest.raises(TypeError, match="2-D uint8"):
        system.push_images(0, np.zeros((480, 640), np.float32))
    with pytest.raises(ValueError, match="features must be"):
        vm.System(dataset=seq, features="lidar")
    with pytest.raises(ValueError, match=r"t_ns \(N,\)"):
        system.push_imu_array(np.zeros(3, np.int64), np.zeros((2, 3)), np.zeros((3, 3)))
