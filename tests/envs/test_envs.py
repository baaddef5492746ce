"""The Gymnasium environments (mudrft.envs): registration, check_env, the MJX vector form."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft

pytest.importorskip("gymnasium")
pytest.importorskip("mujoco")
import gymnasium

import mudrft.envs  # registers the environments
from mudrft._validation import MudrftError
from mudrft.envs.walker import OBS_SIZE
from mudrft.integrations.mjx._lazy import x64_context


def _renders(env) -> bool:
    with warnings.catch_warnings():  # GLFW warns on its way to failing without a display
        warnings.simplefilter("ignore")
        try:
            env.render()
        except MudrftError:  # no OpenGL in this process
            return False
    return True


def test_the_walker_is_registered_with_its_options():
    assert "mudrft/MudWalker-v0" in gymnasium.registry
    env = gymnasium.make("mudrft/MudWalker-v0", foot="semi-sphere", water_content=0.35)
    assert env.spec.max_episode_steps == 1000
    assert isinstance(env.unwrapped.config.foot_object, mudrft.feet.SemiSphere)
    assert env.unwrapped.config.mud.vertical.water_content == pytest.approx(0.35)
    with pytest.raises(MudrftError, match="foot must be one of"):
        gymnasium.make("mudrft/MudWalker-v0", foot="paddle")
    with pytest.raises(MudrftError, match="water_content"):
        gymnasium.make("mudrft/MudWalker-v0", water_content=float("nan"))


def test_check_env_passes():
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make("mudrft/MudWalker-v0", foot="semi-cylinder")
    probe = gymnasium.make("mudrft/MudWalker-v0", render_mode="rgb_array")
    probe.reset(seed=0)
    with pytest.warns(UserWarning, match="infinity"):  # unbounded Box, as MuJoCo's own envs
        check_env(env.unwrapped, skip_render_check=not _renders(probe))


def test_observation_holds_the_sinking_and_the_mud_force():
    env = gymnasium.make("mudrft/MudWalker-v0")
    obs, _ = env.reset(seed=1)
    assert obs.shape == (OBS_SIZE,) and obs.dtype == np.float32
    assert np.all(obs[17:] == 0.0)  # not in the mud yet
    for _ in range(15):  # stand for 0.3 s
        obs, reward, terminated, truncated, info = env.step(np.zeros(6))
    assert not terminated and not truncated
    np.testing.assert_allclose(obs[17:19], 100 * info["sinking [m]"], rtol=1e-6)
    assert np.all(obs[17:19] > 0.3)  # sunk by more than 3 mm
    assert obs[20] > 0.1 and obs[22] > 0.1  # each foot carries part of the weight (F_z)
    assert 0.5 < reward < 1.5  # alive, standing still


@pytest.fixture(scope="module")
def vector_env():
    """Four robots in float32 (MJX's default), two per water content: one compiled step
    shared by the tests below."""
    pytest.importorskip("jax")
    if not mudrft.integrations.mjx.available():
        pytest.skip("mujoco-mjx is not installed (extra 'mjx')")
    with x64_context(False):
        return gymnasium.make_vec(
            "mudrft/MudWalker-v0", num_envs=4, water_content=[0.25, 0.25, 0.45, 0.45]
        )


@pytest.mark.slow
def test_a_vector_of_environments_steps_on_mjx(vector_env):
    envs = vector_env
    assert isinstance(envs, mudrft.envs.MudWalkerVectorEnv)
    obs, _ = envs.reset(seed=0)
    assert obs.shape == (4, OBS_SIZE) and obs.dtype == np.float32
    for _ in range(10):  # stand for 0.2 s
        obs, reward, terminated, truncated, info = envs.step(np.zeros((4, 6)))
    assert obs.shape == (4, OBS_SIZE) and np.all(np.isfinite(obs))
    assert reward.shape == (4,) and not terminated.any() and not truncated.any()
    sink = info["sinking [m]"].mean(axis=1)
    # each robot carries its own mud: the wetter mud lets the feet sink deeper
    assert np.all(sink[2:] > sink[:2].max()), (sink[:2].max(), sink[2:].min())
    obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
    assert np.all(np.isfinite(obs)) and np.all(np.isfinite(reward))


@pytest.mark.slow
def test_the_vector_env_keeps_its_precision_when_the_process_switches_to_float64(vector_env):
    """Made in float32, then mudrft.backends.jax switched the process to float64
    (its first call does, D70): the next step failed on 'lax.add requires arguments to
    have the same dtypes, got int32, int64'. The environment runs in its own precision."""
    envs = vector_env
    with x64_context(False):
        envs.reset(seed=0)
        first = envs.step(np.zeros((4, 6)))[0]
    with x64_context(True):
        obs, reward, terminated, _, _ = envs.step(np.zeros((4, 6)))
        assert np.all(np.isfinite(obs)) and np.all(np.isfinite(reward)) and not terminated.any()
        assert envs.unwrapped._state[0].qpos.dtype == np.float32
        envs.reset(seed=0)
        again = envs.step(np.zeros((4, 6)))[0]
    np.testing.assert_array_equal(again, first)  # the same float32 program, seeded alike


@pytest.mark.slow
def test_an_unstable_robot_of_the_vector_env_ends_and_starts_anew(vector_env):
    """Issue 43: a NaN in one robot's velocities ran on silently. It terminates with
    info["unstable"], the others go on, and it starts anew on the next step."""
    envs = vector_env
    envs.reset(seed=0)
    d, st = envs._state
    envs._state = (d.replace(qvel=d.qvel.at[1].set(np.nan)), st)
    obs, reward, terminated, _, info = envs.step(np.zeros((4, 6)))
    np.testing.assert_array_equal(info["unstable"], [False, True, False, False])
    np.testing.assert_array_equal(terminated, [False, True, False, False])
    assert np.all(np.isfinite(obs)) and np.all(np.isfinite(reward))
    obs, _, terminated, _, info = envs.step(np.zeros((4, 6)))
    assert not info["unstable"].any() and not terminated.any() and np.all(np.isfinite(obs))
    assert np.all(np.isfinite(np.asarray(envs._state[0].qvel)))
