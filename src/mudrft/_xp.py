r"""The array namespace for one foot on Python floats (:data:`pyfloat`), also what numba
compiles. The physics takes ``xp`` as its last, positional parameter and uses only
:data:`ELEMENTWISE`, arithmetic, comparisons and ``| & ~``.

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
    "where", "abs", "sign", "maximum", "minimum", "exp", "expm1", "tanh", "cos", "sin",
    "arccos", "arctan2", "hypot", "sqrt", "clip",
)  # fmt: skip

abs = abs  # the builtin, as a name of this namespace


def where(cond: bool, a: float, b: float) -> float:
    return a if cond else b


def sign(x: float) -> float:
    """-1, 0 or 1 [-] (NaN gives 0, as numpy's gives NaN: callers never pass NaN)."""
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


def maximum(a: float, b: float) -> float:
    return a if a >= b else b


def minimum(a: float, b: float) -> float:
    return a if a <= b else b


def clip(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else (hi if x > hi else x)


def exp(x: float) -> float:
    """``e**x``, inf on overflow as numpy's (``math.exp`` raises above log(DBL_MAX))."""
    return math.inf if x > 709.782712893384 else math.exp(x)


#: This module as a namespace: ``xp=pyfloat`` runs the physics on Python floats.
pyfloat = sys.modules[__name__]
