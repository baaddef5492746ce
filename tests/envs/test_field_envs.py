"""The mud walker on a field of mud drawn anew each episode, with rigid cells, on rigid
ground, and with proprioceptive observations (issue 42)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft

pytest.importorskip("gymnasium")
pytest.importorskip("mujoco")
pytest.importorskip("numba")
from gymnasium.utils.env_checker import check_env

from mudrft._validation import MudrftError
from mudrft.envs import MudWalkerEnv

FIELD = mudrft.MudField(
    {"firm": 0.25, "soft": 0.35}, ["firm soft firm soft"], cell_size=0.5, origin=(-0.25, -5.0)
)
DRAW = {"water_content": (0.15, 0.35), "layout": True}


def test_each_episode_draws_its_field_from_the_seed():
    env = MudWalkerEnv(field=FIELD, randomize=DRAW, observe="proprioceptive")
    with warnings.catch_warnings():  # unbounded Box, as MuJoCo's own envs
        warnings.simplefilter("ignore", UserWarning)
        check_env(env, skip_render_check=True)
    rows = []
    for seed in (3, 3, 4):
        obs, info = env.reset(seed=seed)
        assert obs.shape == (17,)
        rows.append(info["field"].arrays()[2])
        assert env.coupling._compiled.rows[0].tolist() == rows[-1].tolist()  # what steps
    assert np.array_equal(rows[0], rows[1]) and not np.array_equal(rows[0], rows[2])
    for _ in range(20):
        obs, _, terminated, _, info = env.step(np.zeros(6))
        assert not terminated
    assert np.all(info["sinking [m]"] > 0.0)  # standing in the drawn mud
    env.close()


def test_a_field_of_one_mud_walks_as_that_mud():
    runs = []
    for kw in ({"water_content": 0.25}, {"field": mudrft.MudField({"m": 0.25}, ["m"])}):
        env = MudWalkerEnv(**kw)
        env.reset(seed=0)
        for _ in range(30):
            obs, *_ = env.step(np.full(6, 0.2))
        runs.append(obs)
        env.close()
    np.testing.assert_array_equal(runs[0], runs[1])


def test_on_rigid_ground_the_walker_stands_on_the_floor():
    env = MudWalkerEnv(ground="rigid")
    assert env.coupling is None
    obs, _ = env.reset(seed=0)
    for _ in range(50):  # 1 s
        obs, _, terminated, _, info = env.step(np.zeros(6))
    assert not terminated
    assert abs(obs[0]) < 0.005  # the torso within 5 mm of its start height
    assert np.all(info["sinking [m]"] == 0.0) and np.all(obs[17:] == 0.0)
    env.close()


ROCK = mudrft.MudField(
    {"mud": 0.3, "rock": "rigid"}, ["rock mud"], cell_size=0.5, origin=(-0.25, -1.0), border=0.05
)  # the walker starts at x = 0, on the rock; the rock and the mud reach on beyond the grid


def test_on_a_rigid_cell_the_walker_stands_on_its_box_and_the_draws_move_the_boxes():
    """A field of rock and mud: on the rock the biped stands on the cell's box by MuJoCo's
    contact, as on rigid ground (the torso within 1 mm of rigid ground's, the mud's force
    0); each reset's draw of the layout makes exactly its rigid cells' boxes collide."""
    heights = []
    for env in (MudWalkerEnv(field=ROCK), MudWalkerEnv(ground="rigid")):
        env.reset(seed=0)
        for _ in range(30):
            _, _, terminated, _, info = env.step(np.zeros(6))
        assert not terminated and env.data.ncon > 0
        assert np.all(info["mud_force [N]"] == 0.0)
        heights.append(float(env.data.qpos[env.layout.rootz]))
        with warnings.catch_warnings():  # unbounded Box, as MuJoCo's own envs
            warnings.simplefilter("ignore", UserWarning)
            check_env(env, skip_render_check=True)
        env.close()
    assert abs(heights[0] - heights[1]) < 1e-3
    env = MudWalkerEnv(field=ROCK, randomize={"layout": True})
    m = env.layout.model
    seen = set()
    for seed in range(6):
        _, info = env.reset(seed=seed)
        rigid = [info["field"].terrains[r] is None for r in info["field"].cells[0]]
        boxes = [bool(m.geom_contype[m.geom(f"mudrft_rigid_cell_0_{i}").id]) for i in range(2)]
        assert boxes == rigid
        seen.add(tuple(rigid))
    assert len(seen) > 1  # the draws moved the rock
    env.close()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"observe": "all"}, "observe must be one of ['privileged', 'proprioceptive']"),
        ({"ground": "ice"}, "ground must be one of ['mud', 'rigid']"),
        ({"field": 3}, "field must be a MudField or the path of its TOML spec"),
        ({"randomize": {"wet": (0.2, 0.3)}}, "unexpected keyword argument 'wet'"),
        ({"randomize": {"water_content": (0.1, 0.3)}}, "water_content must be (low, high) within"),
        ({"ground": "rigid", "field": FIELD}, "ground='rigid' has no mud"),
    ],
)
def test_a_wrong_field_option_is_refused(options, message):
    with pytest.raises((MudrftError, TypeError)) as err:
        MudWalkerEnv(**options)
    assert message in str(err.value)


def test_a_curriculum_orders_fields_and_gives_them_at_reset():
    from mudrft.envs.curriculum import by_difficulty, difficulty

    fields = [FIELD.randomized(seed, water_content=(0.25, 0.45)) for seed in range(4)]
    ordered = by_difficulty(fields)
    hard = [difficulty(f) for f in ordered]
    assert hard == sorted(hard) and hard[0] < hard[-1]
    wet = mudrft.MudField({"firm": 0.45, "soft": 0.45}, [["firm"] * 4], cell_size=0.5)
    assert difficulty(wet) > difficulty(FIELD)  # wetter mud sinks deeper
    env = MudWalkerEnv(field=FIELD)
    for f in ordered:
        _, info = env.reset(seed=0, options={"field": f})
        assert info["field"] is f
        assert env.coupling._compiled.rows[0].tolist() == f.arrays()[2].tolist()
    with pytest.raises(MudrftError, match="options: reset takes none"):
        env.reset(options={"field": FIELD, "speed": 1})
    with pytest.raises(MudrftError, match="needs an environment made with field= or randomize="):
        MudWalkerEnv().reset(options={"field": FIELD})


@pytest.mark.slow  # compiles the MJX walker for about a minute: CI runs it as its own step
def test_the_vector_walker_steps_each_robot_on_its_own_draw_and_draws_anew_at_autoreset():
    """``gymnasium.make_vec`` with a field and ``randomize``: each of four robots steps on
    its own draw (the same draws from the same seed), the wetter draws sink deeper, and
    the robots that end draw new fields at their autoreset; rigid cells are refused."""
    pytest.importorskip("jax")
    if not mudrft.integrations.mjx.available():
        pytest.skip("mujoco-mjx is not installed (extra 'mjx')")
    import gymnasium

    from mudrft.integrations.mjx._lazy import x64_context

    one_mud = mudrft.MudField({"m": 0.3}, ["m"])
    with x64_context(False):
        envs = gymnasium.make_vec(
            "mudrft/MudWalker-v0", num_envs=4, field=one_mud,
            randomize={"water_content": (0.2, 0.45)}, max_episode_steps=12,
        )  # fmt: skip
    envs.reset(seed=5)
    first = [f.terrains[0].mud.water_content for f in envs.fields]
    envs.reset(seed=5)
    assert [f.terrains[0].mud.water_content for f in envs.fields] == first
    assert len(set(first)) == 4
    for _ in range(12):  # 0.24 s: then every robot is truncated
        obs, _, terminated, truncated, info = envs.step(np.zeros((4, 6)))
    assert np.all(np.isfinite(obs)) and not terminated.any() and truncated.all()
    sink = info["sinking [m]"].mean(axis=1)
    order = np.argsort(first)
    assert sink[order[-1]] > sink[order[0]]  # the wettest draw sinks deeper than the driest
    envs.step(np.zeros((4, 6)))  # the autoreset: new draws
    again = [f.terrains[0].mud.water_content for f in envs.fields]
    assert all(a != b for a, b in zip(first, again, strict=True))
    envs.close()
    rock = mudrft.MudField({"m": 0.3, "r": "rigid"}, ["m r"])
    with pytest.raises(MudrftError, match="steps mud regions only"):
        gymnasium.make_vec("mudrft/MudWalker-v0", num_envs=2, field=rock)
