"""Gymnasium environments: a walker in mud (optional extra ``rl``).

Importing this package registers, under ids that start with ``mudrft/``:

* ``mudrft/MudWalker-v0`` -- the project's planar biped walking in the paper's mud
  (:mod:`mudrft.envs.walker`), options ``foot`` and ``water_content`` among others;
  ``gymnasium.make`` gives :class:`MudWalkerEnv` (MuJoCo on the CPU, the CPU coupling),
  ``gymnasium.make_vec(..., num_envs=N)`` gives :class:`MudWalkerVectorEnv` (MJX, the MJX
  coupling, all robots in one compiled call; needs the ``mjx`` extra).

>>> import gymnasium, mudrft.envs
>>> env = gymnasium.make("mudrft/MudWalker-v0", foot="flat", water_content=0.25)
>>> env.spec.max_episode_steps
1000

``gymnasium.make("mudrft.envs:mudrft/MudWalker-v0")`` imports this package itself.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._gym import gymnasium
from .mud_walker import MudWalkerEnv
from .with_mud import WithMud, with_mud

if TYPE_CHECKING:  # imported by __getattr__ on first use (jax, MJX)
    from .vector import MudWalkerVectorEnv

__all__ = ["ENV_IDS", "MudWalkerEnv", "MudWalkerVectorEnv", "WithMud", "register_envs", "with_mud"]

#: The registered environment ids.
ENV_IDS = ("mudrft/MudWalker-v0",)


def __getattr__(name: str) -> type[MudWalkerVectorEnv]:
    if name == "MudWalkerVectorEnv":  # imports jax and MJX only when asked for
        from .vector import MudWalkerVectorEnv

        return MudWalkerVectorEnv
    raise AttributeError(f"module 'mudrft.envs' has no attribute {name!r}")


def register_envs() -> None:
    """Register the environments with Gymnasium (done on import; idempotent)."""
    if "mudrft/MudWalker-v0" in gymnasium.registry:
        return
    gymnasium.register(
        id="mudrft/MudWalker-v0",
        entry_point="mudrft.envs.mud_walker:make_walker",
        vector_entry_point="mudrft.envs.vector:MudWalkerVectorEnv",
        max_episode_steps=1000,
    )


register_envs()
