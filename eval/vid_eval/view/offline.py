"""A finished run in Rerun: vid_run's folder (state.csv, force.csv, tracks.csv) and, when
given, its dataset (camera images, ground-truth path)."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import numpy as np

from ..errors import ConfigurationError, InputFormatError
from ..tools.gauge import fit_world_gauge
from ..tools.loaders import load_force_estimate, load_state, load_trajectory, load_tracks
from .scene import ENTITIES, Scene


def log_run(scene: Scene, run: Path, dataset: Optional[Path], tracks: Optional[Path],
            image_every: int = 1) -> dict:
    """Log everything found; returns what was logged per entity (counts, for the summary line)."""
    state_csv = run / "state.csv"
    if not state_csv.is_file():
        raise InputFormatError(state_csv, "no state.csv: RUN_DIR must be a vid_run (or vid_live) --out folder")
    st = load_state(state_csv)
    traj = st.trajectory()
    scene.poses(traj.t_ns, traj.p, traj.q)
    counts = {ENTITIES["vehicle"]: len(traj)}
    body, world = load_force_estimate(run / "force.csv")
    at = np.searchsorted(traj.t_ns, world.t_ns).clip(0, len(traj) - 1)  # force rows share state times
    scene.forces(world.t_ns, traj.p[at], world.values, body.sigma)
    counts[ENTITIES["force"]] = len(world)
    tracks = tracks or (run / "tracks.csv" if (run / "tracks.csv").is_file() else None)
    tab = load_tracks(tracks) if tracks is not None else None
    # the run's window: the frames tracked before the filter initialized belong to it too
    span = (int(min(traj.t_ns[0], tab.t_ns[0] if tab is not None else traj.t_ns[0])),
            int(max(traj.t_ns[-1], tab.t_ns[-1] if tab is not None else traj.t_ns[-1])))
    mav0 = _mav0(dataset) if dataset else None
    if mav0 is not None:
        counts.update(_log_groundtruth(scene, mav0, traj))
        counts.update(_log_images(scene, mav0, span, image_every))
    if tab is not None:
        counts.update(_log_tracks(scene, tab))
    return counts


def _mav0(dataset: Path) -> Path:
    mav0 = dataset / "mav0" if (dataset / "mav0").is_dir() else dataset
    if not (mav0 / "imu0").is_dir():
        raise ConfigurationError(f"{dataset}: not a dataset folder (no mav0/imu0)")
    return mav0


def _log_groundtruth(scene: Scene, mav0: Path, est) -> dict:
    """The ground-truth path in the estimator's world (inverse of the posyaw alignment)."""
    gt_csv = mav0 / "state_groundtruth_estimate0" / "data.csv"
    if not gt_csv.is_file():
        return {}
    gt = load_trajectory(str(gt_csv))
    a = fit_world_gauge(est, gt, "posyaw").alignment  # p_gt = s R p_est + t
    p = (gt.p - a.t) @ a.R / a.s
    scene.path(ENTITIES["groundtruth"], p, [200, 200, 200])
    return {ENTITIES["groundtruth"]: 1}


def _log_images(scene: Scene, mav0: Path, span, every: int) -> dict:
    counts = {}
    for cam in (0, 1):
        csv = mav0 / f"cam{cam}" / "data.csv"
        if not csv.is_file():
            continue
        n = 0
        for k, (t, name) in enumerate(_image_rows(csv)):
            if span[0] <= t <= span[1] and k % every == 0 and (mav0 / f"cam{cam}" / "data" / name).is_file():
                scene.image_file(int(t), cam, str(mav0 / f"cam{cam}" / "data" / name))
                n += 1
        counts[f"cam{cam}/image"] = n
    return counts


def _image_rows(csv: Path):
    """(t_ns, file name) of camN/data.csv ('#timestamp [ns],filename')."""
    rows = []
    for lineno, line in enumerate(csv.read_text(encoding="utf-8").splitlines(), start=1):
        if not line.strip() or line.startswith("#"):
            continue
        parts = [x.strip() for x in line.split(",")]
        if len(parts) != 2 or not parts[0].lstrip("-").isdigit():
            raise InputFormatError(csv, "expected 'timestamp [ns],filename'", lineno)
        rows.append((int(parts[0]), parts[1]))
    return rows


def _log_tracks(scene: Scene, tab) -> dict:
    cam, ids, uv = tab.values[:, 0].astype(int), tab.values[:, 1], tab.values[:, 2:4]
    counts = {}
    starts = np.flatnonzero(np.r_[True, np.diff(tab.t_ns) != 0])
    for a, b in zip(starts, np.r_[starts[1:], len(tab.t_ns)]):
        t = int(tab.t_ns[a])
        for c in np.unique(cam[a:b]):
            sel = slice(a, b)
            m = cam[sel] == c
            scene.tracks(t, int(c), ids[sel][m], uv[sel][m])
            counts[f"cam{c}/image/tracks"] = counts.get(f"cam{c}/image/tracks", 0) + 1
    return counts
