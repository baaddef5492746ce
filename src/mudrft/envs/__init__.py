"""Gymnasium environments (optional extra ``rl``), registered on import.

``mudrft/MudWalker-v0`` is the planar biped walking in the paper's mud
(:mod:`mudrft.envs.walker`): ``gymnasium.make`` gives :class:`MudWalkerEnv` (MuJoCo on the
CPU), ``gymnasium.make_vec(..., num_envs=N)`` :class:`MudWalkerVectorEnv` (MJX, extra ``mjx``).
``mudrft/MudGo1-v0`` is Menagerie's Unitree Go1 in mud (:mod:`mudrft.envs.go1`, extra
``robots``). Both take a field of mud patches drawn anew each episode.

>>> import gymnasium, mudrft.envs
>>> env = gymnasium.make("mudrft/MudWalker-v0", foot="flat", water_content=0.25)
>>> env.spec.max_episode_steps
1000
"""

from __future__ import annotations

from typing import TYPE_CHECKING

try:
    import gymnasium
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError("the mudrft environments need gymnasium: pip install 'mudrft[rl]'") from exc

from .go1 import MudGo1Env
from .walker import MudWalkerEnv
from .with_mud import WithMud, with_mud

if TYPE_CHECKING:  # imported by __getattr__ on first use (the MJX coupling)
    from .vector import MudWalkerVectorEnv

__all__ = [
    "ENV_IDS", "MudGo1Env", "MudWalkerEnv", "MudWalkerVectorEnv", "WithMud", "register_envs",
    "with_mud",
]  # fmt: skip

#: The registered environment ids.
ENV_IDS = ("mudrft/MudWalker-v0", "mudrft/MudGo1-v0")


def __getattr__(name: str) -> type[MudWalkerVectorEnv]:
    if name == "MudWalkerVectorEnv":  # imports the MJX coupling only when asked for
        from .vector import MudWalkerVectorEnv

        return MudWalkerVectorEnv
    raise AttributeError(f"module 'mudrft.envs' has no attribute {name!r}")


def register_envs() -> None:
    """Register the environments with Gymnasium (done on import; idempotent)."""
    if "mudrft/MudWalker-v0" in gymnasium.registry:
        return
    gymnasium.register(
        id="mudrft/MudWalker-v0",
        entry_point="mudrft.envs.walker:make_walker",
        vector_entry_point="mudrft.envs.vector:MudWalkerVectorEnv",
        max_episode_steps=1000,
    )
    gymnasium.register(
        id="mudrft/MudGo1-v0", entry_point="mudrft.envs.go1:MudGo1Env", max_episode_steps=1000
    )


register_envs()
