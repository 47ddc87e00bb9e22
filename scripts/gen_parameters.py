#!/usr/bin/env python3
"""Generate docs/parameters.md, the reference of every estimator.yaml and frontend.yaml key,
from the typed parameters themselves: the structs' headers (member, default initializer,
Doxygen comment) and the loaders' field tables (which keys exist, enum spellings).

    python3 scripts/gen_parameters.py            # rewrite docs/parameters.md
    python3 scripts/gen_parameters.py --check    # exit 1 if docs/parameters.md is stale

Fails (exit 1, one line) when a loader key has no member, a member no loader key, or a key no
Doxygen comment (`///` above it or `///<` after it): the reference cannot drift from the code.
tests/python/test_parameters_doc.py runs --check.
"""
from __future__ import annotations

import argparse
import functools
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "parameters.md"


@dataclass
class Source:
    file: str          # preset file name
    struct: str        # C++ struct
    header: str        # header declaring it (relative to ROOT)
    loaders: List[str]  # sources of its loader tables and enum spellings


SOURCES = [
    Source("estimator.yaml", "EstimatorParams", "vio_core/include/vio_core/estimator_params.h",
           ["vio_core/src/estimator_params_yaml.cpp", "vio_core/src/estimator_params.cpp"]),
    Source("frontend.yaml", "FrontendParams", "frontend/include/frontend/frontend_params.h",
           ["frontend/src/frontend_params_yaml.cpp"]),
]


@dataclass
class Member:
    key: str
    ctype: str
    default: str
    doc: str
    section: str


_DECL = re.compile(r"^\s*([\w:]+)\s+(\w+)\s*=\s*([^;]+);\s*(?:///<\s*(.*))?$")
_SECTION = re.compile(r"^\s*//\s*---\s*(.+?)\s*---\s*$")


class GenError(Exception):
    pass


def parse_struct(header: Path, struct: str) -> List[Member]:
    """Members of ``struct`` in declaration order, with default, Doxygen text and section."""
    lines = header.read_text().splitlines()
    start = next((i for i, l in enumerate(lines) if re.match(rf"^struct {struct}\b", l)), None)
    if start is None:
        raise GenError(f"{header}: struct {struct} not found")
    members: List[Member] = []
    pending: List[str] = []
    section = ""
    for line in lines[start + 1:]:
        if line.startswith("};"):
            break
        text = line.strip()
        if m := _SECTION.match(line):
            section, pending = m.group(1), []
        elif text.startswith("///<") and members:  # continuation of the previous member's doc
            members[-1].doc += " " + text[4:].strip()
        elif text.startswith("///"):
            pending.append(text[3:].strip())
        elif m := _DECL.match(line):
            ctype, key, default, trailing = m.groups()
            doc = " ".join(pending + ([trailing.strip()] if trailing else []))
            members.append(Member(key, ctype, default.strip(), doc, section))
            pending = []
        elif not text.startswith("//"):
            pending = []
    return members


def loader_keys(sources: List[Path]) -> tuple[set, Dict[str, str]]:
    """Keys the loader reads (VID_FIELD tables, string/enum keys) and enum spellings
    ``Enum::kValue -> yaml``."""
    keys, spell = set(), {}
    for path in sources:
        text = path.read_text()
        keys |= set(re.findall(r"^\s*VID_FIELD\((\w+)\),", text, re.MULTILINE))
        keys |= set(re.findall(r'y\.has\("(\w+)"\)', text)) & {"mode", "init_mode", "force_frame"}
        keys |= set(re.findall(r'read_enum\(m, "(\w+)"', text))
        for name, enum, value in re.findall(r'"(\w+)"\)?\s*(?:return\s+|,\s*)(\w+)::(\w+)', text):
            spell[f"{enum}::{value}"] = name
    return keys, spell


# The shared types' header: a default may name its one definition there (ImuNoise{}.x, kDefaultGravity).
CALIBRATION = "types/include/types/calibration.h"


@functools.lru_cache(maxsize=None)
def shared_defaults() -> Dict[str, str]:
    """``ImuNoise{}.gyro_noise_density -> 1.0e-3``, ``kDefaultGravity -> 9.81``, ... from the
    shared types' header, so the table shows the value an estimator default refers to."""
    header = ROOT / CALIBRATION
    out = {name: value for name, value in
           re.findall(r"inline constexpr double (k\w+) = ([^;]+);", header.read_text())}
    for struct in ("ImuNoise", "VehicleParams"):
        for m in parse_struct(header, struct):
            out[f"{struct}{{}}.{m.key}"] = out.get(m.default, m.default)
    return out


def yaml_default(member: Member, spell: Dict[str, str]) -> str:
    shared = shared_defaults()
    if member.default in shared:
        return shared[member.default]
    if "::" in member.default:
        if member.default not in spell:
            raise GenError(f"no YAML spelling of {member.default} in the loader")
        return spell[member.default]
    return member.default


def choices(member: Member, spell: Dict[str, str]) -> str:
    enum = member.ctype
    names = [v for k, v in spell.items() if k.startswith(enum + "::")]
    return " \\| ".join(sorted(set(names), key=names.index)) if names else member.ctype


def render() -> str:
    out = ["# Parameter reference", "",
           "Every key of a preset's `estimator.yaml` and `frontend.yaml` with its default and meaning,",
           "generated from the typed parameters by `scripts/gen_parameters.py` (do not edit by hand;",
           "`tests/python/test_parameters_doc.py` fails when this file is stale). A key left out keeps its",
           "default; an unknown key is an error naming file, line and key. A run records the values it used",
           "in `summary.json` (`config`).", "",
           "The other files of a preset are calibration, read as their tools write them:",
           "`imu.yaml` (Kalibr imu chain: `accelerometer_noise_density`, `accelerometer_random_walk`,",
           "`gyroscope_noise_density`, `gyroscope_random_walk`, `update_rate`, `T_i_b`; these set the",
           "estimator's IMU noise keys below), `camchain-imucam.yaml` (Kalibr imucam chain), `vehicle.yaml`",
           "(`mass_kg`, `gravity`, `rotor_thrust_coefficients`; `gravity` sets the estimator's) and",
           "`rotor_sensor.yaml` ([formats.md §1](formats.md)). Where each comes from:",
           "[own-vehicle.md](own-vehicle.md). Each fact has one owner: an `estimator.yaml` value for a key",
           "a calibration file sets (IMU noise and rate, gravity) is replaced by the calibration's, with one",
           "warning line per differing key and the list in `summary.json` (`config_overrides`).", ""]
    for src in SOURCES:
        members = parse_struct(ROOT / src.header, src.struct)
        keys, spell = loader_keys([ROOT / p for p in src.loaders])
        names = {m.key for m in members}
        if keys - names:
            raise GenError(f"{src.loaders[0]}: loader key(s) {sorted(keys - names)} are no member of {src.struct}")
        if names - keys:
            raise GenError(f"{src.header}: member(s) {sorted(names - keys)} have no key in {src.loaders[0]}")
        undocumented = [m.key for m in members if not m.doc]
        if undocumented:
            raise GenError(f"{src.header}: no /// comment for {', '.join(undocumented)}")
        out += [f"## `{src.file}` ({src.struct}, [`{src.header}`](../{src.header}))", ""]
        section = None
        for m in members:
            if m.section != section:
                section = m.section
                out += ([] if out[-1] == "" else [""]) + [f"### {section}", "", "| key | type | default | meaning |",
                                                          "|---|---|---|---|"]
            kind = choices(m, spell) if "::" in m.default else m.ctype
            doc = m.doc.replace("|", "\\|")
            out.append(f"| `{m.key}` | {kind} | `{yaml_default(m, spell)}` | {doc} |")
        out.append("")
    return "\n".join(out).rstrip() + "\n"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--check", action="store_true", help="exit 1 if docs/parameters.md differs from the code")
    p.add_argument("--out", type=Path, default=OUT, help="file to write or check (default docs/parameters.md)")
    args = p.parse_args(argv)
    try:
        text = render()
    except GenError as exc:
        print(f"gen_parameters: error: {exc}", file=sys.stderr)
        return 1
    if args.check:
        if not args.out.is_file() or args.out.read_text() != text:
            print(f"gen_parameters: error: {args.out} is stale: run python3 scripts/gen_parameters.py",
                  file=sys.stderr)
            return 1
        return 0
    args.out.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
