"""Force rules of the feet for the batched and JAX backends, on any ``xp``, unvalidated
(a JAX tracer cannot be validated)."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING, TypeAlias

import numpy as np

from .._typing import Namespace, XpArray
from ..feet.mesh import MeshFoot
from ..feet.surface import PreparedTriangles, integrate_prepared

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = ["ForceRule", "force_function"]

#: ``f(depth, stress, heading) -> world force (..., 3)`` [N], over any array namespace.
ForceRule: TypeAlias = Callable[[XpArray, XpArray, XpArray], XpArray]


def force_function(foot: Foot, xp: Namespace = np) -> ForceRule | None:
    """``f(depth, stress, heading) -> world force (..., 3)`` [N] of a rigid foot on the array
    namespace ``xp``, or None for feet without a vectorized rule (the morphing foot).

    >>> import mudrft
    >>> f = force_function(mudrft.feet.Flat())
    >>> f(0.01, [1e3, 1e3, 1e3], 0.0).round(3).tolist()
    [-1.45, -0.0, 5.2]
    """
    if getattr(foot, "elementwise", False) and foot.initial_foot_state() is None:
        return functools.partial(foot.force_array, xp=xp)
    if isinstance(foot, MeshFoot) and type(foot).force_unchecked is MeshFoot.force_unchecked:
        prep = PreparedTriangles(*(xp.asarray(a) for a in foot._prep))
        return functools.partial(integrate_prepared, prep, trailing=foot.trailing, xp=xp)
    return None
