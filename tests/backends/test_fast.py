"""FastMudFoot (floats/math or numba) gives the forces of MudTerrain + the closed-form foot."""

from __future__ import annotations

import numpy as np
import pytest
from _backend_support import terrain_forces, wandering_path

import mudrft
from mudrft._validation import MudrftError
from mudrft.backends.fast import FastMudFoot, foot_geometry

FEET = [mudrft.feet.Flat(), mudrft.feet.SemiCylinder(), mudrft.feet.SemiSphere()]


def _backends():
    out = ["python"]
    try:
        import numba  # noqa: F401

        out.append("numba")
    except ImportError:
        pass
    return out


# The fast path evaluates the same formulas in the same order on IEEE doubles; the only
# differences are libm versus numpy's vectorized exp/tanh/pow (a few ulp). Forces are sums of
# terms of the size of the largest force along the path, so 1e-11 of that size (~10^5 ulp)
# bounds rounding with a wide margin, while any wrong term or sign is O(1) of it.
RTOL = 1e-11


@pytest.mark.parametrize("backend", _backends())
@pytest.mark.parametrize("foot", FEET, ids=lambda f: f.name)
def test_fast_foot_matches_mud_terrain(foot, backend):
    mud = mudrft.paper_mud(0.3)
    terrain = mudrft.MudTerrain(mud)
    dt = 1e-3
    pos, vel = wandering_path(400, dt, seed=len(foot.name))
    f_ref, s_ref, d_ref = terrain_forces(terrain, foot, pos, vel, dt)
    ff = FastMudFoot(foot, terrain, position=pos[0], backend=backend)
    assert ff.backend == backend
    got_f, got_s, got_d = [], [], []
    for k in range(1, len(pos)):
        got_f.append(ff.step(pos[k], vel[k], dt))
        got_s.append(ff.stress)
        got_d.append(ff.depth)
    scale = np.abs(f_ref).max()
    assert scale > 1.0  # the path really loads the foot
    assert np.any(d_ref == 0) and np.any(d_ref > 0)  # it leaves and re-enters the mud
    np.testing.assert_allclose(got_f, f_ref, rtol=0, atol=RTOL * scale)
    np.testing.assert_allclose(got_s, s_ref, rtol=0, atol=RTOL * np.abs(s_ref).max())
    np.testing.assert_allclose(got_d, d_ref, rtol=0, atol=1e-15)


@pytest.mark.parametrize("backend", _backends())
def test_fast_foot_takes_the_terrain_options(backend):
    """No acceleration term, no reset on exit, structured fresh mud, a custom L_c."""
    foot = mudrft.feet.SemiSphere()
    terrain = mudrft.MudTerrain(
        mudrft.paper_mud(0.4),
        acceleration=False,
        reset_on_exit=False,
        xi0=0.7,
        characteristic_length=0.03,
    )
    dt = 2e-3
    pos, vel = wandering_path(200, dt, seed=7)
    f_ref, _, _ = terrain_forces(terrain, foot, pos, vel, dt)
    ff = FastMudFoot(foot, terrain, position=pos[0], backend=backend)
    got = np.array([ff.step(tuple(pos[k]), list(vel[k]), dt) for k in range(1, len(pos))])
    np.testing.assert_allclose(got, f_ref, rtol=0, atol=RTOL * np.abs(f_ref).max())


@pytest.mark.parametrize("backend", _backends())
def test_fast_foot_reset_restarts_from_undisturbed_mud(backend):
    foot = mudrft.feet.Flat()
    ff = FastMudFoot(foot, mudrft.paper_mud(0.25), backend=backend)
    first = [ff.step((0.0, 0.0, -1e-4 * k), (0.0, 0.0, -0.1), 1e-3) for k in range(1, 20)]
    ff.reset((0.0, 0.0, 0.0))
    again = [ff.step((0.0, 0.0, -1e-4 * k), (0.0, 0.0, -0.1), 1e-3) for k in range(1, 20)]
    np.testing.assert_array_equal(first, again)


@pytest.mark.parametrize("backend", _backends())
def test_fast_foot_rejects_bad_input(backend):
    ff = FastMudFoot(mudrft.feet.Flat(), mudrft.paper_mud(0.25), backend=backend)
    with pytest.raises(MudrftError, match="finite"):
        ff.step((0.0, np.nan, -0.01), (0.0, 0.0, 0.0), 1e-3)
    with pytest.raises(MudrftError, match="dt"):
        ff.step((0.0, 0.0, -0.01), (0.0, 0.0, 0.0), 0.0)
    with pytest.raises(MudrftError, match="3 components"):
        ff.step((0.0, 0.0), (0.0, 0.0, 0.0), 1e-3)
    with pytest.raises(MudrftError, match="real numbers"):
        ff.step((0.0, "a", -0.01), (0.0, 0.0, 0.0), 1e-3)
    with pytest.raises(MudrftError, match="real numbers"):
        ff.step((0.0, 0.0, -0.01), (1j, 0.0, 0.0), 1e-3)


def test_fast_foot_rejects_unsupported_feet_and_batches():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = mudrft.feet.Flat().to_mesh(resolution=1)
    with pytest.raises(MudrftError, match="closed-form foot"):
        FastMudFoot(mesh, mudrft.paper_mud(0.25))
    with pytest.raises(MudrftError, match="backend"):
        FastMudFoot(mudrft.feet.Flat(), mudrft.paper_mud(0.25), backend="cuda")
    p = mudrft.paper_parameters(0.25)
    batch = mudrft.Mud(p.replace(alpha=np.array([1e4, 2e4])), mudrft.paper_mud(0.25).horizontal)
    with pytest.raises(MudrftError, match="BatchedMud"):
        FastMudFoot(mudrft.feet.Flat(), batch)
    assert foot_geometry(mudrft.feet.SemiCylinder(radius=0.05, width=0.07, height=0.03)) == (
        1,
        (0.05, 0.07, 0.03),
    )


def test_numba_fast_foot_and_loop_share_one_compiled_foot_step():
    """Integer input converts to floats (no new specialization, which costs seconds), and
    the loop over feet and the single-foot driver run one compilation of the foot step."""
    pytest.importorskip("numba")
    from mudrft.backends.batch import BatchedMud
    from mudrft.backends.numba import _compiled_one_foot, compiled_fast_foot

    mud = mudrft.paper_mud(0.25)
    ints = FastMudFoot(mudrft.feet.Flat(), mud, position=[0, 0, 1], backend="numba")
    floats = FastMudFoot(mudrft.feet.Flat(), mud, position=[0.0, 0.0, 1.0], backend="numba")
    for z in (0, -1, -2):
        f_int = ints.step([0, 0, z * 0.01], [0, 0, -1], 0.01)
        f_float = floats.step([0.0, 0.0, z * 0.01], [0.0, 0.0, -1.0], 0.01)
        np.testing.assert_array_equal(f_int, f_float)
    assert len(compiled_fast_foot().signatures) == 1
    sim = BatchedMud(mud, mudrft.feet.Flat(), 2, position=np.zeros((2, 3)), backend="numba")
    sim.step(np.full((2, 3), -0.01), np.full((2, 3), -0.1), 1e-3)
    assert len(_compiled_one_foot().signatures) == 1
