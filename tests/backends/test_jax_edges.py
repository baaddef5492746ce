"""JAX at the model's kinks: the foot at the surface, zero speed, the heading switch, the
start of the retraction, xi at 0 and 1, both quasi-static clocks, meshes at the waterline.

What a learning user relies on there: values equal numpy's, and derivatives that are
finite (a NaN from the untaken side of a ``where``, or 0 x inf from a square root or an
arc cosine at 0 or 1, poisons a whole batch of gradients).
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
import pytest

import mudrft
from mudrft.constitutive import step as np_step
from mudrft.constitutive.state import ChannelState

jax = pytest.importorskip("jax")
mjax = pytest.importorskip("mudrft.backends.jax")
jnp = mjax.enable_x64().numpy

HS = 1e-6  # MudTerrain's default heading_speed [m/s]


def _finite(tree) -> bool:
    return all(bool(np.all(np.isfinite(np.asarray(x)))) for x in jax.tree_util.tree_leaves(tree))


def _mesh(foot, resolution=2):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return foot.to_mesh(resolution=resolution)


@pytest.mark.parametrize("foot", [mudrft.feet.SemiCylinder(), mudrft.feet.SemiSphere()])
def test_curved_feet_derivatives_are_finite_at_the_surface_under_plain_jax_numpy(foot):
    """theta_c = arccos(1 - z/R) has an infinite derivative at z = 0: with plain jax.numpy
    (force_function documents it) every derivative of the force at the surface was NaN,
    even by the stresses. The value there is now a constant (D107)."""
    from mudrft.backends.forces import force_function

    fn = force_function(foot, xp=jnp)
    jac = jax.jit(jax.jacrev(fn, argnums=(0, 1, 2)))
    stress = jnp.array([900.0, -400.0, 2500.0])
    fwd = jax.jit(jax.jacfwd(fn, argnums=(0, 1, 2)))
    for depth in (0.0, 1e-13, 0.01, foot.height):
        assert _finite(jac(depth, stress, 0.4)), depth
        assert _finite(fwd(depth, stress, 0.4)), depth  # forward mode: by the stresses too
    # at the surface the force is 0 whatever the stresses; below, it is piecewise linear in
    # them, so a central difference of 1 Pa is exact to rounding
    assert np.all(np.asarray(jac(0.0, stress, 0.4)[1]) == 0.0)
    f_np, s0 = force_function(foot), np.asarray(stress)
    fd = np.stack([(f_np(0.01, s0 + e, 0.4) - f_np(0.01, s0 - e, 0.4)) / 2 for e in np.eye(3)], 1)
    np.testing.assert_allclose(np.asarray(jac(0.01, stress, 0.4)[1]), fd, rtol=1e-9, atol=1e-15)


def test_mesh_vertex_gradient_is_finite_under_plain_jax_numpy():
    """integrate_triangles documents xp=jax.numpy; the unit normal's horizontal part
    sqrt(n_x^2 + n_y^2) is 0 on the sole of a foot, and its infinite derivative made the
    whole vertex gradient NaN. It now equals the gradient of mesh_force (D107)."""
    from mudrft.feet.surface import integrate_triangles

    m = _mesh(mudrft.feet.Flat())
    v, f = m.vertices, m.faces
    stress, wts = jnp.array([900.0, -400.0, 2500.0]), jnp.array([0.3, -0.7, 1.1])

    def both(vv, d):
        plain = jax.grad(lambda x: integrate_triangles(x[f], d, stress, 0.7, xp=jnp) @ wts)(vv)
        safe = jax.grad(lambda x: mjax.mesh_force(x, f, d, stress, 0.7) @ wts)(vv)
        return plain, safe

    both = jax.jit(both)
    for d in (0.0, 0.01, float(v[:, 2].max())):  # at the sole, inside, at the top rim
        plain, safe = both(jnp.asarray(v), d)
        assert _finite(plain), d
        scale = np.abs(np.asarray(safe)).max()
        np.testing.assert_allclose(np.asarray(plain), np.asarray(safe), atol=1e-13 * scale)


def _step_edges():
    """(g_old, g_w, xi, clock, clock_w, gamma, gamma_dot) at the constitutive step's kinks."""
    rows = []
    states = [(0.0, 0.0), (0.3, 0.3), (0.2, 0.3), (-0.3, -0.3)]  # fresh, at g_w, retracting
    for (g0, gw), xi, g, gd, cw in itertools.product(
        states, (0.0, 1.0), (0.0, 1e-300, 0.3, -0.3), (0.0, 1e-300, -1e-12, 2.0), (0.0, 0.2)
    ):
        rows.append((g0, gw, xi, 0.5, cw, g, gd))
    return np.array(rows).T


@pytest.mark.parametrize(
    ("thixotropy", "clock", "acceleration"),
    [("ode", "contact", None), ("ode", "contact", True), ("quasi-static", "retraction", None)],
)
def test_step_values_and_finite_gradients_at_the_kinks(thixotropy, clock, acceleration):
    """Surface (gamma = 0, tiny), zero rate, start of the retraction (gamma = gamma_w),
    xi at 0 and 1, both clocks at 0: JAX equals numpy and every gradient (by the state,
    the inputs and all parameters, n < 1 included) is finite."""
    p = mudrft.paper_parameters(0.25, "vertical").replace(n=0.4)
    g0, gw, xi, cl, cw, g, gd = _step_edges()
    kw = dict(acceleration=acceleration, thixotropy=thixotropy, clock=clock)

    def total(params, g0, gw, xi, cl, cw, g, gd):
        st = ChannelState(g0, gw, xi, 100.0, -50.0, cl, cw)
        return mudrft.constitutive.dynamics.step(params, st, g, gd, 1e-3, xp=jnp, **kw)[1].total

    grads = jax.jit(jax.vmap(jax.grad(total, argnums=tuple(range(8))), (None,) + (0,) * 7))
    assert _finite(grads(mjax.to_jax(p), g0, gw, xi, cl, cw, g, gd))
    got = jax.jit(total)(mjax.to_jax(p), g0, gw, xi, cl, cw, g, gd)
    z = 0.0 * g
    st = ChannelState(g0, gw, xi, z + 100.0, z - 50.0, cl, cw)
    ref = np_step(p, st, g, gd, 1e-3, **kw)[1].total
    np.testing.assert_allclose(np.asarray(got), ref, rtol=1e-13, atol=1e-9)


def _terrain_edges():
    """Start and end tip positions and the velocity of a step at the terrain's kinks [m, m/s]."""
    rows = []
    for z0, z, (vx, vy), vz in itertools.product(
        (0.001, -0.005),  # from out of the mud (entry), from inside (z > z0: retraction)
        (0.0, 1e-13, -1e-13, -0.01),  # at, just below, just above the surface, inside
        ((0.0, 0.0), (HS, 0.0), (0.0, -HS), (0.05, -0.03)),  # still, at the heading switch
        (0.0, -0.02, 0.02),  # still, intruding, retracting
    ):
        rows.append((z0, z, vx, vy, vz))
    z0, z, vx, vy, vz = np.array(rows).T
    return (
        np.stack([0 * z, 0 * z, z0], 1),
        np.stack([vx * 1e-3, vy * 1e-3, z], 1),
        np.stack([vx, vy, vz], 1),
    )


@pytest.mark.parametrize(
    ("foot", "thixotropy", "clock"),
    [
        (mudrft.feet.SemiSphere(), "ode", "contact"),
        (_mesh(mudrft.feet.Flat()), "quasi-static", "contact"),
        (mudrft.feet.SemiCylinder(), "quasi-static", "retraction"),
    ],
    ids=["sphere-ode", "flat-mesh-qs-contact", "cylinder-qs-retraction"],
)
def test_terrain_step_values_and_finite_derivatives_at_the_kinks(foot, thixotropy, clock):
    """A terrain step from undisturbed mud (an entry, or a start inside at its deepest
    point): the force equals MudTerrain's, and its gradient by the parameters, the position
    and the velocity is finite, at the surface, at zero speed, at exactly the heading speed
    and at the start of the retraction."""
    from mudrft.backends.forces import force_function

    mud = mudrft.paper_mud(0.25)
    fn, lc = force_function(foot, xp=mjax.safe_namespace()), foot.characteristic_length
    kw = dict(force_fn=fn, characteristic_length=lc, thixotropy=thixotropy, clock=clock)
    p0, p1, v1 = _terrain_edges()
    wts = jnp.array([0.3, -0.7, 1.1])

    def force_and_grad(params, p0, p1, v1):  # one compilation for values and gradients
        st = mjax.initial_terrain_state(p0, lc)  # the step is element-wise: rows independent
        force, vjp = jax.vjp(lambda q, p, v: mjax.terrain_step(q, st, p, v, 1e-3, **kw)[1][0],
                             params, p1, v1)  # fmt: skip
        return force, vjp(jnp.broadcast_to(wts, force.shape))  # params: summed over the rows

    got, grads = jax.jit(force_and_grad)(mjax.to_jax(mud), p0, p1, v1)
    assert _finite(grads)
    terrain = mudrft.MudTerrain(mud, thixotropy=thixotropy, clock=clock)
    for i in range(len(p0)):
        ref = terrain.step(foot, terrain.initial_state(foot, p0[i]), p1[i], v1[i], 1e-3)[1].force
        np.testing.assert_allclose(got[i], ref, rtol=0, atol=1e-12 * (np.abs(ref).max() + 1))
