"""MudTerrain validates its options where it is made, and its step's inputs."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft import MudrftError
from mudrft.terrains import MudTerrain

MUD = mudrft.paper_mud(0.25)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"heading_speed": -1.0}, "heading_speed"),
        ({"heading_speed": float("nan")}, "heading_speed"),
        ({"xi0": 5.0}, "xi0"),
        ({"xi0": -0.1}, "xi0"),
        ({"characteristic_length": 0.0}, "characteristic_length"),
        ({"characteristic_length": float("inf")}, "characteristic_length"),
        ({"acceleration": "yes"}, "acceleration"),
        ({"reset_on_exit": 1}, "reset_on_exit"),
        ({"name": 3}, "name"),
    ],
)
def test_an_invalid_option_is_refused_at_construction(options, message):
    with pytest.raises(MudrftError, match=message):
        MudTerrain(MUD, **options)


def test_a_parameter_set_that_is_not_a_mud_is_refused():
    with pytest.raises(MudrftError, match="mud must be a Mud"):
        MudTerrain(mudrft.paper_parameters(0.25))


@pytest.mark.parametrize(
    ("position", "velocity", "dt", "message"),
    [
        ([0.0, np.nan, -0.01], [0.0, 0.0, 0.0], 1e-3, "position"),
        ([0.0, 0.0, -0.01], [0.0, np.inf, 0.0], 1e-3, "velocity"),
        ([0.0, 0.0, -0.01], [0.0, 0.0, 0.0], -1.0, "dt"),
        ([0.0, 0.0, -0.01], [0.0, 0.0, 0.0], 0.0, "dt"),
        ([0.0, 0.0], [0.0, 0.0, 0.0], 1e-3, "position"),
        ([0.0, 0.0, -0.01], [0.0, 0.0], 1e-3, "velocity"),
    ],
)
def test_the_step_refuses_bad_motion(position, velocity, dt, message):
    foot = mudrft.feet.Flat()
    terrain = MudTerrain(MUD)
    state = terrain.initial_state(foot, np.zeros(3))
    with pytest.raises(MudrftError, match=message):
        terrain.step(foot, state, position, velocity, dt)


def test_one_foot_on_floats_equals_a_batch_of_one_on_arrays():
    """The single-foot path (Python floats) and the batch path (numpy) run the same step."""
    foot = mudrft.feet.SemiCylinder()
    terrain = MudTerrain(MUD)
    tr = mudrft.gait(0.2)
    s1 = terrain.initial_state(foot, tr.position[0])
    sb = terrain.initial_state(foot, tr.position[:1])
    f1, fb = [], []
    for k in range(1, len(tr)):
        dt = float(tr.time[k] - tr.time[k - 1])
        s1, o1 = terrain.step(foot, s1, tr.position[k], tr.velocity[k], dt)
        sb, ob = terrain.step(foot, sb, tr.position[k : k + 1], tr.velocity[k : k + 1], dt)
        f1.append(o1.force)
        fb.append(ob.force[0])
    # libm and numpy's vectorized exp/tanh may differ by an ulp, and the ODE carries the
    # difference: 1e-12 of the run's peak force. (Of each step's own force it failed with
    # numpy 1.24 at first contact, 4.5e-15 N of 4.2e-4 N, where stresses of 1e4 Pa act on
    # 0.5 um of depth; the largest gap over the run was 7e-12 N of 57 N.)
    gap = np.abs(np.array(f1) - np.array(fb))
    assert gap.max() <= 1e-12 * np.abs(fb).max(), np.unravel_index(gap.argmax(), gap.shape)


def test_the_step_matches_its_tips_to_the_state_or_names_the_state():
    """A batch's state with one position (a planner trying one action on every
    candidate) raised numpy's "truth value of an array ... is ambiguous", and tips that
    do not broadcast with the state numpy's "operands could not be broadcast"."""
    foot = mudrft.feet.Flat()
    terrain = MudTerrain(MUD)
    start = np.array([[0.0, 0.0, -0.01], [0.001, 0.0, -0.012], [0.0, 0.002, 0.001]])
    state = terrain.initial_state(foot, start)
    p, v = np.array([0.0005, 0.0, -0.0105]), np.array([0.5, 0.0, -0.5])
    new, out = terrain.step(foot, state, p, v, 1e-3)
    _, expected = terrain.step(foot, state, np.tile(p, (3, 1)), np.tile(v, (3, 1)), 1e-3)
    np.testing.assert_array_equal(out.force, expected.force)
    assert out.force.shape == (3, 3) and np.shape(new.channels.in_mud) == (3,)
    with pytest.raises(MudrftError, match=r"state is the mud under tips of shape \(3,\)"):
        terrain.step(foot, state, np.tile(p, (5, 1)), np.tile(v, (5, 1)), 1e-3)
    with pytest.raises(MudrftError, match="state must be the MudState"):
        terrain.step(foot, state.channels, p, v, 1e-3)
