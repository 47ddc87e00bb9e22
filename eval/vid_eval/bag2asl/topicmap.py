"""Topic maps: which bag topics become which dataset streams (format in README.md).

A map has either `streams:` or `profiles:` (a list of {name, streams}); profiles are tried in
order and the first one whose required streams all resolve against the bag is used, so one map
can prefer a consistent set of topics (e.g. VID-Dataset /synced/* on one clock) over another.
"""
from __future__ import annotations

import importlib.resources
import pathlib
import re
from dataclasses import dataclass, field

import yaml

from .errors import ConfigError, MissingTopicError

KINDS = ("image", "imu", "rotor", "thrust", "groundtruth", "force")
_REQUIRED_BY_DEFAULT = {"image": True, "imu": True}
_STREAM_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_STREAM_KEYS = {"kind", "topics", "topic", "sources", "required", "stamp", "unit", "order", "scale",
                "field", "mass_normalized", "rotation", "gyro_scale", "accel_scale", "noise_density"}
_SOURCE_KEYS = {"label", "topic", "topics", "field", "stamp", "scale", "unit"}

DEFAULT_MAP = pathlib.Path(str(importlib.resources.files("vid_eval.bag2asl") / "topic_maps" / "vid_dataset.yaml"))


@dataclass
class Source:
    """One way of getting a stream's data: one topic, or one topic per rotor (per_motor)."""
    label: str
    topics: list[str]
    field: str | None
    stamp: str
    scale: float
    unit: str | None

    @property
    def per_motor(self) -> bool:
        return len(self.topics) > 1


@dataclass
class StreamSpec:
    name: str
    kind: str
    sources: list[Source]
    required: bool
    options: dict = field(default_factory=dict)


@dataclass
class ResolvedStream:
    spec: StreamSpec
    source: Source  # the first source whose topics are all in the bag


@dataclass
class TopicMap:
    path: pathlib.Path
    profiles: list[tuple[str, list[StreamSpec]]]


def _err(path, where, text) -> ConfigError:
    return ConfigError(f"{path}: {where}: {text}")


def _as_topics(path, where, value) -> list[str]:
    if isinstance(value, str):
        return [value]
    if isinstance(value, list) and value and all(isinstance(t, str) and t for t in value):
        return list(value)
    raise _err(path, where, "expected a topic name or a non-empty list of topic names")


def _float(path, where, value, default):
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _err(path, where, f"expected a number, got {value!r}")
    return float(value)


def _parse_stream(path, pname, name, body) -> StreamSpec:
    where = f"{pname}.streams.{name}"
    if not _STREAM_NAME.match(str(name)):
        raise _err(path, where, "stream names are folder names like cam0, imu0, rotor0")
    if not isinstance(body, dict):
        raise _err(path, where, "expected a mapping")
    unknown = set(body) - _STREAM_KEYS
    if unknown:
        raise _err(path, where, f"unknown key(s) {sorted(unknown)}; allowed: {sorted(_STREAM_KEYS)}")
    kind = body.get("kind")
    if kind not in KINDS:
        raise _err(path, f"{where}.kind", f"expected one of {list(KINDS)}, got {kind!r}")
    stamp = body.get("stamp", "header")
    if not isinstance(stamp, str):
        raise _err(path, f"{where}.stamp", "expected 'header', 'bag' or a field name")
    scale = _float(path, f"{where}.scale", body.get("scale"), 1.0)
    unit = body.get("unit")
    sources: list[Source] = []
    if "sources" in body:
        if not isinstance(body["sources"], list) or not body["sources"]:
            raise _err(path, f"{where}.sources", "expected a non-empty list")
        for i, src in enumerate(body["sources"]):
            swhere = f"{where}.sources[{i}]"
            if not isinstance(src, dict):
                raise _err(path, swhere, "expected a mapping")
            bad = set(src) - _SOURCE_KEYS
            if bad:
                raise _err(path, swhere, f"unknown key(s) {sorted(bad)}; allowed: {sorted(_SOURCE_KEYS)}")
            if ("topic" in src) == ("topics" in src):
                raise _err(path, swhere, "give exactly one of 'topic' or 'topics' (one per rotor)")
            topics = _as_topics(path, swhere, src.get("topic", src.get("topics")))
            sources.append(Source(str(src.get("label", f"source{i}")), topics, src.get("field", body.get("field")),
                                  src.get("stamp", stamp), _float(path, f"{swhere}.scale", src.get("scale"), scale),
                                  src.get("unit", unit)))
    else:
        if ("topic" in body) == ("topics" in body):
            raise _err(path, where, "give 'topic', 'topics' (candidates, first present wins) or 'sources'")
        for t in _as_topics(path, where, body.get("topic", body.get("topics"))):
            sources.append(Source(t, [t], body.get("field"), stamp, scale, unit))
    for s in sources:
        if s.per_motor and kind != "rotor":
            raise _err(path, where, "a list of topics per source is only meaningful for kind rotor")
        if kind in ("rotor", "thrust") and not s.field:
            raise _err(path, where, f"kind {kind} needs 'field' (dotted path in the message)")
    options = {k: body[k] for k in ("order", "rotation", "mass_normalized", "gyro_scale", "accel_scale",
                                    "noise_density", "unit") if k in body}
    _check_options(path, where, kind, options)
    required = body.get("required", _REQUIRED_BY_DEFAULT.get(kind, False))
    if not isinstance(required, bool):
        raise _err(path, f"{where}.required", "expected true or false")
    return StreamSpec(str(name), kind, sources, required, options)


def _check_options(path, where, kind, options) -> None:
    if "rotation" in options:
        rot = options["rotation"]
        ok = (isinstance(rot, list) and len(rot) == 3 and all(
            isinstance(r, list) and len(r) == 3 and all(isinstance(v, (int, float)) for v in r) for r in rot))
        if not ok or kind != "force":
            raise _err(path, f"{where}.rotation", "expected a 3x3 list of rows, only for kind force")
    if "order" in options:
        order = options["order"]
        if kind != "rotor" or not isinstance(order, list) or not all(isinstance(i, int) for i in order):
            raise _err(path, f"{where}.order", "expected a list of 0-based rotor indices (kind rotor)")
    if "unit" in options and options["unit"] not in ("rpm", "rad/s"):
        raise _err(path, f"{where}.unit", "expected rpm or rad/s")
    if "mass_normalized" in options and (kind != "thrust" or not isinstance(options["mass_normalized"], bool)):
        raise _err(path, f"{where}.mass_normalized", "expected true/false (kind thrust)")


def load(path: pathlib.Path | None) -> TopicMap:
    path = pathlib.Path(path) if path else DEFAULT_MAP
    try:
        doc = yaml.safe_load(path.read_text())
    except OSError as err:
        raise ConfigError(f"{path}: cannot read topic map: {err.strerror or err}") from None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        line = f" line {mark.line + 1}" if mark else ""
        raise ConfigError(f"{path}:{line}: invalid YAML: {getattr(err, 'problem', err)}") from None
    if not isinstance(doc, dict) or ("streams" in doc) == ("profiles" in doc):
        raise ConfigError(f"{path}: top level must be a mapping with 'streams' or 'profiles'")
    raw_profiles = doc["profiles"] if "profiles" in doc else [{"name": "default", "streams": doc["streams"]}]
    if not isinstance(raw_profiles, list) or not raw_profiles:
        raise ConfigError(f"{path}: profiles: expected a non-empty list")
    profiles = []
    for i, prof in enumerate(raw_profiles):
        if not isinstance(prof, dict) or not isinstance(prof.get("streams"), dict) or not prof["streams"]:
            raise ConfigError(f"{path}: profiles[{i}]: expected {{name, streams: {{...}}}}")
        pname = str(prof.get("name", f"profile{i}"))
        profiles.append((pname, [_parse_stream(path, pname, n, b) for n, b in prof["streams"].items()]))
    return TopicMap(path, profiles)


def resolve(tmap: TopicMap, bag_topics: set[str], topic_list: str, bag_path) -> tuple[str, list[ResolvedStream]]:
    """Pick the profile and, per stream, the first source whose topics all exist in the bag."""
    failures = []
    for pname, specs in tmap.profiles:
        resolved, missing = [], []
        for spec in specs:
            src = next((s for s in spec.sources if all(t in bag_topics for t in s.topics)), None)
            if src is not None:
                resolved.append(ResolvedStream(spec, src))
            elif spec.required:
                wanted = " or ".join("+".join(s.topics) for s in spec.sources)
                missing.append(f"{spec.name} needs {wanted}")
        if not missing:
            return pname, resolved
        failures.append(f"profile '{pname}': " + "; ".join(missing))
    raise MissingTopicError(f"{bag_path}: required topic missing ({' | '.join(failures)}); "
                            f"the bag has: {topic_list}")
