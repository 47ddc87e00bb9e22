#!/usr/bin/env python3
"""Writes the two 64x48 8-bit grayscale PNGs of the EuRoC-layout sample (run once; committed).

Uses only the standard library (zlib) so it runs anywhere: python3 make_sample_pngs.py
"""
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
STAMPS = [1403636579763555584, 1403636579813555456]
W, H = 64, 48


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def png(pixels):
    raw = b"".join(b"\x00" + bytes(row) for row in pixels)  # filter type 0 per row
    ihdr = struct.pack(">IIBBBBB", W, H, 8, 0, 0, 0, 0)  # 8-bit grayscale
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


for i, stamp in enumerate(STAMPS):
    # A checkerboard shifted by 2 px between the frames (something a tracker could follow).
    pixels = [[(40 if ((x + 2 * i) // 8 + y // 8) % 2 else 200) for x in range(W)] for y in range(H)]
    path = os.path.join(HERE, "mav0", "cam0", "data", f"{stamp}.png")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(png(pixels))
