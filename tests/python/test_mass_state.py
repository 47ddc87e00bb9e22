"""The mass state in the VIO (issue #21, docs/notes/mass-state.md): with the thrust scale estimated and
a slow external-force model, a payload picked up and dropped in flight (vid_loaded: +0.6 kg on
3.1 kg at 25 s, off again at 45 s) and a continuous loss (spraying) are identified from camera,
IMU and rotor speeds alone; seeds 1-3, feature-level, random initial heading. payload_heavy
(1.2 kg, 39 %) is the case not yet met (strict xfail next to a ratchet, docs/testing.md)."""
import shutil

import numpy as np
import pytest

from vid_eval.tools.loaders import load_mass
from vid_eval.core.mass_metrics import MassResult, settle_times
from vid_eval.core.pairing import PairingOptions, pair_scalars

from ratchets import band, ratchet, target, target_not_met
from test_vid_run_helpers import REPO, simulate_cached, summary, vid_run

SEEDS = (1, 2, 3)

# Measured at 182d56e (mass config below, 60 s, feature level):
#   vid_loaded mass RMSPE after 5 s, seeds 1-6: 1.87 / 1.54 / 2.48 / 2.90 / 1.83 / 2.56 %; each
#   test seed is held at 1.2 x its own value (mean + 3 sd over seeds 1-6 = 3.5 % is looser);
#   mass NEES over seeds 1-3 at common times: mean 0.935, in the 95 % band 81.8 % of the time;
#   the same over other seed triples (4-6, 1-2-4, 2-3-5, 3-5-6): mean 0.61-0.85, in band
#   72.7-81.5 % (sd of the in-band fraction 0.037: ratchet at 0.818 - 3 sd = 0.70, tighter than
#   20 % worse = 0.65); the mean is held two-sided at 0.935 / 1.2 .. 0.935 x 1.2 (a sigma too
#   small or too large by 10 % moves it out; the seed-triple spread, sd 0.12, is looser);
#   payload_heavy seed 1 RMSPE 3.34 % (seeds 2, 3: 4.83, 4.54) -> ratchet 1.2 x 3.34 = 4.01 %.
RMSPE_PCT = {1: 1.87, 2: 1.54, 3: 2.48}
NEES_MEAN, NEES_IN_BAND, NEES_IN_BAND_RATCHET = 0.935, 0.818, 0.70
HEAVY_RMSPE_PCT = 3.34


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    """config/sim as it is (no mass state), and the same with the mass state on and the force
    model slow (a payload vehicle without ropes: the force-rate state off)."""
    mass = tmp_path_factory.mktemp("cfg") / "mass"
    shutil.copytree(REPO / "config" / "sim", mass)
    est = mass / "estimator.yaml"
    text = est.read_text()
    assert "force_rate_random_walk: 0.5" in text
    est.write_text(text.replace("force_rate_random_walk: 0.5", "force_rate_random_walk: 0.0")
                   + "thrust_scale_random_walk: 0.02\n")
    return {"default": REPO / "config" / "sim", "mass": mass}


_RUNS = {}


def run(configs, tmp_path_factory, preset, seed, which):
    key = (preset, seed, which)
    if key not in _RUNS:
        seq = simulate_cached(f"{preset}.yaml", 60.0, seed, features_only=True)
        out = tmp_path_factory.mktemp(f"{preset}_{seed}_{which}")
        r = vid_run(seq, out, "--config", str(configs[which]))
        assert r.returncode == 0, r.stderr
        res = None
        if which == "mass":
            est = load_mass(out / "mass.csv")
            keep = np.flatnonzero(est.t_ns >= est.t_ns[0] + 5_000_000_000)  # after the first 5 s
            gt = load_mass(seq / "mav0" / "mass0" / "data.csv")
            pe, pg = pair_scalars(est.subset(keep), gt, PairingOptions())
            res = MassResult(pe, pg, t0_ns=int(gt.t_ns[0]))
        _RUNS[key] = {"summary": summary(out), "mass": res, "out": out}
    return _RUNS[key]


@pytest.mark.parametrize("seed", SEEDS)
def test_payload_mass_identified(configs, tmp_path_factory, seed):
    m = run(configs, tmp_path_factory, "vid_loaded", seed, "mass")["mass"]
    assert m.rmspe <= 3.0, f"mass RMSPE after 5 s {m.rmspe:.2f} %"  # the target, met
    ratchet(f"vid_loaded seed {seed} mass RMSPE after 5 s [%]", m.rmspe, 1.2 * RMSPE_PCT[seed], RMSPE_PCT[seed])
    events = m.as_dict()["settle_5pct"]
    assert [round(e["t_s"], 1) for e in events] == [25.3, 45.3], events  # end of each 0.3 s ramp
    for e in events:
        assert e["settle_s"] is not None and e["settle_s"] <= 2.0, events


@pytest.mark.parametrize("seed", SEEDS)
def test_mass_state_keeps_pose_and_force(configs, tmp_path_factory, seed):
    """ATE and force RMSE no worse than +5 % of the filter without the mass state (which has to
    call the payload's weight an external force: the true external force here is zero)."""
    with_mass = run(configs, tmp_path_factory, "vid_loaded", seed, "mass")["summary"]
    without = run(configs, tmp_path_factory, "vid_loaded", seed, "default")["summary"]
    assert with_mass["ate_posyaw_m"] <= 1.05 * without["ate_posyaw_m"]
    assert with_mass["force_rmse_world_mps2"] <= 1.05 * without["force_rmse_world_mps2"]
    assert with_mass["force_rmse_world_mps2"] < 0.3


@pytest.fixture(scope="module")
def mass_nees(configs, tmp_path_factory) -> np.ndarray:
    """Run-averaged NEES of the mass over the seeds, at the times all runs share."""
    runs = [run(configs, tmp_path_factory, "vid_loaded", s, "mass")["mass"] for s in SEEDS]
    common = runs[0].est.t_ns
    for r in runs[1:]:
        common = np.intersect1d(common, r.est.t_ns)
    assert len(common) > 10000
    per_run = []
    for r in runs:
        i = np.searchsorted(r.est.t_ns, common)
        per_run.append((r.err[i] / r.est.sigma[i]) ** 2)
    return np.mean(per_run, axis=0)


def _in_band(nees: np.ndarray) -> float:
    """Fraction of the time inside the 95 % band of chi2(3)/3 (3 runs of one dof)."""
    from scipy.stats import chi2
    n = len(SEEDS)
    return float(np.mean((nees > chi2.ppf(0.025, n) / n) & (nees < chi2.ppf(0.975, n) / n)))


def test_mass_sigma_is_the_right_size(mass_nees):
    """Monte-Carlo NEES of the mass over the three seeds at common times: its mean is held
    two-sided at today's value (too small a sigma raises it, too large lowers it)."""
    band("mass NEES mean (seeds 1-3)", float(mass_nees.mean()), NEES_MEAN / 1.2, NEES_MEAN * 1.2)


def test_mass_nees_in_band_ratchet(mass_nees):
    ratchet("mass NEES in band (seeds 1-3)", _in_band(mass_nees), NEES_IN_BAND_RATCHET, NEES_IN_BAND,
            higher_is_better=True)


@target_not_met("issue #21: in band 82 % (target 90 %): the sigma stays wider than the "
                "error after each step while s and F share it (docs/notes/mass-state.md)")
def test_mass_nees_in_band(mass_nees):
    """The issue's criterion: inside the 95 % band of chi2(3)/3 >= 90 % of the time."""
    target("mass NEES in band (seeds 1-3)", _in_band(mass_nees), 0.9, higher_is_better=True)


@pytest.fixture(scope="module")
def heavy(configs, tmp_path_factory):
    """payload_heavy (1.2 kg, 39 %), seed 1: the mass result and its two settle events."""
    m = run(configs, tmp_path_factory, "payload_heavy", 1, "mass")["mass"]
    events = m.as_dict()["settle_5pct"]
    assert len(events) == 2, events
    return m, events


def test_heavy_payload_ratchet(heavy):
    ratchet("payload_heavy mass RMSPE after 5 s [%]", heavy[0].rmspe, 1.2 * HEAVY_RMSPE_PCT, HEAVY_RMSPE_PCT)


@target_not_met("issue #21: 3.3 % RMSPE after 5 s (target 3 %) on the 1.2 kg payload "
                "(the force-jump prior splits the step evenly between F and s)")
def test_heavy_payload_meets_the_targets(heavy):
    m, events = heavy
    worst_settle = max(e["settle_s"] if e["settle_s"] is not None else np.inf for e in events)
    target("payload_heavy mass RMSPE after 5 s [%]", m.rmspe, 3.0)
    target("payload_heavy slowest settle [s]", worst_settle, 2.0)


def test_continuous_mass_loss(configs, tmp_path_factory):
    m = run(configs, tmp_path_factory, "spraying", 41, "mass")["mass"]
    assert m.rmspe <= 3.0, f"spraying: mass RMSPE after 5 s {m.rmspe:.2f} %"


def test_no_mass_file_without_the_state(configs, tmp_path_factory):
    r = run(configs, tmp_path_factory, "vid_loaded", 1, "default")
    assert r["summary"]["config"]["estimator"]["thrust_scale_random_walk"] == 0  # off by default
    assert not (r["out"] / "mass.csv").exists()


def test_fast_force_model_with_the_mass_state_is_warned(configs, tmp_path_factory):
    """The confounded combination (docs/notes/mass-state.md) runs, with one warning line that says why."""
    cfg = tmp_path_factory.mktemp("cfg") / "fast"
    shutil.copytree(REPO / "config" / "sim", cfg)
    with open(cfg / "estimator.yaml", "a") as f:
        f.write("thrust_scale_random_walk: 0.02\n")
    seq = simulate_cached("vid_loaded.yaml", 60.0, 1, features_only=True)
    r = vid_run(seq, tmp_path_factory.mktemp("fast_out"), "--config", str(cfg), "--end", "3")
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if "not separable" in ln]
    assert len(lines) == 1 and "force_rate_random_walk: 0" in lines[0], r.stderr


def test_settle_times_of_a_synthetic_step():
    t = np.arange(0.0, 10.0, 0.01)
    m = np.where(t < 4.0, 2.0, 2.5)
    est = np.where(t < 4.5, 2.0, 2.5)  # late by 0.5 s
    ev = settle_times(t, est, m)
    assert len(ev) == 1 and ev[0]["t_s"] == pytest.approx(4.0) and ev[0]["settle_s"] == pytest.approx(0.5)
    assert settle_times(t, np.full_like(t, 2.0), m)[0]["settle_s"] is None  # never settles
    assert settle_times(t, m, m)[0]["settle_s"] == 0.0
    assert settle_times(t, m, np.full_like(t, 2.0)) == []  # no change, no event
