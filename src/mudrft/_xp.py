r"""Array namespaces the one physics runs on, and the namespace for one foot on floats.

Every equation of the model is written once, as element-wise code over an array namespace
``xp``, its last parameter: ``numpy`` for the reference and for batches, ``jax.numpy`` for
the JAX backend, and this module itself (:data:`pyfloat`) for one foot on Python floats,
which is also what :mod:`mudrft._jit` compiles with numba.

The element-wise subset the physics may use is what every namespace here provides:
``where abs sign maximum minimum exp expm1 tanh cos sin arccos arctan2 hypot sqrt clip``,
arithmetic and comparisons, and ``|``, ``&``, ``~`` on booleans. No stacking, no
reductions, no shapes: those belong to the callers.

``xp`` is a positional-or-keyword parameter, not keyword-only, because numba cannot bind
keyword-only arguments of the functions it compiles.

>>> pyfloat.where(1.0 > 0.0, 2.0, 3.0), pyfloat.maximum(-1.0, 0.0)
(2.0, 0.0)
"""

from __future__ import annotations

import math
import sys
from math import acos as arccos  # noqa: F401 - names of the namespace
from math import atan2 as arctan2  # noqa: F401
from math import cos, expm1, hypot, sin, sqrt, tanh  # noqa: F401

__all__ = ["ELEMENTWISE", "pyfloat"]

#: Names of the element-wise functions the physics may call on ``xp``.
ELEMENTWISE = (
    "where",
    "abs",
    "sign",
    "maximum",
    "minimum",
    "exp",
    "expm1",
    "tanh",
    "cos",
    "sin",
    "arccos",
    "arctan2",
    "hypot",
    "sqrt",
    "clip",
)

abs = abs  # the builtin, as a name of this namespace


def where(cond: bool, a: float, b: float) -> float:
    """``a`` if ``cond`` else ``b``."""
    return a if cond else b


def sign(x: float) -> float:
    """-1, 0 or 1 [-] (NaN gives 0, as numpy's gives NaN: callers never pass NaN)."""
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


def maximum(a: float, b: float) -> float:
    """The larger of ``a`` and ``b``."""
    return a if a >= b else b


def minimum(a: float, b: float) -> float:
    """The smaller of ``a`` and ``b``."""
    return a if a <= b else b


def clip(x: float, lo: float, hi: float) -> float:
    """``x`` limited to ``[lo, hi]``."""
    return lo if x < lo else (hi if x > hi else x)


def exp(x: float) -> float:
    """``e**x`` with numpy's overflow to inf instead of :class:`OverflowError`
    (``math.exp`` overflows just above log(DBL_MAX) = 709.782712893384)."""
    return math.inf if x > 709.782712893384 else math.exp(x)


#: This module as a namespace: ``xp=pyfloat`` runs the physics on Python floats.
pyfloat = sys.modules[__name__]
