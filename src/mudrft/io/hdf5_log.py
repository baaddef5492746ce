"""Intrusion logs as HDF5 (optional extra ``h5py``): load and save.

Layout: one group per trial (group name = trial label, in sorted order), or the datasets
directly in the root for a single trial. Each 1-D dataset is a column named like a CSV
header (``"time [ms]"``), or by the bare name with its unit in a ``unit`` (or ``units``)
attribute; names and units are resolved by :mod:`.columns` as for a CSV log. Root
attributes ``direction``, ``characteristic_length`` [m], ``area`` [m^2] and
``synthetic`` / ``notes`` play the part of the CSV header comments.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ._build import build_trials, check_plausible, resolve_direction, resolve_plate
from .atomic import atomic_write
from .columns import Column, check_roles, fail, resolve_columns, to_si
from .dataset import OVERWRITE_OPTION, IntrusionDataset, Trial

__all__ = ["load_intrusion_hdf5", "save_intrusion_hdf5"]

Columns = dict[str, NDArray[np.float64]]


def _require_h5py() -> Any:
    try:
        import h5py
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("HDF5 logs need h5py: pip install 'mudrft[hdf5]'") from exc
    return h5py


def _text(value: Any) -> str | None:
    """An attribute as text (h5py returns bytes or str)."""
    if value is None:
        return None
    return value.decode() if isinstance(value, bytes) else str(value)


def _attr_float(path: str, attrs: dict[str, Any], key: str) -> float | None:
    """A positive number attribute [SI], or None if absent."""
    if key not in attrs:
        return None
    try:
        v = float(np.asarray(attrs[key]).ravel()[0])
    except (TypeError, ValueError, IndexError):
        raise fail(path, f"attribute {key!r}", f"must be a number, got {attrs[key]!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise fail(path, f"attribute {key!r}", f"must be > 0, got {v!r}")
    return v


def _notes(attrs: dict[str, Any]) -> list[str]:
    notes = []
    for key in ("notes", "synthetic"):
        if key in attrs:
            v = _text(attrs[key])
            notes.append(f"{key}: {v}" if key == "synthetic" else str(v))
    return notes


def _unit_attr(path: str, loc: str, attrs: Any) -> str | None:
    """A dataset's ``unit`` (or ``units``) attribute; both present must agree."""
    found = {k: str(_text(attrs[k])).strip() for k in ("unit", "units") if k in attrs}
    if len(found) == 2 and found["unit"] != found["units"]:
        raise fail(
            path,
            loc,
            f"its 'unit' attribute {found['unit']!r} and its 'units' attribute "
            f"{found['units']!r} disagree; keep one",
        )
    return found.get("unit", found.get("units"))


def _read_group(
    h5py: Any, path: str, gname: str, group: Any, direction: str
) -> tuple[Columns, dict[str, str]]:
    """The columns of one trial's group, in SI, checked, and their labels by role."""
    names = [k for k in group if isinstance(group[k], h5py.Dataset)]

    def locate(j: int) -> str:
        return f"dataset '{gname}/{names[j]}'"

    units = [_unit_attr(path, locate(j), group[k].attrs) for j, k in enumerate(names)]

    columns = resolve_columns(
        path, names, locate=locate, units=units, unit_hint=" (or set a 'unit' attribute)"
    )
    check_roles(path, f"group '{gname}'", columns, names, direction=direction)
    out = {
        role: _column_values(path, group[names[col.position]], col, locate(col.position))
        for role, col in columns.roles.items()
    }
    n = out["time"].size
    for role, arr in out.items():
        if arr.size != n:
            raise fail(path, f"group '{gname}'", f"{role} has {arr.size} values but time has {n}")
    return out, {role: col.label for role, col in columns.roles.items()}


def _column_values(path: str, dataset: Any, col: Column, loc: str) -> NDArray[np.float64]:
    """One recognised dataset in SI, checked."""
    try:
        raw = np.asarray(dataset[()], dtype=float).ravel()
    except (TypeError, ValueError) as exc:
        raise fail(path, loc, f"is not numeric ({exc})") from None

    def locate_row(i: int) -> str:
        return f"{loc}, row {i}"

    return to_si(path, raw, col, locate_row=locate_row)


def load_intrusion_hdf5(
    path: str | os.PathLike[str],
    *,
    area: float | None = None,
    characteristic_length: float | None = None,
    direction: str | None = None,
) -> IntrusionDataset:
    """Load an intrusion log from HDF5 (needs the optional ``h5py``).

    See the module docstring for the layout.

    Parameters
    ----------
    path : str or path-like
        The HDF5 file (opened read-only).
    area : float, optional, keyword-only
        Plate area [m^2], needed when the file logs a force; overrides the ``area``
        attribute.
    characteristic_length : float, optional, keyword-only
        Plate characteristic length [m]; overrides the ``characteristic_length``
        attribute; default 0.05 m (decision D1).
    direction : {"vertical", "horizontal"}, optional, keyword-only
        Loading direction; overrides the ``direction`` attribute; default vertical.

    Returns
    -------
    IntrusionDataset
    """
    h5py = _require_h5py()
    p = Path(os.fspath(path))
    where = str(p)
    if not p.exists():
        raise fail(where, "", "no such file")
    try:
        fh = h5py.File(p, "r")
    except OSError as exc:
        raise fail(where, "", f"is not a readable HDF5 file ({exc})") from None
    with fh:
        attrs = {k: fh.attrs[k] for k in fh.attrs}
        meta_len = _attr_float(where, attrs, "characteristic_length")
        meta_area = _attr_float(where, attrs, "area")
        d = resolve_direction(
            where, direction, _text(attrs.get("direction")), "attribute 'direction'"
        )
        groups = [(k, fh[k]) for k in sorted(fh.keys()) if isinstance(fh[k], h5py.Group)]
        tables = [(g, _read_group(h5py, where, g, obj, d)) for g, obj in groups or [("trial", fh)]]
    L, A, lsrc = resolve_plate(
        where,
        meta_len=meta_len,
        meta_area=meta_area,
        characteristic_length=characteristic_length,
        area=area,
        need_area=any("stress" not in cols for _, (cols, _) in tables),
    )
    trials: list[Trial] = []
    found = []
    for gname, (cols, names) in tables:
        n = cols["time"].size
        group = build_trials(where, cols, [gname] * n, np.arange(n), L=L, A=A)
        trials.extend(group)
        found += [(names, t.depth, t.stress) for t in group]
    check_plausible(where, found, area=A)
    meta: dict[str, Any] = {"characteristic_length_source": lsrc}
    if A is not None:
        meta["area"] = A
    notes = tuple(_notes(attrs))
    return IntrusionDataset(tuple(trials), direction=d, source=where, notes=notes, meta=meta)


def _write_hdf5(h5py: Any, dataset: IntrusionDataset, length: float, path: Path) -> None:
    with h5py.File(path, "w") as fh:
        fh.attrs["direction"] = dataset.direction
        fh.attrs["characteristic_length"] = length
        if dataset.notes:
            fh.attrs["notes"] = "\n".join(dataset.notes)
        for i, tr in enumerate(dataset.trials):
            g = fh.create_group(f"{i:03d}_{tr.name}".replace("/", "_"))
            g.create_dataset("time [s]", data=tr.time)
            g.create_dataset("depth [m]", data=tr.depth)
            g.create_dataset("stress [Pa]", data=tr.stress)


def save_intrusion_hdf5(
    dataset: IntrusionDataset, path: str | os.PathLike[str], *, overwrite: bool = False
) -> Path:
    """Write a dataset to HDF5 in SI units, one group per trial (read by load_intrusion_hdf5).

    Parameters
    ----------
    dataset : IntrusionDataset
        The data.
    path : str or path-like
        Output file; written atomically (:func:`~mudrft.io.atomic_write`).
    overwrite : bool, keyword-only
        Replace an existing file (default: refuse).

    Returns
    -------
    Path
        The file written.
    """
    h5py = _require_h5py()
    if not isinstance(dataset, IntrusionDataset):
        raise MudrftError(f"dataset must be an IntrusionDataset, got {type(dataset).__name__}")
    lengths = {tr.characteristic_length for tr in dataset.trials}
    if len(lengths) != 1:
        raise MudrftError(
            f"save_intrusion_hdf5 needs one characteristic length, got {sorted(lengths)}"
        )
    length = lengths.pop()
    return atomic_write(
        path,
        lambda tmp: _write_hdf5(h5py, dataset, length, tmp),
        overwrite=overwrite,
        option=OVERWRITE_OPTION,
    )
