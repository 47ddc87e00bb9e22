"""A small progress bar on stderr, drawn only when stderr is a terminal.

`done`/`total` are in any unit (bytes read of a ROS1 bag, nanoseconds of bag time otherwise)."""
from __future__ import annotations

import sys
import time


class Progress:
    def __init__(self, total: int, enabled: bool | None = None, stream=None):
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.total = max(int(total), 1)
        self.start = time.monotonic()
        self.last_draw = 0.0

    def update(self, done: int, image_bytes: int, force: bool = False) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if not force and now - self.last_draw < 0.1:
            return
        self.last_draw = now
        frac = min(max(done / self.total, 0.0), 1.0)
        width = 30
        fill = int(frac * width)
        elapsed = now - self.start
        rate = image_bytes / 1e6 / elapsed if elapsed > 0 else 0.0
        eta = elapsed * (1 - frac) / frac if frac > 0 else 0.0
        self.stream.write(f"\r[{'#' * fill}{'.' * (width - fill)}] {frac * 100:5.1f}%  "
                          f"{elapsed:6.1f}s elapsed  eta {eta:6.1f}s  images {rate:6.1f} MB/s")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()
