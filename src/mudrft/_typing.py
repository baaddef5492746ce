"""Type aliases for arrays (annotations only). Shapes are stated in docstrings: ``(3,)`` for
one force, ``(n, 3)`` for a history, ``(..., 3)`` for a batch of feet.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = [
    "ArrayLike", "BoolArray", "FloatArray", "FloatOrArray", "IndexArray", "IntArray", "NDArray",
    "Namespace", "PathLike", "RotationLike", "XpArray",
]  # fmt: skip

#: A float64 array (forces [N], positions [m], stresses [Pa], ...).
FloatArray: TypeAlias = NDArray[np.float64]
#: An integer index array (mesh faces, sample indices).
IntArray: TypeAlias = NDArray[np.intp]
#: An integer array of any width: indices into MuJoCo's arrays (its own ``int32`` model
#: arrays, or the ``int64`` copies the compiled coupling packs).
IndexArray: TypeAlias = NDArray[np.integer]
#: A boolean mask.
BoolArray: TypeAlias = NDArray[np.bool_]
#: A float for one set or one foot, a float64 array for a batch.
FloatOrArray: TypeAlias = float | NDArray[np.float64]
#: A file-system path.
PathLike: TypeAlias = str | os.PathLike[str]
#: A rotation: a proper 3x3 matrix (array_like) or a ``scipy.spatial.transform.Rotation``.
RotationLike: TypeAlias = "ArrayLike | Rotation"
#: A value of code written once over ``xp``: a float, a numpy or a JAX array (``Any``).
XpArray: TypeAlias = Any
#: An array namespace: numpy, ``jax.numpy`` or ``mudrft._xp.pyfloat`` (``Any`` underneath).
Namespace: TypeAlias = Any
