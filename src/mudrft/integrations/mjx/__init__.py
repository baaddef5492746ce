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

# importing these modules imports neither jax nor mujoco: _lazy does on first use
from ._lazy import available, jit
from .coupling import MjxCoupling, attach
from .physics import MjxContact, MjxMudState

__all__ = ["MjxContact", "MjxCoupling", "MjxMudState", "attach", "available", "jit"]
