r"""Array namespaces the one physics runs on.

Every equation of the model is written once, as element-wise code over an array namespace
``xp`` (decision D80 in docs/model.md): ``numpy`` for the reference and for batches,
``jax.numpy`` for the JAX backend, and :data:`pyfloat` below for one foot on Python floats
(10x faster than numpy on 0-d arrays). The single-foot path of :class:`mudrft.MudTerrain`
runs the source rewritten for floats (:func:`mudrft._specialize.on_floats`: the same
results, without the calls), and the numba backend compiles that rewrite
(:mod:`mudrft.backends.numba`).

The element-wise subset the physics may use is what every namespace here provides:
``where abs sign maximum minimum exp expm1 tanh cos sin arccos arctan2 hypot sqrt clip``,
arithmetic and comparisons, and ``|``, ``&``, ``~`` on booleans. No stacking, no
reductions, no shapes: those belong to the callers.

>>> pyfloat.where(1.0 > 0.0, 2.0, 3.0), pyfloat.maximum(-1.0, 0.0)
(2.0, 0.0)
"""

from __future__ import annotations

import math
import types

__all__ = ["ELEMENTWISE", "SCALAR_HELPERS", "pyfloat"]

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


def _where(cond: bool, a: float, b: float) -> float:
    return a if cond else b


def _sign(x: float) -> float:
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


def _maximum(a: float, b: float) -> float:
    return a if a >= b else b


def _minimum(a: float, b: float) -> float:
    return a if a <= b else b


def _clip(x: float, lo: float, hi: float) -> float:
    return lo if x < lo else (hi if x > hi else x)


def _exp(x: float) -> float:
    # numpy semantics: overflow gives inf instead of raising (math.exp overflows exactly
    # above log(DBL_MAX) = 709.782712893384; NaN compares false and stays NaN). One
    # expression, so that the float specialization inlines it (mudrft._specialize).
    return math.inf if x > 709.782712893384 else math.exp(x)


#: The element-wise helpers written here (the rest are the ``math`` module's); the numba
#: backend compiles these same functions.
SCALAR_HELPERS = {
    "where": _where,
    "sign": _sign,
    "maximum": _maximum,
    "minimum": _minimum,
    "clip": _clip,
}

#: The element-wise namespace on Python floats (math module semantics, numpy's names).
pyfloat = types.SimpleNamespace(
    where=_where,
    abs=abs,
    sign=_sign,
    maximum=_maximum,
    minimum=_minimum,
    exp=_exp,
    expm1=math.expm1,
    tanh=math.tanh,
    cos=math.cos,
    sin=math.sin,
    arccos=math.acos,
    arctan2=math.atan2,
    hypot=math.hypot,
    sqrt=math.sqrt,
    clip=_clip,
)
