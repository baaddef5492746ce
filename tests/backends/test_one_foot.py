"""One foot stepped by the compiled rows (a BatchedMud of one, numba) gives MudTerrain's forces.

The compiled path (mudrft.terrains.rows, mudrft._jit) runs the same functions as
MudTerrain's step on Python floats; numba evaluates the same formulas in the same order on
IEEE doubles, so the only differences are its libm calls against Python's (a few ulp).
Forces are sums of terms of the size of the largest force along the path, so 1e-11 of that
size bounds rounding with a wide margin, while any wrong term or sign is O(1) of it.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _backend_support import terrain_forces, wandering_path

import mudrft
from mudrft._validation import MudrftError
from mudrft.backends import BatchedMud

RTOL = 1e-11


def _feet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = mudrft.feet.SemiCylinder().to_mesh(resolution=6)
    return [
        mudrft.feet.Flat(),
        mudrft.feet.SemiCylinder(),
        mudrft.feet.SemiSphere(),
        mesh,
        mudrft.feet.MorphingFoot(),
    ]


def _one(foot, terrain, pos):
    return BatchedMud(terrain, foot, 1, position=pos, backend="numba")


@pytest.mark.parametrize("foot", _feet(), ids=lambda f: type(f).__name__)
def test_one_compiled_foot_matches_mud_terrain(foot):
    terrain = mudrft.MudTerrain(mudrft.paper_mud(0.3))
    dt = 1e-3
    pos, vel = wandering_path(400, dt, seed=3)
    f_ref, s_ref, d_ref = terrain_forces(terrain, foot, pos, vel, dt)
    one = _one(foot, terrain, pos[0])
    got = [
        (one.step(pos[k], vel[k], dt)[0], one.stress[0], one.depth[0]) for k in range(1, len(pos))
    ]
    got_f, got_s, got_d = (np.array(v) for v in zip(*got, strict=True))
    scale = np.abs(f_ref).max()
    assert scale > 1.0  # the path really loads the foot
    assert np.any(d_ref == 0) and np.any(d_ref > 0)  # it leaves and re-enters the mud
    np.testing.assert_allclose(got_f, f_ref, rtol=0, atol=RTOL * scale)
    np.testing.assert_allclose(got_s, s_ref, rtol=0, atol=RTOL * np.abs(s_ref).max())
    np.testing.assert_allclose(got_d, d_ref, rtol=0, atol=1e-15)


def test_one_compiled_foot_takes_the_terrain_options():
    """No acceleration term, no reset on exit, structured fresh mud, a custom L_c, and the
    paper's quasi-static evaluation with its clock restarted at the retraction."""
    foot = mudrft.feet.SemiSphere()
    dt = 2e-3
    pos, vel = wandering_path(200, dt, seed=7)
    for terrain in (
        mudrft.MudTerrain(
            mudrft.paper_mud(0.4), acceleration=False, reset_on_exit=False, xi0=0.7,
            characteristic_length=0.03,
        ),
        mudrft.MudTerrain(mudrft.paper_mud(0.25), thixotropy="quasi-static", clock="retraction"),
    ):  # fmt: skip
        f_ref, _, _ = terrain_forces(terrain, foot, pos, vel, dt)
        one = _one(foot, terrain, pos[0])
        got = np.array([one.step(pos[k], vel[k], dt)[0] for k in range(1, len(pos))])
        np.testing.assert_allclose(got, f_ref, rtol=0, atol=RTOL * np.abs(f_ref).max())


def test_simulate_runs_the_compiled_path_and_the_float_path_alike():
    """simulate() of a foot of mudrft.feet runs the rows; MudTerrain.step, the reference."""
    traj = mudrft.gait(speed=0.26)
    for foot in _feet():
        terrain = mudrft.MudTerrain(mudrft.paper_mud(0.25))
        res = mudrft.simulate(foot, terrain, traj)
        f_ref, _, _ = terrain_forces(terrain, foot, traj.position, traj.velocity, traj.time[1])
        scale = np.abs(f_ref).max()
        np.testing.assert_allclose(res.force[1:], f_ref, rtol=0, atol=RTOL * scale)


def test_reset_restarts_from_undisturbed_mud():
    one = BatchedMud(mudrft.paper_mud(0.25), mudrft.feet.Flat(), 1, backend="numba")
    path = [((0.0, 0.0, -1e-4 * k), (0.0, 0.0, -0.1)) for k in range(1, 20)]
    first = [one.step(p, v, 1e-3).copy() for p, v in path]
    one.reset((0.0, 0.0, 0.0))
    again = [one.step(p, v, 1e-3).copy() for p, v in path]
    np.testing.assert_array_equal(first, again)


def test_bad_input_and_feet_the_rows_do_not_hold_are_refused():
    one = BatchedMud(mudrft.paper_mud(0.25), mudrft.feet.Flat(), 1, backend="numba")
    with pytest.raises(MudrftError, match="finite"):
        one.step((0.0, np.nan, -0.01), (0.0, 0.0, 0.0), 1e-3)
    with pytest.raises(MudrftError, match="dt"):
        one.step((0.0, 0.0, -0.01), (0.0, 0.0, 0.0), 0.0)
    with pytest.raises(MudrftError, match="shape"):
        one.step((0.0, 0.0), (0.0, 0.0, 0.0), 1e-3)

    class Custom(mudrft.feet.Flat):
        pass

    with pytest.raises(MudrftError, match=r"backend 'numba' runs the feet of mudrft\.feet"):
        BatchedMud(mudrft.paper_mud(0.25), Custom(), 1, backend="numba")
