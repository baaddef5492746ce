"""``mudrft/MudWalker-v0`` vectorized: many bipeds in mud, one jit-compiled MJX call a step.

The MJX coupling's step is scanned over ``frame_skip`` physics steps and vmapped over the
robots, with the walker's observation, reward and end of :mod:`mudrft.envs.walker`.
Sub-environments reset on the step after they end (next-step autoreset). With a ``field``
(and ``randomize``), each robot steps on its own draw of the field, drawn anew (from the
environment's seed) whenever it resets, passed to the compiled step as traced arrays. The
first step compiles (tens of seconds on a CPU).
``gymnasium.make_vec("mudrft/MudWalker-v0", num_envs=64)``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, TypeAlias

import gymnasium
import numpy as np

from .._typing import ArrayLike, BoolArray, NDArray
from .._validation import MudrftError, as_array, check_memory, positive_int
from ..integrations.mjx import attach, jit
from ..integrations.mjx._lazy import _jax, x64_context
from ..integrations.mujoco import _mujoco
from ..terrains import MudTerrain
from .walker import (
    ACTION_SIZE,
    NOT_RUNNING,
    OBS_SIZES,
    check_action,
    check_reset,
    controls,
    healthy,
    observation,
    reward,
    walker_config,
    walker_layout,
)

if TYPE_CHECKING:
    import jax
    import mujoco.mjx

    from ..integrations.mjx.coupling import Constants
    from ..integrations.mjx.physics import MjxMudState

#: Every robot's (mjx.Data, mud state, observation): what reset makes and merge picks from.
Robots: TypeAlias = "tuple[mujoco.mjx.Data, MjxMudState, jax.Array]"

__all__ = ["MudWalkerVectorEnv", "robot_functions"]


class MudWalkerVectorEnv(gymnasium.vector.VectorEnv):  # type: ignore[misc]
    """``num_envs`` planar bipeds in mud stepped together with MJX, truncated after
    ``max_episode_steps`` control steps; ``water_content`` [-] is one for all robots or one
    per robot, or ``field`` and ``randomize`` a field each (mud regions: the MJX walker has
    no boxes for rigid cells); the other options are
    :class:`~mudrft.envs.walker.WalkerConfig`'s."""

    metadata = {  # noqa: RUF012 (Gymnasium's attribute)
        "autoreset_mode": gymnasium.vector.AutoresetMode.NEXT_STEP,
        "render_modes": [],
    }

    def __init__(
        self, num_envs: int = 64, *, max_episode_steps: int = 1000,
        water_content: ArrayLike = 0.25, render_mode: str | None = None, **options: Any,
    ) -> None:  # fmt: skip
        self.num_envs = positive_int("num_envs", num_envs)
        self.max_episode_steps = positive_int("max_episode_steps", max_episode_steps)
        if render_mode is not None:
            raise MudrftError("the vector environment does not render; use MudWalkerEnv")
        w = as_array("water_content", water_content)
        if w.ndim > 1 or (w.ndim == 1 and len(w) != num_envs):
            raise MudrftError(
                f"water_content must be a float or one per environment ({num_envs}), got shape {w.shape}"
            )
        own = ("num_envs", "max_episode_steps", "water_content", "render_mode")
        # one mud per value, not per robot; nothing of size num_envs before the memory check
        values, which = np.unique(w, return_inverse=True) if w.ndim else (w.reshape(1), None)
        self.configs = {float(v): walker_config({**options, "water_content": float(v)}, own=own) for v in values}  # fmt: skip
        self.config = cfg = self.configs[float(w.flat[0])]
        fielded = cfg.field is not None or cfg.randomize is not None
        if cfg.ground != "mud" or (fielded and w.ndim):
            raise MudrftError(
                "the vector (MJX) walker takes water_content per robot, or a field (and "
                "randomize); ground='rigid' is MudWalkerEnv's (the CPU coupling)"
            )
        if fielded and cfg.mud_field.has_rigid:
            raise MudrftError(
                "field: the vector (MJX) walker steps mud regions only (rigid cells need "
                "MuJoCo's contact with their boxes: MudWalkerEnv)"
            )
        self.base_field = cfg.mud_field if fielded else None
        self.render_mode = None
        self.layout = lay = walker_layout(cfg)
        # the precision the robots are made in; every later call runs in it
        self._x64 = bool(_jax().config.jax_enable_x64)
        self.coupling = attach(
            lay.model, list(lay.bodies), self.base_field or cfg.mud, feet=cfg.foot_object,
            bottom=cfg.bottom,
        )  # fmt: skip
        reset_one, step_one, merge = robot_functions(self)  # checks the memory first
        vmap = _jax().vmap  # the jit-compiled reset and step of all robots
        self._fns = {
            "reset": jit(vmap(reset_one)),
            "step": jit(vmap(step_one)),
            "merge": jit(merge),
        }
        self.water_content = np.broadcast_to(w, (self.num_envs,)).copy()
        which = np.zeros(self.num_envs, dtype=np.intp) if which is None else which
        per_value = [MudTerrain(self.configs[float(v)].mud).constants for v in values]
        self.constants = _jax().tree_util.tree_map(  # each constant, one per robot
            lambda *c: np.array(c, dtype=float)[which], *per_value
        )
        box, batch = gymnasium.spaces.Box, gymnasium.vector.utils.batch_space
        self.single_action_space = box(-1.0, 1.0, (ACTION_SIZE,), np.float32)
        self.action_space = batch(self.single_action_space, self.num_envs)
        self.single_observation_space = box(-np.inf, np.inf, (OBS_SIZES[cfg.observe],), np.float32)
        self.observation_space = batch(self.single_observation_space, self.num_envs)
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._done = np.zeros(self.num_envs, dtype=bool)
        self._state: Any = None
        self._key: Any = None
        self._fields: Any = None  # each robot's field arrays (stacked), where fielded
        self.fields: list[Any] = []  # each robot's MudField

    def _draw(self, which: NDArray[Any]) -> None:
        """Robots ``which`` (bool, num_envs) step on a new draw of the field from now on."""
        cfg, base = self.config, self.base_field
        if base is None:
            return
        if self._fields is None:  # every robot on the field until its first draw
            self.fields = [base] * self.num_envs
            one = self.coupling.field_arrays()
            self._fields = tuple(np.repeat(np.asarray(a)[None], self.num_envs, 0) for a in one)
        if cfg.randomize is None:
            return
        for i in np.flatnonzero(which):
            self.fields[i] = base.randomized(self.np_random, **cfg.randomize)
            for stacked, a in zip(self._fields, self.coupling.field_arrays(self.fields[i]), strict=True):  # fmt: skip
                stacked[i] = np.asarray(a)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Stand every robot 1 mm above the mud with noise on joints and velocities."""
        import jax

        seed = check_reset(seed, options)
        if self.closed:
            raise MudrftError(NOT_RUNNING["closed"])
        super().reset(seed=seed)
        with x64_context(self._x64):  # the precision the robots were made in
            if seed is not None or self._key is None:
                self._key = jax.random.key(int(self.np_random.integers(2**31)))
            self._key, sub = jax.random.split(self._key)
            self._draw(np.ones(self.num_envs, dtype=bool))
            d, st, obs = self._fns["reset"](jax.random.split(sub, self.num_envs), self._fields)
        self._state = (d, st)
        self._steps[:] = 0
        self._done[:] = False
        return np.asarray(obs, dtype=np.float32), {}

    def step(
        self, actions: ArrayLike
    ) -> tuple[
        NDArray[np.float32], NDArray[np.float64], BoolArray, BoolArray, dict[str, NDArray[Any]]
    ]:
        """One control step of every robot; robots that ended last step start anew.

        A robot whose state is not finite, or whose foot moves faster than
        :data:`mudrft.integrations.mjx.physics.MAX_SPEED`, terminates with
        ``info["unstable"]``. Runs in the precision the environment was made in.
        """
        import jax

        if self.closed or self._state is None:
            raise MudrftError(NOT_RUNNING["closed" if self.closed else "new"])
        a = check_action(actions, (self.num_envs, ACTION_SIZE)).astype(np.float32)
        with x64_context(self._x64):  # the precision the robots were made in
            self._key, sub = jax.random.split(self._key)
            d, st = self._state
            if self._done.any():  # their new fields, before the step that resets them
                self._draw(self._done)
            d, st, obs, rew, term, info = self._fns["step"](d, st, a, self.constants, self._fields)
            if self._done.any():  # next-step autoreset of the robots that ended last step
                fresh = self._fns["reset"](jax.random.split(sub, self.num_envs), self._fields)
                done = jax.numpy.asarray(self._done)
                d, st, obs = self._fns["merge"](done, (d, st, obs), fresh)
                rew, term = np.where(self._done, 0.0, rew), np.asarray(term) & ~self._done
                info = {k: np.where(self._done.reshape((-1,) + (1,) * (np.ndim(v) - 1)),
                                    np.zeros_like(v), v) for k, v in info.items()}  # fmt: skip
        self._state = (d, st)
        term = np.asarray(term)
        self._steps = np.where(self._done, 0, self._steps + 1)
        trunc = (self._steps >= self.max_episode_steps) & ~term
        self._done = term | trunc
        out = {k: np.asarray(v) for k, v in info.items()}
        return (np.asarray(obs, dtype=np.float32), np.asarray(rew, dtype=np.float64), term,
                trunc, out)  # fmt: skip


def robot_functions(env: MudWalkerVectorEnv) -> tuple[Any, Any, Any]:
    """One robot's pure JAX functions, to vmap and jit (as the environment does) or to wrap
    for another training library (``examples/train_mud_walker_brax.py``):

    * ``reset_one(key, field) -> (mjx.Data, mud state, observation)``;
    * ``step_one(data, mud state, action, constants, field) -> (data, mud state,
      observation, reward, terminated, info)``, one control step (``frame_skip`` physics
      steps); ``constants`` is one robot's row of :attr:`MudWalkerVectorEnv.constants`,
      ``field`` the robot's field arrays (:meth:`MjxCoupling.field_arrays`, or ``None``);
    * ``merge(done, robots, fresh)``: the fresh robots where ``done``.

    Checks first that the state of ``env.num_envs`` robots fits in memory."""
    import jax
    import jax.numpy as jnp

    mj = _mujoco()
    lay, cfg, cpl = env.layout, env.config, env.coupling
    data = mj.MjData(lay.model)
    data.qpos[:] = lay.qpos0
    data.ctrl[:] = lay.ctrl0
    mj.mj_forward(lay.model, data)
    d0 = cpl.put_data(data)
    per_env = sum(getattr(x, "nbytes", 0) for x in jax.tree_util.tree_leaves(d0))
    check_memory(  # the state, a fresh reset and their merge of every robot, before any is made
        f"num_envs = {env.num_envs} robots", 3.0 * per_env * env.num_envs,
        hint="use fewer environments (num_envs)",
    )  # fmt: skip
    nv, noise, observe = lay.model.nv, cfg.reset_noise_scale, cfg.observe
    jq = lay.joint_qadr

    def reset_one(key: jax.Array, fld: Any) -> Robots:
        k1, k2 = jax.random.split(key)
        qpos = d0.qpos.at[jq].add(jax.random.uniform(k1, (len(jq),), d0.qpos.dtype, -noise, noise))
        qvel = jax.random.uniform(k2, (nv,), d0.qvel.dtype, -noise, noise)
        d = d0.replace(qpos=qpos, qvel=qvel)
        z = jnp.zeros((2,), d0.qpos.dtype)
        obs = observation(lay, qpos, qvel, z, jnp.zeros((2, 3), z.dtype), xp=jnp, observe=observe)
        return d, cpl.init(d, field=fld), obs

    def step_one(
        d: mujoco.mjx.Data, st: MjxMudState, a: jax.Array, consts: Constants, fld: Any
    ) -> tuple[mujoco.mjx.Data, MjxMudState, jax.Array, jax.Array, jax.Array, dict[str, jax.Array]]:
        x0 = d.qpos[lay.rootx]
        d = d.replace(ctrl=controls(lay, a.astype(d.qpos.dtype), cfg.action_scale, xp=jnp))

        def body(carry: tuple[mujoco.mjx.Data, MjxMudState], _: None) -> tuple[Any, Any]:
            dd, ss = carry
            dd, ss, out = cpl.step(dd, ss, consts, field=fld)
            return (dd, ss), (out.depth, out.force, ~out.unstable)

        (d, st), (depth, force, stable) = jax.lax.scan(body, (d, st), None, length=cfg.frame_skip)
        alive = healthy(lay, d.qpos, xp=jnp) & jnp.all(stable)
        r = reward(cfg, x0, d.qpos[lay.rootx], a, alive, xp=jnp)
        obs = observation(lay, d.qpos, d.qvel, depth[-1], force[-1], xp=jnp, observe=observe)
        obs = jnp.nan_to_num(obs)
        info = {
            "x_velocity": (d.qpos[lay.rootx] - x0) / (cfg.dt * cfg.frame_skip),
            "sinking [m]": depth[-1],
            "mud_force [N]": force[-1],
            "unstable": ~jnp.all(stable),
        }
        return d, st, obs, jnp.nan_to_num(r), ~alive, info

    def merge(done: jax.Array, new: Robots, fresh: Robots) -> Robots:
        def pick(a: jax.Array, b: jax.Array) -> jax.Array:
            return jnp.where(done.reshape(done.shape + (1,) * (a.ndim - 1)), b, a)

        return jax.tree_util.tree_map(pick, new, fresh)

    return reset_one, step_one, merge
