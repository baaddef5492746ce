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
    with pytest.raises(mudrft.MudrftError, match="mud regions only"):
        mudrft.envs.MudGo1Env(field=mudrft.MudField({"m": 0.3, "r": "rigid"}, ["m r"]))
