"""Shared argument checks that fail early with a precise message.

Every public function validates its inputs with these helpers so that a user
mistake produces an error naming the argument, what was expected and what was
given, instead of a NaN or a traceback from deep inside numpy.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

__all__ = [
    "MudrftError",
    "as_array",
    "check_choice",
    "check_finite",
    "check_in_range",
    "check_increasing",
    "check_nonnegative",
    "check_positive",
    "check_shape",
]


class MudrftError(ValueError):
    """A user-facing error raised for invalid input (a ``ValueError``)."""


def _describe(value: Any) -> str:
    arr = np.asarray(value) if not isinstance(value, str) else None
    if arr is not None and arr.ndim > 0:
        return f"an array of shape {arr.shape}"
    return repr(value)


def as_array(name: str, value: Any, *, dtype: Any = float) -> np.ndarray:
    """Convert ``value`` to a float array, or raise naming ``name``."""
    if isinstance(value, str):
        raise MudrftError(
            f"{name} must be a number or an array of numbers, got the string {value!r}"
        )
    try:
        arr = np.asarray(value, dtype=dtype)
    except (TypeError, ValueError) as exc:
        raise MudrftError(
            f"{name} must be a number or an array of numbers, got {type(value).__name__}: {value!r}"
        ) from exc
    return arr


def check_finite(name: str, value: Any) -> np.ndarray:
    """Return ``value`` as a float array; raise if any entry is NaN or infinite."""
    arr = as_array(name, value)
    if not np.all(np.isfinite(arr)):
        bad = arr[~np.isfinite(arr)] if arr.ndim else arr
        raise MudrftError(
            f"{name} must be finite, got {_describe(value)} containing {bad.ravel()[0]}"
        )
    return arr


def check_positive(name: str, value: Any, *, unit: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array; raise unless every entry is > 0."""
    arr = check_finite(name, value)
    if not np.all(arr > 0):
        worst = arr.min() if arr.ndim else arr
        raise MudrftError(f"{name} must be > 0{(' ' + unit) if unit else ''}, got {float(worst)!r}")
    return arr


def check_nonnegative(name: str, value: Any, *, unit: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array; raise unless every entry is >= 0."""
    arr = check_finite(name, value)
    if not np.all(arr >= 0):
        worst = arr.min() if arr.ndim else arr
        raise MudrftError(
            f"{name} must be >= 0{(' ' + unit) if unit else ''}, got {float(worst)!r}"
        )
    return arr


def check_in_range(name: str, value: Any, low: float, high: float, *, unit: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array; raise unless ``low <= value <= high``."""
    arr = check_finite(name, value)
    if not np.all((arr >= low) & (arr <= high)):
        bad = arr[(arr < low) | (arr > high)] if arr.ndim else arr
        u = f" {unit}" if unit else ""
        raise MudrftError(
            f"{name} must lie in [{low}, {high}]{u}, got {float(np.ravel(bad)[0])!r}{u}"
        )
    return arr


def check_choice(name: str, value: Any, choices: Iterable[str]) -> str:
    """Return ``value`` if it is one of ``choices``; raise listing the choices otherwise."""
    options = list(choices)
    if not isinstance(value, str) or value not in options:
        raise MudrftError(f"{name} must be one of {options}, got {value!r}")
    return value


def check_shape(name: str, value: Any, shape: tuple[int | None, ...]) -> np.ndarray:
    """Return ``value`` as a finite float array of the given shape (``None`` = any length)."""
    arr = check_finite(name, value)
    ok = arr.ndim == len(shape) and all(
        s is None or s == a for s, a in zip(shape, arr.shape, strict=False)
    )
    if not ok:
        want = (
            "("
            + ", ".join("n" if s is None else str(s) for s in shape)
            + ("," if len(shape) == 1 else "")
            + ")"
        )
        raise MudrftError(f"{name} must have shape {want}, got shape {arr.shape}")
    return arr


def check_increasing(name: str, value: Any) -> np.ndarray:
    """Return a finite 1-D array that is strictly increasing; raise otherwise."""
    arr = check_shape(name, value, (None,))
    if arr.size >= 2:
        d = np.diff(arr)
        if not np.all(d > 0):
            i = int(np.argmax(d <= 0))
            raise MudrftError(
                f"{name} must be strictly increasing, but {name}[{i + 1}] = {arr[i + 1]!r} "
                f"does not exceed {name}[{i}] = {arr[i]!r}"
            )
    return arr
