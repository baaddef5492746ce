"""Logs and foot paths as text tables: :func:`read_table` (the one CSV reader),
:func:`load_intrusion_csv`, :func:`save_intrusion_csv`, :func:`load_dataset` (CSV or HDF5, by
suffix) and :func:`load_path_csv` (a foot tip's path, as a :class:`~mudrft.Trajectory`).

``#`` lines are notes, ``# key: value`` notes metadata; the header's fields are separated
by commas, tabs or semicolons, whichever it holds most of."""

from __future__ import annotations

import csv
import os
import re
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._typing import PathLike
from .._validation import MudrftError, PlausibilityWarning, plain
from ..trajectories import Trajectory
from ..units import parse_unit
from ._build import assemble, check_roles, file_bytes, resolve_direction
from .columns import LOG_COLUMNS, SI_UNIT, Column, fail, resolve_columns, split_label, to_si
from .dataset import IntrusionDataset
from .hdf5_log import load_intrusion_hdf5

#: File suffixes read as HDF5 by :func:`load_dataset`; every other file is read as CSV.
HDF5_SUFFIXES = (".h5", ".hdf5", ".hdf")
#: A foot path's column names (lower case) -> role (:func:`load_path_csv`).
PATH_COLUMNS = {
    **dict.fromkeys(("time", "t"), "time"),
    **{k: k for k in ("x", "y", "z", "depth")},
    **{f"f{a}": f"F{a}" for a in "xyz"},
}
_MAX_BYTES = 200 * 1024 * 1024
_DELIMITERS = {",": "comma", "\t": "tab", ";": "semicolon"}
#: Metadata keys that hold for the whole file: given twice, they must agree.
_PLATE_KEYS = {"characteristic_length": "length", "area": "area"}


@dataclass
class Table:
    """A text table as read: notes, metadata, header and rows (cells as text), with lines."""

    path: str
    notes: list[str] = field(default_factory=list)
    meta: dict[str, Any] = field(default_factory=dict)
    #: ``key -> (line, value)`` of ``direction`` and the plate's size (SI).
    fixed: dict[str, tuple[int, Any]] = field(default_factory=dict)
    header: list[str] = field(default_factory=list)
    header_line: int = 0
    delimiter: str = ","
    rows: list[list[str]] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)

    def column(self, col: Column) -> NDArray[np.float64]:
        """A column's values in SI; an error names the line and column of a bad cell."""

        def locate(i: int) -> str:
            return f"line {self.lines[i]}, column {col.position + 1} ({col.label!r})"

        cells = [row[col.position].strip() for row in self.rows]
        if self.delimiter != "," and any("," in c for c in cells):  # a decimal comma
            cells = [c.replace(",", ".") for c in cells]
        try:
            raw = np.array(cells, dtype=float)
        except ValueError:  # name the first cell that is no number
            raw = np.empty(len(cells))
            for i, c in enumerate(cells):
                try:
                    raw[i] = float(c)
                except ValueError:
                    why = f"cannot read {c[:40]!r} as a number"
                    why = why if c else "empty cell, expected a number"
                    raise fail(self.path, locate(i), why) from None
        return to_si(self.path, raw, col, locate_row=locate)


def _text(p: Path) -> str:
    """The text of a file; precise errors for a missing, binary or non-UTF-8 one."""
    where = str(p)
    raw = file_bytes(p, "a CSV file", max_bytes=_MAX_BYTES)
    if b"\x00" in raw:
        line = raw[: raw.index(b"\x00")].count(b"\n") + 1
        raise fail(
            where,
            f"line {line}",
            "contains a NUL byte; this is not a text CSV file (binary or HDF5? use "
            "load_intrusion_hdf5)",
        )
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise fail(
            where,
            f"line {line}",
            f"is not valid UTF-8 text (byte {exc.start}: {raw[exc.start : exc.start + 1]!r})",
        ) from None


def _metadata(table: Table, lineno: int, comment: str) -> None:
    """A ``#`` line: a note, and metadata if it reads ``# key: value``."""
    text = comment.lstrip("#").strip()
    table.notes.append(text)
    key, sep, value = (part.strip() for part in text.partition(":"))
    if not sep or not key or len(key) > 60:
        return
    name, unit = split_label(key)
    name = name.lower()
    if name not in (*_PLATE_KEYS, "direction"):
        table.meta[key] = value
        return
    parsed: Any = value
    if name in _PLATE_KEYS:
        quantity = _PLATE_KEYS[name]
        try:
            parsed = float(value) * parse_unit(quantity, unit or SI_UNIT[quantity])
        except (ValueError, MudrftError) as exc:
            raise fail(table.path, f"line {lineno}", f"metadata {key!r}: {exc}") from None
        if not 0 < parsed < float("inf"):
            raise fail(table.path, f"line {lineno}", f"metadata {key!r} must be > 0, got {value!r}")
    first = table.fixed.setdefault(name, (lineno, parsed))
    if first[1] != parsed:
        raise fail(
            table.path,
            f"line {lineno}",
            f"{name} is given again, as {value!r}, after line {first[0]} gave {first[1]!r}; "
            "keep one",
        )


def read_table(path: str | os.PathLike[str]) -> Table:
    """Read a text table: notes and metadata, the header, the rows (cells as text); a
    :class:`MudrftError` names the file and the line of any problem."""
    p = Path(os.fspath(path))
    table = Table(str(p))
    for lineno, line in enumerate(re.split(r"\r\n|\r|\n", _text(p)), start=1):
        if not line.strip():
            continue
        if line.lstrip().startswith("#"):
            _metadata(table, lineno, line.strip())
            continue
        if not table.header:  # the header sets the delimiter
            fields = {d: len(next(csv.reader([line], delimiter=d))) for d in _DELIMITERS}
            table.delimiter = max(_DELIMITERS, key=fields.__getitem__)  # ties: the comma
        try:
            record = next(
                csv.reader([line], delimiter=table.delimiter, skipinitialspace=True, strict=True)
            )
        except csv.Error as exc:
            raise fail(table.path, f"line {lineno}", f"malformed CSV ({exc})") from None
        if not table.header:
            table.header, table.header_line = record, lineno
        elif len(record) != len(table.header):
            raise fail(
                table.path,
                f"line {lineno}",
                f"expected {len(table.header)} {_DELIMITERS[table.delimiter]}-separated fields "
                f"as in the header (line {table.header_line}), got {len(record)}",
            )
        else:
            table.rows.append(record)
            table.lines.append(lineno)
    if not table.header:
        raise fail(
            table.path,
            "",
            "has no header line; expected a line such as 'time [s],depth [m],stress [Pa]'",
        )
    return table


def load_intrusion_csv(
    path: str | os.PathLike[str],
    *,
    area: float | None = None,
    characteristic_length: float | None = None,
    direction: str | None = None,
    columns: Mapping[str, str] | None = None,
) -> IntrusionDataset:
    """Load an intrusion log from a text table (CSV, or tab- or semicolon-separated), in SI.

    Parameters
    ----------
    path : str or path-like
        The file (never modified).
    area : float, optional, keyword-only
        Plate area [m^2], needed for a force log; overrides a ``# area [m^2]: ...`` line.
    characteristic_length : float, optional, keyword-only
        Plate length :math:`L_c` [m]; overrides a ``# characteristic_length [m]: ...``
        line; default 0.05 m (D1).
    direction : {"vertical", "horizontal"}, optional, keyword-only
        Loading direction; overrides a ``# direction: ...`` line; default vertical.
    columns : mapping, optional, keyword-only
        Role (``time``, ``depth``, ``stress``, ``force``, ``trial``) -> the column's name as
        written, for names mudrft does not know (``{"depth": "Pos (mm)"}``).

    Returns
    -------
    IntrusionDataset
        One :class:`Trial` per value of the ``trial`` column (in order of appearance), or
        a single trial.

    Raises
    ------
    MudrftError
        For any problem with the file, naming the file, the line and the column.

    Examples
    --------
    >>> import tempfile, os
    >>> text = "Time (ms)\\tDepth (mm)\\tForce (N)\\n0\\t0\\t0\\n500\\t10\\t2.5\\n1000\\t20\\t4.0\\n"
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "log.txt")
    ...     _ = open(p, "w").write(text)
    ...     ds = load_intrusion_csv(p, area=0.0025)
    >>> ds[0].time.tolist(), ds[0].depth.tolist(), ds[0].stress.tolist()
    ([0.0, 0.5, 1.0], [0.0, 0.01, 0.02], [0.0, 1000.0, 1600.0])
    """
    table = read_table(path)
    where, header = table.path, table.header
    head = f"line {table.header_line}"
    roles = resolve_columns(
        where,
        header,
        aliases=LOG_COLUMNS,
        locate=lambda j: f"{head}, column {j + 1}",
        columns=columns,
    )
    line = table.fixed.get("direction", (0, None))
    d = resolve_direction(where, direction, line[1], f"line {line[0]}")
    check_roles(where, head, roles, header, direction=d)
    if not table.rows:
        raise fail(where, "", "has a header but no data rows")
    values = {r: table.column(c) for r, c in roles.items() if r != "trial"}
    labels = None
    if "trial" in roles:
        labels = [row[roles["trial"].position].strip() for row in table.rows]
        if "" in labels:
            i = labels.index("")
            spot = f"line {table.lines[i]}, column {roles['trial'].position + 1} ('trial')"
            raise fail(where, spot, "empty trial label")

    def sample(i: int | None, role: str | None) -> str:
        col = "" if role is None else f"column {roles[role].label!r}"
        return col if i is None else f"line {table.lines[i]}" + (f", {col}" if col else "")

    used = {c.position for c in roles.values()}
    return assemble(
        where,
        [(values, labels, sample)],
        {r: c.label for r, c in roles.items()},
        direction=d,
        notes=table.notes,
        meta={
            **table.meta,
            "ignored_columns": [h.strip() for j, h in enumerate(header) if j not in used],
        },
        meta_len=table.fixed.get("characteristic_length", (0, None))[1],
        meta_area=table.fixed.get("area", (0, None))[1],
        characteristic_length=characteristic_length,
        area=area,
    )


def load_dataset(
    path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    *,
    area: float | None = None,
    characteristic_length: float | None = None,
    direction: str | None = None,
    columns: Mapping[str, str] | None = None,
) -> IntrusionDataset:
    """Load one or several logs (text tables, or HDF5 by suffix ``.h5``/``.hdf5``) into one
    dataset; several files are merged (same direction). The options are those of
    :func:`load_intrusion_csv`."""
    if isinstance(path, (str, os.PathLike)):
        paths: list[Any] = [path]
    else:
        paths = list(path) if isinstance(path, Iterable) else [None]
        if not all(isinstance(q, (str, os.PathLike)) for q in paths):
            raise MudrftError(
                f"path must be a file path or a sequence of file paths, got {type(path).__name__}"
            )
    if not paths:
        raise MudrftError("path must name at least one file, got an empty list")
    seen: dict[Path, str] = {}
    for pth in paths:  # the same file twice would count its data twice in a fit
        key = Path(os.path.realpath(os.fspath(pth)))
        if key in seen:
            raise MudrftError(
                f"path (CLI: data) names the same file twice, {seen[key]!r} and "
                f"{os.fspath(pth)!r}: its samples would count twice in a fit"
            )
        seen[key] = os.fspath(pth)
    options = {"area": area, "characteristic_length": characteristic_length}
    sets = [
        (load_intrusion_hdf5 if Path(p).suffix.lower() in HDF5_SUFFIXES else load_intrusion_csv)(
            p, direction=direction, columns=columns, **options
        )
        for p in paths
    ]
    return sets[0].merge(*sets[1:]) if len(sets) > 1 else sets[0]


def save_intrusion_csv(
    dataset: IntrusionDataset, path: str | os.PathLike[str], *, overwrite: bool = False
) -> Path:
    """Write a dataset as CSV in SI units, atomically (:meth:`IntrusionDataset.to_csv`).

    Parameters
    ----------
    dataset : IntrusionDataset
        The data.
    path, overwrite
        As :meth:`IntrusionDataset.to_csv`: the output file; replace an existing one.
    """
    if not isinstance(dataset, IntrusionDataset):
        raise MudrftError(f"dataset must be an IntrusionDataset, got {type(dataset).__name__}")
    return dataset.to_csv(path, overwrite=overwrite)


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
