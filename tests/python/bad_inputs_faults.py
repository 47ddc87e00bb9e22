"""Bad-input table, part 3 (issue #52, "silent faults"): inputs that used to run with status ok -
an IMU rate that disagrees with the imu0 stamps, negative thrust, an IMU extrinsic that would be
ignored, a garbage block inside an LCM log, camera data that does not travel over LCM (feat0/) or never
comes. Cases as in bad_inputs_data.py; no tests here."""
from __future__ import annotations

from bad_inputs_data import Case, dataset, rows_of, vid_run, write_rows
from bad_inputs_io import cli_case, log_case, vid_live
from test_vid_run_helpers import replace_file


# --- IMU rate ----------------------------------------------------------------------------------
def _imu_at_100hz(ds) -> None:
    """Keep every 4th row of the 400 Hz imu0 stream: a 100 Hz IMU."""
    csv = ds / "mav0" / "imu0" / "data.csv"
    head, rows = rows_of(csv)
    write_rows(csv, head, rows[::4])


def imu_rate_case(what: str, sensor_yaml: bool) -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        _imu_at_100hz(ds)
        yaml = ds / "mav0" / "imu0" / "sensor.yaml"
        if not sensor_yaml:
            yaml.unlink()
        return vid_run(ds, d), str(yaml)
    return Case("rates", what, make)


def live_rate_case() -> Case:
    """vid_live: --sensors says 100 Hz, the log's IMU messages come at 400 Hz."""
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        yaml = ds / "mav0" / "imu0" / "sensor.yaml"
        text = "\n".join("rate_hz: 100" if line.startswith("rate_hz:") else line
                         for line in yaml.read_text().splitlines())
        replace_file(yaml, (text + "\n").encode())
        argv = vid_live(ctx, f"file://{ctx.log}?speed=0")
        argv[argv.index(str(ctx.feat))] = str(ds)
        return argv, str(yaml)
    return Case("rates", "vid_live: imu0/sensor.yaml rate_hz 100, IMU messages at 400 Hz", make)


def rate_cases() -> list:
    return [imu_rate_case("imu0 at 100 Hz, no imu0/sensor.yaml (config/sim imu_rate_hz 400)", False),
            imu_rate_case("imu0 at 100 Hz, imu0/sensor.yaml rate_hz 400", True),
            live_rate_case()]


# --- Thrust direction -----------------------------------------------------------------------------
def _rotor_to_thrust(ds, sign: float, keep_rotor: bool = False) -> None:
    """Replace rotor0 by (or with keep_rotor, add beside it) thrust0: the collective thrust of
    the rotor speeds, times sign."""
    mav0 = ds / "mav0"
    k = [2.689e-07, 2.819e-07, 2.7263e-07, 2.7741e-07]  # the vid17_like vehicle.yaml
    _, rows = rows_of(mav0 / "rotor0" / "data.csv")
    thrust = []
    for r in rows:
        f = r.split(",")
        thrust.append(f"{f[0]},{sign * sum(ki * float(n) ** 2 for ki, n in zip(k, f[1:])):.6f}")
    if not keep_rotor:
        for f in (mav0 / "rotor0").iterdir():
            f.unlink()
        (mav0 / "rotor0").rmdir()
    (mav0 / "thrust0").mkdir()
    (mav0 / "thrust0" / "data.csv").write_text("#timestamp [ns],thrust [N]\n" + "\n".join(thrust) + "\n")


def negative_thrust_case() -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        _rotor_to_thrust(ds, -1.0)  # what a z-down IMU frame gives
        return vid_run(ds, d), str(ds / "mav0" / "thrust0" / "data.csv")
    return Case("thrust", "thrust0/data.csv: negative collective thrust (z-down frame)", make)


def negative_coefficient_case() -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        yaml = ds / "mav0" / "vehicle.yaml"
        text = "\n".join("rotor_thrust_coefficients: [-2.7e-07, -2.7e-07, -2.7e-07, -2.7e-07]"
                         if line.startswith("rotor_thrust_coefficients") else line
                         for line in yaml.read_text().splitlines())
        replace_file(yaml, (text + "\n").encode())
        return vid_run(ds, d), str(yaml)
    return Case("thrust", "vehicle.yaml: negative rotor_thrust_coefficients (rotor0 thrust < 0)", make)


def _drop_coefficients(ds):
    yaml = ds / "mav0" / "vehicle.yaml"
    text = [line for line in yaml.read_text().splitlines() if not line.startswith("rotor_thrust_coefficients")]
    replace_file(yaml, ("\n".join(text) + "\n").encode())
    return yaml


def vehicle_case(what: str, thrust0: bool, vehicle: str) -> Case:
    """Dynamics mode: what vehicle.yaml must hold (mass_kg always, rotor_thrust_coefficients for rotor0)."""
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        if thrust0:
            _rotor_to_thrust(ds, 1.0)
        yaml = ds / "mav0" / "vehicle.yaml"
        if vehicle == "none":
            yaml.unlink()
            return vid_run(ds, d, "--mode", "dynamics"), "mass_kg"
        _drop_coefficients(ds)
        return vid_run(ds, d, "--mode", "dynamics"), "rotor_thrust_coefficients"
    return Case("thrust", what, make)


def flip_accelerometer(ds) -> None:
    """imu0/data.csv with the accelerometer's sign flipped (-g at rest): the thrust along +z and
    the accelerometer then disagree by 2 g, which the estimator takes for an external force."""
    csv = ds / "mav0" / "imu0" / "data.csv"
    head, rows = rows_of(csv)
    flip = lambda v: v[1:] if v.startswith("-") else "-" + v  # noqa: E731 (exact: no float round trip)
    write_rows(csv, head, [",".join(f[:4] + [flip(v) for v in f[4:7]]) for f in (r.split(",") for r in rows)])


def flipped_accelerometer_case() -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        flip_accelerometer(ds)
        return vid_run(ds, d), "external_force_near_2g"
    return Case("thrust", "imu0/data.csv: accelerometer sign flipped (dynamics mode: 2 g of external force)", make,
                exit=0)


def thrust_cases() -> list:
    return [negative_thrust_case(), negative_coefficient_case(), flipped_accelerometer_case(),
            vehicle_case("--mode dynamics, thrust0, no vehicle.yaml", True, "none"),
            vehicle_case("--mode dynamics, rotor0, vehicle.yaml without rotor_thrust_coefficients", False, "no k")]


# --- IMU extrinsic ---------------------------------------------------------------------------------
def imu_extrinsic_case() -> Case:
    """imu0/sensor.yaml T_BS with a 5 cm offset: refused (the estimator would ignore it)."""
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        yaml = ds / "mav0" / "imu0" / "sensor.yaml"
        lines, in_tbs = [], False
        for line in yaml.read_text().splitlines():
            in_tbs = line.startswith("T_BS") or (in_tbs and line.startswith(" "))
            if not line.startswith("T_BS") and not in_tbs:
                lines.append(line)
        lines.append("T_BS: {cols: 4, rows: 4, data: [1, 0, 0, 0.05, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}")
        replace_file(yaml, ("\n".join(lines) + "\n").encode())
        return vid_run(ds, d), str(yaml)
    return Case("YAML", "imu0/sensor.yaml: T_BS not the identity (5 cm offset)", make)


# --- One line for every program taking --lcm-url ------------------------------------------------
def replay_url_cases() -> list:
    return [cli_case("vid_replay", ["--dataset", "{feat}", "--lcm-url", "nosuchprovider://x", "--fast", "--quiet"],
                     "--lcm-url nosuchprovider://x", kind="LCM URL"),
            cli_case("vid_replay", ["--dataset", "{feat}", "--lcm-url", "udpm://10.0.0.1:7667", "--fast", "--quiet"],
                     "--lcm-url udpm://10.0.0.1:7667", kind="LCM URL")]


def _overwrite_middle(data: bytes, n: int = 1000) -> bytes:
    """n zero bytes written over the middle of a log (a damaged block, not inserted bytes), from
    the header of the first event past the middle after which n bytes hold only IMU / rotor
    events: whole events are lost (zeros inside an image payload would pass unseen - an LCM log
    has no checksum)."""
    at, events = 0, []
    while at + 28 <= len(data):
        ch = int.from_bytes(data[at + 20:at + 24], "big")
        events.append((at, data[at + 28:at + 28 + ch]))
        at += 28 + ch + int.from_bytes(data[at + 24:at + 28], "big")
    for k, (start, _) in enumerate(events):
        covered = [c for a, c in events[k:] if a <= start + n]
        if start >= len(data) // 2 and all(c in (b"IMU", b"ROTORS") for c in covered):
            return data[:start] + b"\0" * n + data[start + n:]
    raise ValueError("no stretch of small events in the log")


# --- Camera data that does not travel (vid_replay) or never comes (vid_live) --------------------
def replay_feat_cases() -> list:
    base = ["--dataset", "{feat}", "--lcm-url", "memq://", "--fast", "--quiet"]
    return [cli_case("vid_replay", base, "{feat}", exit=1, kind="camera"),
            cli_case("vid_replay", [*base, "--no-camera"], "--no-camera", exit=0, kind="camera")]


def no_camera_case() -> Case:
    """vid_live on 3 s of IMU and rotors without one camera frame (the feature-level folder
    replayed with --no-camera): a fault, exit 5."""
    def make(ctx, d):
        return vid_live(ctx, f"file://{ctx.log}?speed=0"), "CAM0"
    return Case("camera", "vid_live: log with IMU and rotors, no camera frame", make, exit=5)


def all_cases() -> list:
    return (rate_cases() + thrust_cases() + [imu_extrinsic_case()] + replay_url_cases()
            + [log_case("1000 bytes overwritten in the middle", _overwrite_middle, exit=0),
               log_case("1000 bytes overwritten in the middle", _overwrite_middle, "--strict")]
            + replay_feat_cases() + [no_camera_case()])
