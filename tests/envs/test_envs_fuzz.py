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
    return mudrft.envs.MudWalkerEnv()


def test_step_before_reset_is_refused(env):
    # it returned reward 0 and terminated=True: the robot at the origin, the mud unset
    fresh = mudrft.envs.MudWalkerEnv()
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


@pytest.mark.parametrize(
    ("seed", "message"),
    [  # gymnasium.error.Error from inside Gymnasium's seeding
        ("abc", r"seed must be None or an integer >= 0, got 'abc'"),
        (-1, r"seed must be None or an integer >= 0, got -1"),
        (1.5, r"got 1\.5"),
        (True, r"got True"),
    ],
)
def test_a_bad_seed_is_named(env, seed, message):
    with pytest.raises(MudrftError, match=message):
        env.reset(seed=seed)
    first, _ = env.reset(seed=np.int64(3))  # Gymnasium refused numpy integers
    np.testing.assert_array_equal(env.reset(seed=3)[0], first)


def test_a_terminated_or_closed_environment_does_not_step():
    """Gymnasium's contract: the raw environment stepped on after its episode ended, and
    after close(). An unstable step (a NaN velocity, which MuJoCo reset with a printed
    warning and the episode went on) terminates with info["unstable"]."""
    env = mudrft.envs.MudWalkerEnv()
    env.reset(seed=0)
    obs, _, terminated, _, info = env.step(np.zeros(6))
    assert not terminated and info["unstable"] is False
    env.data.qvel[3] = np.nan
    obs, reward, terminated, _, info = env.step(np.zeros(6))
    assert terminated and info["unstable"] is True and np.isfinite(reward)
    assert np.all(np.isfinite(obs))
    with pytest.raises(
        MudrftError, match=r"the episode has terminated: call reset\(\) before step"
    ):
        env.step(np.zeros(6))
    env.reset(seed=0)
    env.step(np.zeros(6))  # a new episode steps
    env.close()
    for call in (lambda: env.step(np.zeros(6)), lambda: env.reset(seed=0)):
        with pytest.raises(MudrftError, match=r"the environment is closed: make a new one"):
            call()


def test_human_rendering_without_pygame_names_what_is_missing(monkeypatch):
    # gymnasium.error.DependencyNotInstalled from its HumanRendering wrapper, at reset
    import sys

    monkeypatch.setitem(sys.modules, "pygame", None)  # as if not installed
    with pytest.raises(MudrftError, match=r"render_mode='human' .* pygame, which is not installed"):
        gymnasium.make("mudrft/MudWalker-v0", render_mode="human")


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
    with pytest.raises(MudrftError, match=r"seed must be None or an integer >= 0, got -1"):
        envs.reset(seed=-1)
    envs.close()
    for call in (lambda: envs.step(np.zeros((2, 6))), lambda: envs.reset(seed=0)):
        with pytest.raises(MudrftError, match=r"the environment is closed"):
            call()


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
