#!/usr/bin/env python3
"""Feed the estimator sample by sample from Python and read its state back.

    PYTHONPATH=build/python .venv/bin/python python/examples/push_samples.py SEQ [--config config/sim]

SEQ is a dataset folder (EuRoC/ASL layout with our extensions, e.g. from ``vid_sim``). The
streams are read with numpy, images decoded with Pillow, and pushed in time order with the
tie order of ``vid_run``'s reader (IMU, rotors, thrust, camera), so the estimates equal
``vid_run``'s state.csv. Prints the final state and writes ``--out`` (an .npz of every
estimate) when given. In a live program the samples would come from your drivers instead.
"""
from __future__ import annotations

import argparse
import pathlib
import sys

import numpy as np
from PIL import Image

import vid_msckf

# vid_run's reader breaks timestamp ties in this order (io/src/dataset_reader.cpp).
IMU, ROTORS, THRUST, CAMERA = range(4)


def _rows(csv: pathlib.Path) -> np.ndarray:
    """Numeric rows of an ASL CSV (header skipped), timestamps kept exact as int64 column 0."""
    return np.loadtxt(csv, delimiter=",", comments="#", ndmin=2, dtype=object)


def events(mav0: pathlib.Path) -> list:
    """Every measurement of the dataset as (t_ns, kind, payload), sorted as vid_run reads them."""
    out = []
    imu = _rows(mav0 / "imu0" / "data.csv")
    for r in imu:
        out.append((int(r[0]), IMU, (np.array(r[1:4], float), np.array(r[4:7], float))))
    if (mav0 / "rotor0" / "data.csv").exists():
        for r in _rows(mav0 / "rotor0" / "data.csv"):
            out.append((int(r[0]), ROTORS, [float(x) for x in r[1:]]))
    if (mav0 / "thrust0" / "data.csv").exists():
        for r in _rows(mav0 / "thrust0" / "data.csv"):
            out.append((int(r[0]), THRUST, float(r[1])))
    cams = [c for c in ("cam0", "cam1") if (mav0 / c / "data.csv").exists()]
    if cams:
        names = [dict((int(t), str(f).strip()) for t, f in _rows(mav0 / c / "data.csv")) for c in cams]
        for t in sorted(names[0]):
            out.append((t, CAMERA, [mav0 / c / "data" / n[t] for c, n in zip(cams, names) if t in n]))
    out.sort(key=lambda e: (e[0], e[1]))  # stable: within a stream, file order
    return out


def push_dataset(system: "vid_msckf.System", mav0: pathlib.Path) -> None:
    """Push every measurement of ``mav0`` into ``system`` and finish."""
    for t, kind, payload in events(mav0):
        if kind == IMU:
            system.push_imu(t, *payload)
        elif kind == ROTORS:
            system.push_rotors(t, payload)
        elif kind == THRUST:
            system.push_thrust(t, payload)
        else:
            images = [np.asarray(Image.open(p).convert("L")) for p in payload]
            system.push_images(t, images[0], images[1] if len(images) > 1 else None)
    system.finish()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", type=pathlib.Path, help="dataset folder (SEQ or SEQ/mav0)")
    ap.add_argument("--config", type=pathlib.Path, help="preset folder (default: the dataset's own files)")
    ap.add_argument("--out", type=pathlib.Path, help="write every estimate to this .npz")
    a = ap.parse_args(argv)
    mav0 = a.dataset / "mav0" if (a.dataset / "mav0").is_dir() else a.dataset
    if not (mav0 / "imu0" / "data.csv").exists():
        print(f"push_samples: {mav0}: no imu0/data.csv (not a dataset folder)", file=sys.stderr)
        return 2
    system = vid_msckf.System(dataset=a.dataset, config=a.config)
    push_dataset(system, mav0)
    est = system.latest()
    if est is None:
        print(f"push_samples: the estimator never initialized ({system.status_message})", file=sys.stderr)
        return 1
    print(f"{system.estimates} estimates, {system.camera_frames} frames, status {system.status}")
    print("p_WI [m]      ", np.array2string(est["p_WI"], precision=3))
    print("F_ext_I [m/s2]", np.array2string(est["F_ext_I"], precision=3),
          "±", np.array2string(np.sqrt(np.diag(est["cov_F_I"])), precision=3))
    if a.out:
        np.savez(a.out, **system.history())
        print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
