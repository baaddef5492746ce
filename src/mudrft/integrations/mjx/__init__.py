r"""Mud under MuJoCo bodies in MJX: the CPU coupling's step, run through JAX.

:func:`attach` makes an :class:`MjxCoupling`; its :meth:`~MjxCoupling.step` is a pure
function of an ``mjx.Data`` and the mud state (:class:`MjxMudState`) that jit-compiles,
vmaps over robots, scans over time and differentiates where MJX does::

    import jax, mudrft
    from mudrft.integrations import mjx as mm
    from mudrft.integrations.walk import biped_model
    coupling = mm.attach(biped_model(), ["left_foot", "right_foot"], mudrft.paper_mud(0.25))
    d = coupling.put_data(data)                      # an MjData in its start pose
    d, state, contact = coupling.rollout(d, coupling.init(d), 500)
    many = jax.vmap(coupling.step)                   # a batch of robots

Optional extra ``mjx`` (jax and the ``mujoco-mjx`` matching ``mujoco``).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # what __getattr__ imports on first use, named for type checkers
    from ._lazy import available, jit
    from .coupling import MjxCoupling, attach
    from .physics import MjxContact, MjxMudState

__all__ = ["MjxContact", "MjxCoupling", "MjxMudState", "attach", "available", "jit"]

_ATTRS = {
    "MjxContact": "physics",
    "MjxMudState": "physics",
    "MjxCoupling": "coupling",
    "attach": "coupling",
    "available": "_lazy",
    "jit": "_lazy",
}


def __getattr__(name: str) -> object:
    if name in _ATTRS:
        return getattr(importlib.import_module(f"{__name__}.{_ATTRS[name]}"), name)
    raise AttributeError(f"module 'mudrft.integrations.mjx' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
