"""vid-import --synthetic-features: the call of ``vid_sim --camera-along`` (the converted mocap
poses as a TUM file of T_WI), tested with a stand-in vid_sim that records its arguments and
writes a feat0 stream at the poses' times; vid_info reads the result."""
from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np

from test_import_synth import MASS, csv_map, flight, run_import, write_csv_log
from vid_eval.tools.loaders import load_tum

FAKE = textwrap.dedent('''\
    import pathlib, sys
    args = sys.argv[1:]
    opt = {args[i]: args[i + 1] for i in range(len(args) - 1) if args[i].startswith("--")}
    out = pathlib.Path(opt["--out"]) / "mav0"
    assert "--features-only" in args, args
    (out.parent / "fake_args.txt").write_text(" ".join(args))
    (out.parent / "received_tum.txt").write_text(pathlib.Path(opt["--camera-along"]).read_text())
    if "fail" in pathlib.Path(opt["--scenario"]).read_text():
        print("vid_sim: error: scene says fail", file=sys.stderr)
        sys.exit(3)
    (out / "feat0").mkdir(parents=True)
    rows = ["#timestamp [ns],cam_id,feature_id,u [px],v [px]"]
    for line in pathlib.Path(opt["--camera-along"]).read_text().splitlines()[1::20]:
        s, ns = line.split()[0].split(".")
        rows.append(f"{int(s) * 10**9 + int(ns)},0,1,320.5,240.5")
    (out / "feat0" / "data.csv").write_text("\\n".join(rows) + "\\n")
    for cam in ("cam0", "cam1"):
        (out / cam).mkdir()
        (out / cam / "sensor.yaml").write_text(
            "sensor_type: camera\\nT_BS: {cols: 4, rows: 4, data: [0, 0, 1, 0.1, -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0, 1]}\\n"
            "rate_hz: 30\\nresolution: [640, 480]\\ncamera_model: pinhole\\nintrinsics: [380, 380, 320, 240]\\n"
            "distortion_model: radial-tangential\\ndistortion_coefficients: [0, 0, 0, 0]\\n")
    (out / "landmarks.csv").write_text("#id,x,y,z\\n1,5,0,1\\n")
''')


def _fake(tmp_path):
    path = tmp_path / "vid_sim"
    path.write_text(f"#!{sys.executable}\n" + FAKE)
    path.chmod(0o755)
    return path


def test_features_come_from_vid_sim_along_the_mocap_poses(tmp_path, cpp_program):
    f = flight(seconds=5.0)
    write_csv_log(tmp_path / "log", f, "frd", "ned")
    scene = tmp_path / "room.yaml"
    scene.write_text("name: room\n")
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS,
                   "--imu-frame", "frd", "--world-frame", "ned", "--synthetic-features", "--vid-sim", _fake(tmp_path),
                   "--scene", scene)
    assert r.returncode == 0, r.stderr
    assert "wrote feat0, cam0, cam1, landmarks.csv" in r.stdout
    args = (tmp_path / "out" / "fake_args.txt").read_text().split()
    assert args[args.index("--scenario") + 1] == str(scene)
    assert args[args.index("--out") + 1] == str(tmp_path / "out")
    tum = load_tum(tmp_path / "out" / "received_tum.txt")   # the poses vid_sim was given: T_WI in project frames
    np.testing.assert_array_equal(tum.t_ns, f.t_ns)
    np.testing.assert_allclose(tum.p, f.p, atol=1e-12)
    q = tum.q * np.sign(tum.q[:, :1])
    np.testing.assert_allclose(q, f.q_wxyz(), atol=1e-12)
    for kept in ("imu0", "thrust0", "state_groundtruth_estimate0", "vehicle.yaml"):
        assert (tmp_path / "out" / "mav0" / kept).exists()
    info = subprocess.run([str(cpp_program("vid_info")), str(tmp_path / "out")], capture_output=True, text=True)
    assert info.returncode == 0, info.stderr
    assert "feat0" in info.stdout


def test_vid_sim_failure_is_one_line(tmp_path):
    write_csv_log(tmp_path / "log", flight(seconds=2.0))
    scene = tmp_path / "room.yaml"
    scene.write_text("fail\n")
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS,
                   "--synthetic-features", "--vid-sim", _fake(tmp_path), "--scene", scene)
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1
    assert "--camera-along failed (exit 3): vid_sim: error: scene says fail" in r.stderr


def test_vid_sim_is_found_in_vid_build_dir(tmp_path, monkeypatch):
    (tmp_path / "build" / "bin").mkdir(parents=True)
    fake = _fake(tmp_path)
    fake.rename(tmp_path / "build" / "bin" / "vid_sim")
    write_csv_log(tmp_path / "log", flight(seconds=2.0))
    scene = tmp_path / "room.yaml"
    scene.write_text("name: room\n")
    monkeypatch.setenv("VID_BUILD_DIR", str(tmp_path / "build"))
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS,
                   "--synthetic-features", "--scene", scene)
    assert r.returncode == 0, r.stderr
    assert str(tmp_path / "build" / "bin" / "vid_sim") in r.stdout


def test_missing_vid_sim_is_a_usage_error(tmp_path):
    write_csv_log(tmp_path / "log", flight(seconds=2.0))
    r = run_import(tmp_path / "log", tmp_path / "out", "--map", csv_map(tmp_path / "m.yaml"), "--mass", MASS,
                   "--synthetic-features", "--vid-sim", tmp_path / "nope")
    assert r.returncode == 2 and "--vid-sim" in r.stderr and len(r.stderr.strip().splitlines()) == 1
