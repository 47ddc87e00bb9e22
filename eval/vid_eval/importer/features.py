"""``--synthetic-features``: stereo feature tracks along the recorded flight, for logs without
cameras. The project's feature simulator does the work (``vid_sim --camera-along TRAJ.tum
--scenario SCENE --out DIR --features-only``, which writes only the camera streams along a
recorded trajectory into OUT/mav0, other files untouched); here the converted mocap poses
become the TUM file it reads (T_WI, IMU pose in W, seconds).
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import List, Optional

import numpy as np

from .errors import DataError, MapError

#: The camera streams vid_sim --camera-along writes under OUT/mav0.
CAMERA_ITEMS = ("feat0", "cam0", "cam1", "landmarks.csv")
DEFAULT_SCENE = Path(__file__).resolve().parents[3] / "config" / "sim" / "recorded_room.yaml"


def find_vid_sim(flag: Optional[str]) -> Path:
    """``--vid-sim PATH``, else ``$VID_BUILD_DIR/bin/vid_sim``, else ``vid_sim`` on PATH."""
    if flag:
        path = Path(flag)
        if not path.is_file():
            raise MapError(f"--vid-sim {flag}: no such file")
        return path
    build = os.environ.get("VID_BUILD_DIR")
    if build and (Path(build) / "bin" / "vid_sim").is_file():
        return Path(build) / "bin" / "vid_sim"
    found = shutil.which("vid_sim")
    if not found:
        raise MapError("--synthetic-features needs vid_sim: pass --vid-sim PATH, set VID_BUILD_DIR "
                       "or put the build's bin/ on PATH")
    return Path(found)


def write_tum(path: Path, t_ns: np.ndarray, p_WI: np.ndarray, q_WI_wxyz: np.ndarray) -> None:
    """TUM ``timestamp tx ty tz qx qy qz qw`` (seconds with 9 decimals, exact from int ns)."""
    with open(path, "w", encoding="utf-8") as f:
        f.write("# timestamp tx ty tz qx qy qz qw  (T_WI: IMU pose in W; written by vid-import)\n")
        for t, p, q in zip(t_ns.tolist(), p_WI.tolist(), q_WI_wxyz.tolist()):
            sec, ns = divmod(int(t), 1_000_000_000)
            f.write(f"{sec}.{ns:09d} {p[0]!r} {p[1]!r} {p[2]!r} {q[1]!r} {q[2]!r} {q[3]!r} {q[0]!r}\n")


def synthesize(out: Path, t_ns: np.ndarray, p_WI: np.ndarray, q_WI_wxyz: np.ndarray,
               vid_sim: Path, scene: Path) -> List[str]:
    """Run vid_sim along the poses; it writes the camera streams into ``out/mav0`` and leaves the
    other files alone. Returns the camera items found afterwards."""
    if not scene.is_file():
        raise MapError(f"--scene {scene}: no such scene file (a vid_sim scenario whose cameras:, scene:, "
                       "render: and features: are used)")
    with tempfile.TemporaryDirectory(prefix="vid_import_") as tmp:
        tum = Path(tmp) / "trajectory_tum.txt"
        write_tum(tum, t_ns, p_WI, q_WI_wxyz)
        cmd = [str(vid_sim), "--camera-along", str(tum), "--scenario", str(scene), "--out", str(out),
               "--features-only", "--quiet"]
        r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        last = (r.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise DataError(f"{vid_sim} --camera-along failed (exit {r.returncode}): {last}")
    found = [item for item in CAMERA_ITEMS if (out / "mav0" / item).exists()]
    if "feat0" not in found:
        raise DataError(f"{vid_sim} --camera-along wrote no {out / 'mav0' / 'feat0'}")
    return found
