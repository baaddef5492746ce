"""A log's force sensor saturated or not zeroed: found, named, and kept out of the
constants (decisions D153, D154)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft
from mudrft import MudrftError
from mudrft.calibration import (
    CalibrationWarning,
    FitResult,
    IntrusionDataset,
    Trial,
    calibrate,
    synthetic_dataset,
)
from mudrft.cli import main as mudrft_main

#: Four speeds, 1 % noise, 20 ms samples: the field roboticist's rig of D139, one run more.
FOUR_RUNS = {"speeds": (0.01, 0.02, 0.03, 0.04), "noise": 0.01, "seed": 5, "dt": 0.02}


def _relative_errors(fit, true, names):
    return {k: float(getattr(fit.parameters, k)) / float(getattr(true, k)) - 1 for k in names}


def _clipped_dataset(good, fraction=0.8):
    """``good`` with its second trial clipped at ``fraction`` of its peak stress."""
    tr = good.trials[1]
    limit = fraction * float(np.max(tr.stress))
    clipped = Trial(
        tr.time,
        tr.depth,
        np.minimum(tr.stress, limit),
        name="clipped run",
        characteristic_length=tr.characteristic_length,
    )
    return IntrusionDataset((good.trials[0], clipped, *good.trials[2:]), direction="vertical")


def _shifted(ds, offset):
    """Every trial's stress plus ``offset`` [Pa]: a force sensor that was not zeroed."""
    trials = tuple(
        Trial(t.time, t.depth, t.stress + offset, name=t.name, characteristic_length=0.05)
        for t in ds.trials
    )
    return IntrusionDataset(trials, direction=ds.direction)


def test_a_clipped_run_among_four_is_named_and_its_flat_top_left_out(true_vertical, tmp_path):
    """One run whose sensor saturated at 80 % of its peak, among four, moved lambda by
    42 % and eta_m by 37 % (n 6 %, sigma_y 7 %) at a mean relative RMSE of 1.5 % with no
    warning: the clipped run fitted at 2.2 times the others' relative RMSE but less in
    pascals, under the D139 rule. Its flat top is named and left out of the fit (D153)."""
    good = synthetic_dataset(true_vertical, **FOUR_RUNS)
    data = _clipped_dataset(good)
    with pytest.warns(CalibrationWarning) as record:
        fit = calibrate(data)
    warned = [str(w.message) for w in record if issubclass(w.category, CalibrationWarning)]
    assert len(warned) == 1, warned
    assert warned[0].startswith("trial 'clipped run': 28 of 226 samples sit at the same stress")
    assert "left out of the fit" in warned[0] and "clipped='keep'" in warned[0]
    assert f"warning: {warned[0]}" in fit.summary()
    clean = calibrate(good)
    # the constants the rig identifies come back as from the clean runs: within 5 % of
    # the truth (lambda within 10 %, as the clean fit), and the truth within the intervals
    errors = _relative_errors(fit, true_vertical, ("alpha", "n", "eta_inf", "epsilon", "sigma_y"))
    assert max(abs(e) for e in errors.values()) < 0.05, errors
    assert abs(_relative_errors(fit, true_vertical, ("lam",))["lam"]) < 0.1
    for k in ("alpha", "n", "lam", "epsilon", "sigma_y"):
        lo, hi = fit.confidence_interval[k]
        assert lo <= float(getattr(true_vertical, k)) <= hi, k
    # ... close to the clean fit, which lost nothing: its fitted samples are all there
    assert fit.trial_relative_rmse[1] < 1.5 * np.median(clean.trial_relative_rmse)
    for k in ("alpha", "n", "eta_inf", "sigma_y"):
        assert abs(float(getattr(fit.parameters, k)) / float(getattr(clean.parameters, k)) - 1) < (
            0.02
        ), k
    # the warning is kept with the fit
    fit.to_json(tmp_path / "fit.json")
    assert FitResult.from_json(tmp_path / "fit.json").data_warnings == fit.data_warnings
    # clipped="keep" fits the flat top as data, and shows the bias it leaves
    with pytest.warns(CalibrationWarning, match="clipped='keep'"):
        kept = calibrate(data, clipped="keep")
    assert _relative_errors(kept, true_vertical, ("lam",))["lam"] > 0.2


def test_clean_logs_are_neither_clipped_nor_offset():
    """The checks stay silent on the model's own data, with noise or without, in either
    direction and evaluation: no flat top at an extreme (not even the suction plateau of
    a noise-free log), no offset out of the mud in a vertical test."""
    from mudrft.calibration.sensors import clipped_samples, stress_offset

    for direction in ("vertical", "horizontal"):
        for w in (0.25, 0.45):
            p = mudrft.paper_parameters(w, direction)
            for noise in (0.0, 0.01):
                ds = synthetic_dataset(
                    p, speeds=(0.005, 0.02, 0.08), noise=noise, seed=1, dt=0.01, rest=0.5
                )
                for tr in ds.trials:
                    assert not clipped_samples(tr).any(), (direction, w, noise, tr.name)
                    if direction == "vertical":
                        off = stress_offset(tr)
                        assert off.samples >= 50 and not off.significant, (w, noise, off)


def test_clipped_samples_at_either_extreme_but_not_at_zero():
    from mudrft.calibration.sensors import clipped_samples

    t = np.linspace(0.0, 1.0, 101)
    depth = 0.03 * np.minimum(t, 1.0 - t)
    stress = 1e5 * depth - 300.0 * (t > 0.6)
    top = np.minimum(stress, 1200.0)
    assert np.array_equal(clipped_samples(Trial(t, depth, top)), top == 1200.0)
    bottom = np.maximum(stress, -100.0)  # a suction beyond the sensor's range
    at_limit = (bottom == -100.0) & (depth > 0)  # the last sample is out of the mud
    assert np.array_equal(clipped_samples(Trial(t, depth, bottom)), at_limit)
    # a sensor that reads no tension logs 0 under suction: not a saturation to leave out
    assert not clipped_samples(Trial(t, depth, np.maximum(stress, 0.0))).any()
    # four samples at the top are not enough: the rounding of a coarse digitisation
    few = stress.copy()
    few[np.argsort(stress)[-4:]] = stress.max()
    assert not clipped_samples(Trial(t, depth, few)).any()


def test_an_unzeroed_sensor_is_named_and_can_be_subtracted(true_vertical):
    """A force sensor 3 % of the range off zero in every run moved n by 13 % and sigma_y
    by 16 % at the noise level, with no warning (every run equally off: nothing stands
    out under D139). The stress out of the mud names it; zero="subtract" removes it (D154)."""
    good = synthetic_dataset(true_vertical, **FOUR_RUNS, rest=0.5)
    offset = 0.03 * float(np.mean([np.ptp(t.stress) for t in good.trials]))
    data = _shifted(good, offset)
    with pytest.warns(CalibrationWarning) as record:
        fit = calibrate(data)
    warned = [str(w.message) for w in record if issubclass(w.category, CalibrationWarning)]
    assert [w.split("'")[1] for w in warned] == [t.name for t in good.trials]
    assert all("while the plate is out of the mud (27 samples at depth <= 0" in w for w in warned)
    assert all("zero='subtract'" in w for w in warned)
    assert abs(_relative_errors(fit, true_vertical, ("sigma_y",))["sigma_y"]) > 0.1
    notes = []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        zeroed = calibrate(data, zero="subtract", progress=notes.append)
        reference = calibrate(good, zero="subtract")
    assert any(
        n.startswith("calibrate: sensor zero subtracted (decision D154): v10mm_s ") for n in notes
    )
    errors = _relative_errors(zeroed, true_vertical, ("alpha", "n", "eta_inf", "sigma_y"))
    assert max(abs(e) for e in errors.values()) < 0.05, errors
    for k in ("alpha", "n", "eta_inf", "sigma_y", "epsilon"):  # the offset is gone exactly
        assert float(getattr(zeroed.parameters, k)) == pytest.approx(
            float(getattr(reference.parameters, k)), rel=1e-6
        ), k


def test_zero_and_clipped_options_are_checked(true_vertical):
    good = synthetic_dataset(true_vertical, speeds=(0.02,), dt=0.05)
    with pytest.raises(
        MudrftError, match=r"clipped must be one of \['exclude', 'keep'\], got 'drop'"
    ):
        calibrate(good, clipped="drop")
    with pytest.raises(MudrftError, match=r"zero must be one of \['check', 'subtract'\], got 1"):
        calibrate(good, zero=1)
    # the synthetic run has one sample out of the mud at each end: no zero to measure
    with pytest.raises(MudrftError, match="trial 'v20mm_s' has 2: log the plate above"):
        calibrate(good, zero="subtract")
    horizontal = synthetic_dataset(
        mudrft.paper_parameters(0.25, "horizontal"), speeds=(0.02,), dt=0.05, rest=0.5
    )
    with pytest.raises(MudrftError, match="zero='subtract' needs a vertical test"):
        calibrate(horizontal, zero="subtract")


@pytest.mark.filterwarnings("default::mudrft._validation.CalibrationWarning")  # shown as lines
def test_cli_names_the_sensor_faults_and_takes_the_options(true_vertical, tmp_path, capsys):
    good = synthetic_dataset(
        true_vertical, speeds=(0.01, 0.03), noise=0.01, seed=3, dt=0.05, rest=0.5
    )
    data = _shifted(good, 0.05 * float(np.ptp(good.trials[0].stress)))
    log = tmp_path / "log.csv"
    from mudrft.io import save_intrusion_csv

    save_intrusion_csv(data, log)
    common = ["calibrate", str(log), "--groups", "b", "--quiet"]
    assert mudrft_main(common) == 0
    out, err = capsys.readouterr()
    assert "mudrft calibrate: warning: trial 'v10mm_s': the stress is" in err
    assert "warning: trial 'v30mm_s': the stress is" in out  # the summary names it too
    assert mudrft_main([*common, "--zero", "subtract", "--strict"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert mudrft_main([*common, "--zero", "subtract", "--clipped", "keep", "--strict"]) == 0
    with pytest.raises(SystemExit) as exc:  # argparse's choices, as for --direction
        mudrft_main([*common, "--zero", "nothing"])
    assert exc.value.code == 2
    assert "invalid choice: 'nothing'" in capsys.readouterr().err
