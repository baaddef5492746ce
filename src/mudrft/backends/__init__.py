"""Fast and differentiable backends of the mud model (:class:`BatchedMud`,
:mod:`mudrft.backends.jax`, :mod:`mudrft.backends.numba`); no physics of their own.

>>> import mudrft.backends as mb
>>> mb.available()[0]
'numpy'
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import Any

__all__ = ["BatchedMud", "Snapshot", "available", "batch", "forces", "jax", "numba"]


def available() -> list[str]:
    """The backends usable here: ``"numpy"`` always, ``"numba"`` and ``"jax"`` if installed."""
    return ["numpy"] + [m for m in ("numba", "jax") if importlib.util.find_spec(m) is not None]


def __getattr__(name: str) -> Any:
    if name in ("BatchedMud", "Snapshot"):
        return getattr(importlib.import_module(f"{__name__}.batch"), name)
    if name in ("batch", "forces", "jax", "numba"):
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'mudrft.backends' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
