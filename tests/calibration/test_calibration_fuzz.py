"""Regression tests from a fuzz of the calibration with valid but difficult data."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mudrft.calibration import calibrate, synthetic_dataset
from mudrft.io import IntrusionDataset, Trial


def _intrusion_only(true):
    """Trials cut at their deepest sample: no hold, no retraction, nothing of the suction."""
    full = synthetic_dataset(true, speeds=(0.01, 0.04), noise=0.01, seed=3, dt=0.02)
    cut = []
    for tr in full:
        i = int(np.argmax(tr.depth)) + 1
        cut.append(Trial(tr.time[:i], tr.depth[:i], tr.stress[:i], name=tr.name))
    return IntrusionDataset(tuple(cut))


def test_sigma_y_without_retraction_keeps_its_start_value(true_vertical):
    """sigma_y has no effect before the retraction: the exact linear solve gave it 0, clipped
    to its lower bound (0.01 Pa), so a fit of the intrusion group reported sigma_y "fixed" at
    0.01 Pa (the paper row's 7100 Pa silently replaced) and fit.to_parameters() lost the
    suction. It keeps its starting value, like the suction constants next to it."""
    data = _intrusion_only(true_vertical)
    fit = calibrate(data, groups="b")
    assert fit.identifiability["sigma_y"] == "fixed"
    assert math.isclose(fit.parameters.sigma_y, true_vertical.sigma_y, rel_tol=1e-9)
    fit = calibrate(data, groups=("b", "s"))
    assert fit.identifiability["sigma_y"] == "not identified"
    assert math.isinf(fit.standard_error["sigma_y"])
    assert math.isclose(fit.parameters.sigma_y, true_vertical.sigma_y, rel_tol=1e-6)


def test_held_linear_constants_keep_the_paper_row_values(true_vertical):
    """The default start rescaled every linear constant of the paper row to the data, also
    those a groups= fit holds: they were fitted at the wrong start point and reported
    "fixed". On data with n = 1 a groups="b" fit gave n = 0.81 and alpha 10 % low, both
    "identified", the truth 15 SE away."""
    true = true_vertical.replace(n=1.0)
    data = synthetic_dataset(true, speeds=(0.01, 0.04), noise=0.01, seed=3, dt=0.02)
    fit = calibrate(data, groups="b")
    for k in ("eta_inf", "eta_m", "sigma_y"):
        assert getattr(fit.parameters, k) == getattr(true, k), k
    for k in fit.free:
        lo, hi = fit.confidence_interval[k]
        assert lo <= getattr(true, k) <= hi, k


def test_interval_of_a_parameter_at_a_bound_is_the_bounds(true_vertical):
    """Rule D44: a parameter that ends at a bound is "not identified" and its interval is
    the bounds; it was the linearised interval around the bound (19700-20000 Pa for a true
    alpha of 24000 Pa)."""
    data = synthetic_dataset(true_vertical, speeds=(0.02,), noise=0.01, seed=3, dt=0.02)
    fit = calibrate(data, groups="b", initial=true_vertical, bounds={"alpha": (1.0, 2.0e4)})
    assert fit.parameters.alpha == pytest.approx(2.0e4)
    assert fit.identifiability["alpha"] == "not identified"
    assert fit.confidence_interval["alpha"] == (1.0, 2.0e4)
