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
from mudrft.trajectories import Trajectory

MUD = mudrft.paper_mud(0.25)
V = mudrft.paper_parameters(0.25, "vertical")
H = mudrft.paper_parameters(0.25, "horizontal")


# -- a list or an array where one number belongs ------------------------------------------
@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: terrains.MudTerrain(MUD, xi0=[0.1, 0.2]), r"xi0 must be a single number"),
        (
            lambda: terrains.MudTerrain(MUD, characteristic_length=np.array([0.05, 0.06])),
            r"characteristic_length must be a single number",
        ),
        (lambda: terrains.MudTerrain(MUD, heading_speed=[1e-6]), r"heading_speed must be a single"),
        (lambda: mudrft.plate_intrusion(depth=[0.03, 0.04]), r"depth must be a single number"),
        (lambda: mudrft.plate_intrusion(speed=[0.02, 0.03]), r"speed must be a single number"),
        (lambda: mudrft.plate_intrusion(hold=[1.0]), r"hold must be a single number"),
        (lambda: mudrft.plate_intrusion(angle=[0.1, 0.2]), r"angle must be a single number"),
        (lambda: mudrft.plate_intrusion(dt=[1e-3, 1e-3]), r"dt must be a single number"),
        (lambda: mudrft.LoadControl(weight=[1.0, 2.0]), r"weight must be a single number"),
        (lambda: mudrft.LoadControl(weight=10.0, dt=[1e-3]), r"dt must be a single number"),
        (lambda: mudrft.LoadControl(weight=10.0, duration=[1.0]), r"duration must be a single"),
        (lambda: terrains.LinearStiffness(stiffness=[1e6, 2e6]), r"stiffness must be a single"),
        (lambda: terrains.RigidGround(damping=[1.0, 2.0]), r"damping must be a single number"),
        (lambda: terrains.MaxwellMud(alpha=[1.0, 2.0]), r"alpha must be a single number"),
        (lambda: terrains.GranularRFT(zeta=[1.0, 2.0]), r"zeta must be a single number"),
        (lambda: terrains.GranularRFT3D(rho_c=[1.0, 2.0]), r"rho_c must be a single number"),
        (lambda: OnlineEstimator(forgetting=[0.9]), r"forgetting must be a single number"),
        (
            lambda: OnlineEstimator(characteristic_length=[0.05]),
            r"characteristic_length must be a single number",
        ),
    ],
)
def test_one_number_options_refuse_a_list(make, match):
    # each was a TypeError ("only 0-dimensional arrays can be converted", "can't multiply
    # sequence") or numpy's broadcast error, at construction or inside simulate
    with pytest.raises(MudrftError, match=match):
        make()


def test_simulate_dt_refuses_a_list():
    with pytest.raises(MudrftError, match=r"dt must be a single number \[s\]"):
        mudrft.simulate(feet.Flat(), MUD, mudrft.gait(0.2), dt=[0.01])


def test_one_number_options_are_stored_as_floats():
    lc = mudrft.LoadControl(weight=np.float32(10.0), mass=np.array(1.0))
    assert type(lc.weight) is float and type(lc.mass) is float
    assert type(terrains.RigidGround(stiffness=np.int64(1000)).stiffness) is float


def test_none_is_named_not_read_as_nan():
    # numpy reads None as NaN: the message was "depth must be finite, got nan"
    with pytest.raises(
        MudrftError, match=r"depth must be a number or an array of numbers, got None"
    ):
        feet.Flat().resultant(None, (1.0, 1.0, 1.0), 0.3)
    with pytest.raises(MudrftError, match=r"nu must be a number .* got None"):
        V.replace(nu=None)


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


# -- plausibility ------------------------------------------------------------------------
def test_characteristic_length_in_mm_warns():
    with pytest.warns(PlausibilityWarning, match=r"characteristic_length is 45 m"):
        terrains.MudTerrain(MUD, characteristic_length=45.0)
    with pytest.warns(PlausibilityWarning, match=r"characteristic_length is 50 m"):
        terrains.MaxwellMud(characteristic_length=50.0)
    with pytest.warns(PlausibilityWarning, match=r"characteristic_length is 50 m"):
        OnlineEstimator(characteristic_length=50.0)
    with pytest.raises(MudrftError, match=r"characteristic_length must lie in"):
        terrains.MudTerrain(MUD, characteristic_length=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert terrains.MudTerrain(MUD, characteristic_length=0.05).characteristic_length == 0.05


def test_plate_depth_in_mm_warns():
    with pytest.warns(PlausibilityWarning, match=r"plate_intrusion: a depth of 30 m"):
        mudrft.plate_intrusion(depth=30.0, speed=20.0, dt=0.01)


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


def test_a_trajectory_name_and_meta_are_checked():
    t = np.linspace(0.0, 1.0, 5)
    p = np.zeros((5, 3))
    with pytest.raises(MudrftError, match=r"name must be a string, got 5"):
        Trajectory(t, p, p, name=5)
    with pytest.raises(MudrftError, match=r"meta must be a dict, got list"):
        Trajectory(t, p, p, meta=[1])


def test_normalized_stress_refuses_negative_areas_and_peak_support_a_mask():
    force = np.array([[0.0, 0.0, 10.0]])
    with pytest.raises(MudrftError, match=r"areas must be >= 0 m\^2, got -0.01"):
        metrics.normalized_stress(force, [[0.0, 0.0, -0.01]])
    assert metrics.normalized_stress(force, [[0.0, 0.0, 0.01]])[0, 2] == pytest.approx(1000.0)
    with pytest.raises(MudrftError, match="force_z must be the vertical force"):
        metrics.peak_support(np.array([1.0, 2.0]) > 1.5)
