"""Couplings of the mud model with simulators (optional extras, imported lazily).

:mod:`mudrft.integrations.mujoco` (mud under bodies of any MuJoCo model),
:mod:`mudrft.integrations.mjx` (the same in MJX on JAX) and
:mod:`mudrft.integrations.walk` (a planar biped walking in mud, ``mudrft walk``).
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = [
    "MudBatch", "MudContact", "MudCoupling", "attach", "attach_batch", "biped_model", "body_foot",
    "mjx", "mujoco", "stability_limits", "walk",
]  # fmt: skip

_ATTRS = {
    "MudBatch": "mudrft.integrations.mujoco",
    "MudContact": "mudrft.integrations.mujoco",
    "MudCoupling": "mudrft.integrations.mujoco",
    "attach": "mudrft.integrations.mujoco",
    "attach_batch": "mudrft.integrations.mujoco",
    "body_foot": "mudrft.integrations.mujoco",
    "stability_limits": "mudrft.integrations.mujoco",
    "biped_model": "mudrft.integrations.walk",
}


def __getattr__(name: str) -> Any:
    if name in _ATTRS:
        return getattr(importlib.import_module(_ATTRS[name]), name)
    if name in ("mjx", "mujoco", "walk"):
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'mudrft.integrations' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
