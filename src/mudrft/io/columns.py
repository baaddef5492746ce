"""Column names with units: the one resolver of what a column of a log holds, in SI.

Both loaders (CSV headers, HDF5 dataset names) go through :func:`resolve_columns`: a
name such as ``"depth [mm]"`` is split into its name and unit, the name is looked up in
:data:`COLUMN_ALIASES`, the unit becomes a factor to SI (:func:`mudrft.units.parse_unit`),
and :func:`check_roles` checks that the columns make an intrusion log. Values are
converted at the edge with :func:`to_si`; nothing inside the library sees another unit.

Every problem raises a :class:`~mudrft._validation.MudrftError` made by :func:`fail`,
naming the file and the place (line and column, or dataset).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..units import parse_unit

__all__ = [
    "COLUMN_ALIASES",
    "Column",
    "ColumnMap",
    "check_roles",
    "default_unit",
    "fail",
    "parse_header_name",
    "parse_number",
    "quantity_value",
    "resolve_columns",
    "to_si",
]

#: Column name (lower case) -> (role, quantity for :func:`mudrft.units.parse_unit`).
COLUMN_ALIASES: dict[str, tuple[str, str]] = {
    "time": ("time", "time"),
    "t": ("time", "time"),
    "depth": ("depth", "length"),
    "displacement": ("depth", "length"),
    "stress": ("stress", "stress"),
    "sigma": ("stress", "stress"),
    "fz": ("force", "force"),
    "force": ("force", "force"),
    "f": ("force", "force"),
}

_HEADER_RE = re.compile(r"^\s*([^\[\]]*?)\s*(?:\[([^\[\]]*)\])?\s*$")
_DEFAULT_UNITS = {"length": "m", "area": "m^2", "time": "s", "force": "N", "stress": "Pa"}


def fail(path: str, where: str, problem: str) -> MudrftError:
    """The error for a problem in file ``path`` at place ``where`` (may be empty)."""
    return MudrftError(f"{path}: {where}: {problem}" if where else f"{path}: {problem}")


def parse_header_name(text: str) -> tuple[str, str | None]:
    """'time [ms]' -> ('time', 'ms'); 'trial' -> ('trial', None).

    Raises
    ------
    ValueError
        If the text is not of the form ``name`` or ``name [unit]``.
    """
    m = _HEADER_RE.match(text)
    if m is None:
        raise ValueError(f"cannot read the column name {text!r}; write it as 'name [unit]'")
    name, unit = m.group(1).strip(), m.group(2)
    return name, (unit.strip() if unit is not None else None)


def default_unit(quantity: str) -> str:
    """The SI unit of a quantity, as written in a header ('m', 'Pa', ...)."""
    return _DEFAULT_UNITS[quantity]


def parse_number(text: str) -> float:
    """A finite number from the text of a cell.

    Raises
    ------
    ValueError
        For an empty cell, text that is not a number, NaN or infinity.
    """
    s = text.strip()
    if not s:
        raise ValueError("empty cell, expected a number")
    try:
        v = float(s)
    except ValueError:
        raise ValueError(f"cannot read {s[:40]!r} as a number") from None
    if not math.isfinite(v):
        raise ValueError(f"value {s[:40]!r} is not finite")
    return v


def quantity_value(path: str, where: str, key: str, value: str, quantity: str) -> float:
    """A positive metadata value in SI; ``key`` may carry a unit ('area [cm^2]') [SI].

    Parameters
    ----------
    path, where : str
        File and place, for errors.
    key : str
        The name as written, with an optional unit in brackets (default SI).
    value : str
        The number as written, in that unit.
    quantity : str
        ``"length"``, ``"area"``, ... (:func:`mudrft.units.parse_unit`).
    """
    _, unit = parse_header_name(key)
    try:
        factor = parse_unit(quantity, unit if unit is not None else default_unit(quantity))
        v = parse_number(value) * factor
    except (ValueError, MudrftError) as exc:
        raise fail(path, where, f"metadata {key!r}: {exc}") from None
    if not v > 0:
        raise fail(path, where, f"metadata {key!r} must be > 0, got {value!r}")
    return v


class Column(NamedTuple):
    """A recognised column.

    Attributes
    ----------
    position : int
        Position among the names given to :func:`resolve_columns`.
    label : str
        The name as written.
    role : str
        ``"time"``, ``"depth"``, ``"stress"`` or ``"force"``.
    factor : float
        Factor from the column's unit to SI [SI/unit].
    """

    position: int
    label: str
    role: str
    factor: float


class ColumnMap(NamedTuple):
    """What the columns of a table hold.

    Attributes
    ----------
    roles : dict
        Role -> :class:`Column`.
    trial : int or None
        Index of the ``trial`` label column, if any.
    ignored : list of str
        Names of the other columns (kept as metadata).
    fz : bool
        Whether the force column is named ``Fz`` (the vertical force).
    """

    roles: dict[str, Column]
    trial: int | None
    ignored: list[str]
    fz: bool


def _check_same_unit(path: str, loc: str, label: str, quantity: str, unit: str, attr: str) -> None:
    """Refuse a unit attribute (HDF5) that is not the unit in the name: which one the
    values are in cannot be told."""
    try:
        from_attr = parse_unit(quantity, attr)
    except MudrftError as exc:
        raise fail(path, loc, f"column {label.strip()!r}: its unit attribute: {exc}") from None
    try:
        same = math.isclose(parse_unit(quantity, unit), from_attr, rel_tol=1e-12)
    except MudrftError:
        return  # the unit in the name is reported as unknown by the caller
    if not same:
        raise fail(
            path,
            loc,
            f"the name gives the unit {unit!r} but the unit attribute says {attr!r}; "
            "remove one or make them agree",
        )


def _column(
    path: str, loc: str, index: int, label: str, unit_attr: str | None, unit_hint: str
) -> Column | str | None:
    """One name: a Column, ``"trial"``, or None for a column mudrft does not read."""
    try:
        name, unit = parse_header_name(label)
    except ValueError as exc:
        raise fail(path, loc, str(exc)) from None
    key = name.lower()
    if key == "trial":
        return "trial"
    if key not in COLUMN_ALIASES:
        return None
    role, quantity = COLUMN_ALIASES[key]
    if unit is not None and unit_attr:
        _check_same_unit(path, loc, label, quantity, unit, unit_attr)
    unit = unit if unit is not None else unit_attr
    if not unit:
        raise fail(
            path,
            loc,
            f"column {name!r} has no unit; write it as '{name} [{default_unit(quantity)}]'"
            f"{unit_hint}",
        )
    try:
        factor = parse_unit(quantity, unit)
    except MudrftError as exc:
        raise fail(path, loc, f"column {label.strip()!r}: {exc}") from None
    return Column(index, label.strip(), role, factor)


def resolve_columns(
    path: str,
    names: Sequence[str],
    *,
    locate: Callable[[int], str],
    units: Sequence[str | None] | None = None,
    unit_hint: str = "",
) -> ColumnMap:
    """What each named column holds, with its factor to SI.

    Parameters
    ----------
    path : str
        The file, for errors.
    names : sequence of str
        Column names as written: ``"time [ms]"``, ``"Fz [N]"``, ``"trial"``, ...
    locate : callable, keyword-only
        ``locate(j)`` is the place of column ``j`` in the file, for errors.
    units : sequence, optional, keyword-only
        Units given apart from the names (HDF5 ``unit`` attributes), used when a name
        has no unit in brackets; one that differs from the unit in brackets is refused.
    unit_hint : str, keyword-only
        Appended to the error for a column without a unit.

    Returns
    -------
    ColumnMap
    """
    roles: dict[str, Column] = {}
    trial, ignored = None, []
    for j, label in enumerate(names):
        col = _column(path, locate(j), j, label, units[j] if units else None, unit_hint)
        if col is None:
            ignored.append(label.strip())
        elif col == "trial":
            if trial is not None:
                raise fail(path, locate(j), "column 'trial' appears twice")
            trial = j
        elif isinstance(col, Column):
            if col.role in roles:
                raise fail(
                    path,
                    locate(j),
                    f"two columns give the {col.role} ({roles[col.role].label!r} and "
                    f"{col.label!r}); keep one",
                )
            roles[col.role] = col
    force = roles.get("force")
    fz = force is not None and force.label.lower().startswith("fz")
    return ColumnMap(roles, trial, ignored, fz)


def check_roles(
    path: str, where: str, columns: ColumnMap, names: Sequence[str], *, direction: str
) -> bool:
    """Check that the columns make an intrusion log; return whether a stress is logged.

    A log needs a time and a depth, and a stress or a force; a force named ``Fz`` (the
    vertical force) is refused for a horizontal test.
    """
    for need in ("time", "depth"):
        if need not in columns.roles:
            parens = [n for n in names if re.fullmatch(r"\s*[^()\[\]]+\(\s*[^()]+\)\s*", n)]
            hint = f"; units go in square brackets: {parens[0]!r} reads as a name" if parens else ""
            raise fail(
                path,
                where,
                f"no {need} column; name it {_names_of(need)}, with its unit in brackets "
                f"(e.g. '{need} [{_unit_like(need, names)}]'); got {list(names)!r}{hint}",
            )
    has_stress = "stress" in columns.roles
    if not has_stress and "force" not in columns.roles:
        raise fail(
            path,
            where,
            f"needs a stress or a force column; name it {_names_of('stress')} (e.g. "
            f"'stress [Pa]'), or {_names_of('force')} (e.g. 'force [N]'); got {list(names)!r}",
        )
    if not has_stress and columns.fz and direction == "horizontal":
        raise fail(
            path,
            where,
            "'Fz' is the vertical force but the test is horizontal; name the column "
            "'force [N]' (the force resisting the intrusion)",
        )
    return has_stress


def _names_of(role: str) -> str:
    """The names read for a role, as a header would write them: "'depth' or 'displacement'"."""
    shown = [{"fz": "Fz", "f": "F"}.get(k, k) for k, (r, _) in COLUMN_ALIASES.items() if r == role]
    quoted = [repr(k) for k in shown]
    return quoted[0] if len(quoted) == 1 else f"{', '.join(quoted[:-1])} or {quoted[-1]}"


def _unit_like(role: str, names: Sequence[str]) -> str:
    """The unit of the first column whose unit is one of the role's (the rig's own name for
    it, such as 'position [mm]'), else the SI unit."""
    quantity = {"time": "time", "depth": "length"}[role]
    for label in names:
        try:
            _, unit = parse_header_name(label)
            if unit is not None and parse_unit(quantity, unit) > 0:
                return unit
        except (ValueError, MudrftError):
            continue
    return default_unit(quantity)


def to_si(
    path: str, raw: NDArray[np.float64], column: Column, *, locate_row: Callable[[int], str]
) -> NDArray[np.float64]:
    """Values of a column in SI, every one finite.

    Parameters
    ----------
    path : str
        The file, for errors.
    raw : ndarray
        Values in the column's unit.
    column : Column
        The column.
    locate_row : callable, keyword-only
        ``locate_row(i)`` is the place of value ``i`` in the file, for errors.
    """
    if not np.all(np.isfinite(raw)):
        raise fail(path, locate_row(int(np.argmax(~np.isfinite(raw)))), "value is NaN or infinite")
    with np.errstate(over="ignore"):  # an overflow is reported below, with its place
        vals = raw * column.factor
    if not np.all(np.isfinite(vals)):
        i = int(np.argmax(~np.isfinite(vals)))
        raise fail(path, locate_row(i), "value overflows after unit conversion")
    return vals
