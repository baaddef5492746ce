"""``mudrft/MudGo1-v0``: Menagerie's Unitree Go1 standing and stepping in a field of mud
drawn each episode (issue 42); skipped without the ``robots`` extra."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft

pytest.importorskip("gymnasium")
pytest.importorskip("mujoco")
pytest.importorskip("numba")
import gymnasium
import mujoco
from gymnasium.utils.env_checker import check_env

import mudrft.envs  # registers the environments
from mudrft.integrations.mujoco import menagerie_scene

try:
    menagerie_scene("unitree_go1")
except mudrft.MudrftError as exc:  # the robots extra is not installed
    pytest.skip(str(exc), allow_module_level=True)

FIELD = mudrft.MudField({"a": 0.25, "b": 0.35}, ["a b a b"], cell_size=0.5, origin=(-0.25, -5.0))


def test_go1_stands_in_a_drawn_field_and_passes_check_env():
    env = gymnasium.make(
        "mudrft/MudGo1-v0", field=FIELD, randomize={"water_content": (0.25, 0.35)},
        observe="privileged",
    )  # fmt: skip
    with warnings.catch_warnings():  # unbounded Box, as MuJoCo's own envs
        warnings.simplefilter("ignore", UserWarning)
        check_env(env.unwrapped, skip_render_check=True)
    obs, info = env.reset(seed=5)
    assert obs.shape == (51,)
    drawn = info["field"].arrays()[2]
    assert np.array_equal(env.reset(seed=5)[1]["field"].arrays()[2], drawn)
    for _ in range(100):  # 2 s, servos holding home
        obs, _, terminated, _, info = env.step(np.zeros(12))
        assert not terminated
    depth = info["sinking [m]"]
    # each ball foot carries about a quarter of Go1's 12.7 kg; in W = 25-35 % it settles
    # near 2 cm (19-26 mm in the coupling's Go1 tests), above its 2.3 cm radius
    assert np.all((depth > 0.01) & (depth < 0.03)), depth
    assert abs(obs[0]) < 0.03  # the trunk within 3 cm of its start height
    np.testing.assert_allclose(info["mud_force [N]"][:, 2].sum(), 12.7 * 9.81, rtol=0.15)
    env.close()


def test_go1_proprioceptive_observation_and_wrong_options():
    env = mudrft.envs.MudGo1Env(water_content=0.3)
    assert env.reset(seed=0)[0].shape == (35,)
    env.close()
    with pytest.raises(mudrft.MudrftError, match="observe must be one of"):
        mudrft.envs.MudGo1Env(observe="all")


def test_go1_on_a_rigid_cell_stands_as_on_its_own_floor():
    """A field of rock and mud (Go1 starts on the rock): its feet rest on the cell's box by
    MuJoCo's contact, as deep as on Menagerie's own floor (its soft contact lets a ball
    sink about 13 mm; within 1 mm of that), with no mud force."""
    rock = mudrft.MudField({"mud": 0.3, "rock": "rigid"}, ["rock mud"], cell_size=0.5, origin=(-0.25, -1.0))  # fmt: skip
    env = mudrft.envs.MudGo1Env(field=rock, observe="privileged")
    env.reset(seed=0)
    for _ in range(30):
        _, _, terminated, _, info = env.step(np.zeros(env.model.nu))
    assert not terminated and np.all(info["mud_force [N]"] == 0.0)
    m, d = env.model, env.data
    box = m.geom("mudrft_rigid_cell_0_0").id
    dist = [c.dist for c in d.contact[: d.ncon] if box in (c.geom1, c.geom2)]
    assert len(dist) == 4
    bare_model = mujoco.MjModel.from_xml_path(str(menagerie_scene("unitree_go1")))
    bare = mujoco.MjData(bare_model)
    mujoco.mj_resetDataKeyframe(bare_model, bare, 0)
    bare.ctrl[:] = bare_model.key_ctrl[0]
    mujoco.mj_step(bare_model, bare, 300)
    floor = [c.dist for c in bare.contact[: bare.ncon]]
    assert abs(np.mean(dist) - np.mean(floor)) < 1e-3
    env.close()
