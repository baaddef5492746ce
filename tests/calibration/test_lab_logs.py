"""Calibration from logs the way labs record them (issue 39): no stress in the air, a rate
that survives the depth sensor's noise, errors that admit model error."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import mudrft
from mudrft._validation import CalibrationWarning, MudrftError
from mudrft.calibration import FitResult, IntrusionDataset, Trial, calibrate, synthetic_dataset
from mudrft.calibration._problem import FIT_PARAMETERS
from mudrft.calibration.rate import depth_noise, smooth_dataset, smooth_trial
from mudrft.calibration.uncertainty import at_bound, robust_log_covariance, verdict
from mudrft.cli import main as mudrft_main

TRUE = mudrft.paper_parameters(0.25, "vertical")
#: The issue's rig: a 40 x 40 mm plate, three speeds to 30 mm, a 1 s hold, 500 Hz.
PLATE, AREA = 0.04, 0.04**2
SPEEDS = (0.01, 0.02, 0.04)


def lab_log(seed=0, *, depth_noise=2e-5, force_noise=0.3, dt=0.002, **kw):
    """Three trials as a logger writes them: at rest 5 mm above the surface (the tare), the
    approach, intrusion to 30 mm, a 1 s hold, the retraction out of the mud back to 5 mm
    above; depth noise [m], force noise [N] on the plate."""
    options = {"approach": 0.005, "tare": 0.2, "rest": 0.2, **kw}
    return synthetic_dataset(
        TRUE, SPEEDS, noise=0.0, seed=seed, depth=0.03, hold=1.0, dt=dt,
        characteristic_length=PLATE, stress_noise=force_noise / AREA,
        depth_noise=depth_noise, **options,
    )  # fmt: skip


def _approach(seconds, *, speed=0.01, dt=0.002):
    """A 10 mm/s plate test preceded by ``seconds`` of approach from above, and the index of
    its first sample at the surface."""
    pre = round(seconds / dt)
    test = mudrft.plate_intrusion(depth=0.03, speed=speed, hold=1.0, dt=dt, rest=0.2)
    t = np.r_[dt * np.arange(pre), test.time + pre * dt]
    q = np.r_[-speed * dt * np.arange(pre, 0, -1), test.meta["displacement"]]
    pos = np.zeros((t.size, 3))
    pos[:, 2] = -q
    meta = {"direction": "vertical", "displacement": q}
    return mudrft.Trajectory.from_positions(t, pos, meta=meta), pre


# --------------------------------------------------------------------------------------
# contact: one rule for plate_response, the fit's forward model and simulate
# --------------------------------------------------------------------------------------
def test_a_plate_above_the_surface_feels_nothing_and_the_mud_forgets_the_air():
    """Exactly 0 above the surface; in the mud the same stress after 0 s, 0.1 s or 1 s of
    approach (the old plate_response differed by up to 699 Pa after 0.3 s in the air); and
    the stress simulate gives a flat foot along the same path."""
    foot = mudrft.feet.Flat(length=0.05, width=0.05, height=0.04)  # a 30 mm plate test
    mud = mudrft.paper_mud(0.25)
    L = mudrft.terrains.MudTerrain(mud).length(foot)
    in_mud = []
    for seconds in (0.0, 0.1, 1.0):
        path, at_surface = _approach(seconds)
        res = mudrft.plate_response(path, TRUE, characteristic_length=L)
        above = path.meta["displacement"] <= 0
        assert above[: at_surface + 1].all() and np.all(res.stress[above] == 0.0)
        in_mud.append(res.stress[at_surface:])
        sim = mudrft.simulate(foot, mud, path)
        np.testing.assert_allclose(sim.stress[:, 2], res.stress, rtol=0, atol=1e-6)
    assert np.ptp(in_mud[0]) > 2e4  # a real test: 25 kPa of support and suction
    for other in in_mud[1:]:
        # the same steps after contact; the clock's round-off only
        np.testing.assert_allclose(other, in_mud[0], rtol=0, atol=1e-6)


def test_the_fitted_model_puts_no_stress_on_a_plate_in_the_air():
    """FitResult.predict with the true constants: 0 Pa while the plate rests above the
    surface and approaches (it gave -9,965 Pa and +4 to +11 kPa), the log's stress in the
    mud, and the same in the mud whatever the tare before the approach."""
    # the plate reaches the surface between two samples, as it does in a lab
    ds = lab_log(depth_noise=0.0, force_noise=0.0, dt=0.01, tare=0.205)
    fixed = {k: getattr(TRUE, k) for k in FIT_PARAMETERS if k != "sigma_y"}
    fit = calibrate(ds, initial=TRUE, fixed=fixed, groups="sigma_y", phases=False)
    assert fit.parameters.sigma_y == pytest.approx(TRUE.sigma_y, rel=1e-3)
    for tr, pred in zip(ds.trials, fit.predict(), strict=True):
        above = tr.depth <= 0
        assert above.sum() > 20 and np.all(pred[above] == 0.0)
        # the log's stress in the mud (but at the samples just after a change of speed)
        assert np.median(np.abs(pred - tr.stress)[~above]) < 1e-3 * np.ptp(tr.stress)
    longer = lab_log(depth_noise=0.0, force_noise=0.0, dt=0.01, tare=1.005)
    for pa, pb in zip(fit.predict(ds), fit.predict(longer), strict=True):
        assert np.all(pb[:80] == 0.0)  # 0.8 s more at rest above the surface
        np.testing.assert_allclose(pb[80:], pa, rtol=0, atol=1e-3)  # round-off of the clock


def test_samples_above_the_surface_serve_the_tare_not_the_fit(true_vertical):
    """An unzeroed sensor (2 N) is measured on the samples before contact and subtracted;
    those samples are not fitted (a fit of them would pull the constants to the offset)."""
    ds = lab_log(depth_noise=0.0, force_noise=0.0, dt=0.01, offset=2.0 / AREA)
    with pytest.warns(CalibrationWarning, match="not zeroed"):
        unzeroed = calibrate(ds, groups="b")
    notes = []
    fit = calibrate(ds, groups="b", zero="subtract", progress=notes.append)
    assert any("1250 Pa" in n for n in notes if "zero subtracted" in n)
    assert fit.parameters.alpha == pytest.approx(TRUE.alpha, rel=1e-3)
    assert abs(unzeroed.parameters.alpha / TRUE.alpha - 1) > 0.01


def test_a_constant_stress_trial_gets_a_clear_error():
    """Issue 43: every sample of a constant trial counted as saturated, and the fit failed
    inside numpy (np.ptp of an empty selection)."""
    t = np.linspace(0.0, 2.0, 201)
    tr = Trial(t, 0.03 * np.minimum(t, 2.0 - t), np.full(t.size, 500.0))
    with pytest.raises(MudrftError, match=r"trial 'trial'.*500 Pa.*nothing to fit"):
        calibrate(IntrusionDataset((tr,)))


# --------------------------------------------------------------------------------------
# a rate that survives the depth sensor's noise
# --------------------------------------------------------------------------------------
def test_the_depth_is_read_as_the_rig_moved_it():
    """0.02 mm of noise at 500 Hz: the noise is measured, the corners are found within a
    millisecond, the hold is exactly still and the rate in the mud is the speed to 0.1 %."""
    clean, noisy = lab_log(depth_noise=0.0), lab_log(depth_noise=2e-5)
    for c, tr in zip(clean, noisy, strict=True):
        assert depth_noise(tr.depth) == pytest.approx(2e-5, rel=0.1)
        read, how = smooth_trial(tr)
        assert how.method == "segments" and len(how.changes) == 4
        v = tr.meta["speed"]
        corners = np.cumsum([0.2, 0.005 / v + 0.03 / v, 1.0, 0.03 / v + 0.005 / v])
        np.testing.assert_allclose([a for a, _ in how.changes], corners, atol=1e-3)
        hold = (tr.time > corners[1] + 0.01) & (tr.time < corners[2] - 0.01)
        assert np.ptp(read.depth[hold]) == 0.0
        rate = np.diff(read.depth) / np.diff(read.time)
        moving = (c.depth[1:] > 0) & (np.abs(np.diff(c.depth)) > 0)
        moving &= ~how.excluded(tr.time)[1:]
        err = rate[moving] - np.diff(c.depth)[moving] / np.diff(c.time)[moving]
        assert np.abs(err).max() < 1e-3 * v


def test_a_raw_noisy_rate_warns_with_the_size_of_the_bias():
    ds = lab_log()
    warned = smooth_dataset(ds, "raw")[2]
    assert len(warned) == 3
    # 0.02 mm at 2 ms: 14 mm/s of noise, 141 % of 10 mm/s, a bias of 2/3
    share = float(re.search(r"([\d.]+) % of the speed", warned[0]).group(1))
    bias = float(re.search(r"about ([\d.]+) % too small", warned[0]).group(1))
    assert 130 < share < 150 and 62 < bias < 70
    assert smooth_dataset(ds)[2] == []


def test_a_curved_motion_is_smoothed_over_a_window_chosen_from_the_noise():
    t = np.arange(0.0, 4.0, 0.002)
    q = 0.015 * (1 - np.cos(np.pi * t / 2)) + np.random.default_rng(3).normal(0, 2e-5, t.size)
    how = smooth_trial(Trial(t, q, 1e5 * np.clip(q, 0.0, None)))[1]
    assert how.method == "kernel" and how.window > 20
    # the window's rate noise is 1 % of the speed
    assert how.rate_noise == pytest.approx(0.01 * how.speed, rel=0.1)
    assert "smoothed over" in how.note() and f"{how.window} samples" in how.note()


def test_rate_option_is_checked():
    for bad in ("smooth", 4, 0, True, 2.5):
        with pytest.raises(MudrftError, match="rate must be 'auto', 'raw' or an odd number"):
            calibrate(lab_log(dt=0.05), rate=bad)


# --------------------------------------------------------------------------------------
# errors that admit model error
# --------------------------------------------------------------------------------------
def test_robust_errors_match_the_noise_for_white_residuals_and_widen_for_correlated():
    """A line fitted to white noise: the sandwich error is the noise-only one; to AR(1)
    noise with rho = 0.8, the long-run factor sqrt((1 + rho)/(1 - rho)) = 3 wider."""
    rng = np.random.default_rng(11)
    m = 20000
    J = np.column_stack([np.ones(m), np.linspace(-1.0, 1.0, m)])
    trial = np.repeat([0, 1], m // 2)
    white = rng.normal(size=m)
    ar = np.empty(m)
    ar[0] = white[0]
    for i in range(1, m):
        ar[i] = 0.8 * ar[i - 1] + 0.6 * white[i]  # unit variance
    classic = np.sqrt(np.diag(np.linalg.inv(J.T @ J)))
    np.testing.assert_allclose(robust_log_covariance(white, J, trial), classic, rtol=0.05)
    np.testing.assert_allclose(robust_log_covariance(ar, J, trial), 3.0 * classic, rtol=0.15)


def test_a_model_slightly_off_widens_the_robust_interval_and_the_verdict_follows():
    """Data from a mud without the acceleration term (the model's term of decision D6
    dropped) fitted with it: the truth lies 10 to 60 noise-only errors away; the residuals,
    correlated in time, make every robust error at least twice as wide, the verdicts
    follow the robust errors, and the summary says what each interval covers."""
    ds = synthetic_dataset(TRUE, SPEEDS, noise=0.002, seed=4, dt=0.02, hold=1.0, acceleration=False)
    fit = calibrate(ds)
    z = {k: abs(np.log(getattr(fit.parameters, k) / getattr(TRUE, k))) for k in fit.free}
    assert max(z[k] / fit.relative_standard_error[k] for k in fit.free) > 10
    assert all(fit.robust_standard_error[k] > 2 * fit.relative_standard_error[k] for k in fit.free)
    by_noise = {k: verdict(fit.relative_standard_error[k], False) for k in fit.free}
    assert {fit.identifiability[k] for k in fit.free if by_noise[k] == "identified"} > {
        "identified"
    }
    bound = at_bound({k: getattr(fit.parameters, k) for k in fit.free}, fit.free, fit.bounds)
    for k in fit.free:
        assert fit.identifiability[k] == verdict(fit.robust_standard_error[k], bound[k])
    text = fit.summary()
    assert "assumes the model exact" in text and "holds for all free parameters at once" in text
    back = FitResult.from_dict(json.loads(json.dumps(fit.to_dict())))
    for k in fit.free:
        assert back.robust_interval[k] == pytest.approx(fit.robust_interval[k])
        assert back.robust_standard_error[k] == pytest.approx(fit.robust_standard_error[k])
    assert back.depth_notes == fit.depth_notes and back.rate == "auto"


# --------------------------------------------------------------------------------------
# the rig, end to end through the command line, over seeds
# --------------------------------------------------------------------------------------
def _write_lab_files(ds, folder):
    """One tab-separated file per trial, as a logger writes it: time in s, depth in mm,
    force in N."""
    paths = []
    for tr in ds:
        path = folder / f"{tr.name}.txt"
        rows = "".join(
            f"{t:.4f}\t{1e3 * q:.5f}\t{s * AREA:.5f}\n"
            for t, q, s in zip(tr.time, tr.depth, tr.stress, strict=True)
        )
        path.write_text("Time (s)\tDepth (mm)\tForce (N)\n" + rows)
        paths.append(str(path))
    return paths


@pytest.mark.filterwarnings("default::mudrft._validation.CalibrationWarning")  # shown as lines
def test_mudrft_calibrate_recovers_the_truth_from_a_lab_log(tmp_path, capsys):
    """Issue 39's must-show, one seed: logs with an approach from 5 mm above, a tare (an
    unzeroed 0.5 N sensor, subtracted from the samples above the surface), 0.02 mm of depth
    noise and 0.3 N of force noise, at 10, 20 and 40 mm/s: every parameter the fit reports
    identified lies within its robust 95 % interval, and the leak, too fast to show in these
    tests, is reported not identified. Over ten seeds: the study below."""
    files = _write_lab_files(lab_log(0, offset=0.5 / AREA), tmp_path)
    out = tmp_path / "fit.json"
    argv = ["calibrate", *files, "--area", "1600mm^2", "--length", "40mm"]
    assert mudrft_main([*argv, "--zero", "subtract", "--quiet", "--out", str(out)]) == 0
    warned = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warned) == 1 and "fitting every 3rd sample" in warned[0]  # 500 Hz
    fit = json.loads(out.read_text())
    identified = [k for k in fit["free"] if fit["identifiability"][k] == "identified"]
    assert len(identified) >= 3
    for k in identified:
        lo, hi = fit["robust_interval"][k]
        assert lo <= getattr(TRUE, k) <= hi, (k, lo, hi)
    assert fit["identifiability"]["tau_leak"] != "identified"


@pytest.mark.study
@pytest.mark.filterwarnings("default::mudrft._validation.CalibrationWarning")
def test_mudrft_calibrate_recovers_the_truth_from_lab_logs_over_seeds(tmp_path):
    """Issue 39's must-show over seeds (a study: about 15 s a seed, so CI runs it as its own
    step, ``pytest -m study``): in at least 9 of 10 seeds every parameter the fit reports
    identified lies within its robust 95 % interval, and the leak is never identified."""
    missed_by_seed, unidentified = {}, set()
    for seed in range(10):
        folder = tmp_path / f"seed{seed}"
        folder.mkdir()
        files = _write_lab_files(lab_log(seed, offset=0.5 / AREA), folder)
        out = folder / "fit.json"
        argv = ["calibrate", *files, "--area", "1600mm^2", "--length", "40mm"]
        assert mudrft_main([*argv, "--zero", "subtract", "--quiet", "--out", str(out)]) == 0
        fit = json.loads(out.read_text())
        missed = []
        for k in fit["free"]:
            lo, hi = fit["robust_interval"][k]
            if fit["identifiability"][k] != "identified":
                unidentified.add(k)
            elif not lo <= getattr(TRUE, k) <= hi:
                missed.append(k)
        missed_by_seed[seed] = missed
    assert sum(not m for m in missed_by_seed.values()) >= 9, missed_by_seed
    assert "tau_leak" in unidentified
