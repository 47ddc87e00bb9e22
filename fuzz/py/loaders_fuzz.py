#!/usr/bin/env python3
"""atheris target of vid-eval's file loaders (eval/vid_eval/tools/loaders.py, table_reader.py).

Byte 0 mod 10 picks the loader (the digits '0'..'9' do): 0 TUM, 1 EuRoC pose CSV, 2 state.csv,
3 format detection + load (.txt), 4 the same for .csv, 5 force.csv, 6 force0 CSV, 7 mass CSV,
8 phase0 CSV, 9 vehicle.yaml mass; the rest is the file. The loaders' documented error,
InputFormatError (a VidEvalError), is an expected outcome; any other exception is a bug.
Run through fuzz/run.sh, or: python loaders_fuzz.py [libFuzzer flags] CORPUS_DIR...
"""
import os
import pathlib
import sys
import tempfile

import atheris

# The source tree itself (not the editable install's import hook, which atheris cannot instrument).
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "eval"))

with atheris.instrument_imports():
    from vid_eval.tools import loaders
    from vid_eval.errors import VidEvalError

# run.sh's scratch folder (removed after the run), else tmpfs: a file is written per input
_DIR = tempfile.mkdtemp(prefix="vid_fuzz_py_", dir=os.environ.get("VID_FUZZ_SCRATCH")
                        or ("/dev/shm" if os.path.isdir("/dev/shm") else None))
_LOADERS = [loaders.load_tum, loaders.load_euroc_pose_csv, loaders.load_state, loaders.load_trajectory,
            loaders.load_trajectory, loaders.load_force_estimate, loaders.load_force_gt, loaders.load_mass,
            loaders.load_phases, loaders.load_vehicle_mass]


def test_one_input(data: bytes) -> None:
    if not data:
        return
    kind = data[0] % len(_LOADERS)
    path = os.path.join(_DIR, "traj.txt" if kind == 3 else "data.csv")
    with open(path, "wb") as f:
        f.write(data[1:])
    try:
        _LOADERS[kind](path)
    except VidEvalError:
        pass


def main() -> None:
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
