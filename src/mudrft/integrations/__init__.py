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


def __getattr__(name: str) -> Any:
    if name in ("mjx", "mujoco", "walk"):
        return importlib.import_module(f"{__name__}.{name}")
    if name == "biped_model":
        return importlib.import_module(f"{__name__}.walk").biped_model
    if name in __all__:  # the other names are the MuJoCo coupling's
        return getattr(importlib.import_module(f"{__name__}.mujoco"), name)
    raise AttributeError(f"module 'mudrft.integrations' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
