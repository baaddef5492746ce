"""Fast and differentiable backends of the mud model.

* :class:`BatchedMud` (:mod:`mudrft.backends.batch`): N feet, each with its own mud, state
  and motion, advanced by one call (numpy, numba or JAX kernels);
* :class:`FastMudFoot` (:mod:`mudrft.backends.fast`): one closed-form foot stepped on
  floats (numba or plain Python), microseconds per step, for per-step coupling;
* both keep their state inside: ``snapshot()`` copies it (a :class:`Snapshot`) and
  ``restore(snapshot)`` puts it back, for a planner's rollouts (decision D143);
* :mod:`mudrft.backends.jax`: jit-compiled, vmapped, differentiable step, scan over a
  trajectory and surface integration (optional extra ``jax``);
* :mod:`mudrft.backends.numba`: the one physics compiled on floats with numba (optional
  extra), and the compiled loop over feet.

The backends hold no physics: each equation is written once, element-wise over an array
namespace, in the core (decision D80 in docs/model.md); a backend runs it on its arrays
or compiles it.

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
    "FastMudFoot",
    "Snapshot",
    "available",
    "batch",
    "fast",
    "forces",
    "jax",
    "numba",
]

_ATTRS = {
    "BatchedMud": ("mudrft.backends.batch", "BatchedMud"),
    "FastMudFoot": ("mudrft.backends.fast", "FastMudFoot"),
    "Snapshot": ("mudrft.backends._snapshot", "Snapshot"),
}
_MODULES = {"batch", "fast", "forces", "jax", "numba"}


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
