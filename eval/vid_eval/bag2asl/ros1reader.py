"""Sequential ROS1 (bag format v2.0) reader: constant memory in the bag's size.

rosbags' ROS1 Reader loads the index entry of every message (~180 B each) before it yields the
first one. This reader instead walks the file once from the front, one chunk at a time:

* open() reads the bag header record (op 0x03) and the index section it points to: connection
  records (op 0x07, with the embedded `message_definition`) and chunk info records (op 0x06).
  Per chunk only three integers are kept (position, first and last message time, ~24 B per chunk
  of ~1 MB); the per-message index data records (op 0x04) are skipped, never loaded.
* messages() reads each chunk record (op 0x05), decompresses it (none, bz2, lz4 frame), takes the
  connection records inside it as they appear and yields its message data records (op 0x02).

Order: messages come out exactly as rosbags' Reader.messages() yields them, sorted by record
time (ties: position of the connection in `connections`, then file order). A chunk's messages go
into a small heap that is released up to the earliest start time of all later chunks, so messages
are held back only where chunks overlap in time. A recorded bag writes messages in arrival order
and its chunks hardly overlap; `max_overlap_bytes` (from the chunk infos, before reading) bounds
how much could be held back, so a caller can refuse (or read differently) bags that are not
roughly time-ordered on disk.

Every structural problem raises Ros1FormatError naming the byte offset in the file (and in the
decompressed chunk where it applies).
"""
from __future__ import annotations

import bz2
import heapq
import pathlib
import struct
from array import array
from dataclasses import dataclass
from typing import BinaryIO, Iterable, Iterator

import lz4.frame
from rosbags.interfaces import MessageDefinition, MessageDefinitionFormat
from rosbags.typesys.msg import normalize_msgtype

MAGIC = b"#ROSBAG V2.0\n"
OP_MSG_DATA, OP_BAG_HEADER, OP_INDEX_DATA, OP_CHUNK, OP_CHUNK_INFO, OP_CONNECTION = 2, 3, 4, 5, 6, 7

_U32 = struct.Struct("<I")
_U64 = struct.Struct("<Q")
_TIME = struct.Struct("<II")
_NO_TIME = 2**63 - 1


class Ros1FormatError(Exception):
    """The file is not a well-formed, indexed ROS1 v2.0 bag; the message names the byte offset."""


@dataclass
class Ros1Connection:
    """One connection (topic + type + definition), as in the bag's connection records."""

    id: int
    topic: str
    msgtype: str  # normalized 'pkg/msg/Name'
    msgdef: MessageDefinition
    digest: str  # md5sum field
    msgcount: int
    callerid: str | None = None
    latching: int | None = None


def normalize_topic(name: str) -> str:
    """Collapse repeated '/' and drop a trailing one (rosbags' spelling of topic names)."""
    lead = "/" if name.startswith("/") else ""
    return lead + "/".join(part for part in name.split("/") if part)


def parse_fields(buf, start: int, end: int, where: str) -> dict[bytes, bytes]:
    """Header fields in buf[start:end]: repeated (uint32 length, b'name=value')."""
    fields = {}
    pos = start
    while pos < end:
        if end - pos < 4:
            raise Ros1FormatError(f"{where}: header field length cut off")
        (size,) = _U32.unpack_from(buf, pos)
        pos += 4
        if size > end - pos:
            raise Ros1FormatError(f"{where}: header field of {size} bytes overruns its header")
        name, sep, value = bytes(buf[pos:pos + size]).partition(b"=")
        if not sep:
            raise Ros1FormatError(f"{where}: header field without '='")
        fields[name] = value
        pos += size
    return fields


def _field(fields: dict, name: str, kind: str, where: str):
    try:
        raw = fields[name.encode()]
        if kind == "u8":
            if len(raw) != 1:
                raise ValueError(name)
            return raw[0]
        if kind == "u32":
            return _U32.unpack(raw)[0]
        if kind == "u64":
            return _U64.unpack(raw)[0]
        if kind == "time":
            sec, nsec = _TIME.unpack(raw)
            return sec * 1_000_000_000 + nsec
        return raw.decode()
    except KeyError:
        raise Ros1FormatError(f"{where}: header field '{name}' missing") from None
    except (struct.error, UnicodeDecodeError, ValueError):
        raise Ros1FormatError(f"{where}: header field '{name}' is not a valid {kind}") from None


class Ros1Reader:
    """Streams an indexed ROS1 v2.0 bag chunk by chunk (see the module docstring)."""

    def __init__(self, path: str | pathlib.Path):
        self.path = pathlib.Path(path)
        self._file: BinaryIO | None = None
        self.connections: list[Ros1Connection] = []
        self.file_size = 0
        self.data_start = 0  # first record after the bag header
        self.index_pos = 0  # start of the index section = end of the chunk data
        self.position = 0  # file offset up to which messages() has read
        self.start_time = self.end_time = 0  # first message time, last message time + 1
        self.message_count = 0
        self.max_overlap_bytes = 0
        self.peak_held_messages = 0
        self.peak_held_bytes = 0
        self._pos = array("q")  # per chunk, in file order
        self._first = array("q")
        self._last = array("q")

    def __enter__(self) -> Ros1Reader:
        self.open()
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None

    # -- low-level record access ---------------------------------------------------------------
    def _read_exact(self, offset: int, size: int, what: str) -> bytes:
        f = self._file
        f.seek(offset)
        data = f.read(size)
        if len(data) != size:
            raise Ros1FormatError(f"truncated {what} at byte {offset}: needs {size} bytes, "
                                  f"the file ends after {len(data)} (file size {self.file_size})")
        return data

    def _record_header(self, offset: int, what: str) -> tuple[dict, int, int]:
        """Fields of the record at OFFSET, offset of its data and the data length."""
        (hlen,) = _U32.unpack(self._read_exact(offset, 4, what))
        where = f"{what} at byte {offset}"
        if hlen > self.file_size - offset - 8:
            raise Ros1FormatError(f"truncated {what} at byte {offset}: header of {hlen} bytes "
                                  f"overruns the file (size {self.file_size})")
        raw = self._read_exact(offset + 4, hlen + 4, what)
        fields = parse_fields(raw, 0, hlen, where)
        (dlen,) = _U32.unpack_from(raw, hlen)
        data_pos = offset + 8 + hlen
        if dlen > self.file_size - data_pos:
            raise Ros1FormatError(f"truncated {what} at byte {offset}: {dlen} data bytes overrun the "
                                  f"file (size {self.file_size})")
        return fields, data_pos, dlen

    # -- open: bag header and index section ------------------------------------------------------
    def open(self) -> None:
        try:
            self._file = open(self.path, "rb")  # noqa: SIM115 - closed in close()
        except OSError as err:
            raise Ros1FormatError(f"cannot open: {err.strerror or err}") from None
        try:
            self._open()
        except BaseException:
            self.close()
            raise

    def _open(self) -> None:
        self._file.seek(0, 2)
        self.file_size = self._file.tell()
        self._file.seek(0)
        magic = self._file.read(len(MAGIC))
        if magic != MAGIC:
            raise Ros1FormatError("not a ROS1 v2.0 bag (the file does not start with '#ROSBAG V2.0') at byte 0")
        fields, data_pos, dlen = self._record_header(len(MAGIC), "bag header record")
        where = f"bag header record at byte {len(MAGIC)}"
        if _field(fields, "op", "u8", where) != OP_BAG_HEADER:
            raise Ros1FormatError(f"{where}: expected op 0x03")
        if fields.get(b"encryptor"):
            raise Ros1FormatError(f"{where}: encrypted bags ({fields[b'encryptor'].decode(errors='replace')}) "
                                  "are not supported")
        self.index_pos = _field(fields, "index_pos", "u64", where)
        conn_count = _field(fields, "conn_count", "u32", where)
        chunk_count = _field(fields, "chunk_count", "u32", where)
        self.data_start = self.position = data_pos + dlen
        if self.index_pos == 0:
            raise Ros1FormatError(f"{where}: bag is not indexed (unfinished recording?); run 'rosbag reindex'")
        if self.index_pos > self.file_size or self.index_pos < self.data_start:
            raise Ros1FormatError(f"{where}: index position {self.index_pos} lies outside the file "
                                  f"(size {self.file_size}): file truncated?")
        offset = self.index_pos
        for _ in range(conn_count):
            conn, offset = self._connection_record(offset)
            self.connections.append(conn)
        counts: dict[int, int] = {}
        chunks = []
        for _ in range(chunk_count):
            chunk, offset = self._chunk_info_record(offset, counts)
            chunks.append(chunk)
        ids = {c.id for c in self.connections}
        if set(counts) - ids:
            raise Ros1FormatError(f"index section at byte {self.index_pos}: chunk infos count messages "
                                  f"of connection(s) {sorted(set(counts) - ids)} without a connection record")
        for c in self.connections:
            c.msgcount = counts.get(c.id, 0)
        chunks.sort()
        for pos, first, last in chunks:
            self._pos.append(pos)
            self._first.append(first)
            self._last.append(last)
        with_msgs = [(f, l) for _, f, l in chunks if f != _NO_TIME]
        self.message_count = sum(counts.values())
        if with_msgs:
            self.start_time = min(f for f, _ in with_msgs)
            self.end_time = max(l for _, l in with_msgs) + 1
        self._suffix_first = self._suffix_min_first()
        self.max_overlap_bytes = self._overlap_bound()

    def _connection_record(self, offset: int) -> tuple[Ros1Connection, int]:
        fields, data_pos, dlen = self._record_header(offset, "connection record")
        where = f"connection record at byte {offset}"
        if _field(fields, "op", "u8", where) != OP_CONNECTION:
            raise Ros1FormatError(f"{where}: expected op 0x07")
        data = self._read_exact(data_pos, dlen, "connection record")
        return self._make_connection(fields, data, where), data_pos + dlen

    @staticmethod
    def _make_connection(fields: dict, data, where: str) -> Ros1Connection:
        conn_fields = parse_fields(data, 0, len(data), where)
        latching = conn_fields.get(b"latching")
        return Ros1Connection(
            id=_field(fields, "conn", "u32", where),
            topic=normalize_topic(_field(fields, "topic", "str", where)),
            msgtype=normalize_msgtype(_field(conn_fields, "type", "str", where)),
            msgdef=MessageDefinition(MessageDefinitionFormat.MSG,
                                     _field(conn_fields, "message_definition", "str", where)),
            digest=_field(conn_fields, "md5sum", "str", where),
            msgcount=0,
            callerid=conn_fields[b"callerid"].decode(errors="replace") if b"callerid" in conn_fields else None,
            latching=int(latching) if latching not in (None, b"") else None)

    def _chunk_info_record(self, offset: int, counts: dict) -> tuple[tuple[int, int, int], int]:
        fields, data_pos, dlen = self._record_header(offset, "chunk info record")
        where = f"chunk info record at byte {offset}"
        if _field(fields, "op", "u8", where) != OP_CHUNK_INFO:
            raise Ros1FormatError(f"{where}: expected op 0x06")
        if _field(fields, "ver", "u32", where) != 1:
            raise Ros1FormatError(f"{where}: chunk info version {_field(fields, 'ver', 'u32', where)} unsupported")
        pos = _field(fields, "chunk_pos", "u64", where)
        count = _field(fields, "count", "u32", where)
        if dlen != 8 * count:
            raise Ros1FormatError(f"{where}: {dlen} data bytes for {count} connections")
        if not self.data_start <= pos < self.index_pos:
            raise Ros1FormatError(f"{where}: chunk position {pos} is outside the chunk data")
        data = self._read_exact(data_pos, dlen, "chunk info record")
        total = 0
        for k in range(count):
            conn, n = struct.unpack_from("<II", data, 8 * k)
            counts[conn] = counts.get(conn, 0) + n
            total += n
        if total == 0:
            return (pos, _NO_TIME, -1), data_pos + dlen
        first = _field(fields, "start_time", "time", where)
        last = _field(fields, "end_time", "time", where)
        return (pos, first, last), data_pos + dlen

    def _suffix_min_first(self) -> array:
        """suffix[i] = earliest message time in chunks i.. (file order); suffix[n] = +inf."""
        n = len(self._pos)
        out = array("q", [_NO_TIME]) * (n + 1)
        for i in range(n - 1, -1, -1):
            out[i] = min(out[i + 1], self._first[i])
        return out

    def _overlap_bound(self) -> int:
        """Most on-disk chunk bytes whose messages may wait in the reorder heap at one time."""
        held: list[tuple[int, int]] = []  # (last time, chunk bytes on disk)
        total = peak = 0
        n = len(self._pos)
        for i in range(n):
            size = (self._pos[i + 1] if i + 1 < n else self.index_pos) - self._pos[i]
            heapq.heappush(held, (self._last[i], size))
            total += size
            while held and held[0][0] < self._suffix_first[i + 1]:
                total -= heapq.heappop(held)[1]
            peak = max(peak, total)
        return peak

    # -- streaming ---------------------------------------------------------------------------
    def messages(self, connections: Iterable[Ros1Connection] = (), start: int | None = None,
                 stop: int | None = None) -> Iterator[tuple[Ros1Connection, int, bytes]]:
        """(connection, record time ns, serialized message) with start <= time < stop, time-ordered."""
        if self._file is None:
            raise Ros1FormatError("reader is not open")
        take_all = not connections
        wanted = list(connections) or list(self.connections)
        rank = {c.id: k for k, c in enumerate(wanted)}
        by_id = {c.id: c for c in self.connections}
        lo = -1 if start is None else start
        hi = _NO_TIME if stop is None else stop
        heap: list = []
        held_bytes = 0
        seq = 0
        chunk_index = 0
        n = len(self._pos)
        offset = self.data_start
        while offset < self.index_pos:
            fields, data_pos, dlen = self._record_header(offset, "record")
            where = f"record at byte {offset}"
            if data_pos + dlen > self.index_pos:
                raise Ros1FormatError(f"{where}: its {dlen} data bytes overrun the index section at byte "
                                      f"{self.index_pos}")
            op = _field(fields, "op", "u8", where)
            if op == OP_CHUNK:
                if chunk_index >= n or self._pos[chunk_index] != offset:
                    raise Ros1FormatError(f"chunk at byte {offset} is not in the bag's index (index damaged? "
                                          "run 'rosbag reindex')")
                i = chunk_index
                chunk_index += 1
                if self._suffix_first[i] >= hi:
                    break  # no later message is before stop
                if self._last[i] >= lo and self._first[i] != _NO_TIME:
                    for conn_id, t, data in self._chunk_messages(fields, offset, data_pos, dlen, by_id):
                        r = rank.get(conn_id)
                        if r is None and take_all:  # connection first seen inside this chunk
                            r = rank[conn_id] = len(rank)
                        if r is not None and lo <= t < hi:
                            heapq.heappush(heap, (t, r, seq, conn_id, data))
                            seq += 1
                            held_bytes += len(data)
                self.peak_held_messages = max(self.peak_held_messages, len(heap))
                self.peak_held_bytes = max(self.peak_held_bytes, held_bytes)
                release_below = self._suffix_first[i + 1]
                self.position = data_pos + dlen
                while heap and heap[0][0] < release_below:
                    t, _, _, conn_id, data = heapq.heappop(heap)
                    held_bytes -= len(data)
                    yield by_id[conn_id], t, data
            elif op == OP_CONNECTION:
                self._learn_connection(fields, self._read_exact(data_pos, dlen, "connection record"),
                                       where, by_id)
            elif op != OP_INDEX_DATA:
                raise Ros1FormatError(f"{where}: unexpected record op 0x{op:02x} between chunks")
            offset = data_pos + dlen
        else:
            if chunk_index != n:
                raise Ros1FormatError(f"the index lists a chunk at byte {self._pos[chunk_index]} that the "
                                      f"chunk data (bytes {self.data_start}..{self.index_pos}) does not contain")
        self.position = self.index_pos
        while heap:
            t, _, _, conn_id, data = heapq.heappop(heap)
            yield by_id[conn_id], t, data

    def _learn_connection(self, fields: dict, data, where: str, by_id: dict) -> None:
        conn = self._make_connection(fields, data, where)
        known = by_id.get(conn.id)
        if known is None:  # not in the index section: keep it so its messages can be named
            self.connections.append(conn)
            by_id[conn.id] = conn
        elif known.topic != conn.topic or known.msgtype != conn.msgtype:
            raise Ros1FormatError(f"{where}: connection {conn.id} is {conn.topic} ({conn.msgtype}) here but "
                                  f"{known.topic} ({known.msgtype}) in the index")

    def _chunk_messages(self, fields: dict, offset: int, data_pos: int, dlen: int,
                        by_id: dict) -> Iterator[tuple[int, int, bytes]]:
        """Decompress one chunk and yield (connection id, time, data) of its message records."""
        where = f"chunk at byte {offset}"
        compression = _field(fields, "compression", "str", where)
        size = _field(fields, "size", "u32", where)
        raw = self._read_exact(data_pos, dlen, "chunk")
        try:
            if compression == "none":
                buf = raw
            elif compression == "bz2":
                buf = bz2.decompress(raw)
            elif compression == "lz4":
                buf = lz4.frame.decompress(raw)
            else:
                raise Ros1FormatError(f"{where}: compression '{compression}' not supported (none, bz2, lz4)")
        except (OSError, ValueError, EOFError, RuntimeError) as err:
            raise Ros1FormatError(f"{where}: {compression} data cannot be decompressed ({err})") from None
        del raw
        if len(buf) != size:
            raise Ros1FormatError(f"{where}: decompressed to {len(buf)} bytes, its header says {size}")
        pos = 0
        while pos < size:
            inner = f"{where}, offset {pos} in the decompressed chunk"
            if size - pos < 4:
                raise Ros1FormatError(f"truncated record in {inner}")
            (hlen,) = _U32.unpack_from(buf, pos)
            if hlen > size - pos - 8:
                raise Ros1FormatError(f"truncated record in {inner}: header of {hlen} bytes overruns the chunk")
            rec = parse_fields(buf, pos + 4, pos + 4 + hlen, inner)
            (rlen,) = _U32.unpack_from(buf, pos + 4 + hlen)
            body = pos + 8 + hlen
            if rlen > size - body:
                raise Ros1FormatError(f"truncated record in {inner}: {rlen} data bytes overrun the chunk")
            op = _field(rec, "op", "u8", inner)
            if op == OP_MSG_DATA:
                conn_id = _field(rec, "conn", "u32", inner)
                if conn_id not in by_id:
                    raise Ros1FormatError(f"message in {inner} uses connection {conn_id}, which has no "
                                          "connection record")
                yield conn_id, _field(rec, "time", "time", inner), buf[body:body + rlen]
            elif op == OP_CONNECTION:
                self._learn_connection(rec, buf[body:body + rlen], inner, by_id)
            else:
                raise Ros1FormatError(f"{inner}: unexpected record op 0x{op:02x} inside a chunk")
            pos = body + rlen
