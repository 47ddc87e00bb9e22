#!/usr/bin/env python3
"""Regenerate the committed seed corpora fuzz/corpus/<target>/ (issue #26).

Seeds come from the test data (tests/data/euroc_sample), the shipped configs (config/) and,
with --sim SEQ, a short simulated sequence (vid_sim --features-only --duration 0.3), so every
stream of the dataset format has a valid example. CSV files are cut to a few rows: the fuzzer
needs the shapes, not the data, and the committed corpora stay a few KB each.

Usage: .venv/bin/python fuzz/make_seeds.py [--sim SEQ]   (needs lcm-gen and the eval[test] venv)
"""
import argparse
import pathlib
import shutil
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "fuzz" / "corpus"
EUROC = ROOT / "tests" / "data" / "euroc_sample" / "mav0"


def head(path: pathlib.Path, rows: int = 4) -> str:
    lines = path.read_text().splitlines(keepends=True)
    return "".join(lines[: rows + 1])


def put(target: str, name: str, data) -> None:
    d = OUT / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(data.encode() if isinstance(data, str) else data)


def csv_seeds() -> None:
    put("csv", "imu", "\x00" + head(EUROC / "imu0" / "data.csv"))
    put("csv", "gt", "\x00" + head(EUROC / "state_groundtruth_estimate0" / "data.csv", 2))
    put("csv", "header", "\x02#t,x,y\n1,2.5,a\n2,-1e3,b\n")
    put("csv", "tum", "\x05# t x y z\n1 0 0 0\n2\t1.5  nan inf\n")


def dataset_seeds(sim: pathlib.Path | None) -> None:
    cam = "#timestamp [ns],filename\n1000000,1.png\n2000000,2.png\n3000000,3.png\n"
    euroc = "@imu0\n" + head(EUROC / "imu0" / "data.csv", 6) + "@cam0\n" + cam
    euroc += "@cam0.yaml\n" + (EUROC / "cam0" / "sensor.yaml").read_text()
    euroc += "@gt\n" + head(EUROC / "state_groundtruth_estimate0" / "data.csv", 2)
    put("dataset", "euroc", euroc)
    put("dataset", "imu_only", "@imu0\n" + head(EUROC / "imu0" / "data.csv", 3) + "@opts\ndw\n")
    if sim is None:
        return
    mav0 = sim / "mav0"
    text = ""
    for name, rel in [("imu0", "imu0/data.csv"), ("rotor0", "rotor0/data.csv"), ("feat0", "feat0/data.csv"),
                      ("force0", "force0/data.csv"), ("mass0", "mass0/data.csv"),
                      ("gt", "state_groundtruth_estimate0/data.csv")]:
        text += f"@{name}\n" + head(mav0 / rel, 3)
    for name, rel in [("cam0.yaml", "cam0/sensor.yaml"), ("cam1.yaml", "cam1/sensor.yaml"),
                      ("imu0.yaml", "imu0/sensor.yaml"), ("rotor0.yaml", "rotor0/sensor.yaml"),
                      ("vehicle.yaml", "vehicle.yaml")]:
        text += f"@{name}\n" + (mav0 / rel).read_text()
    put("dataset", "sim", text)
    put("dataset", "sim_thrust", text + "@thrust0\n#timestamp [ns],thrust [N]\n1,30.1\n2,30.2\n@opts\nsl\n")


def yaml_seeds(sim: pathlib.Path | None) -> None:
    # byte 0 picks the loader: '0' camera, '1' imu, '2' rotor, '3' vehicle, '4' Kalibr imu,
    # '5' Kalibr imucam, '6' estimator, '7' reader options / generic getters
    put("yaml", "camera", "0" + (EUROC / "cam0" / "sensor.yaml").read_text())
    put("yaml", "imu", "1" + (EUROC / "imu0" / "sensor.yaml").read_text())
    put("yaml", "rotor", "2" + (ROOT / "config" / "vid_dataset" / "rotor_sensor.yaml").read_text())
    put("yaml", "vehicle", "3" + (ROOT / "config" / "vid_dataset" / "vehicle.yaml").read_text())
    put("yaml", "kalibr_imu", "4" + (ROOT / "config" / "vid_dataset" / "imu.yaml").read_text())
    put("yaml", "kalibr_imucam", "5" + (ROOT / "config" / "vid_dataset" / "camchain-imucam.yaml").read_text())
    put("yaml", "estimator", "6" + (ROOT / "config" / "vid_dataset" / "estimator.yaml").read_text())
    put("yaml", "options", "7drop_bad_timestamps: true\nread_images: false\nm: {rows: 4, cols: 4, "
        "data: [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}\nl: [1, 2.5, -3]\n")
    if sim is not None:
        put("yaml", "camera_sim", "0" + (sim / "mav0" / "cam1" / "sensor.yaml").read_text())


def lcm_seeds() -> None:
    import lcm  # noqa: F401 (EventLog)

    with tempfile.TemporaryDirectory() as tmp:
        types = sorted(str(p) for p in (ROOT / "io" / "lcm").glob("*.lcm"))
        subprocess.run(["lcm-gen", "--python", "--ppath", tmp, *types], check=True)
        sys.path.insert(0, tmp)
        from vid import force_t, image_t, imu_t, rotor_speeds_t, state_t, status_t, thrust_t

        imu = imu_t(); imu.timestamp = 10; imu.gyro = [0.1, 0.2, 0.3]; imu.accel = [0.0, 0.0, 9.81]
        img = image_t(); img.timestamp = 20; img.width = 4; img.height = 2; img.encoding = "mono8"
        img.size = 8; img.data = bytes(range(8))
        rot = rotor_speeds_t(); rot.timestamp = 30; rot.count = 4; rot.speeds = [5000.0] * 4; rot.unit = "rpm"
        thr = thrust_t(); thr.timestamp = 40; thr.thrust = 30.0
        st = status_t(); st.timestamp = 50; st.status_text = "tracking"; st.num_counters = 2
        st.counter_names = ["a", "b"]; st.counter_values = [1, 2]
        msgs = [imu, img, rot, thr, state_t(), st, force_t()]
        for i, m in enumerate(msgs):
            put("lcm", f"{type(m).__name__}", bytes([ord("0") + i]) + m.encode())
        log = pathlib.Path(tmp) / "log.lcm"
        ev = lcm.EventLog(str(log), "w", overwrite=True)
        ev.write_event(1, "IMU", imu.encode())
        ev.write_event(2, "CAM0", img.encode())
        ev.close()
        put("lcm", "log", b"7" + log.read_bytes())
    put("lcm", "url_in", "8file:///tmp/x.lcm?speed=1&mode=r")
    put("lcm", "url_out", "9udpm://239.255.76.67:7667?ttl=1&recv_buf_size=1000&transmit_only=true")


def py_loader_seeds() -> None:
    sys.path.insert(0, str(ROOT / "eval"))
    from vid_eval.core import formats

    def table(names, row):
        return "#" + ",".join(names) + "\n" + "".join(",".join(str(v) for v in r) + "\n" for r in row)

    # byte 0 picks the loader (fuzz/py/loaders_fuzz.py)
    put("py_loaders", "tum", "0# t x y z qx qy qz qw\n1.0 0 0 0 0 0 0 1\n1.5 1 2 3 0 0 0.7071 0.7071\n")
    put("py_loaders", "euroc", "1" + head(EUROC / "state_groundtruth_estimate0" / "data.csv", 2))
    state = [n for n, _ in formats.STATE_COLUMNS]
    row = [1000] + [0.0] * (len(state) - 1)
    row[state.index("q_w")] = 1.0
    put("py_loaders", "state", "2" + table(state, [row, [2000] + row[1:]]))
    put("py_loaders", "detect_txt", "3 1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n")
    put("py_loaders", "detect_csv", "4" + head(EUROC / "state_groundtruth_estimate0" / "data.csv", 2))
    force = [n for n, _ in formats.FORCE_COLUMNS]
    put("py_loaders", "force", "5" + table(force, [[1000] + [0.5] * (len(force) - 1)]))
    put("py_loaders", "force0", "6#timestamp [ns],f_x [N],f_y [N],f_z [N]\n1,0,0,-30\n2,0.1,0,-30\n")
    put("py_loaders", "mass", "7#timestamp [ns],mass [kg]\n1,3.1\n2,3.2\n")
    put("py_loaders", "phase", "8#timestamp [ns],phase\n1,0\n2,1\n")
    put("py_loaders", "vehicle", "9" + (ROOT / "config" / "vid_dataset" / "vehicle.yaml").read_text())


def py_bag_seeds() -> None:
    import numpy as np

    sys.path.insert(0, str(ROOT / "eval"))
    from vid_eval.bag2asl.synthetic import BagWriter

    t0, ms = 1_600_000_000_000_000_000, 1_000_000
    with tempfile.TemporaryDirectory() as tmp:
        for compression in ("none", "bz2", "lz4"):
            path = pathlib.Path(tmp) / f"{compression}.bag"
            w = BagWriter(path, compression=compression)
            w.w.chunk_threshold = 300  # several chunks
            for k in range(4):
                t = t0 + k * ms
                w.write("/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (0, 0, k), (0, 0, 9.81)))
                w.write("/motor", "uavmotor/msg/motordata", t, w.motordata(t, t, [k, 1, 2, 3]))
            if compression == "none":
                img = np.arange(8 * 4, dtype=np.uint8).reshape(4, 8)
                w.write("/cam", "sensor_msgs/msg/Image", t0, w.image(t0, "mono8", img))
            w.close()
            put("py_bag", compression, path.read_bytes())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sim", type=pathlib.Path, help="a vid_sim --features-only sequence folder")
    args = ap.parse_args()
    for t in ("csv", "dataset", "yaml", "lcm", "py_loaders", "py_bag"):
        shutil.rmtree(OUT / t, ignore_errors=True)
    csv_seeds()
    dataset_seeds(args.sim)
    yaml_seeds(args.sim)
    lcm_seeds()
    py_loader_seeds()
    py_bag_seeds()
    return 0


if __name__ == "__main__":
    sys.exit(main())
