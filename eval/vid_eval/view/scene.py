"""The entity layout of a run in Rerun, written once for the offline and the live view.

Timeline ``data_time``: the data's own nanosecond timestamps. Entities (``ENTITIES``):

* ``world/vehicle``: pose ``T_WI`` of the estimate (Transform3D with axes), ``world/trajectory``:
  the estimated path, ``world/groundtruth``: the ground-truth path in the estimator's world;
* ``world/force``: the estimated external force as an arrow at the vehicle, ``FORCE_SCALE`` m
  per m/s² (mass-normalized, world frame; 9.81 m/s² of ground reaction = 0.49 m);
* ``cam0/image`` (and ``cam1``): the camera images; ``cam0/image/tracks``: tracked features
  (points, colour by feature id) and ``cam0/image/trails``: their last ``TRAIL`` positions;
* ``plots/force/{x,y,z}`` and ``plots/force_sigma/{x,y,z}`` (body 1-sigma): time series;
  ``status``: the estimator's status messages (live).
"""
from __future__ import annotations

from collections import deque
from typing import Dict, Optional

import numpy as np

from ..errors import ConfigurationError

TIMELINE = "data_time"
FORCE_SCALE = 0.05  # arrow length [m] per m/s^2
TRAIL = 8           # frames of a feature's trail
ENTITIES = {
    "vehicle": "world/vehicle", "trajectory": "world/trajectory", "groundtruth": "world/groundtruth",
    "force": "world/force", "force_plot": "plots/force", "sigma_plot": "plots/force_sigma",
    "status": "status",
}


def image_entity(cam: int) -> str:
    return f"cam{cam}/image"


def rerun():
    """The rerun module, or one clear line saying how to get it."""
    try:
        import rerun as rr
    except ImportError:
        raise ConfigurationError("vid-eval view needs the rerun-sdk package: "
                                 "pip install 'vid-eval[view]' (scripts/setup.sh installs it)") from None
    return rr


def open_recording(rrd: Optional[str], spawn: bool, name: str):
    """A recording stream writing the file ``rrd``, or feeding a spawned viewer."""
    rr = rerun()
    rec = rr.RecordingStream("vid_msckf", recording_id=name)
    if spawn:  # a viewer process of its own (the rerun-sdk wheel ships it)
        rec.spawn()
    else:
        rec.save(rrd)
    rec.log("world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)  # W: z up
    return rec


def _colors(ids: np.ndarray) -> np.ndarray:
    """A stable colour per feature id (golden-ratio hue steps)."""
    import colorsys
    return np.array([[int(255 * c) for c in colorsys.hsv_to_rgb((i * 0.618034) % 1.0, 0.85, 1.0)]
                     for i in ids.astype(np.int64)], dtype=np.uint8)


class Scene:
    """Logs the pieces of a run into one recording (see the module docstring)."""

    def __init__(self, rec):
        self.rr = rerun()
        self.rec = rec
        self.trails: Dict[int, Dict[int, deque]] = {}
        rr = self.rr  # styles, static: one row each however often the entity is logged
        rec.log(ENTITIES["vehicle"], rr.TransformAxes3D(0.3), static=True)
        rec.log(ENTITIES["force"], rr.Arrows3D.from_fields(colors=[[255, 80, 40]], radii=[0.01]), static=True)

    def at(self, t_ns: int) -> None:
        self.rec.set_time(TIMELINE, timestamp=np.datetime64(int(t_ns), "ns"))

    def poses(self, t_ns: np.ndarray, p: np.ndarray, q_wxyz: np.ndarray) -> None:
        """Vehicle poses over time (one column send) and the whole path (static)."""
        rr = self.rr
        self.rec.send_columns(ENTITIES["vehicle"], indexes=[self._times(t_ns)],
                              columns=rr.Transform3D.columns(translation=p, quaternion=q_wxyz[:, [1, 2, 3, 0]]))
        self.path(ENTITIES["trajectory"], p, [30, 144, 255])

    def path(self, entity: str, p: np.ndarray, color, static: bool = True) -> None:
        self.rec.log(entity, self.rr.LineStrips3D([p], colors=[color], radii=[0.01]), static=static)

    def forces(self, t_ns: np.ndarray, origins: np.ndarray, f_world: np.ndarray,
               sigma_body: Optional[np.ndarray] = None) -> None:
        """Force arrows at the vehicle and the force (and sigma) as time series."""
        rr = self.rr
        times = [self._times(t_ns)]
        self.rec.send_columns(ENTITIES["force"], indexes=times,
                              columns=rr.Arrows3D.columns(origins=origins, vectors=FORCE_SCALE * f_world))
        for k, axis in enumerate("xyz"):
            self.rec.send_columns(f"{ENTITIES['force_plot']}/{axis}", indexes=times,
                                  columns=rr.Scalars.columns(scalars=f_world[:, k]))
            if sigma_body is not None:
                self.rec.send_columns(f"{ENTITIES['sigma_plot']}/{axis}", indexes=times,
                                      columns=rr.Scalars.columns(scalars=sigma_body[:, k]))

    def image_file(self, t_ns: int, cam: int, path: str) -> None:
        """A camera image as its file's bytes (PNG/JPEG: decoded by the viewer)."""
        self.at(t_ns)
        self.rec.log(image_entity(cam), self.rr.EncodedImage(path=path))

    def image_array(self, t_ns: int, cam: int, gray: np.ndarray) -> None:
        self.at(t_ns)
        self.rec.log(image_entity(cam), self.rr.Image(gray))

    def tracks(self, t_ns: int, cam: int, ids: np.ndarray, uv: np.ndarray) -> None:
        """Tracked features of one frame and their trails over the last ``TRAIL`` frames."""
        rr = self.rr
        self.at(t_ns)
        colors = _colors(ids)
        ent = image_entity(cam)
        self.rec.log(f"{ent}/tracks", rr.Points2D(uv, colors=colors, radii=[2.0], keypoint_ids=ids.astype(np.uint16)))
        trails = self.trails.setdefault(cam, {})
        alive = set(int(i) for i in ids)
        for i, p in zip(ids.astype(np.int64), uv):
            trails.setdefault(int(i), deque(maxlen=TRAIL)).append(p)
        for i in [i for i in trails if i not in alive]:
            del trails[i]
        strips = [np.array(trails[int(i)]) for i in ids.astype(np.int64)]
        self.rec.log(f"{ent}/trails", rr.LineStrips2D(strips, colors=colors, radii=[1.0]))

    def status(self, t_ns: int, text: str) -> None:
        self.at(t_ns)
        self.rec.log(ENTITIES["status"], self.rr.TextLog(text))

    def _times(self, t_ns: np.ndarray):
        return self.rr.TimeColumn(TIMELINE, timestamp=np.asarray(t_ns, dtype="datetime64[ns]"))
