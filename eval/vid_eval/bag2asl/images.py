"""sensor_msgs/Image and sensor_msgs/CompressedImage -> 8-bit grayscale (numpy, h x w).

Encodings (documented in README.md):
  mono8, 8UC1                -> as is
  mono16, 16UC1              -> high byte (value >> 8), endianness from is_bigendian
  bgr8, rgb8, bgra8, rgba8,  -> ITU-R BT.601 luma, 0.299 R + 0.587 G + 0.114 B, rounded
  8UC3 (as bgr8), 8UC4 (as bgra8)
  CompressedImage (png/jpeg) -> decoded by Pillow and converted to luma ("L")
Row padding (step > width * bytes per pixel) is removed.
"""
from __future__ import annotations

import io

import numpy as np
from PIL import Image

from .errors import UnknownTypeError

_LUMA = np.array([0.299, 0.587, 0.114])  # R, G, B weights

# encoding -> (channels, bytes per channel, channel order or None)
_ENCODINGS = {
    "mono8": (1, 1, None), "8uc1": (1, 1, None),
    "mono16": (1, 2, None), "16uc1": (1, 2, None),
    "bgr8": (3, 1, "bgr"), "8uc3": (3, 1, "bgr"), "rgb8": (3, 1, "rgb"),
    "bgra8": (4, 1, "bgr"), "8uc4": (4, 1, "bgr"), "rgba8": (4, 1, "rgb"),
}

SUPPORTED = sorted(_ENCODINGS)


def _color_to_gray(pix: np.ndarray, order: str) -> np.ndarray:
    """pix: h x w x c uint8 (c = 3 or 4) -> h x w uint8 luma."""
    r, g, b = (pix[..., 2], pix[..., 1], pix[..., 0]) if order == "bgr" else (
        pix[..., 0], pix[..., 1], pix[..., 2])
    luma = _LUMA[0] * r + _LUMA[1] * g + _LUMA[2] * b
    return np.clip(np.rint(luma), 0, 255).astype(np.uint8)


def raw_to_gray(encoding: str, height: int, width: int, step: int, is_bigendian: int,
                data: np.ndarray, where: str) -> np.ndarray:
    """Convert the fields of a sensor_msgs/Image to a h x w uint8 array."""
    key = encoding.lower()
    if key not in _ENCODINGS:
        raise UnknownTypeError(
            f"{where}: image encoding '{encoding}' not supported (supported: {', '.join(SUPPORTED)})")
    channels, depth, order = _ENCODINGS[key]
    row_bytes = width * channels * depth
    buf = np.frombuffer(data, dtype=np.uint8) if not isinstance(data, np.ndarray) else data
    if step < row_bytes or buf.size < step * (height - 1) + row_bytes:
        raise UnknownTypeError(
            f"{where}: image data too short for {width}x{height} {encoding} with step {step}")
    if buf.size < step * height:  # last row may omit its padding
        buf = np.concatenate([buf, np.zeros(step * height - buf.size, np.uint8)])
    rows = buf[: step * height].reshape(height, step)[:, :row_bytes]
    if depth == 2:
        dtype = ">u2" if is_bigendian else "<u2"
        return (np.ascontiguousarray(rows).view(dtype).reshape(height, width) >> 8).astype(np.uint8)
    if channels == 1:
        return rows
    return _color_to_gray(rows.reshape(height, width, channels), order)


def image_msg_to_gray(msg, where: str) -> np.ndarray:
    return raw_to_gray(msg.encoding, int(msg.height), int(msg.width), int(msg.step),
                       int(msg.is_bigendian), msg.data, where)


def compressed_msg_to_gray(msg, where: str) -> np.ndarray:
    try:
        with Image.open(io.BytesIO(bytes(msg.data))) as img:
            return np.asarray(img.convert("L"))
    except Exception as err:  # Pillow raises several types for bad data
        raise UnknownTypeError(f"{where}: cannot decode compressed image '{msg.format}': {err}") from None
