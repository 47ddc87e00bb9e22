"""Without phase0 `vid-eval traj` and `vid-eval force` print and write what they did before
issue #29: the goldens in tests/python/golden/ were recorded with vid_eval at 6a5dc8f (before
the per-phase report) on the folder of phase_testdata.write_flight without phase0, by running
this file as a script with --update (the named command that records them; a change of the
goldens is reviewed like code, with the commit of vid_eval it ran):

    PYTHONPATH=<old checkout>/eval:tests/python python tests/python/test_eval_phases_unchanged.py --update

Printed text must be byte-identical, the JSON must have the same keys and the same values. Keys
added to the output since the recording are listed in ADDED_SINCE_RECORDING (never written into
the golden by the code under test); each has its own test of its value.
"""
from __future__ import annotations

import json
import pathlib
import sys

import pytest

from eval_testdata import run_cli_in_process
from phase_testdata import MASS, write_flight

GOLDEN = pathlib.Path(__file__).resolve().parent / "golden"
TMP = "<TMP>"  # the folder the case was written to, in the goldens
# Keys vid_eval gained after the goldens were recorded: {command: {key path: where its value is tested}}.
ADDED_SINCE_RECORDING = {
    "traj": {},
    "force": {".force.fraction_within_3sigma": "eddff49 (#25); test_eval_force_mass.py"},
}


def _commands(paths: dict, out: pathlib.Path) -> dict:
    return {"traj": ("traj", paths["state"], paths["gt"], "--json", out / "traj.json"),
            "force": ("force", paths["force"], paths["force0"], "--mass", MASS,
                      "--json", out / "force.json")}


def _run_all(root: pathlib.Path) -> dict:
    """{command: (stdout, JSON text with the folder replaced by <TMP>)}."""
    paths = write_flight(root, phases=False)
    results = {}
    for name, args in _commands(paths, root).items():
        proc = run_cli_in_process(*args)
        assert proc.returncode == 0, proc.stderr
        text = (root / f"{name}.json").read_text().replace(str(root.resolve()), TMP)
        results[name] = (proc.stdout, text)
    return results


def _keys(obj, prefix=""):
    """Every key path of a JSON value (list items share the path ``[]``)."""
    if isinstance(obj, dict):
        return {p for k, v in obj.items() for p in {f"{prefix}.{k}"} | _keys(v, f"{prefix}.{k}")}
    if isinstance(obj, list):
        return {p for v in obj for p in _keys(v, prefix + "[]")}
    return set()


@pytest.mark.parametrize("command", ["traj", "force"])
def test_output_without_phase0_is_unchanged(tmp_path, command):
    stdout, text = _run_all(tmp_path)[command]
    assert stdout == (GOLDEN / f"phases_absent_{command}.txt").read_text()
    got, want = json.loads(text), json.loads((GOLDEN / f"phases_absent_{command}.json").read_text())
    assert "phases" not in got
    assert list(got) == list(want)  # the same top-level keys in the same order
    got = strip_added(command, got, want)
    assert _keys(got) == _keys(want)
    assert _same(got, want)


def strip_added(command: str, got: dict, want: dict) -> dict:
    """got without the keys added since the golden was recorded (each must be in got and not
    in the golden: the golden stays as recorded)."""
    added = set(ADDED_SINCE_RECORDING[command])
    assert added <= _keys(got) and not added & _keys(want), "listed as added, yet missing or in the golden"
    got = json.loads(json.dumps(got))
    for path in added:
        *parents, last = path.strip(".").split(".")
        obj = got
        for k in parents:
            obj = obj[k]
        del obj[last]
    return got


def _same(a, b) -> bool:
    """Equal JSON values, floats to 1e-9 relative (the last bits may differ across BLAS)."""
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return isinstance(b, list) and len(a) == len(b) and all(map(_same, a, b))
    if isinstance(a, float) and isinstance(b, (int, float)):
        return a == pytest.approx(b, rel=1e-9, abs=1e-12)
    return a == b


if __name__ == "__main__":  # record the goldens with the vid_eval on PYTHONPATH
    import tempfile

    if sys.argv[1:] != ["--update"]:
        sys.exit("usage: PYTHONPATH=<checkout>/eval:tests/python python tests/python/test_eval_phases_unchanged.py "
                 "--update  (rewrites tests/python/golden/phases_absent_*; commit with the vid_eval commit used)")

    with tempfile.TemporaryDirectory() as tmp:
        for name, (stdout, text) in _run_all(pathlib.Path(tmp)).items():
            (GOLDEN / f"phases_absent_{name}.txt").write_text(stdout)
            (GOLDEN / f"phases_absent_{name}.json").write_text(text)
            print(f"recorded {name}", file=sys.stderr)
