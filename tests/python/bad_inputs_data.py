"""Bad-input table, part 1 (issues #26, #28): the input kinds read from a dataset folder -
CSV streams, images, sensor / config YAML, stream gaps and --start/--end ranges.

Each case is Case(kind, input, make, exit, ...): make(ctx, d) builds the bad input in the
empty folder d and returns (argv, named), `named` being the file, flag or topic that the one
line on stderr must name. No tests here (tests/python/test_bad_inputs.py runs them).
"""
from __future__ import annotations

import dataclasses
import io
import pathlib
from typing import Callable

import numpy as np
from PIL import Image

from test_vid_run_helpers import REPO, link_copy, program, replace_file

SIM_CONFIG = str(REPO / "config" / "sim")


@dataclasses.dataclass
class Case:
    kind: str                       # CSV, images, YAML, gaps, ranges, LCM log, LCM URL, bags, topic maps, CLI
    input: str                      # what is wrong, in a few words (the table's "input" column)
    make: Callable                  # (ctx, d) -> (argv, named)
    exit: int = 1                   # 2: usage error; 0: a tolerated fault (one warning, counted)
    counted: str | None = None      # tolerated: the summary.json counts key that must be 1


def dataset(ctx, d: pathlib.Path, seq: str) -> pathlib.Path:
    return link_copy(getattr(ctx, seq), d / "ds")


def vid_run(ds, d, *extra) -> list:
    return [str(program("vid_run")), "--dataset", str(ds), "--out", str(d / "out"), "--quiet", "--config", SIM_CONFIG,
            *extra]


def rows_of(path: pathlib.Path):
    lines = path.read_text().splitlines()
    head = [line for line in lines if line.startswith("#")]
    return head, [line for line in lines if line and not line.startswith("#")]


def write_rows(path: pathlib.Path, head, rows) -> None:
    replace_file(path, ("\n".join(head + rows) + "\n").encode())


# --- CSV: one fault at data row K of a stream --------------------------------------------------
K = 5


def _field0(rows, k, value):
    f = rows[k].split(",")
    f[0] = value
    rows[k] = ",".join(f)


CSV_FAULTS = {
    "non-numeric field": lambda h, r: (h, r[:K] + [r[K].rsplit(",", 1)[0] + ",abc"] + r[K + 1:]),
    "missing column": lambda h, r: (h, r[:K] + [r[K].rsplit(",", 1)[0]] + r[K + 1:]),
    "extra column": lambda h, r: (h, r[:K] + [r[K] + ",1,2,3"] + r[K + 1:]),
    "row repeated (duplicate)": lambda h, r: (h, r[:K] + [r[K - 1]] + r[K + 1:]),
    "timestamp before the previous row": lambda h, r: (h, r[:K] + [_earlier(r, K)] + r[K + 1:]),
    "non-integer timestamp": lambda h, r: (h, r[:K] + ["1.5e9" + r[K][r[K].index(","):]] + r[K + 1:]),
    "negative timestamp": lambda h, r: (h, ["-5" + r[0][r[0].index(","):]] + r[1:]),
    "empty file": lambda h, r: ([], []),
    "header only": lambda h, r: (h, []),
}


def _earlier(rows, k):
    prev = int(rows[k - 1].split(",")[0])
    return str(prev - 1_000_000) + rows[k][rows[k].index(","):]


def csv_case(stream: str, fault: str, seq: str = "feat") -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, seq)
        csv = ds / "mav0" / stream / "data.csv"
        head, rows = CSV_FAULTS[fault](*rows_of(csv))
        if fault == "empty file":
            replace_file(csv, b"")
        else:
            write_rows(csv, head, rows)
        return vid_run(ds, d), str(csv)
    return Case("CSV", f"{stream}/data.csv: {fault}", make)


def missing_csv_case(stream: str) -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        (ds / "mav0" / stream / "data.csv").unlink()
        return vid_run(ds, d), str(ds / "mav0" / stream / "data.csv") if stream == "imu0" else str(stream)
    return Case("CSV", f"{stream}/data.csv missing", make)


CSV_STREAMS = ["imu0", "rotor0", "feat0", "state_groundtruth_estimate0", "force0", "mass0"]


def csv_cases() -> list:
    cases = [csv_case(s, f) for s in CSV_STREAMS for f in CSV_FAULTS]
    # cam0's second column is a file name: any text is one (a missing image, see image_cases)
    cases += [csv_case("cam0", f, "img") for f in CSV_FAULTS if f not in ("extra column", "non-numeric field")]
    cases.append(missing_csv_case("imu0"))
    return cases


# --- Images: tolerated (one warning, counted), --strict, vid_track -----------------------------
def png_bytes(width, height, depth=8) -> bytes:
    buf = io.BytesIO()
    arr = np.full((height, width), 128, np.uint16 if depth == 16 else np.uint8)
    Image.fromarray(arr).save(buf, format="PNG")
    return buf.getvalue()


def _truncate(p):
    data = p.read_bytes()
    replace_file(p, data[: len(data) // 2])


def _flip_crc(p):
    data = bytearray(p.read_bytes())
    data[40] ^= 0xFF  # inside IHDR/IDAT: the chunk's CRC no longer matches
    replace_file(p, bytes(data))


IMAGE_FAULTS = {  # name -> (how, summary counts key)
    "missing file": (lambda p: p.unlink(), "images_missing"),
    "truncated PNG": (_truncate, "images_unreadable"),
    "corrupt PNG (bad CRC)": (_flip_crc, "images_unreadable"),
    "not an image (text)": (lambda p: replace_file(p, b"this is not a png"), "images_unreadable"),
    "empty file": (lambda p: replace_file(p, b""), "images_unreadable"),
    "truncated JPEG": (lambda p: replace_file(p, b"\xff\xd8\xff\xe0" + b"\0" * 64), "images_unreadable"),
    "wrong size (320x240)": (lambda p: replace_file(p, png_bytes(320, 240)), "images_wrong_size"),
}


def image_case(fault: str, program_name: str, strict: bool, cam: str = "cam0") -> Case:
    how, key = IMAGE_FAULTS[fault]

    def make(ctx, d):
        ds = dataset(ctx, d, "img")
        _, rows = rows_of(ds / "mav0" / cam / "data.csv")
        img = ds / "mav0" / cam / "data" / rows[20].split(",")[1].strip()
        how(img)
        extra = ["--strict"] if strict else []
        if program_name == "vid_run":
            return vid_run(ds, d, *extra), str(img)
        return [str(program("vid_track")), "--dataset", str(ds), "--out", str(d / "tracks.csv"), "--quiet",
                *extra], str(img)
    label = f"{cam} image: {fault} ({program_name}{' --strict' if strict else ''})"
    return Case("images", label, make, exit=1 if strict else 0, counted=key if program_name == "vid_run" and not strict
                else None)


def image_cases() -> list:
    cases = [image_case(f, "vid_run", False) for f in IMAGE_FAULTS]
    cases += [image_case(f, "vid_run", True) for f in IMAGE_FAULTS]
    cases += [image_case(f, "vid_track", False) for f in ("missing file", "truncated PNG", "wrong size (320x240)")]
    cases += [image_case(f, "vid_track", True) for f in ("missing file", "truncated PNG", "wrong size (320x240)")]
    cases += [image_case(f, "vid_run", False, "cam1") for f in ("truncated PNG", "wrong size (320x240)")]
    return cases


# --- YAML: sensor files of the dataset, the estimator preset -----------------------------------
def _edit_yaml(path: pathlib.Path, fault: str, key: str):
    text = path.read_text()
    if fault == "not YAML":
        new = text + "\n  - [unclosed\n"
    elif fault == "empty file":
        new = ""
    elif fault == "missing key":
        new = "\n".join(line for line in text.splitlines() if not line.startswith(key + ":")) + "\n"
    elif fault == "text for a number":
        new = "\n".join(f"{key}: abc" if line.startswith(key + ":") else line for line in text.splitlines()) + "\n"
    elif fault == "unknown key":
        new = text + "\nno_such_key: 1\n"
    elif fault == "key given twice":  # appended as an override; yaml-cpp alone would keep the first
        top_level = [line for line in text.splitlines() if line[:1].isalpha() and ":" in line]
        first = next(line for line in top_level if not key or line.startswith(key + ":"))
        new = text + "\n" + first + "\n"
    else:
        raise ValueError(fault)
    replace_file(path, new.encode())


SENSOR_YAML = {"imu0/sensor.yaml": "gyroscope_noise_density", "cam0/sensor.yaml": "intrinsics",
               "rotor0/sensor.yaml": "count", "vehicle.yaml": "mass_kg"}
YAML_FAULTS = ["not YAML", "empty file", "missing key", "text for a number", "unknown key", "key given twice"]


def yaml_case(rel: str, fault: str) -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, "feat")
        path = ds / "mav0" / rel
        _edit_yaml(path, fault, SENSOR_YAML[rel])
        return vid_run(ds, d), str(path)
    return Case("YAML", f"{rel}: {fault}" + (f" ({SENSOR_YAML[rel]})" if "key" in fault or "number" in fault
                                              else ""), make)


def preset_case(fault: str) -> Case:
    def make(ctx, d):
        cfg = d / "estimator.yaml"
        cfg.write_text((REPO / "config" / "sim" / "estimator.yaml").read_text())
        if fault == "missing file":
            cfg.unlink()
        elif fault == "text for a number":
            cfg.write_text("init_accel_std_max: abc\n")
        else:
            _edit_yaml(cfg, fault, "")
        argv = vid_run(ctx.feat, d)
        argv[argv.index(SIM_CONFIG)] = str(cfg)
        return argv, str(cfg)
    return Case("YAML", f"--config estimator.yaml: {fault}", make)


def yaml_cases() -> list:
    cases = [yaml_case(rel, f) for rel in SENSOR_YAML for f in YAML_FAULTS]
    cases += [preset_case(f) for f in ("missing file", "not YAML", "unknown key", "text for a number",
                                              "key given twice")]
    return cases


# --- Gaps and ranges ---------------------------------------------------------------------------
def gap_case(stream: str, seq: str = "feat", extra=(), exit=1, seconds=3600.0, counted=None) -> Case:
    def make(ctx, d):
        ds = dataset(ctx, d, seq)
        csv = ds / "mav0" / stream / "data.csv"
        head, rows = rows_of(csv)
        times = sorted({int(r.split(",")[0]) for r in rows})
        cut = times[len(times) // 2]
        shift = int(seconds * 1e9)
        rows = [(str(int(r.split(",")[0]) + shift) + r[r.index(","):]) if int(r.split(",")[0]) >= cut else r
                for r in rows]
        write_rows(csv, head, rows)
        return vid_run(ds, d, *extra), str(csv)
    what = f"{stream}: {seconds:g} s time gap" + (f" ({' '.join(extra)})" if extra else "")
    return Case("gaps", what, make, exit=exit, counted=counted)


def range_case(args, program_name="vid_run") -> Case:
    def make(ctx, d):
        if program_name == "vid_run":
            return vid_run(ctx.feat, d, *args), args[0]
        return [str(program("vid_replay")), "--dataset", str(ctx.feat), "--lcm-url", "memq://", "--fast", "--quiet",
                *args], args[0]
    return Case("ranges", f"{program_name} {' '.join(args)}", make, exit=2)


RANGES = [["--start", "1000"], ["--start", "-5"], ["--start", "2", "--end", "1"], ["--start", "1", "--end", "1"],
          ["--end", "0"], ["--end", "-3"], ["--end", "500"], ["--start", "3.5"]]


def gap_range_cases() -> list:
    cases = [gap_case(s) for s in ("imu0", "rotor0", "feat0")]
    cases.append(gap_case("cam0", "img"))
    cases.append(gap_case("imu0", extra=("--max-gap-periods", "1000"), seconds=10.0))
    # under --allow-gaps: one warning naming file and line, the estimator bridges it (counts.imu_gaps)
    cases.append(gap_case("imu0", extra=("--allow-gaps",), exit=0, seconds=1.0, counted="imu_gaps"))
    cases += [range_case(a) for a in RANGES]
    cases += [range_case(a, "vid_replay") for a in RANGES]
    return cases


def all_cases() -> list:
    return csv_cases() + image_cases() + yaml_cases() + gap_range_cases()
