"""Shared argument checks (the error names the argument, what was expected and what was
given), input limits, and warnings for values that look like a unit mistake."""

from __future__ import annotations

import importlib
import math
import os
import re
import sys
import warnings
from collections.abc import Iterable
from types import ModuleType

import numpy as np
from numpy.typing import DTypeLike

#: Most samples one run may hold: a trajectory, a load-controlled run, a walk.
MAX_SAMPLES = 5_000_000
#: Largest allocation mudrft makes [bytes], unless ``MUDRFT_MEMORY_LIMIT`` sets another.
MEMORY_LIMIT = 4 * 1024**3
#: Sizes a foot dimension may have at all [m]; outside, an error.
LENGTH_LIMITS = (1e-6, 100.0)
#: Overall sizes of a plausible robot foot [m]; outside, a :class:`PlausibilityWarning`.
PLAUSIBLE_FOOT_SIZE = (1e-3, 1.0)


_NUMPY_REPR = re.compile(r"\bnp\.(?:float|int|uint|bool|complex|str)_?\d*\(([^()]*)\)")


def plain_text(message: str) -> str:
    """``message`` with numpy scalar reprs made plain (``np.float64(1.0)`` reads ``1.0``)."""
    return _NUMPY_REPR.sub(r"\1", message)


class MudrftError(ValueError):
    """A user-facing error raised for invalid input (a ``ValueError``), numbers shown plainly."""

    def __init__(self, *args: object) -> None:
        if args and isinstance(args[0], str):
            args = (plain_text(args[0]), *args[1:])
        super().__init__(*args)


class PlausibilityWarning(UserWarning):
    """An input was accepted but looks like a unit mistake (a mm column labelled m, ...)."""


class CalibrationWarning(UserWarning):
    """A fit ran, but its data were thinned or the model does not describe them."""


#: Optional packages and the extra of ``pip install 'mudrft[EXTRA]'`` that provides them.
EXTRAS = {
    "matplotlib": "plot",
    "mujoco": "mujoco",
    "jax": "jax",
    "numba": "numba",
    "pandas": "pandas",
    "h5py": "hdf5",
    "dask": "sweep",
    "distributed": "sweep",
    "xarray": "sweep",
    "zarr": "sweep",
}


def require_extra(module: str, *, needed_for: str, unless: str | None = None) -> ModuleType:
    """Import an optional package, or fail with one line naming the extra to install
    (and ``unless``, the option that does without it)."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MudrftError(
            f"{needed_for} needs the optional package {module}, which is not installed: "
            f"pip install 'mudrft[{EXTRAS.get(module, module)}]'"
            + (f", or pass {unless}" if unless else "")
        ) from exc


def plain(value: object) -> str:
    """``value`` as a message shows it: plain numbers, arrays by their shape.

    >>> plain(np.float64(1.0)), plain(np.int64(3)), plain(True), plain("a"), plain(np.zeros(2))
    ('1.0', '3', 'True', "'a'", 'an array of shape (2,)')
    """
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    if isinstance(value, np.ndarray):
        return plain(value.item()) if value.ndim == 0 else f"an array of shape {value.shape}"
    if isinstance(value, str):
        return repr(str(value))
    return repr(value)


def _describe(value: object) -> str:
    if isinstance(value, (list, tuple)):
        try:
            return f"an array of shape {np.asarray(value, dtype=float).shape}"
        except (TypeError, ValueError):
            return f"a {type(value).__name__} of {len(value)} items"
    return plain(value)


def as_array(name: str, value: object, *, dtype: DTypeLike = float) -> np.ndarray:
    """``value`` as a float array, or an error naming ``name`` (strings, booleans and None
    are refused)."""
    if value is None:
        raise MudrftError(f"{name} must be a number or an array of numbers, got None")
    if isinstance(value, str):
        raise MudrftError(
            f"{name} must be a number or an array of numbers, got the string {value!r}"
        )
    if isinstance(value, (bool, np.bool_)):
        raise MudrftError(f"{name} must be a number, got the boolean {bool(value)}")
    try:
        return np.asarray(value, dtype=dtype)
    except (TypeError, ValueError) as exc:
        raise MudrftError(
            f"{name} must be a number or an array of numbers, got {type(value).__name__}: "
            f"{_describe(value)}"
        ) from exc


def check_finite(name: str, value: object) -> np.ndarray:
    """Return ``value`` as a float array; raise if any entry is NaN or infinite."""
    arr = as_array(name, value)
    if not np.all(np.isfinite(arr)):
        if arr.ndim == 0:
            raise MudrftError(f"{name} must be finite, got {plain(arr)}")
        bad = arr[~np.isfinite(arr)]
        raise MudrftError(
            f"{name} must be finite, got {_describe(value)} containing {plain(bad[0])}"
        )
    return arr


def _check_bound(name: str, value: object, unit: str, *, strict: bool) -> np.ndarray:
    arr = check_finite(name, value)
    if not np.all(arr > 0 if strict else arr >= 0):
        u = f" {unit}" if unit else ""
        op = ">" if strict else ">="
        raise MudrftError(f"{name} must be {op} 0{u}, got {float(arr.min())!r}")
    return arr


def check_positive(name: str, value: object, *, unit: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array; raise unless every entry is > 0."""
    return _check_bound(name, value, unit, strict=True)


def check_nonnegative(name: str, value: object, *, unit: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array; raise unless every entry is >= 0."""
    return _check_bound(name, value, unit, strict=False)


def check_in_range(
    name: str, value: object, low: float, high: float, *, unit: str = ""
) -> np.ndarray:
    """Return ``value`` as a finite float array; raise unless ``low <= value <= high``."""
    arr = check_finite(name, value)
    if not np.all((arr >= low) & (arr <= high)):
        bad = arr[(arr < low) | (arr > high)] if arr.ndim else arr
        u = f" {unit}" if unit else ""
        raise MudrftError(
            f"{name} must lie in [{low}, {high}]{u}, got {float(np.ravel(bad)[0])!r}{u}"
        )
    return arr


def check_choice(name: str, value: object, choices: Iterable[str]) -> str:
    """Return ``value`` if it is one of ``choices``; raise listing the choices otherwise."""
    options = list(choices)
    if not isinstance(value, str) or value not in options:
        raise MudrftError(f"{name} must be one of {options}, got {plain(value)}")
    return value


def check_shape(name: str, value: object, shape: tuple[int | None, ...]) -> np.ndarray:
    """Return ``value`` as a finite float array of the given shape (``None`` = any length)."""
    arr = check_finite(name, value)
    ok = arr.ndim == len(shape) and all(
        s is None or s == a for s, a in zip(shape, arr.shape, strict=False)
    )
    if not ok:
        dims = ", ".join("n" if s is None else str(s) for s in shape)
        want = f"({dims}{',' if len(shape) == 1 else ''})"
        raise MudrftError(f"{name} must have shape {want}, got shape {arr.shape}")
    return arr


def check_increasing(name: str, value: object) -> np.ndarray:
    """Return a finite 1-D array that is strictly increasing; raise otherwise."""
    arr = check_shape(name, value, (None,))
    if arr.size >= 2:
        d = np.diff(arr)
        if not np.all(d > 0):
            i = int(np.argmax(d <= 0))
            raise MudrftError(
                f"{name} must be strictly increasing, but {name}[{i + 1}] = {plain(arr[i + 1])} "
                f"does not exceed {name}[{i}] = {plain(arr[i])}"
            )
    return arr


def format_bytes(nbytes: float) -> str:
    """A byte count for a message, in binary units.

    >>> format_bytes(969 * 1024**3), format_bytes(512)
    ('969 GiB', '512 B')
    """
    n = float(nbytes)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if n < 1024:
            return f"{n:.3g} {unit}"
        n /= 1024
    return f"{n:.3g} PiB"


def check_memory(what: str, nbytes: float, *, hint: str) -> None:
    """Refuse ``what`` if it needs ``nbytes`` [bytes], more than ``MUDRFT_MEMORY_LIMIT``
    [bytes], else :data:`MEMORY_LIMIT`."""
    text = os.environ.get("MUDRFT_MEMORY_LIMIT", "").strip()
    limit = float(MEMORY_LIMIT)
    if text:
        try:
            limit = float(text)
        except ValueError:
            limit = math.nan
        if not (math.isfinite(limit) and limit > 0):
            raise MudrftError(
                f"the environment variable MUDRFT_MEMORY_LIMIT must be a number of bytes > 0 "
                f"(e.g. 16e9), got {text!r}"
            )
    if not nbytes <= limit:  # also catches NaN
        raise MudrftError(
            f"{what} would need about {format_bytes(nbytes)} of memory, more than the limit of "
            f"{format_bytes(limit)} (raise it with the environment variable "
            f"MUDRFT_MEMORY_LIMIT=BYTES); {hint}"
        )


def check_samples(what: str, count: float, *, hint: str, bytes_per_sample: float = 200.0) -> int:
    """``ceil(count)`` samples of a run, or an error if above :data:`MAX_SAMPLES` (``what``
    and ``hint`` word it; ``bytes_per_sample`` [bytes] estimates the memory)."""
    if not count <= MAX_SAMPLES:  # also catches NaN
        raise MudrftError(
            f"{what} = {float(count):.3g} samples, more than the {MAX_SAMPLES:.0e} one run may "
            f"hold (it would need about {format_bytes(float(count) * bytes_per_sample)}); {hint}"
        )
    return max(math.ceil(count), 0)


def check_broadcast(**shapes: tuple[int, ...]) -> tuple[int, ...]:
    """The broadcast of the named shapes, or an error that gives each argument's shape."""
    try:
        return np.broadcast_shapes(*shapes.values())
    except ValueError:
        listed = ", ".join(f"{k} {v}" for k, v in shapes.items())
        raise MudrftError(f"the shapes must broadcast together, got {listed}") from None


def check_number(name: str, value: object, *, unit: str = "") -> float:
    """One finite number as a float; an array or a sequence is refused, naming ``name``."""
    arr = value if isinstance(value, np.ndarray) else as_array(name, value)
    if arr.ndim:
        u = f" [{unit}]" if unit else ""
        raise MudrftError(f"{name} must be a single number{u}, got {_describe(value)}")
    v = float(arr)
    if not math.isfinite(v):
        raise MudrftError(f"{name} must be finite, got {plain(v)}")
    return v


def positive_int(name: str, value: object, *, what: str = "") -> int:
    """A count >= 1 as an int (booleans refused); ``what`` says what it counts."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise MudrftError(f"{name} must be an integer >= 1{what}, got {value!r}")
    return int(value)


def positive_number(name: str, value: object, *, unit: str = "") -> float:
    """One finite number > 0 as a float (``unit`` for the messages)."""
    return float(check_positive(name, check_number(name, value, unit=unit), unit=unit))


def nonnegative_number(name: str, value: object, *, unit: str = "") -> float:
    """One finite number >= 0 as a float."""
    return float(check_nonnegative(name, check_number(name, value, unit=unit), unit=unit))


def number_in_range(name: str, value: object, low: float, high: float, *, unit: str = "") -> float:
    """One finite number in ``[low, high]`` as a float."""
    return float(check_in_range(name, check_number(name, value, unit=unit), low, high, unit=unit))


def set_number(obj: object, name: str, value: object) -> None:
    """Store ``value`` as the float field ``name`` of the frozen dataclass ``obj``; an array
    or a sequence is refused, naming the field."""
    object.__setattr__(obj, name, check_number(name, value))


def check_length(name: str, value: object) -> float:
    """A size [m] as a float, within :data:`LENGTH_LIMITS`; errors name ``name``."""
    v = positive_number(name, value, unit="m")
    low, high = LENGTH_LIMITS
    if not low <= v <= high:
        raise MudrftError(
            f"{name} must lie in [{low:g}, {high:g}] m for a foot, got {v!r} m (sizes are in "
            "metres: 45 mm is 0.045)"
        )
    return v


def check_dimensions(what: str, **sizes: object) -> dict[str, float]:
    """The foot ``what``'s ``sizes`` [m] as floats (:func:`check_length`); an implausible
    largest one warns.

    >>> check_dimensions("Flat", length=0.08, width=0.065)
    {'length': 0.08, 'width': 0.065}
    """
    out = {k: check_length(k, v) for k, v in sizes.items()}
    name = max(out, key=out.__getitem__)
    label = f"{what}: its largest dimension, {name}, is"
    hint = "sizes are in metres (45 mm is 0.045)"
    warn_implausible(label, out[name], PLAUSIBLE_FOOT_SIZE, unit="m", hint=hint)
    return out


def check_characteristic_length(what: str, value: object) -> float:
    """A characteristic length :math:`L_c` [m] as a float; an implausible one warns."""
    v = check_length("characteristic_length", value)
    label, hint = f"{what}: characteristic_length is", "it is in metres (50 mm is 0.05)"
    warn_implausible(label, v, PLAUSIBLE_FOOT_SIZE, unit="m", hint=hint)
    return v


def warn_implausible(
    what: str, value: float, plausible: tuple[float, float], *, unit: str, hint: str,
) -> bool:  # fmt: skip
    """Warn (:class:`PlausibilityWarning`) and return True if ``value`` is outside
    ``plausible`` (both in ``unit``): valid, but more likely a unit mistake."""
    low, high = plausible
    v = float(value)
    if low <= v <= high:
        return False
    side = f"more than {high:g}" if v > high else f"less than {low:g}"
    warn_plausibility(
        f"{what} {v:.3g} {unit}, {side} {unit} (implausible; a unit mistake?): {hint}"
    )
    return True


def warn_plausibility(message: str, category: type[Warning] = PlausibilityWarning) -> None:
    """Warn with ``category`` at the user's line."""
    warnings.warn(plain_text(message), category, stacklevel=_caller_level())


def _caller_level() -> int:
    """The ``stacklevel`` of the first caller outside mudrft (3.11 has no ``skip_file_prefixes``)."""
    frame, level = sys._getframe(2), 2
    while frame.f_back is not None and f"{frame.f_globals.get('__name__')}.".startswith("mudrft."):
        frame, level = frame.f_back, level + 1
    return level
