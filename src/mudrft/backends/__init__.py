"""Fast and differentiable backends of the mud model.

* :class:`BatchedMud` (:mod:`mudrft.backends.batch`): N feet, each with its own mud, state
  and motion, advanced by one call (numpy, numba or JAX kernels);
  (a batch of one foot with ``backend="numba"`` is the fast single-foot stepper for
  per-step coupling, a few microseconds a step);
* it keeps its state inside: ``snapshot()`` copies it (a :class:`Snapshot`) and
  ``restore(snapshot)`` puts it back, for a planner's rollouts;
* :mod:`mudrft.backends.jax`: jit-compiled, vmapped, differentiable step, scan over a
  trajectory and surface integration (optional extra ``jax``);
* :mod:`mudrft.backends.numba`: the compiled loop over feet (numba, a core dependency),
  multi-threaded for large batches.

The backends hold no physics: each equation is written once, element-wise over an array
namespace, in the core; a backend runs it on its arrays or compiles it (:mod:`mudrft._jit`).

Heavy optional dependencies load on first use. See docs/model.md.

>>> import mudrft.backends as mb
>>> mb.available()[0]
'numpy'
"""

from __future__ import annotations

import importlib
import importlib.util
from typing import Any

__all__ = [
    "BatchedMud",
    "Snapshot",
    "available",
    "batch",
    "forces",
    "jax",
    "numba",
]

_ATTRS = {
    "BatchedMud": ("mudrft.backends.batch", "BatchedMud"),
    "Snapshot": ("mudrft.backends.batch", "Snapshot"),
}
_MODULES = {"batch", "forces", "jax", "numba"}


def available() -> list[str]:
    """The backends usable here: ``"numpy"`` always, ``"numba"`` and ``"jax"`` if installed."""
    return ["numpy"] + [m for m in ("numba", "jax") if importlib.util.find_spec(m) is not None]


def __getattr__(name: str) -> Any:
    if name in _ATTRS:
        mod, attr = _ATTRS[name]
        return getattr(importlib.import_module(mod), attr)
    if name in _MODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'mudrft.backends' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
