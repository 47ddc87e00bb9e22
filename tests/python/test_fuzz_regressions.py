"""Inputs the atheris targets (fuzz/py/, issue #26) found escaping the loaders with an exception
other than InputFormatError; each must now be one InputFormatError naming file (and line)."""
from __future__ import annotations

import pytest

from vid_eval.tools import loaders
from vid_eval.errors import InputFormatError


def _error(tmp_path, name: str, data: bytes, loader) -> InputFormatError:
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(InputFormatError) as info:
        loader(path)
    return info.value


def test_table_not_utf8_names_the_line(tmp_path):
    # fuzz input (loaders_fuzz '7', mass CSV): raised UnicodeDecodeError from the line iterator
    err = _error(tmp_path, "mass.csv", b"#timestamp [ns],mass [kg]\n1,3.1\n2,3\xec\x01\n", loaders.load_mass)
    assert str(err) == f"{tmp_path / 'mass.csv'}:3: mass CSV: not UTF-8 text (byte 0xec)"


def test_trajectory_detection_not_utf8(tmp_path):
    err = _error(tmp_path, "traj.txt", b"\xff\xfe1 0 0 0 0 0 0 1\n", loaders.load_trajectory)
    assert err.line == 1 and "trajectory: not UTF-8 text (byte 0xff)" in str(err)


@pytest.mark.parametrize("data, loader", [
    (b"99999999999999999999,3.1\n", loaders.load_mass),       # was OverflowError from numpy
    (b"-9223372036854775809,3.1\n", loaders.load_mass),
    (b"1e99999 0 0 0 0 0 0 1\n", loaders.load_tum),          # was decimal.Overflow (x 1e9)
    (b"1e400000000,0,0,-30\n", loaders.load_force_gt),       # a 400-million-digit integer
])
def test_timestamp_beyond_int64(tmp_path, data, loader):
    err = _error(tmp_path, "t.csv", data, loader)
    assert err.line == 1 and "is out of range (int64 nanoseconds)" in str(err)


def test_timestamp_int64_limits_still_load(tmp_path):
    path = tmp_path / "mass.csv"
    path.write_text("-9223372036854775808,3.0\n9223372036854775807,3.1\n")
    assert loaders.load_mass(path).t_ns.tolist() == [-(2**63), 2**63 - 1]


@pytest.mark.parametrize("text, message", [
    ("mass_kg: 1" + "0" * 400, "key 'mass_kg' is not a number"),         # was OverflowError
    ("mass_kg: 2001-13-01", "invalid YAML value (month must be in 1..12)"),  # was ValueError
    ("mass_kg: " + "[" * 3000, "invalid YAML (nested too deeply)"),      # was RecursionError
    (b"mass_kg: 3\xe9".decode("latin-1"), "vehicle.yaml: not UTF-8 text (byte 0xe9)"),
])
def test_vehicle_yaml(tmp_path, text, message):
    err = _error(tmp_path, "vehicle.yaml", text.encode("latin-1"), loaders.load_vehicle_mass)
    assert message in str(err)
