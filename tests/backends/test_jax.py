"""JAX backend: equal to the numpy backend, and its gradients equal finite differences."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
from _backend_support import channel_inputs, parameter_sets, wandering_path
from hypothesis import given, settings

import mudrft
from mudrft._validation import MudrftError
from mudrft.constitutive import run, step
from mudrft.parameters.base import PARAMETER_UNITS

jax = pytest.importorskip("jax")
mjax = pytest.importorskip("mudrft.backends.jax")

# XLA's exp, tanh, expm1 and pow differ from numpy's libm by a few ulp; the constitutive
# step is a contraction (every state decays exponentially), so these differences do not
# grow along a run. Stresses are compared relative to the sum of the magnitudes of their
# terms with 1e-11 (~10^5 ulp): rounding is far below, a modelling difference far above.
RTOL = 1e-11


def _scale(out) -> np.ndarray:
    return np.abs(out.elastic) + np.abs(out.thixotropic) + np.abs(out.suction) + 1.0


@settings(max_examples=30, deadline=None)
@given(parameter_sets(), channel_inputs(shape=(5,)))
def test_jax_step_matches_numpy_step(p, inputs):
    state, gamma, gdot, dt, seal = inputs
    ref_state, ref = step(p, state, gamma, gdot, dt, seal=seal)
    new, out = mjax.step(mjax.to_jax(p), state, gamma, gdot, dt, seal=seal)
    sc = _scale(ref)
    for name in ("total", "elastic", "thixotropic", "suction"):
        assert np.all(np.abs(np.asarray(getattr(out, name)) - getattr(ref, name)) <= RTOL * sc), (
            name
        )
    for a, b in zip(new, ref_state, strict=True):
        assert np.all(np.abs(np.asarray(a) - b) <= RTOL * (np.abs(b) + 1e3))


def test_vmapped_step_gives_each_member_its_own_parameters():
    muds = [mudrft.paper_mud(w) for w in (0.25, 0.3, 0.4)]
    rng = np.random.default_rng(2)
    from mudrft.terrains import channel_parameters

    ps = [channel_parameters(m) for m in muds]
    jp = mjax.JaxParams(
        *(np.stack([np.asarray(getattr(p, k)) for p in ps]) for k in PARAMETER_UNITS)
    )
    state = mjax.initial_state((3, 3), xi0=0.2)
    g = rng.normal(size=(3, 3)) * 0.2
    gd = rng.normal(size=(3, 3))
    _, out = mjax.batched_step(jp, state, g, gd, 1e-2)
    for i, p in enumerate(ps):
        _, ref = step(p, mudrft.constitutive.initial_state((3,), xi0=0.2), g[i], gd[i], 1e-2)
        np.testing.assert_allclose(
            np.asarray(out.total[i]), ref.total, rtol=0, atol=RTOL * _scale(ref).max()
        )


def test_jax_run_matches_numpy_run_along_a_plate_test():
    traj = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=0.5, dt=2e-3)
    p = mudrft.paper_parameters(0.35)
    g = traj.depth / 0.05
    ref = run(p, traj.time, g)
    h = mjax.run(mjax.to_jax(p), traj.time, g)
    assert ref.suction.min() < -100.0  # the test reaches the suction phase
    for name in ("total", "elastic", "thixotropic", "suction", "xi"):
        r = getattr(ref, name)
        np.testing.assert_allclose(
            np.asarray(getattr(h, name)),
            r,
            rtol=0,
            atol=RTOL
            * (np.abs(ref.elastic) + np.abs(ref.thixotropic) + np.abs(ref.suction) + 1.0).max(),
        )


@pytest.mark.parametrize("clock", ["contact", "retraction"])
def test_jax_run_matches_numpy_run_in_the_quasi_static_evaluation(clock):
    traj = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=0.5, dt=2e-3)
    p = mudrft.paper_parameters(0.25)
    g = traj.depth / 0.05
    ref = run(p, traj.time, g, thixotropy="quasi-static", clock=clock)
    h = mjax.run(mjax.to_jax(p), traj.time, g, thixotropy="quasi-static", clock=clock)
    assert ref.suction.min() < -100.0  # the test reaches the suction phase
    scale = (np.abs(ref.elastic) + np.abs(ref.thixotropic) + np.abs(ref.suction) + 1.0).max()
    for name in ("total", "thixotropic", "suction"):
        np.testing.assert_allclose(
            np.asarray(getattr(h, name)), getattr(ref, name), rtol=0, atol=RTOL * scale
        )


def test_jax_simulate_matches_mudrft_simulate_in_the_quasi_static_evaluation():
    from mudrft.backends.forces import force_function
    from mudrft.simulation import simulate

    foot = mudrft.feet.Flat()
    pos, vel = wandering_path(150, 1e-3, seed=5)
    traj = mudrft.Trajectory(time=np.arange(150) * 1e-3, position=pos, velocity=vel)
    mud = mudrft.paper_mud(0.25)
    ref = simulate(foot, mudrft.MudTerrain(mud, thixotropy="quasi-static"), traj)
    force, _stress, _depth = mjax.simulate(
        mjax.to_jax(mud),
        traj.time,
        pos,
        vel,
        force_fn=force_function(foot, xp=mjax.safe_namespace()),
        characteristic_length=foot.characteristic_length,
        thixotropy="quasi-static",
    )
    scale = np.abs(ref.force).max()
    np.testing.assert_allclose(np.asarray(force), ref.force, rtol=0, atol=RTOL * scale)


def test_params_round_trip_and_k_r():
    p = mudrft.paper_parameters(0.45, "horizontal")
    jp = mjax.to_jax(p)
    assert float(jp.k_r) == pytest.approx(p.k_r, rel=1e-15)
    back = mjax.from_jax(jp)
    for k in PARAMETER_UNITS:
        assert getattr(back, k) == getattr(p, k)
    tied = jp._replace(lam=2.0 * jp.lam).with_default_k_a()
    assert float(tied.k_a) == pytest.approx(0.5 / p.lam, rel=1e-15)


def test_run_rejects_bad_input():
    jp = mjax.to_jax(mudrft.paper_parameters(0.25))
    with pytest.raises(MudrftError, match="strictly increasing"):
        mjax.run(jp, [0.0, 0.2, 0.1], [0.0, 0.1, 0.2])
    with pytest.raises(MudrftError, match="same length"):
        mjax.run(jp, [0.0, 0.1, 0.2], [0.0, 0.1])
    with pytest.raises(MudrftError, match="MudParameters"):
        mjax.to_jax({"alpha": 1.0})
    channels = mjax.to_jax(mudrft.paper_mud(0.3))  # fields of shape (3,): not a batch of 5
    with pytest.raises(MudrftError, match="leading axis of length 5"):
        mjax.batched_step(
            channels, mjax.initial_state((5, 3)), np.zeros((5, 3)), np.zeros((5, 3)), 1e-3
        )
    vertical = mjax.to_jax(mudrft.paper_parameters(0.25))
    for call, made_by in [
        (lambda: mjax.step(vertical, None, 0.1, 1.0, 0.1), "initial_state(...)"),
        (
            lambda: mjax.batched_step(vertical, None, np.zeros(2), np.zeros(2), 0.1),
            "initial_state((N, ...))",
        ),
    ]:
        message = f"state must be a ChannelState ({made_by}), got NoneType"
        with pytest.raises(MudrftError, match=re.escape(message)):
            call()


# ---------------------------------------------------------------------------------------
# gradients against central finite differences
# ---------------------------------------------------------------------------------------
# Central differences with a relative step h = 1e-6 in float64: truncation error
# ~h^2 |f'''| ~ 1e-12 relative, rounding error ~eps |f| / h ~ 1e-10 |f|. We require
# |p (g_ad - g_fd)| <= 1e-6 (|f| + |p g_fd|): four orders of magnitude above both errors,
# while a wrong derivative (a missing term, a wrong chain rule) is O(1) of |p g|.
FD_REL_STEP = 1e-6
FD_TOL = 1e-6


def _central(f, x, h):
    return (f(x + h) - f(x - h)) / (2.0 * h)


def test_gradients_with_respect_to_every_parameter_match_finite_differences():
    traj = mudrft.plate_intrusion(depth=0.03, speed=0.03, hold=0.3, dt=5e-3)
    t = traj.time
    g = traj.depth / 0.05
    p = mudrft.paper_parameters(0.35)
    w = np.sin(np.arange(t.size) * 0.37)  # a generic weighting of the stress history

    def loss_np(q):
        return float(np.sum(w * run(q, t, g).total))

    jp = mjax.to_jax(p)

    def loss_jax(params):
        return jax.numpy.sum(w * mjax.run(params, t, g).total)

    grad = jax.grad(loss_jax)(jp)
    f0 = loss_np(p)
    for k in PARAMETER_UNITS:
        v = float(getattr(p, k))
        h = FD_REL_STEP * v
        fd = _central(
            lambda x, k=k: loss_np(
                p.replace(**{k: x}) if k != "lam" else p.replace(lam=x, k_a=p.k_a)
            ),
            v,
            h,
        )
        ad = float(getattr(grad, k))
        assert abs(v * (ad - fd)) <= FD_TOL * (abs(f0) + abs(v * fd)), (k, ad, fd)
    assert abs(float(grad.alpha)) > 0 and abs(float(grad.sigma_y)) > 0  # both phases matter


def _small_mesh():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = mudrft.feet.SemiSphere().to_mesh(resolution=3)
    return m.vertices, m.faces


def test_mesh_force_matches_numpy_and_its_vertex_gradient_matches_finite_differences():
    from mudrft.feet.surface import integrate_triangles

    v, f = _small_mesh()
    depth, stress, heading = 0.0137, np.array([900.0, -400.0, 2500.0]), 0.61
    ref = integrate_triangles(v[f], depth, stress, heading)
    wts = np.array([0.3, -0.7, 1.1])

    def force_and_grad(verts):  # one compilation for the force and its vertex gradient
        force = mjax.mesh_force(verts, f, depth, stress, heading)
        grad = jax.grad(lambda vv: mjax.mesh_force(vv, f, depth, stress, heading) @ wts)(verts)
        return force, grad

    got, grad = jax.jit(force_and_grad)(jax.numpy.asarray(v))
    # same formulas, XLA vs numpy rounding on a sum of ~70 facet forces: 1e-13 of the largest
    # component (~500 ulp) is a wide margin for rounding and far below any rule difference
    np.testing.assert_allclose(np.asarray(got), ref, rtol=0, atol=1e-13 * np.abs(ref).max())
    grad = np.asarray(grad)
    rng = np.random.default_rng(0)
    for _ in range(6):
        i, j = int(rng.integers(len(v))), int(rng.integers(3))
        h = FD_REL_STEP * 0.05  # relative to the foot size (5 cm)

        def f1(x, i=i, j=j):
            vv = v.copy()
            vv[i, j] = x
            return float(integrate_triangles(vv[f], depth, stress, heading) @ wts)

        fd = _central(f1, v[i, j], h)
        f0 = abs(float(ref @ wts))
        assert abs(0.05 * (grad[i, j] - fd)) <= FD_TOL * (f0 + abs(0.05 * fd)), (i, j)
    assert np.abs(grad).max() > 0


@pytest.mark.parametrize("kind", ["closed-form", "mesh"])
def test_jax_simulate_matches_mudrft_simulate(kind):
    from mudrft.backends.forces import force_function
    from mudrft.simulation import simulate

    if kind == "mesh":
        v, f = _small_mesh()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            foot = mudrft.feet.MeshFoot(v, f, trailing=True)
    else:
        foot = mudrft.feet.SemiCylinder()
    pos, vel = wandering_path(150, 1e-3, seed=3)
    traj = mudrft.Trajectory(time=np.arange(150) * 1e-3, position=pos, velocity=vel)
    mud = mudrft.paper_mud(0.3)
    ref = simulate(foot, mud, traj)
    fn = force_function(foot, xp=mjax.safe_namespace())
    force, _stress, depth = mjax.simulate(
        mjax.to_jax(mud),
        traj.time,
        pos,
        vel,
        force_fn=fn,
        characteristic_length=foot.characteristic_length,
    )
    scale = np.abs(ref.force).max()
    np.testing.assert_allclose(np.asarray(force), ref.force, rtol=0, atol=RTOL * scale)
    np.testing.assert_allclose(np.asarray(depth), ref.depth, rtol=0, atol=1e-15)


def test_gradient_of_a_simulated_force_with_respect_to_foot_vertices():
    """Foot design: d(impulse)/d(vertices) through the whole scan equals finite differences."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = mudrft.feet.SemiSphere().to_mesh(resolution=1)
    v, f = m.vertices, m.faces
    pos, vel = wandering_path(60, 2e-3, seed=5)
    t = np.arange(60) * 2e-3
    jp = mjax.to_jax(mudrft.paper_mud(0.3))
    lc = 0.04

    def impulse_z(verts):
        fn = lambda d, s, h: mjax.mesh_force(verts, f, d, s, h, trailing=True)  # noqa: E731
        force, _, _ = mjax.simulate(jp, t, pos, vel, force_fn=fn, characteristic_length=lc)
        return jax.numpy.sum(force[:, 2]) * 2e-3

    vg = jax.jit(jax.value_and_grad(impulse_z))  # one compilation serves value and gradient
    f0, g = vg(v)
    g = np.asarray(g)
    i, j = int(np.argmax(np.abs(g).max(axis=1))), 2
    h = FD_REL_STEP * 0.05
    vp, vm = v.copy(), v.copy()
    vp[i, j] += h
    vm[i, j] -= h
    fd = (float(vg(vp)[0]) - float(vg(vm)[0])) / (2 * h)
    assert abs(0.05 * (g[i, j] - fd)) <= FD_TOL * (abs(float(f0)) + abs(0.05 * fd))
    assert abs(g[i, j]) > 0
