"""``mudrft/MudWalker-v0``: one biped walking in mud, MuJoCo on the CPU with the CPU coupling
(the robot, action, observation, reward and end: :mod:`mudrft.envs.walker`)."""

from __future__ import annotations

import importlib.util
from typing import TYPE_CHECKING, Any

import gymnasium
import numpy as np
from numpy.typing import NDArray

from .._typing import ArrayLike
from .._validation import MudrftError
from .walker import (
    ACTION_SIZE,
    OBS_SIZES,
    _CpuEnv,
    check_action,
    controls,
    healthy,
    observation,
    reward,
    walker_config,
    walker_layout,
)

if TYPE_CHECKING:
    import mujoco

__all__ = ["MudWalkerEnv", "make_walker"]


class MudWalkerEnv(_CpuEnv):
    """The planar biped walking in mud (Gymnasium ``Env``; id ``mudrft/MudWalker-v0``).

    ``backend`` is the CPU coupling's (``"auto"`` or ``"numba"``: the compiled one);
    ``render_mode="rgb_array"`` renders the side camera offscreen (OpenGL needed); the
    other ``options`` are :class:`~mudrft.envs.walker.WalkerConfig`'s (field, observation,
    ground). ``info`` holds each foot's sinking and mud force.

    >>> import gymnasium, mudrft.envs
    >>> env = gymnasium.make("mudrft/MudWalker-v0", foot="semi-sphere", water_content=0.35)
    >>> obs, info = env.reset(seed=0)
    >>> obs.shape
    (23,)
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}  # noqa: RUF012 (Gymnasium's attribute)

    def __init__(
        self, *, backend: str = "auto", render_mode: str | None = None, **options: Any
    ) -> None:
        from ..integrations.mujoco import _mujoco, attach

        if render_mode not in (None, "rgb_array"):
            raise MudrftError(
                f"render_mode must be None or 'rgb_array' ('human' through gymnasium.make), "
                f"got {render_mode!r}"
            )
        self.config = cfg = walker_config(options, own=("backend", "render_mode"))
        self.layout = walker_layout(cfg)
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": round(1.0 / (cfg.dt * cfg.frame_skip))}
        self._mj = _mujoco()
        m = self.layout.model
        self.data = self._mj.MjData(m)
        foot = cfg.foot_object
        fielded = cfg.field is not None or cfg.randomize is not None
        self.field = self.base_field = cfg.mud_field if fielded else None
        self.coupling = None if cfg.ground == "rigid" else attach(
            m, list(self.layout.bodies), self.base_field or cfg.mud, feet=foot, bottom=cfg.bottom,
            backend=backend,
        )  # fmt: skip
        box = gymnasium.spaces.Box
        self.action_space = box(-1.0, 1.0, (ACTION_SIZE,), dtype=np.float32)
        self.observation_space = box(-np.inf, np.inf, (OBS_SIZES[cfg.observe],), dtype=np.float32)
        self._renderer: mujoco.Renderer | None = None
        self._depth, self._force = np.zeros(2), np.zeros((2, 3))

    def _obs(self) -> NDArray[np.float32]:
        d = self.data
        o = observation(
            self.layout, d.qpos, d.qvel, self._depth, self._force, observe=self.config.observe
        )
        return np.asarray(o, dtype=np.float32)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Stand the biped 1 mm above the mud, with uniform noise on joints and velocities;
        the field is ``options={"field": f}`` (a curriculum's next, of the shape of the
        environment's), else drawn anew with ``randomize`` from ``seed``."""
        given = self._begin_reset(seed, options)
        lay, d, mj = self.layout, self.data, self._mj
        mj.mj_resetData(lay.model, d)
        noise = self.config.reset_noise_scale
        d.qpos[:] = lay.qpos0
        d.qpos[lay.joint_qadr] += self.np_random.uniform(-noise, noise, ACTION_SIZE)
        d.qvel[:] = self.np_random.uniform(-noise, noise, lay.model.nv)
        d.ctrl[:] = lay.ctrl0
        mj.mj_forward(lay.model, d)
        if self.base_field is not None:
            self._draw_field(given, self.base_field, self.config.randomize, lay.model)
        if self.coupling is not None:
            self.coupling.reset(d)
        self._depth, self._force = np.zeros(2), np.zeros((2, 3))
        self._phase = "running"
        return self._obs(), {"x_position": float(d.qpos[lay.rootx]), "field": self.field}

    def step(
        self, action: ArrayLike
    ) -> tuple[NDArray[np.float32], float, bool, bool, dict[str, Any]]:
        """One control step: ``frame_skip`` physics steps with the mud; an unstable step
        terminates the episode with ``info["unstable"] = True``."""
        lay, cfg, d, mj = self.layout, self.config, self.data, self._mj
        self._check_running()
        a = check_action(action, (ACTION_SIZE,))
        x0 = float(d.qpos[lay.rootx])
        d.ctrl[:] = controls(lay, a, cfg.action_scale)
        bad = [int(w) for w in (mj.mjtWarning.mjWARN_BADQPOS, mj.mjtWarning.mjWARN_BADQVEL,
                                mj.mjtWarning.mjWARN_BADQACC)]  # fmt: skip
        warned = int(d.warning.number[bad].sum())
        try:
            if self.coupling is None:  # rigid ground: MuJoCo's contact alone
                mj.mj_step(lay.model, d, nstep=cfg.frame_skip)
            else:
                out = self.coupling.step(d, cfg.frame_skip)
                self._depth, self._force = np.array(out.depth), np.array(out.force)
            unstable = int(d.warning.number[bad].sum()) > warned or not (
                np.isfinite(d.qpos).all() and np.isfinite(d.qvel).all()
            )
        except MudrftError:  # the coupling refused a diverged state
            unstable = True
        if unstable:  # keep the observation finite
            d.qpos[:] = np.nan_to_num(d.qpos)
            d.qvel[:] = 0.0
        ok = not unstable and bool(healthy(lay, d.qpos))
        self._phase = "running" if ok else "ended"
        x1 = float(d.qpos[lay.rootx])
        r = float(reward(cfg, x0, x1, a, float(ok)))
        return self._obs(), r, not ok, False, self._info(x0, x1, cfg.dt * cfg.frame_skip, unstable)

    def render(self) -> np.ndarray | None:
        """An RGB image of the side camera (``render_mode="rgb_array"``), else None."""
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            from ..integrations.walk import _renderer

            self._renderer = _renderer(self.layout.model)
            if self._renderer is None:
                raise MudrftError(
                    "rendering needs OpenGL: set MUJOCO_GL=egl (or osmesa) before mujoco is "
                    "imported"
                )
        self._renderer.update_scene(self.data, camera="side")
        return np.asarray(self._renderer.render())

    def close(self) -> None:
        """Release the offscreen renderer, if one was made, and the mud coupling's hold on
        MuJoCo's step; the environment steps no more."""
        super().close()
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


def make_walker(*, render_mode: str | None = None, **options: Any) -> gymnasium.Env:
    """The registered entry point: :class:`MudWalkerEnv`, or with ``render_mode="human"``
    its frames in a window (Gymnasium's ``HumanRendering``, which needs pygame)."""
    if render_mode != "human":
        return MudWalkerEnv(render_mode=render_mode, **options)
    if importlib.util.find_spec("pygame") is None:
        raise MudrftError(
            "render_mode='human' shows the frames with pygame, which is not installed: "
            "pip install pygame (Gymnasium's extra 'classic-control' has it), or use "
            "render_mode='rgb_array'"
        )
    return gymnasium.wrappers.HumanRendering(MudWalkerEnv(render_mode="rgb_array", **options))
