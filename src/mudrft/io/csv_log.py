"""Intrusion logs as CSV: :func:`load_intrusion_csv` and :func:`save_intrusion_csv`.

The file is read once as UTF-8 text (never written); ``#`` lines are notes, and
``# key: value`` notes are metadata (``direction``, ``characteristic_length [m]``,
``area [m^2]``, ...). The header names the columns with their units, resolved by
:mod:`.columns` like the datasets of an HDF5 log.
"""

from __future__ import annotations

import csv
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ._build import build_trials, check_plausible, resolve_direction, resolve_plate
from .columns import (
    Column,
    check_roles,
    fail,
    parse_header_name,
    parse_number,
    quantity_value,
    resolve_columns,
    to_si,
)
from .dataset import IntrusionDataset

__all__ = ["load_intrusion_csv", "save_intrusion_csv"]

_MAX_BYTES = 200 * 1024 * 1024


def _read_bytes(path: Path) -> bytes:
    where = str(path)
    try:
        if path.is_dir():
            raise fail(where, "", "is a directory, expected a CSV file")
        size = path.stat().st_size
        if size > _MAX_BYTES:
            raise fail(
                where,
                "",
                f"is {size} bytes; intrusion logs above {_MAX_BYTES} bytes are not supported "
                "as CSV (use HDF5)",
            )
        with open(path, "rb") as fh:  # read only: the loader never writes the input
            return fh.read()
    except FileNotFoundError as exc:
        raise fail(where, "", "no such file") from exc
    except PermissionError as exc:
        raise fail(where, "", "permission denied (cannot read the file)") from exc
    except IsADirectoryError as exc:
        raise fail(where, "", "is a directory, expected a CSV file") from exc
    except OSError as exc:
        raise fail(where, "", f"cannot be read ({exc.strerror or exc})") from exc


def _read_text(path: Path) -> str:
    """The text of a CSV file; precise errors for a missing, binary or non-UTF-8 file."""
    where = str(path)
    raw = _read_bytes(path)
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
        ) from exc


@dataclass
class _Table:
    """The parts of a CSV log: notes, metadata, header and data rows (as text)."""

    where: str
    notes: list[str] = field(default_factory=list)
    meta: dict[str, Any] = field(default_factory=dict)
    meta_len: float | None = None
    meta_area: float | None = None
    direction: str | None = None
    direction_line: str = ""
    header: list[str] | None = None
    header_line: int = 0
    rows: list[list[str]] = field(default_factory=list)
    row_lines: list[int] = field(default_factory=list)
    #: The first line and value of each metadata key that must not be given twice.
    meta_lines: dict[str, tuple[int, str | float]] = field(default_factory=dict)

    def add_comment(self, lineno: int, comment: str) -> None:
        """A ``#`` line: a note, and metadata if it reads ``# key: value``."""
        self.notes.append(comment.lstrip("#").strip())
        key, sep, value = comment.lstrip("#").strip().partition(":")
        key, value = key.strip(), value.strip()
        if not sep or not key or len(key) > 60:
            return
        try:
            name = parse_header_name(key)[0].lower()
        except ValueError:
            name = key
        where = f"line {lineno}"
        if name in ("characteristic_length", "area", "direction"):
            parsed: Any = value
            if name != "direction":
                kind = "length" if name == "characteristic_length" else "area"
                parsed = quantity_value(self.where, where, key, value, kind)
            first = self.meta_lines.setdefault(name, (lineno, parsed))
            if first[1] != parsed:  # the last one used to win, silently
                raise fail(
                    self.where,
                    where,
                    f"{name} is given again, as {value!r}, after line {first[0]} gave "
                    f"{first[1]!r}; keep one",
                )
        if name == "characteristic_length":
            self.meta_len = parsed
        elif name == "area":
            self.meta_area = parsed
        elif name == "direction":
            self.direction, self.direction_line = value, where
        else:
            self.meta[key] = value

    def add_record(self, lineno: int, line: str) -> None:
        """A line of data, or the header if none was read yet."""
        try:
            rec = next(csv.reader([line], skipinitialspace=True, strict=True))
        except csv.Error as exc:
            raise fail(self.where, f"line {lineno}", f"malformed CSV ({exc})") from None
        if self.header is None:
            for sep, what in ((";", "semicolons"), ("\t", "tabs")):
                if len(rec) == 1 and sep in line:
                    raise fail(
                        self.where,
                        f"line {lineno}",
                        f"the header's fields are separated by {what}; mudrft reads "
                        "comma-separated files (save as CSV with ',' as the separator)",
                    )
            self.header, self.header_line = rec, lineno
            return
        if len(rec) != len(self.header):
            raise fail(
                self.where,
                f"line {lineno}",
                f"expected {len(self.header)} comma-separated fields as in the header "
                f"(line {self.header_line}), got {len(rec)}",
            )
        self.rows.append(rec)
        self.row_lines.append(lineno)


def _parse(where: str, text: str) -> _Table:
    table = _Table(where)
    for lineno, line in enumerate(re.split(r"\r\n|\r|\n", text), start=1):  # \r alone too
        if not line.strip():
            continue
        if line.lstrip().startswith("#"):
            table.add_comment(lineno, line.strip())
        else:
            table.add_record(lineno, line)
    if table.header is None:
        raise fail(
            where,
            "",
            "has no header line; expected a line such as 'time [s],depth [m],stress [Pa]'",
        )
    return table


def _column_values(table: _Table, col: Column) -> NDArray[np.float64]:
    """One recognised column in SI, with the line and column of any bad cell."""

    def locate(i: int) -> str:
        return f"line {table.row_lines[i]}, column {col.position + 1} ({col.label!r})"

    raw = np.empty(len(table.rows))
    for i, rec in enumerate(table.rows):
        try:
            raw[i] = parse_number(rec[col.position])
        except ValueError as exc:
            raise fail(table.where, locate(i), str(exc)) from None
    return to_si(table.where, raw, col, locate_row=locate)


def _labels(table: _Table, j: int | None) -> list[str] | None:
    """The trial label of each row, if the log has a ``trial`` column."""
    if j is None:
        return None
    labels = []
    for i, rec in enumerate(table.rows):
        label = rec[j].strip()
        if not label:
            where = f"line {table.row_lines[i]}, column {j + 1} ('trial')"
            raise fail(table.where, where, "empty trial label")
        labels.append(label)
    return labels


def load_intrusion_csv(
    path: str | os.PathLike[str],
    *,
    area: float | None = None,
    characteristic_length: float | None = None,
    direction: str | None = None,
) -> IntrusionDataset:
    """Load an intrusion log from a CSV file, converting every column to SI.

    Parameters
    ----------
    path : str or path-like
        The CSV file (read only; it is never modified).
    area : float, optional, keyword-only
        Plate area [m^2], needed when the file logs a force instead of a stress.
        Overrides a ``# area [m^2]: ...`` header line.
    characteristic_length : float, optional, keyword-only
        Plate characteristic length :math:`L_c` [m]; overrides a
        ``# characteristic_length [m]: ...`` header line; default 0.05 m (decision D1).
    direction : {"vertical", "horizontal"}, optional, keyword-only
        Loading direction; overrides a ``# direction: ...`` header line; default vertical.

    Returns
    -------
    IntrusionDataset
        One :class:`Trial` per distinct value of the ``trial`` column (in order of
        first appearance), or a single trial if there is no such column.

    Raises
    ------
    MudrftError
        For any problem with the file, naming the file, the line and the column.

    Examples
    --------
    >>> import tempfile, os
    >>> text = "time [ms],depth [mm],Fz [N]\\n0,0,0\\n500,10,2.5\\n1000,20,4.0\\n"
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "log.csv")
    ...     _ = open(p, "w").write(text)
    ...     ds = load_intrusion_csv(p, area=0.0025)
    >>> ds[0].time.tolist(), ds[0].depth.tolist(), ds[0].stress.tolist()
    ([0.0, 0.5, 1.0], [0.0, 0.01, 0.02], [0.0, 1000.0, 1600.0])
    """
    p = Path(os.fspath(path))
    where = str(p)
    table = _parse(where, _read_text(p))
    header = table.header
    assert header is not None

    def locate(j: int) -> str:
        return f"line {table.header_line}, column {j + 1}"

    columns = resolve_columns(where, header, locate=locate)
    d = resolve_direction(where, direction, table.direction, table.direction_line)
    has_stress = check_roles(where, f"line {table.header_line}", columns, header, direction=d)
    if not table.rows:
        raise fail(where, "", "has a header but no data rows")
    values = {role: _column_values(table, col) for role, col in columns.roles.items()}
    labels = _labels(table, columns.trial)
    L, A, lsrc = resolve_plate(
        where,
        meta_len=table.meta_len,
        meta_area=table.meta_area,
        characteristic_length=characteristic_length,
        area=area,
        need_area=not has_stress,
    )

    def sample(i: int | None, role: str | None) -> str:
        col = "" if role is None else f"column {columns.roles[role].label!r}"
        return col if i is None else f"line {table.row_lines[i]}" + (f", {col}" if col else "")

    trials = build_trials(where, values, labels, sample, L=L, A=A)
    names = {role: col.label for role, col in columns.roles.items()}
    check_plausible(where, [(names, t.depth, t.stress, t.time) for t in trials], area=A)
    meta = {**table.meta, "characteristic_length_source": lsrc, "ignored_columns": columns.ignored}
    if A is not None:
        meta["area"] = A
    return IntrusionDataset(trials, direction=d, source=where, notes=tuple(table.notes), meta=meta)


def save_intrusion_csv(
    dataset: IntrusionDataset, path: str | os.PathLike[str], *, overwrite: bool = False
) -> Path:
    """Write a dataset as CSV in SI units, with its notes and metadata as ``#`` comments.

    Parameters
    ----------
    dataset : IntrusionDataset
        The data.
    path : str or path-like
        Output file; written atomically (:func:`~mudrft.io.atomic_write`).
    overwrite : bool, keyword-only
        Replace an existing file (default: refuse, so a user's data are never lost).

    Returns
    -------
    Path
        The file written.
    """
    if not isinstance(dataset, IntrusionDataset):
        raise MudrftError(f"dataset must be an IntrusionDataset, got {type(dataset).__name__}")
    return dataset.to_csv(path, overwrite=overwrite)
