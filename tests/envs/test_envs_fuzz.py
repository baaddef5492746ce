"""User mistakes with the walker environments: options, reset and step out of order, named
as MudrftError (a fuzz of the environments; every case here went wrong before)."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

pytest.importorskip("gymnasium")
pytest.importorskip("mujoco")
import gymnasium

import mudrft.envs  # registers the environments
from mudrft._validation import MudrftError
from mudrft.envs.walker import WalkerConfig, check_action


@pytest.mark.parametrize(
    ("options", "message"),
    [
        # TypeError: '>' not supported between instances of 'list' and 'float'
        ({"dt": [0.001, 0.002]}, r"dt must be a single number \[s\], got an array of shape \(2,\)"),
        # taken, and broadcast into the servo targets, the noise or the reward
        ({"action_scale": [0.5, 0.5]}, r"action_scale must be a single number \[rad\]"),
        ({"reset_noise_scale": [0.1] * 6}, r"reset_noise_scale must be a single number \[rad\]"),
        ({"healthy_reward": [1.0, 2.0]}, r"healthy_reward must be a single number"),
        ({"bottom": [0.1]}, r"bottom must be a single number \[m\]"),
        # True was one physics step per control step
        ({"frame_skip": True}, r"frame_skip must be an integer >= 1, got True"),
        # one step ran for hours
        (
            {"frame_skip": 10**9},
            r"frame_skip must hold an action for at most 1 s .* got 1000000000 steps of 0\.002 s",
        ),
        ({"frame_skip": 501}, r"frame_skip must hold an action for at most 1 s"),
    ],
)
def test_walker_options_are_single_numbers(options, message):
    with pytest.raises(MudrftError, match=message):
        WalkerConfig(**options)


def test_walker_options_are_stored_as_floats():
    assert WalkerConfig(frame_skip=500).frame_skip == 500  # one second of 2 ms steps
    cfg = WalkerConfig(healthy_reward=1, bottom=np.float32(0.15))
    assert type(cfg.healthy_reward) is float and type(cfg.bottom) is float


def test_an_unknown_option_is_named_with_the_known_ones():
    # it was "WalkerConfig.__init__() got an unexpected keyword argument 'watercontent'"
    with pytest.raises(
        MudrftError,
        match=r"watercontent: not an option of the mud walker \(did you mean 'water_content'\?\); "
        r"expected one of backend, render_mode, foot, water_content",
    ):
        gymnasium.make("mudrft/MudWalker-v0", watercontent=0.35)


@pytest.fixture(scope="module")
def env():
    return mudrft.envs.MudWalkerEnv(backend="numpy")


def test_step_before_reset_is_refused(env):
    # it returned reward 0 and terminated=True: the robot at the origin, the mud unset
    fresh = mudrft.envs.MudWalkerEnv(backend="numpy")
    with pytest.raises(MudrftError, match=r"call reset\(\) before step\(\)"):
        fresh.step(np.zeros(6))


@pytest.mark.parametrize("options", [{"water_content": 0.45}, {"foot": "flat"}, [1]])
def test_reset_options_are_refused_not_ignored(env, options):
    # the mud stayed at 0.25 without a word
    with pytest.raises(MudrftError, match=r"options: reset takes none .* got"):
        env.reset(options=options)


@pytest.mark.parametrize("options", [None, {}])
def test_reset_without_options_still_works(env, options):
    obs, _ = env.reset(seed=0, options=options)
    assert obs.shape == (23,)


def _vector_env_available() -> None:
    pytest.importorskip("jax")
    if not mudrft.integrations.mjx.available():
        pytest.skip("mujoco-mjx is not installed (extra 'mjx')")


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"num_envs": True}, r"num_envs must be an integer >= 1, got True"),
        (
            {"num_envs": 2, "max_episode_steps": True},
            r"max_episode_steps must be an integer >= 1, got True",
        ),
        # numpy's "could not convert string to float: 'a'"; "0.3" was read as a number
        (
            {"num_envs": 2, "water_content": ["a", "b"]},
            r"water_content must be a number or an array of numbers",
        ),
        (
            {"num_envs": 2, "water_content": "0.3"},
            r"water_content must be a number or an array of numbers, got the string '0\.3'",
        ),
        (
            {"num_envs": 2, "nope": 1},
            r"nope: not an option of the mud walker; expected one of num_envs",
        ),
        # a MudTerrain per robot, built in a Python loop that did not end (1e7 robots)
        ({"num_envs": 10**9}, r"num_envs = 1000000000 robots would need about .* of memory"),
    ],
)
def test_vector_env_options_are_named(options, message):
    _vector_env_available()
    from mudrft.envs.vector import MudWalkerVectorEnv

    with pytest.raises(MudrftError, match=message):
        MudWalkerVectorEnv(**options)


def test_vector_env_refuses_reset_options_before_compiling():
    _vector_env_available()
    from mudrft.envs.vector import MudWalkerVectorEnv

    envs = MudWalkerVectorEnv(num_envs=2, water_content=[0.25, 0.35])
    np.testing.assert_array_equal(envs.water_content, [0.25, 0.35])
    with pytest.raises(MudrftError, match=r"options: reset takes none"):
        envs.reset(options={"water_content": 0.45})


@pytest.mark.parametrize(
    ("action", "message"),
    [
        (np.zeros(5), r"action must have shape \(6,\), got shape \(5,\)"),
        ([0.0] * 5 + [np.nan], r"action must be finite, got NaN or inf"),
        (["a"] * 6, r"action must be numbers of shape \(6,\)"),
        # numpy dropped the imaginary part with a ComplexWarning and the step went on
        (np.full(6, 0.5 + 0.5j), r"action must be real numbers of shape \(6,\), got complex"),
    ],
)
def test_a_bad_action_is_named(action, message):
    with pytest.raises(MudrftError, match=message):
        check_action(action, (6,))
    assert check_action([0.5] * 6, (6,)).dtype == np.float64
