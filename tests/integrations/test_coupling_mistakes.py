"""Mistakes with the MuJoCo and MJX couplings and the walker: each is a MudrftError.

Found by a fuzz of the integrations. Before the fix an MjData of another model crashed
the process (segmentation fault) or coupled the wrong bodies, ``implicit="no"`` was read
as True, ``bottom_stiffness`` without ``bottom`` was ignored, ``step(d, 0)`` returned a
zero contact while the foot sat in the mud, a CPU MjData given to MJX failed deep inside
it, NaN states ran on silently, and a NaN action gave the walker a NaN reward.
"""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError

pytest.importorskip("mujoco")
from mudrft.integrations.walk import biped_model

from ._reference import attach, attach_batch
from .conftest import box_foot_model, mujoco

MUD = mudrft.paper_mud(0.25)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"bodies": 3}, r"body id must be in \[1, 1\], got 3"),
        ({"bodies": 2.5}, r"bodies must be 'auto', a body's or geom's name or a body's id, or a"),
        ({"bodies": ["foot", "world"]}, r"bodies cannot include the world \('world'\)"),
        ({"implicit": "no"}, r"option implicit= was removed in mudrft 0.3: the coupling always"),
        ({"bottom_stiffness": 1e4}, r"give its depth with bottom="),
        ({"feet": "box"}, r"feet must be a foot \(mudrft.feet\), one per body"),
        ({"surface": [0.0, 0.0]}, r"surface must be a single number \[m\]"),
        ({"resolution": True}, r"resolution must be an integer >= 1, got True"),
    ],
)
def test_attach_names_a_wrong_option(kwargs, message):
    model = box_foot_model()
    bodies = kwargs.pop("bodies", "foot")
    with pytest.raises(MudrftError, match=message):
        attach(model, bodies, MUD, **kwargs)


def test_data_of_another_model_is_refused_not_a_crash():
    coupling = attach(biped_model(), ["left_foot", "right_foot"], MUD)
    other = mujoco.MjData(box_foot_model())
    with pytest.raises(MudrftError, match=r"data was made for another model"):
        coupling.reset(other)  # was: a segmentation fault
    with pytest.raises(MudrftError, match=r"data must be a mujoco.MjData"):
        coupling.reset(None)


def test_one_mjdata_for_two_robots_is_refused():
    model = box_foot_model()
    batch = attach_batch(model, "foot", MUD, n=2)
    d = mujoco.MjData(model)
    with pytest.raises(MudrftError, match=r"the same one was given twice"):
        batch.reset([d, d])


@pytest.mark.parametrize("backend", ["numpy", "numba"])
@pytest.mark.parametrize("nstep", [0, -1, 2.5, True, "3"])
def test_nstep_must_be_a_count(backend, nstep):
    if backend == "numba":
        pytest.importorskip("numba")
    model = box_foot_model()
    d = mujoco.MjData(model)
    coupling = attach(model, "foot", MUD, backend=backend)
    coupling.reset(d)
    with pytest.raises(MudrftError, match=r"nstep must be an integer >= 1"):
        coupling.step(d, nstep)  # numba returned a zero contact for 0
    with pytest.raises(MudrftError, match=r"nstep must be an integer >= 1"):
        coupling.advance(d, nstep)
    assert coupling.step(d, 3).depth.shape == (1,)


@pytest.mark.slow  # compiles MJX: CI runs it as its own step
def test_mjx_refuses_a_cpu_mjdata_a_nan_state_and_a_wrong_rollout():
    pytest.importorskip("jax")
    from mudrft.integrations import mjx as mm

    model = box_foot_model()
    cpl = mm.attach(model, "foot", MUD)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with pytest.raises(MudrftError, match=r"d must be an mjx.Data .* got MjData"):
        cpl.init(data)
    bad = mujoco.MjData(model)
    bad.qpos[2] = np.nan
    with pytest.raises(MudrftError, match=r"data.qpos must be finite"):
        cpl.put_data(bad)
    with pytest.raises(MudrftError, match=r"data was made for another model"):
        cpl.put_data(mujoco.MjData(biped_model()))
    d = cpl.put_data(data)
    state = cpl.init(d)
    with pytest.raises(MudrftError, match=r"n must be an integer >= 1, got 0"):
        cpl.rollout(d, state, 0)
    with pytest.raises(MudrftError, match=r"ctrl must have shape \(n, nu\) = \(3, 0\)"):
        cpl.rollout(d, state, 3, ctrl=np.zeros((2, 1)))
    with pytest.raises(MudrftError, match=r"state must be an MjxMudState"):
        cpl.step(d, None)


def test_the_walker_refuses_a_nan_or_misshaped_action():
    gym = pytest.importorskip("gymnasium")
    import mudrft.envs  # noqa: F401 - registers the environments

    env = gym.make("mudrft/MudWalker-v0")
    env.reset(seed=0)
    with pytest.raises(MudrftError, match=r"action must be finite"):
        env.step(np.full(6, np.nan))  # was: a NaN reward, and the episode went on
    with pytest.raises(MudrftError, match=r"action must have shape \(6,\), got shape \(2, 3\)"):
        env.step(np.zeros((2, 3)))  # was: reshaped silently
    _, reward, *_ = env.step(np.zeros(6))
    assert np.isfinite(reward)


def test_stability_limits_takes_the_mud_as_attach_does_and_names_mistakes():
    from mudrft.integrations.mujoco import stability_limits

    foot = mudrft.feet.Flat()
    a = stability_limits(foot, MUD, mass=0.3, depth=0.01)
    assert stability_limits(foot, mudrft.MudTerrain(MUD), mass=0.3, depth=0.01) == a
    with pytest.raises(MudrftError, match=r"foot must be a Foot .* got str"):
        stability_limits("flat", MUD, mass=0.3, depth=0.01)
    with pytest.raises(MudrftError, match=r"mud must be a Mud or a MudTerrain, got Flat"):
        stability_limits(foot, foot, mass=0.3, depth=0.01)
    with pytest.raises(MudrftError, match=r"mass must be a single number \[kg\]"):
        stability_limits(foot, MUD, mass=[1.0, 2.0], depth=0.01)


def test_the_jax_backend_names_raw_parameters_and_a_missing_batch_axis():
    pytest.importorskip("jax")
    from mudrft.backends import jax as mjax
    from mudrft.backends.jax import terrain_step

    p = mudrft.paper_parameters(0.25, "vertical")
    st = mjax.initial_state(())
    with pytest.raises(MudrftError, match=r"params must be a JaxParams .* got MudParameters"):
        mjax.step(p, st, 0.1, 1.0, 0.1)  # to_jax forgotten: was JAX's "abstract array" error
    with pytest.raises(MudrftError, match=r"state must be a ChannelState"):
        mjax.step(mjax.to_jax(p), None, 0.1, 1.0, 0.1)
    with pytest.raises(MudrftError, match=r"gamma must have a leading batch axis"):
        mjax.batched_step(mjax.to_jax(p), st, 0.1, 1.0, 0.1)
    with pytest.raises(MudrftError, match=r"the mud's x, y, z channel sets"):
        terrain_step(
            mjax.to_jax(p), None, np.zeros(3), np.zeros(3), 1e-3,
            force_fn=None, characteristic_length=0.05,
        )  # fmt: skip


def test_jax_mesh_force_refuses_faces_that_do_not_index_the_vertices():
    """JAX clips an index out of range and wraps a negative one: the force was [0, 0, 0]."""
    pytest.importorskip("jax")
    from mudrft.backends import jax as mjax
    from mudrft.feet.meshgen import box_mesh

    v, f = box_mesh(0.08, 0.065, 0.026)
    v = v - v.min(axis=0) * np.array([0.0, 0.0, 1.0])  # tip at z = 0
    good = np.asarray(mjax.mesh_force(v, f, 0.01, [0.0, 0.0, 1e4], 0.0))
    assert good[2] > 0
    for faces, message in (
        (f + 10, r"faces must index the 8 vertices \(0 to 7\), got 10 to 17"),
        (f - 1, r"got -1 to 6"),
        (f.astype(float), r"faces must be integers of shape \(m, 3\)"),
    ):
        with pytest.raises(MudrftError, match=message):
            mjax.mesh_force(v, faces, 0.01, [0.0, 0.0, 1e4], 0.0)
    with pytest.raises(MudrftError, match=r"vertices must have shape \(v, 3\)"):
        mjax.mesh_force(v[:, :2], f, 0.01, [0.0, 0.0, 1e4], 0.0)
    with pytest.raises(MudrftError, match=r"stress must have shape \(..., 3\)"):
        mjax.mesh_force(v, f, 0.01, [0.0, 1e4], 0.0)
