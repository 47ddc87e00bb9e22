"""Mass-identification plots with every curve visible (issue #25): ELM, RELM and OSELM give
the same estimate to ~1e-6 kg and the filters agree closely, so overlaid curves hid each other.
The figures are checked as rendered: hiding any labelled curve must change pixels."""
from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from plot_checks import hidden_curves
from vid_eval.plots import elm_study
from vid_eval.plots import massid_study as massid_plots
from vid_eval.plots.methods import CaseSeries, methods_grid, rmspe


def _series(tmp_path, rng):
    """series/<traj>__<profile>.csv as `vid_massid elm-study` writes them; ELM = RELM exactly,
    OSELM 1e-7 kg away (what the study measures)."""
    t = np.arange(0, 10, 0.01)
    folder = tmp_path / "series"
    folder.mkdir()
    for profile, truth in (("constant", np.full_like(t, 1.2)), ("step_drop", np.where(t < 5, 1.2, 0.9))):
        relm = truth + 0.01 * rng.standard_normal(len(t))
        cols = {"t": t, "mass_true": truth, "elm": relm, "relm": relm.copy(), "oselm": relm + 1e-7}
        with open(folder / f"lemniscate__{profile}.csv", "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols)
            w.writerows(np.column_stack(list(cols.values())))
    return {p.stem.split("__")[1]: p for p in folder.glob("*.csv")}


def test_elm_grid_shows_every_method_and_the_truth(tmp_path):
    files = _series(tmp_path, np.random.default_rng(7))
    fig = elm_study.elm_figure("lemniscate", files)
    titles = [ax.get_title() for ax in fig.axes]
    assert len(fig.axes) == 2 * 3  # profiles x methods
    assert [t.split(":")[0] for t in titles[:3]] == ["relm", "elm", "oselm"]
    assert "max |elm − relm| 0.0e+00 kg" in titles[1] and "max |oselm − relm| 1.0e-07 kg" in titles[2]
    labels = {ln.get_label().split(" ")[0] for ax in fig.axes for ln in ax.get_lines()}
    assert labels == {"truth", "elm", "relm", "oselm"}
    assert hidden_curves(fig) == []


def test_elm_plots_command_writes_each_trajectory(tmp_path):
    """`vid-eval elm-plots OUT`, as `vid_massid elm-study --plots` runs it."""
    _series(tmp_path, np.random.default_rng(7))
    vid_eval = Path(sys.executable).parent / "vid-eval"
    r = subprocess.run([vid_eval, "elm-plots", tmp_path], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "figures" / "elm_lemniscate.png").stat().st_size > 10000
    r = subprocess.run([vid_eval, "elm-plots", tmp_path / "nothing"], capture_output=True, text=True)
    assert r.returncode == 1 and r.stderr.count("\n") == 1 and "no series/ folder" in r.stderr, r.stderr


def test_hidden_nodes_plot_shows_equal_elm_and_relm(tmp_path):
    rows = [{"trajectory": tr, "method": m, "hidden": str(L), "test_rmse_pct": str(2 + 0.001 * L + k),
             "weight_norm": str(3 + 0.01 * L + 2 * k)}
            for k, tr in enumerate(("loop", "square")) for m in ("elm", "relm") for L in (50, 100, 200, 400)]
    fig = elm_study.hidden_nodes_figure(rows)
    assert hidden_curves(fig) == []
    assert {ln.get_label() for ln in fig.axes[0].get_lines()} == {"loop elm", "loop relm", "square elm", "square relm"}


def test_filter_grid_shows_every_filter(tmp_path):
    """vid_massid report's per-trajectory figure (massid_plots) on estimates CSVs."""
    rng = np.random.default_rng(3)
    t = np.arange(0, 8, 0.01)
    for prof in ("constant", "up_down"):
        truth = np.where((t > 3) & (t < 6), 1.5, 1.2) if prof == "up_down" else np.full_like(t, 1.2)
        d = tmp_path / "estimates" / "loop" / prof
        d.mkdir(parents=True)
        base = truth + 0.002 * rng.standard_normal(len(t))
        cols = {"t": t, "mass_true": truth, "thrust_cmd": 12 + 0 * t, "wx": 0 * t, "wy": 0 * t, "wz": 0 * t,
                "ekf": base, "ukf": base + 1e-5, "msckf": base - 1e-5, "swls": base, "vio": base + 2e-5}
        with open(d / "run_000.csv", "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols)
            w.writerows(np.column_stack(list(cols.values())))
    fig = massid_plots.trajectory_figure("loop", massid_plots.find_runs(tmp_path))
    assert len(fig.axes) == 2 * 5
    assert hidden_curves(fig) == []


def test_overlaid_equal_curves_are_detected_as_hidden():
    """The check itself can fail: two equal curves on one axes, as the plots drew them before."""
    import matplotlib.pyplot as plt

    t = np.linspace(0, 1, 200)
    fig, ax = plt.subplots()
    ax.plot(t, np.sin(t), lw=1.0, label="elm")
    ax.plot(t, np.sin(t), lw=1.0, label="relm")
    assert hidden_curves(fig) == [": elm"]
    case = CaseSeries("c", t, np.sin(t) + 2, {"a": np.sin(t) + 2.01, "b": np.sin(t) + 2.01})
    assert hidden_curves(methods_grid([case], ["a", "b"])) == []
    assert rmspe(np.array([1.1]), np.array([1.0])) == pytest.approx(10.0)
