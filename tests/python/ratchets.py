"""Ratchet + target pairs (docs/testing.md): no tests here.

A figure the estimator does not yet reach is held twice:

* a passing **ratchet** at today's measured value plus a margin from its spread over seeds
  (`ratchet(...)`): a regression fails it; an improvement prints a note to tighten it;
* a **strict xfail** at the target whose only expected failure is the comparison itself: the
  marker `target_not_met(reason)` expects `TargetNotMet` (raised by `target(...)`), so a crash,
  a non-zero exit or a wrong count inside the test (plain `assert`, `AssertionError`) fails it.

Both print the measured value (`pytest -s` or the captured output of a failure shows it).
"""
from __future__ import annotations

import pytest


class TargetNotMet(AssertionError):
    """The figure misses its target: the one failure a strict xfail of a target expects."""


def target_not_met(reason: str):
    """Strict xfail that expects only `TargetNotMet`: setup failures stay failures."""
    return pytest.mark.xfail(strict=True, raises=TargetNotMet, reason=reason)


def target(what: str, value: float, limit: float, higher_is_better: bool = False, unit: str = "") -> None:
    """Raise TargetNotMet unless value meets the target (<= limit, or >= with higher_is_better)."""
    ok = value >= limit if higher_is_better else value <= limit
    print(f"[target] {what}: {value:.4g}{unit} (target {'>=' if higher_is_better else '<='} {limit:.4g}{unit})")
    if not ok:
        raise TargetNotMet(f"{what} {value:.4g}{unit}, target {'>=' if higher_is_better else '<='} {limit:.4g}{unit}")


def ratchet(what: str, value: float, limit: float, measured: float, higher_is_better: bool = False,
            unit: str = "") -> None:
    """Assert value is no worse than limit (today's `measured` value plus its margin, as the
    caller's comment derives it). Prints the value; one that beats `measured` by more than the
    margin asks for the ratchet to be tightened (docs/testing.md)."""
    worse = value < limit if higher_is_better else value > limit
    print(f"[ratchet] {what}: {value:.4g}{unit} (ratchet {limit:.4g}, measured {measured:.4g} when set)")
    assert not worse, (f"{what} regressed: {value:.4g}{unit}, ratchet {'>=' if higher_is_better else '<='} "
                       f"{limit:.4g} (measured {measured:.4g} when set)")
    margin = abs(limit - measured)
    if (measured - value if not higher_is_better else value - measured) > margin:
        print(f"[ratchet] {what} improved past its margin: tighten the ratchet to the new value "
              f"(docs/testing.md)")


def band(what: str, value: float, lo: float, hi: float, unit: str = "") -> None:
    """Two-sided ratchet: lo <= value <= hi (a consistency figure may fail in either direction)."""
    print(f"[ratchet] {what}: {value:.4g}{unit} (band [{lo:.4g}, {hi:.4g}])")
    assert lo <= value <= hi, f"{what} {value:.4g}{unit} outside [{lo:.4g}, {hi:.4g}]"
