"""Issue 17: abrupt external forces (tether snaps, impacts, steps, a recorded force file) are
followed without rejecting the accelerometer, under the one set of defaults (config/sim).

Each preset runs with the force-jump detection (the default) and without it (the estimator
before issue 17), feature level, fixed seed, random initial heading. Thresholds are the issue's
acceptance values; those the estimator does not reach (force RMSE on rope_snap and impacts,
settling after steps) are strict xfails with the measured numbers and the reason
(docs/notes/abrupt-forces.md), each next to a ratchet at today's value (docs/testing.md).
"""
import shutil

import pytest

from ratchets import ratchet, target, target_not_met
from test_vid_run_helpers import REPO, run_and_score, simulate

ABRUPT = ["rope_snap_short", "impacts_short", "force_steps_short"]


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    """config/sim as it is, and a copy as the estimator was before issue 17: the force-jump
    detection off and a gate that rejects (instead of down-weighting) samples past it."""
    base = tmp_path_factory.mktemp("cfg")
    off = base / "jump_off"
    shutil.copytree(REPO / "config" / "sim", off)
    with open(off / "estimator.yaml", "a") as fh:
        fh.write("\nforce_jump_detection: false\naccel_gate_downweight: false\n")
    return {"on": REPO / "config" / "sim", "off": off}


_RUNS = {}


def run_preset(configs, tmp_path_factory, preset, duration=None, noise_free=False, which="on"):
    """vid_sim (features, seed 1) once per preset, vid_run once per configuration; scores."""
    key = (preset, duration, noise_free, which)
    if key not in _RUNS:
        base = tmp_path_factory.getbasetemp() / "abrupt"
        seq = base / f"{preset}_{duration}_{noise_free}"
        if not (seq / "mav0" / "imu0" / "data.csv").exists():
            scenario = REPO / "config" / "sim" / f"{preset}.yaml"
            dur = duration or float(scenario.read_text().split("duration_s:")[1].split()[0])
            simulate(seq, f"{preset}.yaml", dur, 1, True, noise_free=noise_free)
        out = base / f"run_{preset}_{duration}_{noise_free}_{which}"
        _RUNS[key] = run_and_score(seq, out, configs[which], skip_s=5.0)
    return _RUNS[key]


@pytest.mark.parametrize("preset", ABRUPT)
def test_abrupt_forces_are_followed(configs, tmp_path_factory, preset):
    on = run_preset(configs, tmp_path_factory, preset)
    off = run_preset(configs, tmp_path_factory, preset, which="off")
    s = on["summary"]
    assert s["status"] == "ok"
    assert s["accel"]["force_jumps"] >= 3, "the snaps / impacts / steps are detected"
    # Issue acceptance met: pose, attitude and lag.
    assert s["ate_posyaw_m"] <= 0.02, f"ATE {s['ate_posyaw_m']:.4f} m"
    assert on["att_err_max_deg"] <= 1.5, f"attitude error {on['att_err_max_deg']:.2f} deg after 5 s"
    lag_ms = on["force"]["response"]["lag_ms"]["combined"]
    assert lag_ms is not None and lag_ms <= 50.0, f"lag {lag_ms} ms"
    # And against the estimator without the detection: every figure better.
    assert s["force_rmse_world_mps2"] < 0.85 * off["summary"]["force_rmse_world_mps2"]
    assert s["ate_posyaw_m"] < off["summary"]["ate_posyaw_m"]
    assert s["accel"]["rejected"] == 0 < off["summary"]["accel"]["rejected"], "down-weighted, never dropped"


# Measured with config/sim, seeds 1-3 (seed 1 is the test's), 182d56e:
#   force RMSE rope_snap_short 0.466 / 0.477 / 0.485 m/s^2 (mean + 3 sd = 0.505, tighter than
#   1.2 x 0.466 = 0.560); impacts_short 0.950 / 0.914 / 0.830 (mean + 3 sd = 1.083 < 1.2 x 0.950);
#   settling after the steps of force_steps_short 0.635 / 0.805 / 1.435 s (1.2 x 0.635 = 0.762).
FORCE_RMSE = {"rope_snap_short": (0.466, 0.505), "impacts_short": (0.950, 1.083)}  # (measured, ratchet)
SETTLING_S = (0.635, 0.762)


@pytest.fixture(params=["rope_snap_short", "impacts_short"])
def abrupt_gap(request, configs, tmp_path_factory):
    """(preset, summary) of a preset whose force RMSE is short of the target; the run's own
    checks (exit code, status) are here, outside the xfail."""
    s = run_preset(configs, tmp_path_factory, request.param)["summary"]
    assert s["status"] == "ok"
    return request.param, s


def test_abrupt_force_rmse_ratchet(abrupt_gap):
    preset, s = abrupt_gap
    measured, limit = FORCE_RMSE[preset]
    ratchet(f"{preset} force RMSE [m/s^2]", s["force_rmse_world_mps2"], limit, measured)


@target_not_met("open (issue 17): force RMSE 0.47 (rope_snap_short) / 0.95 (impacts_short) "
                "m/s^2 > 0.25; a causal filter told the exact jump times does 0.42 / 0.38 on the full "
                "presets (vid-eval force-bound --jump-oracle 0.2): docs/notes/abrupt-forces.md")
def test_abrupt_force_rmse_target(abrupt_gap):
    preset, s = abrupt_gap
    target(f"{preset} force RMSE [m/s^2]", s["force_rmse_world_mps2"], 0.25)


@pytest.fixture(scope="module")
def step_response(configs, tmp_path_factory):
    """force_steps_short's step response (vid-eval force): every step found."""
    resp = run_preset(configs, tmp_path_factory, "force_steps_short")["force"]["response"]
    assert resp["summary"]["steps"] >= 3
    return resp


def test_settling_after_steps_ratchet(step_response):
    ratchet("force_steps_short settling max [s]", step_response["summary"]["settling_max_s"], SETTLING_S[1],
            SETTLING_S[0])


@target_not_met("open (issue 17): settling after 2.6-3.2 m/s^2 steps takes up to 0.64 s "
                "> 0.3 s; 400 samples of 2 m/s^2 noise are needed to pin a level to 0.1 m/s^2")
def test_settling_after_steps(step_response):
    target("force_steps_short settling max [s]", step_response["summary"]["settling_max_s"], 0.3)


def test_recorded_force_file_meets_the_targets(configs, tmp_path_factory):
    """from_file (120 s): a 20 N step and a 0.3 s 15 N pulse replayed from a CSV."""
    run = run_preset(configs, tmp_path_factory, "from_file")
    s, resp = run["summary"], run["force"]["response"]
    assert s["force_rmse_world_mps2"] <= 0.25, f"force RMSE {s['force_rmse_world_mps2']:.3f}"
    assert s["ate_posyaw_m"] <= 0.025, f"ATE {s['ate_posyaw_m']:.4f} m"
    assert run["att_err_max_deg"] <= 1.5
    assert resp["lag_ms"]["combined"] <= 50.0
    assert resp["summary"]["steps"] >= 2 and resp["summary"]["not_settled"] == 0
    assert resp["summary"]["settling_max_s"] <= 0.3


@pytest.mark.parametrize("preset", ABRUPT + ["from_file_short"])
def test_noise_free_copies_reject_almost_nothing(configs, tmp_path_factory, preset):
    s = run_preset(configs, tmp_path_factory, preset, noise_free=True)["summary"]
    acc = s["accel"]
    assert acc["samples"] > 0.9 * 400 * 20
    past_gate = acc["rejected"] + acc["downweighted"]
    assert past_gate <= 0.001 * acc["samples"], f"{past_gate} of {acc['samples']} rejected or down-weighted"
    assert len(acc["rejected_spans_ns"]) == min(acc["rejected_span_count"], 200)
    assert len(acc["downweighted_spans_ns"]) == min(acc["downweighted_span_count"], 200)


@pytest.mark.parametrize("preset", ["vid17_like_short", "wind_gusts"])
def test_smooth_presets_unchanged(configs, tmp_path_factory, preset):
    """One set of defaults: on smooth forces the detection changes (almost) nothing."""
    on = run_preset(configs, tmp_path_factory, preset, duration=25.0)["summary"]
    off = run_preset(configs, tmp_path_factory, preset, duration=25.0, which="off")["summary"]
    assert on["force_rmse_world_mps2"] <= 1.05 * off["force_rmse_world_mps2"]
    assert on["ate_posyaw_m"] <= 1.05 * off["ate_posyaw_m"]
