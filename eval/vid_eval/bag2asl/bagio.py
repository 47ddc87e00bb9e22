"""Opening ROS1/ROS2 bags, building message types from the bag's own definitions, iterating.

Types are registered from each connection's embedded definition (ROS1 connection records,
ROS2 metadata/MCAP schemas) with rosbags.typesys get_types_from_msg / get_types_from_idl into a
typestore per distinct definition, so custom types (uavmotor, djiros, mav_msgs, quadrotor_msgs,
robotiq_ft_sensor, ...) need no hard-coding and two definitions of one name cannot clash.
Only when a connection carries no definition the stock store (ROS1 Noetic / ROS2 Humble) is used.

ROS1 bags are streamed by the sequential reader of ros1reader.py (memory independent of the bag's
size). Only a bag whose chunks overlap in time by more than MAX_OVERLAP_BYTES (not written in
arrival order, e.g. merged topic by topic) is read with rosbags' indexed Reader, whose memory
grows with the message count; a warning says so. ROS2 bags use rosbags' Reader.
"""
from __future__ import annotations

import pathlib
import struct
import sys
import zlib
from dataclasses import dataclass
from typing import Iterator

import lz4.frame  # noqa: F401  lz4 chunks: fail at import, not mid-bag, if lz4 is missing
from rosbags.interfaces import MessageDefinitionFormat
from rosbags.rosbag1 import Reader as Reader1
from rosbags.rosbag1 import ReaderError as ReaderError1
from rosbags.rosbag2 import Reader as Reader2
from rosbags.rosbag2 import ReaderError as ReaderError2
from rosbags.serde import SerdeError
from rosbags.typesys import Stores, TypesysError, get_types_from_idl, get_types_from_msg, get_typestore

from .errors import CorruptBagError, UnknownTypeError
from .ros1reader import Ros1FormatError, Ros1Reader

_IDL_SEP = "=" * 80 + "\n"

# chunk bytes (on disk) that may wait in the sequential reader's reorder heap; above: indexed reader
MAX_OVERLAP_BYTES = 64 << 20


def short_type(msgtype: str) -> str:
    """'pkg/msg/Name' -> 'pkg/Name' (how ROS1 users spell types)."""
    parts = msgtype.split("/")
    return f"{parts[0]}/{parts[-1]}" if len(parts) == 3 and parts[1] == "msg" else msgtype


@dataclass
class TopicInfo:
    topic: str
    msgtype: str  # 'pkg/msg/Name'
    count: int


class Bag:
    """A ROS1 .bag file or a ROS2 bag directory, opened for streaming."""

    def __init__(self, path: pathlib.Path):
        self.path = path
        if not path.exists():
            raise CorruptBagError(f"{path}: no such file or directory")
        self.is2 = path.is_dir() or path.suffix in (".db3", ".mcap", ".yaml")
        if self.is2 and not path.is_dir():
            path = path.parent
        self.sequential = False
        self.note = ""  # why the indexed reader was used, for the summary
        try:
            if self.is2:
                self.reader = Reader2(path)
                self.reader.open()
            else:
                self._open_ros1(path)
        except Ros1FormatError as err:
            raise CorruptBagError(f"{path}: corrupt or truncated bag: {err}") from None
        except (ReaderError1, ReaderError2, OSError, struct.error, ValueError, KeyError,
                EOFError, zlib.error) as err:
            raise CorruptBagError(_corrupt_message(path, err)) from None
        self._fallback = None
        self._stores: dict[tuple[str, str], object] = {}

    def _open_ros1(self, path: pathlib.Path) -> None:
        seq = Ros1Reader(path)
        seq.open()
        if seq.max_overlap_bytes <= MAX_OVERLAP_BYTES:
            self.reader = seq
            self.sequential = True
            return
        seq.close()
        self.note = (f"chunks overlap in time by up to {seq.max_overlap_bytes / 1e6:.1f} MB (not written in "
                     "time order): indexed reader, memory grows with the message count")
        print(f"warning: {path}: {self.note}", file=sys.stderr)
        self.reader = Reader1(path)
        self.reader.open()

    def reader_summary(self) -> dict:
        """Which reader streamed the bag, and how much the sequential one held back for ordering."""
        if self.is2:
            return {"reader": "rosbags ROS2 reader"}
        if not self.sequential:
            return {"reader": "indexed ROS1 reader (rosbags)", "reason": self.note}
        return {"reader": "sequential ROS1 reader (one chunk at a time)",
                "chunk_overlap_bound_mb": round(self.reader.max_overlap_bytes / 1e6, 3),
                "reorder_peak_messages": self.reader.peak_held_messages,
                "reorder_peak_mb": round(self.reader.peak_held_bytes / 1e6, 3)}

    def progress(self, bag_ns: int, t0: int, t1: int) -> tuple[int, int]:
        """(done, total) for the progress bar: bytes read of the sequential reader, else bag time."""
        if self.sequential:
            r = self.reader
            return r.position - r.data_start, r.index_pos - r.data_start
        return bag_ns - t0, t1 - t0

    def close(self) -> None:
        try:
            self.reader.close()
        except Exception:  # closing a half-broken bag must not hide the real error
            pass

    # -- metadata -----------------------------------------------------------------------------
    @property
    def start_ns(self) -> int:
        return int(self.reader.start_time) if self.reader.message_count else 0

    @property
    def end_ns(self) -> int:
        return int(self.reader.end_time) if self.reader.message_count else 0

    def topics(self) -> dict[str, TopicInfo]:
        out: dict[str, TopicInfo] = {}
        for conn in self.reader.connections:
            info = out.setdefault(conn.topic, TopicInfo(conn.topic, conn.msgtype, 0))
            info.count += int(conn.msgcount)
        return out

    def topic_list(self) -> str:
        """'topic (type), ...' for error messages."""
        items = sorted(self.topics().values(), key=lambda t: t.topic)
        return ", ".join(f"{t.topic} ({short_type(t.msgtype)})" for t in items) or "(no topics)"

    def connections(self, topic: str):
        return [c for c in self.reader.connections if c.topic == topic]

    # -- types ----------------------------------------------------------------------------------
    def _fallback_store(self):
        if self._fallback is None:
            self._fallback = get_typestore(Stores.ROS2_HUMBLE if self.is2 else Stores.ROS1_NOETIC)
        return self._fallback

    def typestore_for(self, conn):
        """Typestore that can deserialize CONN's messages (built from its embedded definition)."""
        msgdef = conn.msgdef
        data = msgdef.data if msgdef is not None else ""
        key = (conn.msgtype, data)
        if key in self._stores:
            return self._stores[key]
        if not data or msgdef.format == MessageDefinitionFormat.NONE:
            store = self._fallback_store()
            if conn.msgtype not in store.fielddefs:
                raise UnknownTypeError(
                    f"{self.path}: topic {conn.topic}: unknown message type {short_type(conn.msgtype)} "
                    "(the bag carries no definition for it and it is not a standard ROS type)")
        else:
            store = get_typestore(Stores.EMPTY)
            try:
                if msgdef.format == MessageDefinitionFormat.MSG:
                    types = get_types_from_msg(data, conn.msgtype)
                elif data.startswith(_IDL_SEP + "IDL: "):
                    types = {}
                    for part in data.split(_IDL_SEP)[1:]:
                        types.update(get_types_from_idl(part.split("\n", 1)[1]))
                else:
                    types = get_types_from_idl(data)
                store.register(types)
            except (TypesysError, ValueError, KeyError) as err:
                raise UnknownTypeError(
                    f"{self.path}: topic {conn.topic}: cannot parse the embedded definition of "
                    f"{short_type(conn.msgtype)}: {err}") from None
            if conn.msgtype not in store.fielddefs:
                raise UnknownTypeError(
                    f"{self.path}: topic {conn.topic}: embedded definition does not define "
                    f"{short_type(conn.msgtype)}")
        self._stores[key] = store
        return store

    def deserializer(self, conn):
        store = self.typestore_for(conn)
        fn = store.deserialize_cdr if self.is2 else store.deserialize_ros1
        msgtype = conn.msgtype

        def deser(raw: bytes):
            try:
                return fn(raw, msgtype)
            except (SerdeError, struct.error, ValueError, IndexError, KeyError, UnicodeDecodeError) as err:
                raise CorruptBagError(
                    f"{self.path}: topic {conn.topic}: cannot decode a {short_type(msgtype)} message "
                    f"({err or type(err).__name__}); bag corrupt or definition wrong") from None

        return deser

    # -- streaming ------------------------------------------------------------------------------
    def messages(self, conns, start_ns: int | None, stop_ns: int | None) -> Iterator[tuple]:
        """(connection, bag time ns, raw bytes) in bag-time order; read errors -> CorruptBagError."""
        it = self.reader.messages(connections=conns, start=start_ns, stop=stop_ns)
        while True:
            try:
                item = next(it)
            except StopIteration:
                return
            except Ros1FormatError as err:
                raise CorruptBagError(f"{self.path}: corrupt or truncated bag: {err}") from None
            except (ReaderError1, ReaderError2, OSError, struct.error, ValueError, KeyError, EOFError,
                    AssertionError, IndexError, zlib.error, RuntimeError) as err:
                raise CorruptBagError(_corrupt_message(self.path, err)) from None
            yield item


def _corrupt_message(path: pathlib.Path, err: Exception) -> str:
    text = str(err) or type(err).__name__
    hint = ""
    if "not indexed" in text.lower() or "index" in text.lower():
        hint = " (truncated or unfinished recording? try 'rosbag reindex')"
    return f"{path}: corrupt or truncated bag: {text}{hint}"

