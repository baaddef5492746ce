"""Mistakes a fuzz of the public Python API found: each raised a TypeError, an IndexError
or numpy's error from deep inside a formula, misnamed the argument, or returned a number
without a word. Each now raises a MudrftError naming the argument (or warns)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft
from mudrft import feet, metrics, terrains
from mudrft._validation import MudrftError, PlausibilityWarning
from mudrft.calibration import OnlineEstimator, calibrate, example_dataset

MUD = mudrft.paper_mud(0.25)
V = mudrft.paper_parameters(0.25, "vertical")
H = mudrft.paper_parameters(0.25, "horizontal")


# -- parameter sets ------------------------------------------------------------------------
def test_parameter_fields_must_broadcast():
    # shapes (2,) and (3,) were accepted and failed inside a step
    with pytest.raises(MudrftError, match=r"broadcast together, got alpha \(2,\).*lam \(3,\)"):
        V.replace(alpha=np.full(2, 24e3), lam=np.full(3, 1.9))
    with pytest.raises(MudrftError, match=r"alpha must hold at least one value"):
        V.replace(alpha=np.array([]))
    with pytest.raises(MudrftError, match=r"vertical \(2,\), horizontal \(3,\)"):
        mudrft.Mud(V.replace(alpha=np.full(2, 24e3)), H.replace(alpha=np.full(3, 9e3)))


def test_water_content_and_name_of_a_set_are_checked():
    # Mud(water_content="x") was accepted and its repr failed; 5.0 (%) was accepted
    with pytest.raises(MudrftError, match=r"water_content must be a number"):
        mudrft.Mud(V, H, water_content="x")
    with pytest.raises(
        MudrftError, match=r"volume fraction in \[0, 1\], got 25.0 \(give a fraction"
    ):
        V.replace(water_content=25.0)
    with pytest.raises(MudrftError, match=r"name must be a string, got 5"):
        mudrft.Mud(V, H, name=5)
    assert mudrft.Mud(V, H, water_content=np.float32(0.25)).water_content == pytest.approx(0.25)


def test_stack_and_from_dict_name_the_mistake():
    with pytest.raises(MudrftError, match=r"sets\[1\] must be a MudParameters, got str"):
        mudrft.MudParameters.stack([V, "x"])
    with pytest.raises(MudrftError, match=r"sets\[1\] must be a single parameter set"):
        mudrft.MudParameters.stack([V, V.replace(alpha=np.full(2, 24e3))])
    with pytest.raises(MudrftError, match=r"data must be a dict .* got list"):
        mudrft.MudParameters.from_dict([1, 2])  # type: ignore[arg-type]


def test_paper_mud_extrapolate_is_a_flag_and_a_0d_array_is_a_number():
    # extrapolate="no" is true in Python: it extrapolated
    with pytest.raises(MudrftError, match=r"extrapolate must be True or False, got 'no'"):
        mudrft.paper_mud(0.2, extrapolate="no")  # type: ignore[arg-type]
    assert mudrft.paper_mud(np.array(0.35)).vertical.alpha == mudrft.paper_mud(0.35).vertical.alpha


# -- metrics -------------------------------------------------------------------------------
def test_impulse_and_energy_check_the_force_shape():
    # a scalar force was an IndexError; (n, 3, 4) and (n, 2) returned numbers
    with pytest.raises(MudrftError, match=r"force must have shape \(2,\) or \(2, 3\)"):
        metrics.impulse([0.0, 1.0], 5.0)
    with pytest.raises(MudrftError, match=r"force must have shape \(2,\) or \(2, 3\)"):
        metrics.energy([0.0, 1.0], 5.0, 1.0)
    with pytest.raises(MudrftError, match=r"force must have shape"):
        metrics.impulse([0.0, 1.0], np.zeros((2, 3, 4)))
    with pytest.raises(MudrftError, match=r"time must hold at least one sample"):
        metrics.impulse([], np.zeros((0, 3)))
    assert metrics.impulse([0.0, 1.0], [[1.0, 2.0, 3.0]] * 2).tolist() == [1.0, 2.0, 3.0]


def test_sinking_depth_refuses_the_tips_z():
    result = mudrft.simulate(feet.Flat(), MUD, mudrft.gait(0.2))
    # the tip's z is <= 0 in the mud: its maximum read 0 sinking for a foot that sank 20 mm
    with pytest.raises(MudrftError, match=r"depth must be >= 0 m .* tip's z"):
        metrics.sinking_depth(result.position[:, 2])
    with pytest.raises(MudrftError, match=r"final must be True or False, got 'no'"):
        metrics.sinking_depth(result.depth, final="no")  # type: ignore[arg-type]
    assert metrics.sinking_depth(result.depth) == pytest.approx(0.02)


# -- calibration options -------------------------------------------------------------------
@pytest.mark.parametrize(
    ("options", "match"),
    [
        ({"xi0": [0.1]}, r"xi0 must be a single number"),
        ({"phases": "no"}, r"phases must be True or False, got 'no'"),
        ({"trace_limit": -1}, r"trace_limit must be an integer >= 0, got -1"),
        ({"trace_limit": 1.5}, r"trace_limit must be an integer >= 0, got 1.5"),
        ({"fixed": {"alpha": [1.0, 2.0]}}, r"fixed\['alpha'\] must be a single number"),
        ({"fixed": {"alpha": "1"}}, r"fixed\['alpha'\] must be a number .* string '1'"),
    ],
)
def test_calibrate_checks_its_options(options, match):
    with pytest.raises(MudrftError, match=match):
        calibrate(example_dataset(), "vertical", **{"max_nfev": 1, "phases": False, **options})
