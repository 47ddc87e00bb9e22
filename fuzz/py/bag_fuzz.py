#!/usr/bin/env python3
"""atheris target of the ROS1 bag reading of vid-bag2asl: the sequential reader
(eval/vid_eval/bag2asl/ros1reader.py) and the Bag layer on top (bagio.py: typestores built from
the bag's embedded definitions, message decoding).

The input is a .bag file. Ros1FormatError from the reader, and the converter's own errors
(Bag2AslError: CorruptBagError, UnknownTypeError) from the Bag layer, are expected outcomes;
any other exception (struct.error, IndexError, ...) is a bug.
Run through fuzz/run.sh, or: python bag_fuzz.py [libFuzzer flags] CORPUS_DIR...
"""
import os
import pathlib
import sys
import tempfile

import atheris

# The source tree itself (not the editable install's import hook, which atheris cannot instrument).
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "eval"))

with atheris.instrument_imports():
    from vid_eval.bag2asl.bagio import Bag
    from vid_eval.bag2asl.errors import Bag2AslError
    from vid_eval.bag2asl.ros1reader import Ros1FormatError, Ros1Reader

_DIR = tempfile.mkdtemp(prefix="vid_fuzz_bag_", dir=os.environ.get("VID_FUZZ_SCRATCH")
                        or ("/dev/shm" if os.path.isdir("/dev/shm") else None))
_PATH = pathlib.Path(_DIR) / "in.bag"
_MAX_MESSAGES = 200


def read_raw() -> None:
    """The reader alone: every record it yields."""
    with Ros1Reader(_PATH) as r:
        for n, _ in enumerate(r.messages()):
            if n >= _MAX_MESSAGES:
                break


def read_bag() -> None:
    """As vid-bag2asl reads: topics, then every message decoded with its connection's type."""
    bag = Bag(_PATH)
    try:
        bag.topics()
        bag.topic_list()
        bag.reader_summary()
        deser = {}
        for n, (conn, _, raw) in enumerate(bag.messages(bag.reader.connections, None, None)):
            if conn.id not in deser:
                deser[conn.id] = bag.deserializer(conn)
            deser[conn.id](raw)
            if n >= _MAX_MESSAGES:
                break
    finally:
        bag.close()


def test_one_input(data: bytes) -> None:
    _PATH.write_bytes(data)
    try:
        read_raw()
    except Ros1FormatError:
        pass
    try:
        read_bag()
    except Bag2AslError:
        pass


def main() -> None:
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
