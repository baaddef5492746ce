"""Unit conversion at the edges of the library: mudrft computes in SI (m, s, N, Pa, Pa s)."""

from __future__ import annotations

import math
import re

from ._validation import MudrftError

__all__ = ["MPA", "SCALE", "parse_quantity", "parse_unit", "to_si"]

MPA = 1.0e6  #: 1 MPa in Pa

#: Factor that converts a value in the given unit to SI, grouped by quantity.
SCALE: dict[str, dict[str, float]] = {
    "time": {"s": 1.0, "ms": 1.0e-3, "us": 1.0e-6, "min": 60.0},
    "length": {"m": 1.0, "cm": 1.0e-2, "mm": 1.0e-3, "um": 1.0e-6, "in": 0.0254},
    "force": {"N": 1.0, "kN": 1.0e3, "mN": 1.0e-3},
    "stress": {"Pa": 1.0, "kPa": 1.0e3, "MPa": 1.0e6, "N/m^2": 1.0, "N/m2": 1.0},
    "area": {"m^2": 1.0, "m2": 1.0, "cm^2": 1.0e-4, "cm2": 1.0e-4, "mm^2": 1.0e-6, "mm2": 1.0e-6},
    "velocity": {"m/s": 1.0, "mm/s": 1.0e-3, "cm/s": 1.0e-2},
    "angle": {"rad": 1.0, "deg": math.pi / 180.0},
    # granular RFT's stress per unit depth (Li et al. 2013 print N/cm^3)
    "stress per depth": {
        "N/m^3": 1.0,
        "N/m3": 1.0,
        "kN/m^3": 1.0e3,
        "N/cm^3": 1.0e6,
        "N/cm3": 1.0e6,
    },
    "dimensionless": {"-": 1.0, "": 1.0, "1": 1.0},
}


def parse_unit(quantity: str, unit: str) -> float:
    """The factor [SI/unit] that converts ``unit`` (``"mm"``) of ``quantity`` (a key of
    :data:`SCALE`: ``"time"``, ``"length"``, ...) to SI.

    >>> parse_unit("length", "mm")
    0.001
    """
    table = SCALE.get(quantity)
    if table is None:
        raise MudrftError(f"quantity must be one of {sorted(SCALE)}, got {quantity!r}")
    if not isinstance(unit, str):
        raise MudrftError(
            f"unit for {quantity} must be a unit string, one of {sorted(table)}, got {unit!r} "
            f"({type(unit).__name__})"
        )
    u = unit.strip()
    if u not in table:
        raise MudrftError(f"unit for {quantity} must be one of {sorted(table)}, got {unit!r}")
    return table[u]


def to_si(value: float, quantity: str, unit: str) -> float:
    """Convert ``value`` given in ``unit`` of ``quantity`` to SI (:func:`parse_unit`).

    >>> to_si(0.024, "stress", "MPa")
    24000.0
    """
    return value * parse_unit(quantity, unit)


_QUANTITY = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S*)\s*")


def parse_quantity(name: str, text: str, quantity: str) -> float:
    """``text``, a number with an optional unit as typed on a command line (``"40 mm"``; a
    bare number is SI), in SI; ``name`` (``"--length"``) is for the messages.

    >>> parse_quantity("--length", "40mm", "length"), parse_quantity("--area", "0.0016", "area")
    (0.04, 0.0016)
    """
    m = _QUANTITY.fullmatch(text)
    if m is None:
        example = {"area": "1600mm^2", "length": "40mm"}.get(quantity, "1.5")
        raise MudrftError(
            f"{name} must be a number with an optional unit (e.g. {example!r}; a bare number "
            f"is in SI), got {text!r}"
        )
    try:
        factor = parse_unit(quantity, m[2]) if m[2] else 1.0
    except MudrftError as exc:
        raise MudrftError(f"{name}: {exc}") from None
    return float(m[1]) * factor
