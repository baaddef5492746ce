"""Shared fixtures of the calibration tests: synthetic data and one reference fit.

The reference fit is computed once per session (about 2 s) and reused by the tests
that only read it.
"""

from __future__ import annotations

import pytest

import mudrft
from mudrft.calibration import calibrate, synthetic_dataset

#: Settings of the round-trip data: three speeds, 1 % noise, coarse 20 ms samples (the
#: constitutive step is exact for piecewise-linear inputs, so a coarse grid loses nothing
#: but samples), a 1.5 s hold so that the relaxation time is visible.
ROUND_TRIP = {"speeds": (0.01, 0.02, 0.04), "noise": 0.01, "seed": 7, "dt": 0.02, "hold": 1.5}


@pytest.fixture(scope="session")
def true_vertical() -> mudrft.MudParameters:
    return mudrft.paper_parameters(0.25, "vertical")


@pytest.fixture(scope="session")
def vertical_data(true_vertical):
    return synthetic_dataset(true_vertical, **ROUND_TRIP)


@pytest.fixture(scope="session")
def vertical_fit(vertical_data):
    return calibrate(vertical_data)
