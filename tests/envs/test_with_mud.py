"""Mud under gymnasium's own MuJoCo environments: mudrft.envs.with_mud."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError

mujoco = pytest.importorskip("mujoco")
gymnasium = pytest.importorskip("gymnasium")
pytest.importorskip("imageio")  # gymnasium's MuJoCo environments need it
envs = pytest.importorskip("mudrft.envs")


def test_ant_in_mud_passes_check_env_and_reports_each_foot():
    from gymnasium.utils.env_checker import check_env

    env = envs.with_mud(gymnasium.make("Ant-v5"), mud=mudrft.paper_mud(0.35))
    assert len(env.coupling.bodies) == 4  # the four anonymous ankle bodies
    floor = env.unwrapped.model.geom("floor").id
    assert env.unwrapped.model.geom_pos[floor, 2] == pytest.approx(-0.5)  # lowered
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # gymnasium: a wrapped env
        check_env(env, skip_render_check=True)
    obs, info = env.reset(seed=1)
    assert info["mud_depth"].shape == (4,) and info["mud_force"].shape == (4, 3)
    # Ant integrates with RK4, which the coupling refuses: the wrapper switched it
    assert env.unwrapped.model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    support = 0.0
    for _ in range(200):  # 10 s: the ant falls from 0.75 m onto the mud and stands in it
        obs, _, terminated, _, info = env.step(np.zeros(8))
        support = info["mud_force"][:, 2].sum()
    weight = env.unwrapped.model.body_subtreemass[1] * 9.81
    assert np.all(info["mud_depth"] > 0) and support == pytest.approx(weight, rel=0.1)
    assert np.all(np.isfinite(obs)) and not terminated


def test_humanoid_in_mud_steps_with_both_feet_found():
    env = envs.with_mud(gymnasium.make("Humanoid-v5"))
    assert [b.body for b in env.coupling.bodies] == ["right_foot", "left_foot"]
    env.reset(seed=0)
    for _ in range(10):
        obs, _, _, _, info = env.step(env.action_space.sample() * 0)
    assert np.all(np.isfinite(obs)) and info["mud_force"].shape == (2, 3)


def test_a_non_mujoco_environment_is_refused():
    with pytest.raises(MudrftError, match=r"env must be a gymnasium MuJoCo environment"):
        envs.with_mud(gymnasium.make("CartPole-v1"))
