"""Silent faults of the live path (issue #52): an LCM log with unreadable bytes in the middle,
a feature-level folder given to vid_replay, a camera that never delivers.

The log is vid_replay's of 2 s of a rendered sequence; damage is written over whole events so
that what LCM loses is known exactly from the clean log.
"""
import json

import pytest

from test_live import lcm_types, program, run
from test_vid_run_helpers import REPO, simulate_cached, summary

SIM = REPO / "config" / "sim"


def events(data: bytes) -> list:
    """(offset, event number, channel) of every event of an LCM log (sync word, number, time,
    channel length, data length, big-endian)."""
    out, at = [], 0
    while at + 28 <= len(data):
        assert data[at:at + 4] == b"\xed\xa1\xda\x01", at
        number = int.from_bytes(data[at + 4:at + 12], "big")
        ch_len = int.from_bytes(data[at + 20:at + 24], "big")
        d_len = int.from_bytes(data[at + 24:at + 28], "big")
        out.append((at, number, data[at + 28:at + 28 + ch_len].decode()))
        at += 28 + ch_len + d_len
    assert at == len(data)
    return out


def live(log, seq, out, *extra, timeout=300):
    return run([program("vid_live"), "--lcm-url", f"file://{log}?speed=0", "--sensors", seq, "--config", SIM,
                "--out", out, "--quiet", *extra], timeout=timeout)


@pytest.fixture(scope="module")
def seq():
    return simulate_cached("vid17_like_short.yaml", 3.0, 1, features_only=False)


@pytest.fixture(scope="module")
def clean(seq, tmp_path_factory):
    log = tmp_path_factory.mktemp("live_faults") / "clean.log"
    r = run([program("vid_replay"), "--dataset", seq, "--lcm-url", "memq://", "--fast", "--end", "2", "--log", log,
             "--quiet"])
    assert r.returncode == 0, r.stderr
    return log


def damage_small_events(data: bytes, n_bytes: int):
    """Zero n_bytes from the header of the first event past the middle after which n_bytes hold
    only IMU / rotor events (a damaged block that destroys whole events, no image)."""
    ev = events(data)
    for k, (at, _, _) in enumerate(ev):
        if at < len(data) // 2:
            continue
        j = k
        while j < len(ev) and ev[j][0] < at + n_bytes:
            j += 1
        if all(c in ("IMU", "ROTORS") for _, _, c in ev[k:j + 1]):
            return data[:at] + b"\0" * n_bytes + data[at + n_bytes:], ev[k:j], ev[j][0]
    raise AssertionError("no stretch of small events")


def test_the_log_writer_numbers_events(clean):
    """What the events-lost count relies on: vid_replay's log (lcm::LogFile, as lcm-logger)
    numbers its events 0, 1, 2, ..."""
    import lcm
    ev = events(clean.read_bytes())
    assert [n for _, n, _ in ev] == list(range(len(ev)))
    assert [e.eventnum for e in lcm.EventLog(str(clean), "r")] == list(range(len(ev)))


def test_damaged_log_is_read_past_with_one_warning(seq, clean, tmp_path):
    data = clean.read_bytes()
    bad, lost, end = damage_small_events(data, 1000)
    log = tmp_path / "bad.log"
    log.write_bytes(bad)
    start = lost[0][0]
    r = live(log, seq, tmp_path / "out")
    assert r.returncode == 0, r.stderr
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and ": warning:" in lines[0], r.stderr
    assert f"at bytes {start}-{end}: {len(lost)} events lost" in lines[0], lines[0]
    s = summary(tmp_path / "out")
    info = s["input"]["lcm_log"]
    assert info["damaged_spans"] == [{"start_byte": start, "end_byte": end, "bytes": end - start,
                                      "events_lost": len(lost)}]
    assert info["events_lost"] == len(lost) and info["events"] == len(events(data)) - len(lost)
    # The estimator met the lost IMU / rotor messages as gaps in their streams: counted missing.
    assert s["faults"]["imu.missing"] == sum(c == "IMU" for _, _, c in lost)
    assert s["faults"]["rotors.missing"] == sum(c == "ROTORS" for _, _, c in lost)
    assert s["status"] == "ok" and s["input_end"] == "eof"

    r = live(log, seq, tmp_path / "strict", "--strict")
    lines = r.stderr.splitlines()
    assert r.returncode == 1 and len(lines) == 1, r.stderr
    assert ": error:" in lines[0] and f"no event header at byte {start}" in lines[0], lines[0]


def test_clean_log_has_no_damage(seq, clean, tmp_path):
    r = live(clean, seq, tmp_path / "out", "--strict")
    assert r.returncode == 0 and r.stderr == "", r.stderr
    info = summary(tmp_path / "out")["input"]["lcm_log"]
    assert info["damaged_spans"] == [] and info["events_lost"] == 0


def test_replay_refuses_a_feature_level_folder(tmp_path):
    feat = simulate_cached("vid17_like_short.yaml", 3.0, 1, features_only=True)
    base = [program("vid_replay"), "--dataset", feat, "--lcm-url", "memq://", "--fast", "--quiet",
            "--log", tmp_path / "f.log", "--report", tmp_path / "r.json"]
    r = run(base)
    lines = r.stderr.splitlines()
    assert r.returncode == 1 and len(lines) == 1, r.stderr
    assert str(feat) in lines[0] and "feat0" in lines[0] and "vid_run" in lines[0] and "--no-camera" in lines[0]
    assert not (tmp_path / "r.json").exists()
    r = run(base + ["--no-camera"])
    lines = r.stderr.splitlines()
    assert r.returncode == 0 and len(lines) == 1 and ": warning:" in lines[0] and "feat0" in lines[0], r.stderr
    report = json.loads((tmp_path / "r.json").read_text())
    assert set(report["published"]) == {"IMU", "ROTORS"} and report["camera_published"] is False


def no_camera_log(seq, path, *extra):
    r = run([program("vid_replay"), "--dataset", seq, "--lcm-url", "memq://", "--fast", "--log", path, "--quiet",
             *extra])
    assert r.returncode == 0, r.stderr
    return path


def test_a_camera_that_never_delivers_is_a_fault(seq, tmp_path):
    """IMU and rotors, no frame: health no_camera (on VID_STATE and VID_STATUS as soon as the
    bound passes), one error line, summary status no_camera, exit 5."""
    import lcm
    lcm_types()
    from vid import state_t, status_t
    log = no_camera_log(seq, tmp_path / "nocam.log", "--no-camera")
    pub = tmp_path / "pub.log"
    r = live(log, seq, tmp_path / "out", "--no-camera-s", "1.5", "--publish-url", f"file://{pub}?mode=w")
    lines = r.stderr.splitlines()
    assert r.returncode == 5 and len(lines) == 1, r.stderr
    assert ": error:" in lines[0] and "CAM0" in lines[0] and "no camera frame in 1.5 s" in lines[0], lines[0]
    s = summary(tmp_path / "out")
    assert s["status"] == "no_camera" and s["health"] == "no_camera" and s["counts"]["camera_frames"] == 0
    assert s["camera_first_frame_after_s"] is None
    states = [state_t.decode(e.data) for e in lcm.EventLog(str(pub), "r") if e.channel == "VID_STATE"]
    statuses = [status_t.decode(e.data) for e in lcm.EventLog(str(pub), "r") if e.channel == "VID_STATUS"]
    assert states[-1].status == state_t.STATUS_NO_CAMERA
    assert statuses[-1].status_text == "no_camera" and statuses[-1].status == state_t.STATUS_NO_CAMERA
    t0 = states[0].timestamp
    # within 1.5 s (+ one IMU period) of IMU data the published health says so
    first = next(st.timestamp for st in states if st.status == state_t.STATUS_NO_CAMERA)
    assert first - t0 <= 1.6e9
    assert any(m.status_text == "no_camera" and m.timestamp <= first + 5e6 for m in statuses)

    # Input shorter than the bound: the fault is reported at the end, still one line, exit 5.
    r = live(log, seq, tmp_path / "out_short")
    lines = r.stderr.splitlines()
    assert r.returncode == 5 and len(lines) == 1 and "in the whole input" in lines[0], r.stderr
    assert summary(tmp_path / "out_short")["status"] == "no_camera"


def test_a_camera_that_starts_late_still_succeeds(seq, tmp_path):
    """No image in the first 1.2 s, then the camera delivers: within the bound nothing is said
    and the run ends ok; past the bound the fault is reported and then cleared."""
    log = no_camera_log(seq, tmp_path / "late.log", "--camera-stall", "0", "1.2")
    r = live(log, seq, tmp_path / "out")
    assert r.returncode == 0 and r.stderr == "", r.stderr
    s = summary(tmp_path / "out")
    assert s["status"] == "ok" and s["health"] != "no_camera" and s["counts"]["camera_frames"] > 30
    assert 1.1 < s["camera_first_frame_after_s"] < 1.3
    r = live(log, seq, tmp_path / "out_bound", "--no-camera-s", "0.8")
    lines = r.stderr.splitlines()
    assert r.returncode == 0 and len(lines) == 1 and "no camera frame in 0.8 s" in lines[0], r.stderr
    s = summary(tmp_path / "out_bound")
    assert s["status"] == "ok" and s["health"] != "no_camera"
