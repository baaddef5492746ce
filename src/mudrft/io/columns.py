"""Column names with units (``depth [mm]``, ``Depth (mm)``, ``depth in mm``): the one
resolver of what a column of a table holds (:func:`resolve_columns`), for CSV and HDF5
logs and foot paths alike."""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..units import parse_unit

#: An intrusion log's column names (lower case) -> role.
LOG_COLUMNS = {
    **dict.fromkeys(("time", "t"), "time"),
    **dict.fromkeys(("depth", "displacement"), "depth"),
    **dict.fromkeys(("stress", "sigma"), "stress"),
    **dict.fromkeys(("fz", "force", "f"), "force"),
    "trial": "trial",
}
#: Role -> the quantity of its unit (a key of :data:`mudrft.units.SCALE`); None: no unit.
QUANTITY: dict[str, str | None] = {
    **dict(time="time", depth="length", stress="stress", force="force", trial=None),
    **dict.fromkeys(("x", "y", "z"), "length"),
    **dict.fromkeys(("Fx", "Fy", "Fz"), "force"),
}
#: SI units, as a header writes them.
SI_UNIT = {"length": "m", "area": "m^2", "time": "s", "force": "N", "stress": "Pa"}

_LABEL = re.compile(
    r"\s*(?P<name>.*?)\s*(?:\[(?P<b>[^\[\]]*)\]|\((?P<p>[^()]*)\)|\s+in\s+(?P<i>\S+))?\s*",
    re.DOTALL,
)


def fail(path: str, where: str, problem: str) -> MudrftError:
    """The error for a problem in file ``path`` at place ``where`` (may be empty)."""
    return MudrftError(f"{path}: {where}: {problem}" if where else f"{path}: {problem}")


def split_label(text: str) -> tuple[str, str | None]:
    """A column name and its unit, as a logger writes them.

    Examples
    --------
    >>> split_label("time [ms]"), split_label("Depth (mm)"), split_label("force in N")
    (('time', 'ms'), ('Depth', 'mm'), ('force', 'N'))
    >>> split_label("trial")
    ('trial', None)
    """
    m = _LABEL.fullmatch(text)
    assert m is not None  # every text matches: the unit is optional
    unit = next((m[g] for g in ("b", "p", "i") if m[g] is not None), None)
    return m["name"], (unit.strip() if unit is not None else None)


class Column(NamedTuple):
    """A recognised column: position, name as written, role and factor to SI."""

    position: int
    label: str
    role: str
    factor: float


def _mapped(
    path: str, names: Sequence[str], columns: Mapping[str, str], roles: set[str]
) -> dict[str, tuple[int, str | None]]:
    """The caller's ``columns`` (role -> name): role -> (position, unit given with it)."""
    out: dict[str, tuple[int, str | None]] = {}
    keys = [n.strip().lower() for n in names]
    for role, label in columns.items():
        if role not in roles or not isinstance(label, str):
            raise MudrftError(
                f"columns must map roles, of {sorted(roles)}, to column names (str), got "
                f"{role!r}: {label!r}"
            )
        if label.strip().lower() in keys:
            j, unit = keys.index(label.strip().lower()), None
        else:  # "Position [mm]" for a file's "Position": the unit comes with the mapping
            name, unit = split_label(label)
            bare = [i for i, n in enumerate(names) if split_label(n) == (n.strip(), None)]
            found = [i for i in bare if names[i].strip().lower() == name.lower()]
            if not found or unit is None:
                raise fail(
                    path,
                    "",
                    f"columns maps {role} to {label!r}, but no column is named so; the "
                    f"columns are {[n.strip() for n in names]}",
                )
            j = found[0]
        taken = [r for r, (i, _) in out.items() if i == j]
        if taken:
            raise MudrftError(f"columns maps both {taken[0]} and {role} to {label!r}; map one")
        out[role] = (j, unit)
    return out


def resolve_columns(
    path: str,
    names: Sequence[str],
    *,
    aliases: Mapping[str, str],
    locate: Callable[[int], str],
    columns: Mapping[str, str] | None = None,
    units: Sequence[str | None] | None = None,
    require_units: bool = True,
) -> dict[str, Column]:
    """What each of the ``names`` of a table in ``path`` holds: role -> :class:`Column`.

    A name is looked up, without its unit and case, in ``aliases`` (name -> role), or
    mapped by the caller's ``columns`` (role -> name as written; a unit may come with it,
    ``{"depth": "Position [mm]"}``, when the file states none). ``units`` are given apart
    from the names (HDF5 ``unit`` attributes) and must agree with them; ``locate(j)`` is
    the place of column ``j`` for errors; without ``require_units`` a column without a
    unit is read as SI.
    """
    roles = set(aliases.values())
    chosen = _mapped(path, names, columns or {}, roles)
    found: dict[str, tuple[int, str | None]] = dict(chosen)
    for j, label in enumerate(names):
        role = aliases.get(split_label(label)[0].lower())
        if role is None or role in chosen or any(j == i for i, _ in chosen.values()):
            continue  # not read, or the caller chose another column for its role
        if role in found:
            first = names[found[role][0]].strip()
            what = "'trial' appears twice" if role == "trial" else f"two columns give the {role}"
            raise fail(
                path,
                locate(j),
                f"{what} ({first!r} and {label.strip()!r}); keep one, or choose one with "
                f"columns={{'{role}': ...}}",
            )
        found[role] = (j, None)
    out = {}
    for role, (j, mapped_unit) in found.items():
        quantity = QUANTITY[role]
        if quantity is None:
            out[role] = Column(j, names[j].strip(), role, 1.0)
            continue
        unit = mapped_unit or split_label(names[j])[1]
        given = units[j] if units else None
        if unit is not None and given:  # refuse a unit attribute that is not the name's
            try:
                same = parse_unit(quantity, given) == parse_unit(quantity, unit)
            except MudrftError as exc:
                raise fail(path, locate(j), f"its unit attribute or name: {exc}") from None
            if not same:
                raise fail(
                    path,
                    locate(j),
                    f"the name gives the unit {unit!r} but the unit attribute says {given!r}; "
                    "remove one or make them agree",
                )
        unit = unit or given or None
        if unit is None and require_units:
            raise fail(
                path,
                locate(j),
                f"column {names[j].strip()!r} has no unit; write it as "
                f"'{split_label(names[j])[0]} [{SI_UNIT[quantity]}]'",
            )
        try:
            factor = parse_unit(quantity, unit or SI_UNIT[quantity])
        except MudrftError as exc:
            raise fail(path, locate(j), f"column {names[j].strip()!r}: {exc}") from None
        out[role] = Column(j, names[j].strip(), role, factor)
    return out


def to_si(
    path: str, raw: NDArray[np.float64], column: Column, *, locate_row: Callable[[int], str]
) -> NDArray[np.float64]:
    """A column's values in SI, every one finite; an error names the first bad value."""
    with np.errstate(over="ignore", invalid="ignore"):  # reported below, with the place
        vals = raw * column.factor
    bad = ~np.isfinite(vals)
    if bad.any():
        i = int(np.argmax(bad))
        what = "is not finite" if not np.isfinite(raw[i]) else "overflows after unit conversion"
        raise fail(path, locate_row(i), f"value {raw[i]!r} {what}")
    return vals
