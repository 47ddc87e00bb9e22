"""Bad-input table, part 2 (issues #26, #28): LCM logs and URLs (vid_live), bags and topic maps
(vid-bag2asl), dynamics without rotors, and command-line flags and paths of every program.
Cases as in bad_inputs_data.py; no tests here."""
from __future__ import annotations

import os
import pathlib

from bad_inputs_data import SIM_CONFIG, Case, dataset, vid_run
from test_bag2asl_errors import small_bag
from test_vid_run_helpers import REPO, program

VENV_BIN = pathlib.Path(os.environ.get("VID_VENV_BIN", REPO / ".venv" / "bin"))


# --- LCM logs and URLs (vid_live) --------------------------------------------------------------
def vid_live(ctx, url, *extra, sensors=None) -> list:
    return [str(program("vid_live")), "--lcm-url", url, "--sensors", str(sensors or ctx.feat), "--config", SIM_CONFIG,
            "--quiet", *extra]


def log_case(what: str, content, *extra, exit=1) -> Case:
    """vid_live on the rendered sequence's log (camera included) changed by content(bytes)."""
    def make(ctx, d):
        log = d / "in.log"
        data = content(ctx.img_log.read_bytes())
        if data is not None:
            log.write_bytes(data)
        return vid_live(ctx, f"file://{log}?speed=0", *extra, sensors=ctx.img), str(log)
    label = what + (f" ({' '.join(extra)})" if extra else "")
    return Case("LCM log", label, make, exit=exit)


def url_case(url: str, what: str, flag="--lcm-url", named=None) -> Case:
    def make(ctx, d):
        u = url.format(log=ctx.log, d=d)
        if flag == "--lcm-url":
            return vid_live(ctx, u), named or flag
        return vid_live(ctx, f"file://{ctx.log}?speed=0", flag, u), named or flag
    return Case("LCM URL", f"{flag} {url.replace('{log}', 'LOG').replace('{d}', 'DIR')}: {what}", make, exit=2)


def lcm_cases() -> list:
    cases = [
        log_case("missing log file", lambda b: None),
        log_case("empty log", lambda b: b""),
        log_case("random bytes", lambda b: os.urandom(4096)),
        log_case("garbage before the first event", lambda b: b"garbage!" + b),
        # read past (LCM's reader would stop there), one warning, counted in summary.json input.lcm_log
        log_case("garbage between events", _garbage_between, exit=0),
        log_case("garbage between events", _garbage_between, "--strict"),
        log_case("garbage after the last event", lambda b: b + b"\0" * 64),
        log_case("cut mid-event", lambda b: b[: _event_end(b, 200) + 40]),
        log_case("cut inside an event header", lambda b: b[: _event_end(b, 200) + 10]),
        log_case("text file", lambda b: b"timestamp,x\n1,2\n" * 20),
    ]
    cases += [
        url_case("file://{log}?speed=abc", "speed not a number"),
        url_case("file://{log}?speed=-1", "negative speed"),
        url_case("file://{log}?mode=x", "unknown mode"),
        url_case("file://{log}?mode=w", "input log opened for writing"),
        url_case("file://{log}?sped=0", "unknown option"),
        url_case("file://{log}?start_timestamp=abc", "start_timestamp not a number"),
        url_case("file://", "no log file"),
        url_case("udpm://192.168.1.5:7667", "unicast address"),
        url_case("udpm://239.255.76.67:99999", "port out of range"),
        url_case("udpm://239.255.76.67:7667?ttl=300", "ttl out of range"),
        url_case("udpm://239.255.76.67:7667?transmit_only=maybe", "bad boolean"),
        url_case("udpm://not.an.address:7667", "not an IPv4 address"),
        url_case("nosuchprovider://x", "unknown provider"),
        url_case("just-a-path.log", "not a URL"),
        url_case("file://{d}/out.log?mode=q", "bad mode", flag="--publish-url"),
        url_case("udpm://10.0.0.1:7667", "unicast address", flag="--publish-url"),
    ]
    return cases


def _garbage_between(b: bytes) -> bytes:
    return b[:_event_end(b, 3)] + b"\0" * 16 + b[_event_end(b, 3):]


def _event_end(data: bytes, n: int) -> int:
    """Byte offset after the first n events of an LCM log."""
    at = 0
    for _ in range(n):
        ch = int.from_bytes(data[at + 20:at + 24], "big")
        ln = int.from_bytes(data[at + 24:at + 28], "big")
        at += 28 + ch + ln
    return at


# --- Bags and topic maps (vid-bag2asl) ---------------------------------------------------------
def bag2asl(*args) -> list:
    return [str(VENV_BIN / "vid-bag2asl"), "--no-progress", "--mass", "1", *map(str, args)]  # a case's --mass wins


def bag_case(what: str, make_bag, *extra, named=None, exit=1) -> Case:
    def make(ctx, d):
        bag = make_bag(ctx, d)
        return bag2asl(bag, d / "out", *extra), named or str(bag)
    return Case("bags", what, make, exit=exit)


def _bytes_bag(data_of):
    def make(ctx, d):
        bag = d / "x.bag"
        bag.write_bytes(data_of(ctx.bag.read_bytes()))
        return bag
    return make


def _no_rotor_bag(ctx, d):
    return small_bag(d / "b.bag", n=20, rotors=False)


def _imu_only_bag(ctx, d):
    from vid_eval.bag2asl.synthetic import BagWriter
    w = BagWriter(d / "b.bag")
    t = 1_650_000_000_000_000_000
    w.write("/djiros/imu", "sensor_msgs/msg/Imu", t, w.imu(t, (0, 0, 0), (0, 0, 9.8)))
    w.close()
    return d / "b.bag"


def map_case(what: str, text: str) -> Case:
    def make(ctx, d):
        tmap = d / "map.yaml"
        tmap.write_text(text)
        return bag2asl(ctx.bag, d / "out", "--topics", tmap), str(tmap)
    return Case("topic maps", what, make)


def bag_cases() -> list:
    ok = lambda ctx, d: ctx.bag  # noqa: E731
    return [
        bag_case("missing bag file", lambda ctx, d: d / "none.bag"),
        bag_case("empty file", _bytes_bag(lambda b: b"")),
        bag_case("text file", _bytes_bag(lambda b: b"hello, not a bag\n" * 10)),
        bag_case("truncated at 2/3", _bytes_bag(lambda b: b[: len(b) * 2 // 3])),
        bag_case("truncated after the header", _bytes_bag(lambda b: b[:4200])),
        bag_case("no rotor-speed topic", _no_rotor_bag, named="/m100withm3508/target_rpm"),
        bag_case("required camera topic missing", _imu_only_bag, named="cam0 needs /camera/infra1/image_rect_raw"),
        bag_case("--jobs 0", ok, "--jobs", "0", named="--jobs", exit=2),
        bag_case("--jobs -1", ok, "--jobs", "-1", named="--jobs", exit=2),
        bag_case("--png-level 12", ok, "--png-level", "12", named="--png-level", exit=2),
        bag_case("--start -1", ok, "--start", "-1", named="--start", exit=2),
        bag_case("--start past the end", ok, "--start", "100", named="--start", exit=2),
        bag_case("--end before --start", ok, "--start", "0.5", "--end", "0.2", named="--end", exit=2),
        bag_case("--end past the end", ok, "--end", "100", named="--end", exit=2),
        bag_case("--mass -1", ok, "--mass", "-1", named="--mass", exit=2),
        bag_case("--preset missing folder", ok, "--preset", "/nonexistent/preset", named="/nonexistent/preset"),
        bag_case("--topics missing file", ok, "--topics", "/nonexistent/map.yaml", named="/nonexistent/map.yaml"),
        bag_case("unknown flag", ok, "--fast", named="--fast", exit=2),
        map_case("invalid YAML", "streams:\n  cam0: {kind: image, topics: [/a]\n"),
        map_case("unknown kind", "streams:\n  cam0: {kind: camera, topics: [/a]}\n"),
        map_case("unknown stream key", "streams:\n  cam0: {kind: image, topics: [/a], colour: red}\n"),
        map_case("no topics", "streams:\n  cam0: {kind: image}\n"),
        map_case("empty file", ""),
        map_case("rotor without field", "streams:\n  rotor0: {kind: rotor, topics: [/r]}\n"),
        map_case("required: maybe", "streams:\n  cam0: {kind: image, topics: [/a], required: maybe}\n"),
    ]


def dynamics_without_rotors() -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        for f in (ds / "mav0" / "rotor0").iterdir():
            f.unlink()
        (ds / "mav0" / "rotor0").rmdir()
        return vid_run(ds, d, "--mode", "dynamics"), "--mode imu"
    return Case("CLI", "vid_run --mode dynamics on a dataset without rotor0/thrust0", make)


# --- Command-line flags and paths of every program ---------------------------------------------
def cli_case(prog: str, args, named: str, exit=2, kind="CLI") -> Case:
    def make(ctx, d):
        argv = [a.format(feat=ctx.feat, img=ctx.img, d=d, log=ctx.log, sim=SIM_CONFIG, repo=REPO) for a in args]
        exe = str(VENV_BIN / prog) if prog.startswith("vid-") else str(program(prog))
        return [exe, *argv], named.format(feat=ctx.feat, d=d)
    shown = " ".join(args).replace("{feat}", "SEQ").replace("{img}", "SEQ").replace("{d}", "DIR")
    shown = shown.replace("{log}", "LOG").replace("{sim}", "config/sim").replace("{repo}", "REPO")
    return Case(kind, f"{prog} {shown}", make, exit=exit)


RUN = ["--dataset", "{feat}", "--out", "{d}/out", "--quiet"]
SCEN = "{repo}/config/sim/hover.yaml"


def cli_cases() -> list:
    c = cli_case
    return [
        c("vid_run", ["--out", "{d}/out"], "--dataset"),
        c("vid_run", ["--dataset", "{feat}"], "--out"),
        c("vid_run", [*RUN, "--bogus"], "--bogus"),
        c("vid_run", [*RUN, "--mode", "fast"], "--mode"),
        c("vid_run", [*RUN, "--features", "lines"], "--features"),
        c("vid_run", [*RUN, "--init", "magic"], "--init"),
        c("vid_run", [*RUN, "--start", "abc"], "--start"),
        c("vid_run", [*RUN, "--decode-threads", "99"], "--decode-threads"),
        c("vid_run", [*RUN, "--max-gap-periods", "-1"], "--max-gap-periods"),
        c("vid_run", [*RUN, "--start"], "--start"),
        c("vid_run", ["--dataset", "{d}/missing", "--out", "{d}/out", "--quiet"], "{d}/missing", exit=1,
          kind="paths"),
        c("vid_run", ["--dataset", "{d}", "--out", "{d}/out", "--quiet"], "{d}", exit=1, kind="paths"),
        c("vid_run", ["--dataset", "{feat}/mav0/imu0/data.csv", "--out", "{d}/out", "--quiet"], "data.csv", exit=1,
          kind="paths"),
        c("vid_run", ["--dataset", "{feat}", "--out", "/proc/version/out", "--quiet"], "/proc/version", exit=1,
          kind="paths"),
        c("vid_run", [*RUN, "--config", "{d}/no_preset"], "{d}/no_preset", exit=1, kind="paths"),
        c("vid_run", [*RUN, "--features", "images"], "cam0", exit=1),
        c("vid_track", ["--out", "{d}/t.csv"], "--dataset"),
        c("vid_track", ["--dataset", "{img}", "--out", "{d}/t.csv", "--draw-every", "0"], "--draw-every"),
        c("vid_track", ["--dataset", "{img}", "--out", "{d}/t.csv", "--nope"], "--nope"),
        c("vid_track", ["--dataset", "{feat}", "--out", "{d}/t.csv", "--quiet"], "cam0", exit=1),
        c("vid_track", ["--dataset", "{img}", "--out", "{d}/no/dir/t.csv", "--quiet"], "{d}/no/dir/t.csv", exit=1,
          kind="paths"),
        c("vid_track", ["--dataset", "{img}", "--out", "{d}/t.csv", "--config", "{d}/none.yaml", "--quiet"],
          "{d}/none.yaml", exit=1, kind="paths"),
        c("vid_replay", ["--dataset", "{feat}"], "--lcm-url"),
        c("vid_replay", ["--dataset", "{feat}", "--lcm-url", "memq://", "--rate", "-2"], "--rate"),
        c("vid_replay", ["--dataset", "{feat}", "--lcm-url", "memq://", "--rate", "2", "--fast"], "--fast"),
        c("vid_replay", ["--dataset", "{feat}", "--lcm-url", "memq://", "--drop-images", "1.5"], "--drop-images"),
        c("vid_replay", ["--dataset", "{feat}", "--lcm-url", "memq://", "--camera-stall", "-1", "2"],
          "--camera-stall"),
        c("vid_replay", ["--dataset", "{feat}", "--lcm-url", "memq://", "--camera-stall", "1"], "--camera-stall"),
        c("vid_replay", ["--dataset", "{d}/missing", "--lcm-url", "memq://", "--fast", "--quiet"], "{d}/missing",
          exit=1, kind="paths"),
        c("vid_live", ["--sensors", "{feat}"], "--lcm-url"),
        c("vid_live", ["--lcm-url", "memq://", "--overload", "maybe"], "--overload"),
        c("vid_live", ["--lcm-url", "memq://", "--max-queued-frames", "0"], "--max-queued-frames"),
        c("vid_live", ["--lcm-url", "memq://", "--reorder-window-ms", "-5"], "--reorder-window-ms"),
        c("vid_live", ["--lcm-url", "memq://", "--init", "groundtruth"], "--init"),
        c("vid_live", ["--lcm-url", "file://{log}?speed=0", "--sensors", "{d}/none", "--quiet"], "{d}/none", exit=1,
          kind="paths"),
        c("vid_info", [], "DATASET"),
        c("vid_info", ["{feat}", "--yaml"], "--yaml"),
        c("vid_info", ["{d}/missing"], "{d}/missing", exit=1, kind="paths"),
        c("vid_sim", ["--out", "{d}/s"], "--scenario"),
        c("vid_sim", ["--scenario", SCEN, "--out", "{d}/s", "--duration", "-3"], "--duration"),
        c("vid_sim", ["--scenario", SCEN, "--out", "{d}/s", "--duration", "0"], "--duration"),
        c("vid_sim", ["--scenario", SCEN, "--out", "{d}/s", "--seed", "x"], "--seed"),
        c("vid_sim", ["--scenario", SCEN, "--out", "{d}/s", "--initial-heading", "north"], "--initial-heading"),
        c("vid_sim", ["--scenario", "{d}/none.yaml", "--out", "{d}/s", "--quiet"], "{d}/none.yaml", exit=1,
          kind="paths"),
        c("vid_massid", [], "subcommand"),
        c("vid_massid", ["nosuchcommand"], "unknown subcommand 'nosuchcommand'"),
        c("vid-eval", [], "COMMAND"),
        c("vid-eval", ["traj", "{d}/a.txt"], "gt"),
        c("vid-eval", ["traj", "{d}/a.txt", "{d}/b.txt"], "{d}/a.txt", exit=1, kind="paths"),
        c("vid-bag2asl", [], "bag"),
    ]


def all_cases() -> list:
    return lcm_cases() + bag_cases() + [dynamics_without_rotors()] + cli_cases()
