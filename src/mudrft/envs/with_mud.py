"""Mud under any gymnasium MuJoCo environment: :func:`with_mud`.

>>> import gymnasium, mudrft.envs
>>> env = mudrft.envs.with_mud(gymnasium.make("Ant-v5"), feet="auto")  # doctest: +SKIP
>>> obs, info = env.reset(seed=0)  # doctest: +SKIP
>>> info["mud_depth"].shape  # doctest: +SKIP
(4,)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, SupportsFloat

import gymnasium
import numpy as np

from .._progress import logger
from .._validation import MudrftError

if TYPE_CHECKING:
    from ..integrations.mujoco import MudCoupling
    from ..parameters import Mud
    from ..terrains import MudTerrain

__all__ = ["WithMud", "with_mud"]


class WithMud(gymnasium.Wrapper, gymnasium.utils.RecordConstructorArgs):  # type: ignore[misc]
    """Put mud under a gymnasium MuJoCo environment's model (Ant, Humanoid, Walker2d, ...).

    The physics steps go through :func:`mudrft.integrations.mujoco.attach`, which takes
    ``feet`` (``"auto"``, or bodies by name, geom name or id), ``mud`` (default the paper's
    at 25 % water content), ``floor`` (``"below"`` lowers the model's floor to a bed under
    the surface, in place) and ``attach_options``. An RK4 model (Ant's) is switched to
    ``implicitfast``. Each step's ``info`` gains ``"mud_force"`` (nfeet, 3) [N] (world
    frame) and ``"mud_depth"`` (nfeet,) [m]. ``coupling`` is the mud coupling.
    """

    def __init__(
        self, env: Any, feet: str | int | Sequence[str | int] = "auto",
        mud: Mud | MudTerrain | None = None, *, floor: str = "below", **attach_options: Any,
    ) -> None:  # fmt: skip
        from .. import paper_mud
        from ..integrations.mujoco import _mujoco, attach

        gymnasium.utils.RecordConstructorArgs.__init__(
            self, feet=feet, mud=mud, floor=floor, **attach_options
        )
        gymnasium.Wrapper.__init__(self, env)
        base = env.unwrapped
        if not all(hasattr(base, a) for a in ("model", "data", "_step_mujoco_simulation")):
            raise MudrftError(
                "env must be a gymnasium MuJoCo environment (gymnasium.envs.mujoco.MujocoEnv, "
                f"e.g. gymnasium.make('Ant-v5')), got {type(base).__name__}"
            )
        self._mj = _mujoco()
        mud = paper_mud(0.25) if mud is None else mud
        rk4 = self._mj.mjtIntegrator.mjINT_RK4
        if int(base.model.opt.integrator) == int(rk4):  # Ant's: the coupling refuses RK4
            base.model.opt.integrator = self._mj.mjtIntegrator.mjINT_IMPLICITFAST
            logger.info("with_mud: the model's RK4 integrator is now implicitfast")
        self.coupling: MudCoupling = attach(base.model, feet, mud, floor=floor, **attach_options)
        base._step_mujoco_simulation = self._simulate  # the environment's physics steps

    def _simulate(self, ctrl: Any, n_frames: int) -> None:
        base: Any = self.env.unwrapped
        base.data.ctrl[:] = ctrl
        self.coupling.advance(base.data, n_frames)
        self._mj.mj_rnePostConstraint(base.model, base.data)

    def _info(self, info: dict[str, Any]) -> dict[str, Any]:
        last, n = self.coupling.last, len(self.coupling.bodies)
        info["mud_force"] = np.zeros((n, 3)) if last is None else last.force.copy()
        info["mud_depth"] = np.zeros(n) if last is None else last.depth.copy()
        return info

    def reset(self, **kwargs: Any) -> tuple[Any, dict[str, Any]]:
        """Reset the environment, then the mud under the feet in their new pose."""
        obs, info = self.env.reset(**kwargs)
        self.coupling.reset(self.env.unwrapped.data)  # type: ignore[attr-defined]
        return obs, self._info(info)

    def close(self) -> None:
        """Take the mud out of MuJoCo's step, then close the environment."""
        self.coupling.detach()
        super().close()

    def step(self, action: Any) -> tuple[Any, SupportsFloat, bool, bool, dict[str, Any]]:
        """Step the environment in mud; a state MuJoCo found non-finite ends the episode
        with ``info["unstable"]`` (MuJoCo has reset it)."""
        try:
            obs, reward, terminated, truncated, info = self.env.step(action)
        except MudrftError as exc:
            if "MuJoCo" not in str(exc):
                raise
            obs = self.env.unwrapped._get_obs()  # type: ignore[attr-defined]
            return obs, 0.0, True, False, self._info({"unstable": True, "error": str(exc)})
        return obs, reward, terminated, truncated, self._info(info)


#: :class:`WithMud` by its function-style name.
with_mud = WithMud
