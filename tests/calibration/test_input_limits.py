"""Calibration against hostile inputs (issue 15): long logs, too few samples, unit mistakes.

Each test fails on the behaviour before the fix: a 1e6-row log fitted at full length with
no warning (it did not end in 600 s), 9 samples for 10 parameters reported as converged,
a depth column in mm labelled [m] or a stress in kPa labelled [Pa] loaded without a word.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft.calibration._problem as options
from mudrft._validation import MudrftError, PlausibilityWarning
from mudrft.calibration import CalibrationWarning, calibrate, synthetic_dataset
from mudrft.io import IntrusionDataset, Trial, load_dataset


@pytest.fixture(scope="module")
def plunge(true_vertical):
    """One plate test at 20 ms steps: 226 samples."""
    return synthetic_dataset(true_vertical, speeds=(0.02,), noise=0.01, seed=3, dt=0.02)


def test_long_logs_are_thinned_to_the_target_with_a_warning(plunge, monkeypatch):
    monkeypatch.setattr(options, "FIT_SAMPLES", 50)  # a 1e6-row log against 2000, scaled down
    assert options.auto_decimate(plunge) == 5
    # a Python warning: the library's logger has only a NullHandler, so a logged
    # warning reached no one who called calibrate() without configuring logging
    with pytest.warns(CalibrationWarning) as record:
        fit = calibrate(plunge, groups="b", phases=False, max_nfev=3)
    warned = [str(w.message) for w in record if issubclass(w.category, CalibrationWarning)]
    assert warned == [
        "the longest trial has 226 samples; fitting every 5th sample (about 45 per trial, "
        "decision D104) to keep the fit to minutes; pass decimate=1 (CLI: --decimate 1) to "
        "fit every sample"
    ]
    assert len(fit.dataset[0]) <= 50


@pytest.mark.parametrize(
    ("fit_samples", "words"), [(113, "every 2nd sample"), (76, "every 3rd"), (11, "every 21st")]
)
def test_the_thinning_warning_writes_english_ordinals(plunge, monkeypatch, fit_samples, words):
    """It said 'fitting every 2th sample'; 226 samples / fit_samples gives k."""
    monkeypatch.setattr(options, "FIT_SAMPLES", fit_samples)
    with pytest.warns(CalibrationWarning, match=words):
        calibrate(plunge, groups="b", phases=False, max_nfev=1)


def test_a_fit_that_does_not_describe_the_data_warns_in_python(plunge):
    """The flag of a poor fit went to the logger only (silent in a script)."""
    tr = plunge[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)  # the sign looks flipped: it is
        flipped = IntrusionDataset((Trial(tr.time, tr.depth, -tr.stress),))
    with pytest.warns(CalibrationWarning, match=r"^the model does not describe these data"):
        fit = calibrate(flipped, groups="b", phases=False, max_nfev=3)
    assert fit.relative_rmse > 0.25


def test_an_explicit_decimate_is_kept(plunge, monkeypatch):
    monkeypatch.setattr(options, "FIT_SAMPLES", 50)
    lines: list[str] = []
    with pytest.raises(MudrftError, match="decimate must be an integer >= 1, got 0"):
        calibrate(plunge, decimate=0)
    fit = calibrate(plunge, groups="b", phases=False, max_nfev=3, decimate=1, progress=lines.append)
    assert len(fit.dataset[0]) == len(plunge[0]) and not any("every" in m for m in lines)


def test_fewer_samples_than_free_parameters_is_refused(plunge):
    tr = plunge[0]
    # nine samples: the one at the surface and the first in the mud are not fitted
    nine = IntrusionDataset((Trial(tr.time[:9], tr.depth[:9], tr.stress[:9]),))
    with pytest.raises(MudrftError, match=r"7 fitted sample.*10 free parameter"):
        calibrate(nine)


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_a_depth_in_mm_labelled_metres_warns_naming_column_value_and_fix(tmp_path):
    depth_mm = np.r_[np.linspace(0, 30, 31), np.linspace(29, 0, 30)]
    rows = "\n".join(f"{0.1 * i:g},{d:g},{1e3 * d:g}" for i, d in enumerate(depth_mm))
    path = write(tmp_path, "mm.csv", "time [s],depth [m],stress [Pa]\n" + rows + "\n")
    with pytest.warns(
        PlausibilityWarning, match=r"'depth \[m\]' reaches a depth of 30 m.*'depth \[mm\]'"
    ):
        load_dataset(path)


def test_a_stress_in_kpa_labelled_pascal_warns(tmp_path):
    path = write(
        tmp_path, "kpa.csv", "time [s],depth [m],stress [Pa]\n0,0,0\n1,0.02,7.2\n2,0.03,-1.5\n"
    )
    with pytest.warns(
        PlausibilityWarning, match=r"'stress \[Pa\]' peaks at 7.2 Pa.*'stress \[kPa\]'"
    ):
        load_dataset(path)
    force = write(tmp_path, "f.csv", "time [s],depth [m],Fz [kN]\n0,0,0\n1,0.02,30\n2,0.03,60\n")
    with pytest.warns(PlausibilityWarning, match=r"'Fz \[kN\]' over the plate area 0.0025"):
        load_dataset(force, area=0.0025)


def test_a_plausible_log_loads_without_warnings(tmp_path):
    path = write(
        tmp_path, "ok.csv", "time [ms],depth [mm],stress [kPa]\n0,0,0\n500,10,2.5\n1000,20,4\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        assert load_dataset(path)[0].stress.max() == 4000.0


def test_a_bad_run_among_good_ones_is_named_by_a_warning_and_the_summary(true_vertical):
    """One run whose depth zero is 3 mm off, among three good ones, pulls the fit off its
    truth (a rig's example: alpha, n, sigma_y by 6-21 %, "identified", intervals excluding
    the truth) at a mean relative RMSE of 2 %: nothing said which run (D139)."""
    good = synthetic_dataset(true_vertical, noise=0.01, seed=5, dt=0.02)
    tr = good.trials[1]
    bad = Trial(tr.time, tr.depth + 0.003, tr.stress, name="depth zero off")
    with pytest.warns(CalibrationWarning) as record:
        fit = calibrate(IntrusionDataset((*good.trials, bad)))
    warned = [str(w.message) for w in record if issubclass(w.category, CalibrationWarning)]
    assert len(warned) == 1 and warned[0].startswith("trial 'depth zero off' ("), warned
    summary = fit.summary()
    assert "relative RMSE per trial: " in summary and "warning: trial 'depth zero off'" in summary
    names = [t.name for t in good.trials]
    assert all(f"{n} " in summary.split("per trial: ")[1] for n in names)
    with warnings.catch_warnings():  # the good runs alone: no such warning
        warnings.simplefilter("error")
        clean = calibrate(good)
    assert "warning" not in clean.summary()
    assert "relative RMSE per trial: " in clean.summary()
