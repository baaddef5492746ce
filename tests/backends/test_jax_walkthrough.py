"""What a learning researcher ran into with the JAX terrain step.

Each test failed before its fix: inputs JAX read silently wrong (a position without its z,
one dt per member of a vmapped batch, a mesh whose tip is not at the origin), concrete
mistakes that gave NaN or numpy's messages, and the foot that could not be passed as such.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError

jax = pytest.importorskip("jax")
mjax = pytest.importorskip("mudrft.backends.jax")
jnp = mjax.enable_x64().numpy

MUD = mudrft.paper_mud(0.25)
FOOT = mudrft.feet.Flat()
LC = FOOT.characteristic_length


def _fn(foot=FOOT):
    from mudrft.backends.forces import force_function

    return force_function(foot, xp=mjax.safe_namespace())


def _path(n=40, dt=1e-3):
    """A foot that enters the mud, moves sideways and retracts [s, m, m/s]."""
    t = np.arange(n) * dt
    z = 0.002 - 0.02 * np.sin(np.pi * t / t[-1])
    pos = np.stack([0.05 * t, 0.0 * t, z], 1)
    return t, pos, np.gradient(pos, t, axis=0)


def test_a_position_without_its_z_is_refused_not_read_as_depth():
    """JAX clips an out-of-range index: pos[..., 2] of a (..., 2) position read y as z and
    the step ran."""
    jp, st = mjax.to_jax(MUD), mjax.initial_terrain_state(np.zeros(3), LC)
    kw = dict(force_fn=_fn(), characteristic_length=LC)
    with pytest.raises(MudrftError, match=r"position must have shape \(\.\.\., 3\).*\(2,\)"):
        mjax.terrain_step(jp, st, np.array([0.0, -0.01]), np.zeros(3), 1e-3, **kw)
    with pytest.raises(MudrftError, match=r"velocity must have shape \(\.\.\., 3\).*\(4, 2\)"):
        mjax.terrain_step(jp, st, np.zeros((4, 3)), np.zeros((4, 2)), 1e-3, **kw)
    with pytest.raises(MudrftError, match="position must have shape"):
        mjax.initial_terrain_state(np.zeros(2), LC)
    t, pos, vel = _path()
    with pytest.raises(MudrftError, match="position must have shape"):
        mjax.simulate(jp, t, pos[:, :2], vel[:, :2], **kw)
    # traced: the static shape is still checked inside the caller's jit
    step = jax.jit(lambda p, v: mjax.terrain_step(jp, st, p, v, 1e-3, **kw)[1][0])
    with pytest.raises(MudrftError, match="position must have shape"):
        step(jnp.zeros(2), jnp.zeros(2))


def test_batched_step_refuses_one_dt_per_member():
    """dt is shared (in_axes None): an array of N steps gave every member all N, an (N, N)
    result."""
    p = mjax.to_jax(MUD.vertical)
    st = mjax.initial_state((4,))
    with pytest.raises(MudrftError, match=r"dt must be one step shared by the batch.*\(4,\)"):
        mjax.batched_step(p, st, np.full(4, 0.01), np.ones(4), np.full(4, 1e-3))
    _, out = mjax.batched_step(p, st, np.full(4, 0.01), np.ones(4), 1e-3)
    assert out.total.shape == (4,)
    # a state for another batch ended in vmap's "inconsistent sizes for array axes"
    with pytest.raises(MudrftError, match=r"state.gamma must have a leading axis of length 4"):
        mjax.batched_step(p, mjax.initial_state((5,)), np.full(4, 0.01), np.ones(4), 1e-3)


def test_mesh_force_refuses_vertices_whose_tip_is_not_at_the_origin():
    """The depth is the tip's: a mesh 1 cm above its origin gave forces off by 77 N of 92 on
    the paper's gait, silently."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        m = mudrft.feet.SemiSphere().to_mesh(resolution=3)
    stress = np.array([1e3, 1e3, 5e3])
    with pytest.raises(MudrftError, match=r"tip \(lowest point\) at z = 0.*0\.01 m"):
        mjax.mesh_force(m.vertices + np.array([0.0, 0.0, 0.01]), m.faces, 0.02, stress, 0.0)
    # shifted sideways only: the tip is still at z = 0, and the force is unchanged
    f0 = mjax.mesh_force(m.vertices, m.faces, 0.02, stress, 0.0, trailing=True)
    f1 = mjax.mesh_force(
        m.vertices + np.array([0.01, 0.0, 0.0]), m.faces, 0.02, stress, 0.0, trailing=True
    )
    np.testing.assert_allclose(np.asarray(f1), np.asarray(f0), rtol=0, atol=1e-12 * 20.0)


@pytest.mark.parametrize(
    ("case", "match"),
    [
        ("dt", r"dt must be > 0 s, got -0\.001"),
        ("nan", "position must be finite"),
        ("time", "time must be strictly increasing"),
        ("length", r"time must have shape \(n,\).*time \(39,\), position \(40, 3\)"),
        ("lc", r"characteristic_length must be > 0 m, got 0\.0"),
    ],
)
def test_concrete_mistakes_raise_before_the_scan(case, match):
    """Outside jit the values are known: a negative step, a NaN, a time that goes back, a
    time shorter than the path and L_c = 0 gave NaN forces or numpy's and scan's messages."""
    jp, st = mjax.to_jax(MUD), mjax.initial_terrain_state(np.zeros(3), LC)
    t, pos, vel = _path()
    with pytest.raises(MudrftError, match=match):
        if case == "dt":
            mjax.terrain_step(jp, st, pos[1], vel[1], -1e-3, force_fn=FOOT)
        elif case == "nan":
            mjax.terrain_step(jp, st, [0.0, 0.0, np.nan], vel[1], 1e-3, force_fn=FOOT)
        elif case == "time":
            mjax.simulate(jp, t[::-1], pos, vel, force_fn=FOOT)
        elif case == "length":
            mjax.simulate(jp, t[:-1], pos, vel, force_fn=FOOT)
        else:
            mjax.simulate(jp, t, pos, vel, force_fn=_fn(), characteristic_length=0.0)


@pytest.mark.parametrize("kind", ["flat", "semi-cylinder", "mesh from to_mesh"])
def test_a_foot_passed_as_force_fn_is_the_foot_of_mudrft_simulate(kind):
    """force_fn=foot gives the foot's own rule and L_c: a mesh made with to_mesh
    loads its trailing faces, which partial(mesh_force, v, f) left out (35 N of 92 N off
    on the paper's gait)."""
    foot = mudrft.feet.SemiCylinder() if kind == "semi-cylinder" else FOOT
    if kind.startswith("mesh"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            foot = mudrft.feet.SemiSphere().to_mesh(resolution=3)
        assert foot.trailing
    t, pos, vel = _path()
    ref = mudrft.simulate(foot, MUD, mudrft.Trajectory(time=t, position=pos, velocity=vel))
    force, _, depth = mjax.simulate(mjax.to_jax(MUD), t, pos, vel, force_fn=foot)
    scale = np.abs(ref.force).max()
    assert scale > 1.0
    np.testing.assert_allclose(np.asarray(force), ref.force, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(np.asarray(depth), ref.depth, rtol=0, atol=1e-15)


def test_force_fn_mistakes_name_the_argument():
    jp, st = mjax.to_jax(MUD), mjax.initial_terrain_state(np.zeros(3), LC)
    p, v = np.array([0.0, 0.0, -0.01]), np.array([0.0, 0.0, -0.01])
    with pytest.raises(MudrftError, match="MorphingFoot has no force rule under JAX"):
        mjax.terrain_step(jp, st, p, v, 1e-3, force_fn=mudrft.feet.MorphingFoot())
    with pytest.raises(MudrftError, match=r"force_fn must be a foot .* got str"):
        mjax.terrain_step(jp, st, p, v, 1e-3, force_fn="flat", characteristic_length=LC)
    with pytest.raises(MudrftError, match=r"characteristic_length \[m\] must be given"):
        mjax.terrain_step(jp, st, p, v, 1e-3, force_fn=_fn())
    with pytest.raises(MudrftError, match=r"characteristic_length must be a length .* Flat"):
        mjax.initial_terrain_state(np.zeros(3), FOOT)
    # a numpy rule under jit: JAX's TracerArrayConversionError, now a message that says
    # what to pass instead
    from mudrft.backends.forces import force_function

    numpy_rule = force_function(FOOT)
    step = jax.jit(lambda q: mjax.terrain_step(q, st, p, v, 1e-3, force_fn=numpy_rule,
                                               characteristic_length=LC)[1][0])  # fmt: skip
    with pytest.raises(MudrftError, match=r"force_fn must compute with jax\.numpy"):
        step(jp)
    # foot.force (numpy, validating) is read as the foot: it failed under jit on its check
    # of a traced depth
    by_method = jax.jit(lambda q: mjax.terrain_step(q, st, p, v, 1e-3, force_fn=FOOT.force)[1][0])
    by_foot = jax.jit(lambda q: mjax.terrain_step(q, st, p, v, 1e-3, force_fn=FOOT)[1][0])
    assert np.array_equal(np.asarray(by_method(jp)), np.asarray(by_foot(jp)))


def test_run_refuses_numpy_parameters_and_channel_sets_without_channels():
    t = np.linspace(0.0, 1.0, 11)
    with pytest.raises(MudrftError, match="params must be a JaxParams"):
        mjax.run(mudrft.paper_parameters(0.25), t, 0.2 * t)
    with pytest.raises(MudrftError, match=r"params.alpha has shape \(3,\).*shape \(n, 3\)"):
        mjax.run(mjax.to_jax(MUD), t, 0.2 * t)
    h = mjax.run(mjax.to_jax(MUD), t, np.stack([0.2 * t] * 3, 1))  # one column per channel
    assert h.total.shape == (11, 3)
    # the numpy run said "setting an array element with a sequence"
    from mudrft.terrains import channel_parameters

    with pytest.raises(MudrftError, match=r"params.alpha has shape \(3,\).*shape \(n, 3\)"):
        mudrft.constitutive.run(channel_parameters(MUD), t, 0.2 * t)
    ref = mudrft.constitutive.run(channel_parameters(MUD), t, np.stack([0.2 * t] * 3, 1))
    np.testing.assert_allclose(np.asarray(h.total), ref.total, rtol=1e-11, atol=1e-9)


@pytest.mark.slow
def test_a_traced_characteristic_length_is_a_design_variable():
    """L_c [m] may be traced (it is checked only when concrete): its derivative through a
    simulated path equals a central difference."""
    jp = mjax.to_jax(MUD)
    t, pos, vel = _path()
    fn = _fn()

    @jax.jit
    def impulse_z(lc):
        f, _, _ = mjax.simulate(jp, t, pos, vel, force_fn=fn, characteristic_length=lc)
        return jnp.sum(f[:, 2]) * 1e-3

    g = float(jax.grad(impulse_z)(LC))
    h = 1e-6 * LC
    fd = (float(impulse_z(LC + h)) - float(impulse_z(LC - h))) / (2 * h)
    assert abs(g) > 0
    assert abs(LC * (g - fd)) <= 1e-6 * (abs(float(impulse_z(LC))) + abs(LC * fd))


def test_mud_constants_are_the_terrain_constants_and_differentiable():
    """The constants the MJX coupling's constants= takes, from to_jax(mud), traceable: a
    learning user had to rebuild them with tree_map and channel_constants."""
    got = mjax.mud_constants(mjax.to_jax(MUD))
    ref = mudrft.MudTerrain(MUD).constants
    for g, r in zip(got, ref, strict=True):
        assert type(g) is type(r)
        np.testing.assert_allclose([float(x) for x in g], [float(x) for x in r], rtol=1e-15)
    grad = jax.grad(lambda p: mjax.mud_constants(p)[1].alpha)(mjax.to_jax(MUD))
    np.testing.assert_array_equal(np.asarray(grad.alpha), [0.0, 0.0, 1.0])
