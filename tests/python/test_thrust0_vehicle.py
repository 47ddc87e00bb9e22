"""Dynamics mode on thrust0 (issue #52 item 2.3): thrust0 needs only vehicle.yaml's mass_kg, also
beside a rotor0 stream whose rotor_thrust_coefficients are not given (thrust0 is then the thrust,
rotor0 unused, summary.json says so); the error without vehicle.yaml names what is missing."""
from __future__ import annotations

import json
import subprocess
import types

from bad_inputs_data import dataset, vid_run
from bad_inputs_faults import _drop_coefficients, _rotor_to_thrust, vehicle_case
from test_vid_run_helpers import simulate_cached


def _ctx():
    return types.SimpleNamespace(feat=simulate_cached("vid17_like_short.yaml", 3.0, 1, features_only=True))


def test_thrust0_beside_rotor0_without_coefficients_runs(tmp_path):
    ctx = _ctx()
    ds = dataset(ctx, tmp_path, "feat")
    _rotor_to_thrust(ds, 1.0, keep_rotor=True)
    _drop_coefficients(ds)
    r = subprocess.run(vid_run(ds, tmp_path, "--mode", "dynamics"), capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["status"] == "ok" and s["mode"] == "dynamics"
    assert s["thrust_source"].startswith("thrust0")


def test_thrust0_without_vehicle_names_only_mass(tmp_path):
    argv, named = vehicle_case("x", True, "none").make(_ctx(), tmp_path)
    r = subprocess.run(argv, capture_output=True, text=True, timeout=300)
    assert r.returncode == 1
    assert "vehicle.yaml with mass_kg" in r.stderr and "rotor_thrust_coefficients" not in r.stderr, r.stderr
