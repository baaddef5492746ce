"""Foot paths as CSV: :func:`load_path_csv` reads the path of a foot's tip as a
:class:`~mudrft.Trajectory` for :func:`mudrft.simulate`."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from .._typing import PathLike
from .._validation import PlausibilityWarning, plain
from ..trajectories import Trajectory
from .columns import PATH_COLUMNS, fail, resolve_columns
from .csv_log import read_table


def load_path_csv(path: PathLike, *, columns: Mapping[str, str] | None = None) -> Trajectory:
    """Read a foot tip's path from a CSV file, as a trajectory to simulate.

    ``time`` and ``z`` (the tip's height, negative below the mud surface; or ``depth``,
    positive below it) are required, ``x`` and ``y`` are 0 when absent, forces ``Fx``,
    ``Fy``, ``Fz`` [N] are kept; each column is named with its unit (``x [mm]``; SI when
    none), as docs/guide/forces.md shows. Other columns are ignored; ``#`` lines are notes.

    Parameters
    ----------
    path : str or path-like
        The CSV file.
    columns : mapping, optional, keyword-only
        Role (``time``, ``x``, ``y``, ``z``, ``depth``, ``Fx``, ``Fy``, ``Fz``) -> the
        column's name as written, for names mudrft does not know.

    Returns
    -------
    Trajectory
        Times [s] and tip positions [m] in the world frame (z < 0 below the mud
        surface) as in the file, the velocity [m/s] the rate of each step
        (:meth:`Trajectory.from_positions`), named after the file; the file's force
        columns [N] by name in ``meta["measured_force"]`` (``{"Fz": array}``), if any.

    Raises
    ------
    MudrftError
        Naming the file, line and column of any problem.

    Warns
    -----
    PlausibilityWarning
        When the path never goes below the mud surface (z >= 0 throughout).
    """
    table = read_table(path)
    where, head = table.path, f"line {table.header_line}"
    found = resolve_columns(
        where,
        table.header,
        aliases=PATH_COLUMNS,
        locate=lambda j: f"{head}, column {j + 1}",
        columns=columns,
        require_units=False,
    )
    missing = [] if "time" in found else ["time"]
    if "z" not in found and "depth" not in found:
        missing.append("z (or depth)")
    if missing:
        raise fail(
            where,
            head,
            f"the header {', '.join(table.header)!r} has no {' and no '.join(missing)} column; "
            "a path needs 'time [s]' and 'z [m]' (the tip's height, negative below the "
            "surface), optionally 'x [m]' and 'y [m]'",
        )
    if "z" in found and "depth" in found:
        raise fail(
            where,
            head,
            f"found {found['z'].label!r} and {found['depth'].label!r} both give the "
            "tip's height (z = -depth); keep one",
        )
    if len(table.rows) < 2:
        raise fail(where, "", f"has {len(table.rows)} data row(s); a path needs at least 2")
    values = {role: table.column(col) for role, col in found.items()}
    time = values["time"]
    steps = np.diff(time)
    if not np.all(steps > 0):
        k = int(np.argmax(steps <= 0)) + 1
        raise fail(
            where,
            f"line {table.lines[k]}",
            f"time {plain(time[k])} s does not exceed the previous row's {plain(time[k - 1])} s; "
            "the times of a path must increase",
        )
    position = np.zeros((time.size, 3))
    for axis, role in enumerate(("x", "y", "z")):
        if role in values:
            position[:, axis] = values[role]
    if "depth" in values:
        position[:, 2] = -values["depth"]
    if not np.any(position[:, 2] < 0.0):
        warnings.warn(
            f"{where}: the path never goes below the mud surface (z >= 0 throughout, "
            f"lowest {plain(position[:, 2].min())} m): z is the tip's height, negative in "
            "the mud; name a column 'depth' if it is positive downward",
            PlausibilityWarning,
            stacklevel=2,
        )
    measured = {r: values[r] for r in ("Fx", "Fy", "Fz") if r in values}
    meta = {"measured_force": measured} if measured else {}
    return Trajectory.from_positions(time, position, name=Path(path).name, meta=meta)
