"""Type aliases for arrays, and the shape conventions they carry.

Annotations only: nothing here converts or checks a value at run time.

- An input a user may give as a number, a list or an array is :data:`ArrayLike`; the
  public function validates it (:mod:`mudrft._validation`) into a float array.
- A float array the library returns is :data:`FloatArray` (``float64``). Its shape is
  stated in the docstring: ``(3,)`` for one force or position, ``(n, 3)`` for a history
  of ``n`` samples, ``(..., 3)`` for a batch of feet.
- A value that is a float for one foot and an array for a batch is :data:`FloatOrArray`.
- A path is :data:`PathLike`.
- Code written once over an array namespace ``xp`` (numpy, jax.numpy or the float
  namespace of :mod:`mudrft._xp`) types its values :data:`XpArray` and the namespace
  :data:`Namespace`: both are ``Any`` underneath, since a float, a numpy array and a JAX
  array or tracer share no static type, but the names say what an argument is.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from scipy.spatial.transform import Rotation

__all__ = [
    "ArrayLike",
    "BoolArray",
    "FloatArray",
    "FloatOrArray",
    "IndexArray",
    "IntArray",
    "NDArray",
    "Namespace",
    "PathLike",
    "RotationLike",
    "XpArray",
]

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
#: A value of code written once over ``xp``: a float, a numpy array, or a JAX array or
#: tracer (``Any`` underneath; see the module docstring).
XpArray: TypeAlias = Any
#: An array namespace: numpy, ``jax.numpy`` or ``mudrft._xp.pyfloat`` (``Any`` underneath).
Namespace: TypeAlias = Any
