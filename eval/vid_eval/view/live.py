"""vid_live's LCM output in Rerun as it comes: VID_STATE (pose, path), VID_FORCE (arrow, time
series), VID_STATUS (text log) and, when they are on the same bus, the camera images.

The message classes are the ones lcm-gen writes at build time (``<build>/python/vid``; the
folder is ``--lcm-types``, by default ``$VID_BUILD_DIR/python``, else ``build/python`` of the
repository)."""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path
from typing import Dict, Optional

import numpy as np

from ..errors import ConfigurationError
from ..tools.sim_runs import REPO
from .scene import ENTITIES, Scene

DEFAULT_CHANNELS = {"state": "VID_STATE", "force": "VID_FORCE", "status": "VID_STATUS",
                    "cam0": "CAM0", "cam1": "CAM1"}  # io/include/io/lcm/channels.h
PATH_EVERY = 20  # states between re-logs of the path so far (the path is O(n) per log)


def lcm_types(folder: Optional[str]):
    """Import the generated ``vid`` LCM package from ``folder`` (see the module docstring)."""
    path = Path(folder) if folder else Path(os.environ.get("VID_BUILD_DIR", REPO / "build")) / "python"
    if not (path / "vid" / "state_t.py").is_file():
        raise ConfigurationError(f"{path}/vid/state_t.py: no LCM types there (build the vid_lcm_types "
                                 f"target, or give --lcm-types BUILD/python)")
    if str(path) not in sys.path:
        sys.path.insert(0, str(path))
    import vid  # noqa: F401  (the generated package)
    return vid


def follow(scene: Scene, url: str, channels: Dict[str, str], types_dir: Optional[str],
           idle_s: float, max_s: Optional[float] = None) -> dict:
    """Subscribe and log until no message came for ``idle_s`` (or ``max_s`` passed)."""
    import lcm
    vid = lcm_types(types_dir)
    lc = lcm.LCM(url)
    counts = {k: 0 for k in ("state", "force", "status", "cam0", "cam1")}
    path: list = []
    last_p = np.zeros(3)

    def on_state(_, data):
        nonlocal last_p
        m = vid.state_t.decode(data)
        last_p = np.array(m.p)
        scene.at(m.timestamp)
        scene.rec.log(ENTITIES["vehicle"], scene.rr.Transform3D(
            translation=m.p, quaternion=scene.rr.Quaternion(xyzw=[m.q[1], m.q[2], m.q[3], m.q[0]])))
        path.append(last_p)
        counts["state"] += 1
        if counts["state"] % PATH_EVERY == 1:
            scene.path(ENTITIES["trajectory"], np.array(path), [30, 144, 255], static=False)

    def on_force(_, data):
        m = vid.force_t.decode(data)
        f = np.array(m.f_world)
        scene.forces(np.array([m.timestamp]), last_p[None, :], f[None, :], np.array(m.sigma_body)[None, :])
        counts["force"] += 1

    def on_status(_, data):
        m = vid.status_t.decode(data)
        scene.status(m.timestamp, f"{m.status_text}: {m.message}" if m.message else m.status_text)
        counts["status"] += 1

    def on_image(cam):
        def handle(_, data):
            m = vid.image_t.decode(data)
            if m.encoding == "mono8" and m.size == m.width * m.height:
                scene.image_array(m.timestamp, cam, np.frombuffer(m.data, np.uint8).reshape(m.height, m.width))
                counts[f"cam{cam}"] += 1
        return handle

    lc.subscribe(channels["state"], on_state)
    lc.subscribe(channels["force"], on_force)
    lc.subscribe(channels["status"], on_status)
    lc.subscribe(channels["cam0"], on_image(0))
    lc.subscribe(channels["cam1"], on_image(1))
    start = last = time.monotonic()
    while time.monotonic() - last < idle_s and (max_s is None or time.monotonic() - start < max_s):
        try:
            got = lc.handle_timeout(100)
        except OSError:  # LCM's file provider reports the end of a log this way
            if url.startswith("file://"):
                break
            raise ConfigurationError(f"{url}: reading LCM messages failed") from None
        if got > 0:
            last = time.monotonic()
    if path:
        scene.path(ENTITIES["trajectory"], np.array(path), [30, 144, 255], static=False)
    return counts
