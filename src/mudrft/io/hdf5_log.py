"""Intrusion logs as HDF5 (optional extra ``h5py``): load and save.

Layout: one group per trial (labelled by its ``trial`` attribute, else its name), or the
datasets of a single trial in the root, never both. Each dataset is a 1-D column of real
numbers named like a CSV header (``"time [ms]"``), or by the bare name with a ``unit`` (or
``units``) attribute. Root attributes ``direction``, ``characteristic_length`` [m],
``area`` [m^2] (a key may carry its unit: ``"area [cm^2]"``), ``synthetic`` and ``notes``
play the part of the CSV header comments. Anything else (nested groups, a ``trial``
dataset, file-wide attributes on a group, a broken link) is refused, naming the place.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError, plain, require_extra
from ..units import parse_unit
from ._build import Columns, Locate, assemble, check_roles, file_bytes, resolve_direction
from .atomic import atomic_write
from .columns import LOG_COLUMNS, SI_UNIT, Column, fail, resolve_columns, split_label, to_si
from .dataset import OVERWRITE_OPTION, IntrusionDataset

if TYPE_CHECKING:  # h5py is an optional extra; at run time it is imported on use
    import h5py


Table = tuple[str, Columns, dict[str, str], Locate]

#: Attributes read from the root only: they hold for every trial of the file.
_ROOT_ONLY = ("direction", "characteristic_length", "area", "synthetic")
#: dtype kinds of a column: signed and unsigned integers, floats.
_REAL_KINDS = "iuf"


def _text(value: Any) -> str | None:
    """An attribute as text (h5py returns bytes or str)."""
    if value is None:
        return None
    return value.decode() if isinstance(value, bytes) else str(value)


def _first_line(exc: BaseException) -> str:
    """The first line of an h5py error, at most 200 characters."""
    text = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc  # no quotes
    lines = str(text).strip().splitlines()
    text = lines[0] if lines else type(exc).__name__
    return text if len(text) <= 200 else text[:197] + "..."


def _key_name(key: str) -> str:
    """'area [cm^2]' -> 'area': an attribute or dataset name without its unit, lower case."""
    return split_label(key)[0].lower()


def _listing(names: Iterable[str]) -> str:
    items = [repr(n) for n in names]
    return ", ".join(items[:3] + (["..."] if len(items) > 3 else []))


def _plate_attr(path: str, attrs: dict[str, Any], name: str, quantity: str) -> float | None:
    """A plate size [SI] from the root attribute ``name`` or ``name [unit]``, or None."""
    keys = [k for k in attrs if _key_name(k) == name]
    if not keys:
        return None
    if len(keys) > 1:
        raise fail(path, f"attributes {_listing(keys)}", f"all give the {name}; keep one")
    key = keys[0]
    where = f"attribute {key!r}"
    arr = np.asarray(attrs[key])
    if arr.size != 1:
        raise fail(path, where, f"must be one number, got an array of shape {arr.shape}")
    value = arr.reshape(())[()]
    try:
        unit = split_label(key)[1]
        factor = parse_unit(quantity, unit if unit is not None else SI_UNIT[quantity])
        if arr.dtype.kind not in _REAL_KINDS + "SUO":
            raise ValueError(f"got {value!r}")
        v = float(value if arr.dtype.kind in _REAL_KINDS else str(_text(value))) * factor
    except (MudrftError, ValueError, TypeError) as exc:
        raise fail(path, where, f"must be a number: {exc}") from None
    if not (np.isfinite(v) and v > 0):
        raise fail(path, where, f"must be > 0 and finite, got {plain(v)} (SI)")
    return v


def _members(
    h5py: ModuleType, path: str, group: h5py.Group, prefix: str
) -> dict[str, h5py.HLObject]:
    """The objects of a group by name, links followed; a link that leads nowhere is named."""
    out = {}
    for key in group:
        try:
            out[key] = group[key]
        except (KeyError, OSError, RuntimeError) as exc:
            why = f"cannot be opened ({_first_line(exc)})"
            try:
                link = group.get(key, getlink=True)
            except (KeyError, OSError, RuntimeError):  # pragma: no cover - a damaged file
                link = None
            if isinstance(link, h5py.SoftLink):
                why = f"is a soft link to {link.path!r}, which is not in the file"
            elif isinstance(link, h5py.ExternalLink):
                why = (
                    f"is an external link to {link.filename!r} (object {link.path!r}), which {why}"
                )
            raise fail(path, f"link '{prefix}{key}'", why) from None
    return out


def _unit_attr(path: str, loc: str, attrs: h5py.AttributeManager) -> str | None:
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


def _read_file(
    h5py: ModuleType, path: str, fh: h5py.File, direction: str, columns: Mapping[str, str] | None
) -> list[Table]:
    """The tables of the file: its groups, or its root when it has no group."""
    root = _members(h5py, path, fh, "")
    groups = sorted(k for k, v in root.items() if isinstance(v, h5py.Group))
    datasets = [k for k, v in root.items() if isinstance(v, h5py.Dataset)]
    if not groups:
        if not datasets:
            raise fail(
                path,
                "",
                "holds no datasets and no groups; expected one group per trial, or datasets "
                "such as 'time [s]', 'depth [m]' and 'stress [Pa]' in the root",
            )
        return [("trial", *_read_group(h5py, path, None, root, direction, columns))]
    stray = [k for k in datasets if _key_name(k) in LOG_COLUMNS]
    if stray:
        raise fail(
            path,
            "root group",
            f"holds the datasets {_listing(stray)} beside the group{'s' * (len(groups) > 1)} "
            f"{_listing(groups)}: a file holds one group per trial, or a single trial in the "
            "root, not both; move the root's datasets into a group of their own",
        )
    tables = []
    for g in groups:
        members = _members(h5py, path, root[g], f"{g}/")
        name = _text(root[g].attrs.get("trial")) or g  # the writer's label, else the group's
        group = _read_group(h5py, path, g, members, direction, columns, root[g].attrs)
        tables.append((name, *group))
    return tables


def _read_group(
    h5py: ModuleType,
    path: str,
    gname: str | None,
    members: dict[str, h5py.HLObject],
    direction: str,
    columns: Mapping[str, str] | None,
    attrs: h5py.AttributeManager | None = None,
) -> tuple[Columns, dict[str, str], Locate]:
    """The columns of one trial (a group, or the root) in SI, their labels by role, and
    where a sample stands in the file."""
    prefix = f"{gname}/" if gname else ""
    place = f"group '{gname}'" if gname else "root group"
    for key in attrs if attrs is not None else ():
        if _key_name(key) in _ROOT_ONLY:
            raise fail(
                path,
                f"{place}, attribute {key!r}",
                f"mudrft reads {_key_name(key)!r} from the file's root attributes only, one "
                "value for every trial; set it on the root, or save trials that differ in "
                "it to separate files",
            )
    for key, obj in members.items():
        if isinstance(obj, h5py.Group) and any(_key_name(k) in LOG_COLUMNS for k in obj):
            raise fail(
                path,
                f"group '{prefix}{key}'",
                "is nested; mudrft reads one group per trial, in the root of the file: "
                "move it there",
            )
    names = [k for k, v in members.items() if isinstance(v, h5py.Dataset)]

    def locate(j: int) -> str:
        return f"dataset '{prefix}{names[j]}'"

    units = [_unit_attr(path, locate(j), members[k].attrs) for j, k in enumerate(names)]
    roles = resolve_columns(
        path, names, aliases=LOG_COLUMNS, locate=locate, columns=columns, units=units
    )
    if "trial" in roles:
        raise fail(
            path,
            locate(roles["trial"].position),
            "is not read: in HDF5 the groups are the trials (one group per trial, named by "
            "its label); split the rows into groups",
        )
    check_roles(path, place, roles, names, direction=direction)
    out = {
        role: _column_values(path, members[names[col.position]], col, locate(col.position))
        for role, col in roles.items()
    }
    n = out["time"].size
    for role, arr in out.items():
        if arr.size != n:
            raise fail(
                path,
                place,
                f"{locate(roles[role].position)} has {arr.size} values but "
                f"{locate(roles['time'].position)} has {n}",
            )

    def sample(i: int | None, role: str | None) -> str:
        at = place if role is None else locate(roles[role].position)
        return at if i is None else f"{at}, row {i}"

    return out, {role: col.label for role, col in roles.items()}, sample


def _column_values(path: str, dataset: h5py.Dataset, col: Column, loc: str) -> NDArray[np.float64]:
    """One recognised dataset in SI, checked: 1-D, real, finite."""
    shape = dataset.shape
    if shape is None or len(shape) != 1:
        raise fail(
            path,
            loc,
            f"must be 1-D (one value per sample), got shape {shape}; store each column as "
            "a 1-D dataset of its own",
        )
    if dataset.dtype.kind not in _REAL_KINDS:
        raise fail(
            path, loc, f"must hold real numbers (integers or floats), got dtype {dataset.dtype}"
        )
    try:
        raw = np.asarray(dataset[()], dtype=float)
    except (OSError, TypeError, ValueError) as exc:
        raise fail(path, loc, f"cannot be read ({_first_line(exc)})") from None
    return to_si(path, raw, col, locate_row=lambda i: f"{loc}, row {i}")


def load_intrusion_hdf5(
    path: str | os.PathLike[str],
    *,
    area: float | None = None,
    characteristic_length: float | None = None,
    direction: str | None = None,
    columns: Mapping[str, str] | None = None,
) -> IntrusionDataset:
    """Load an intrusion log from HDF5 (needs ``h5py``; layout in :mod:`mudrft.io.hdf5_log`).

    Parameters
    ----------
    path : str or path-like
        The HDF5 file (opened read-only).
    area, characteristic_length, direction, columns : optional, keyword-only
        As :func:`~mudrft.io.load_intrusion_csv` (plate area [m^2], length [m]); they
        override the root attributes of the same names.

    Raises
    ------
    MudrftError
        Naming the file and the place, for a missing or unreadable file or any content
        the layout does not allow.
    """
    h5py = require_extra("h5py", needed_for="load_intrusion_hdf5")
    p = Path(os.fspath(path))
    where = str(p)
    file_bytes(p, "an HDF5 file", max_bytes=0)
    try:
        fh = h5py.File(p, "r")
    except OSError as exc:
        raise fail(where, "", f"is not a readable HDF5 file ({_first_line(exc)})") from None
    with fh:
        attrs = {}
        for k in fh.attrs:
            try:
                attrs[k] = fh.attrs[k]
            except (OSError, TypeError, ValueError) as exc:
                why = f"cannot be read ({_first_line(exc)})"
                raise fail(where, f"attribute {k!r}", why) from None
        meta_len = _plate_attr(where, attrs, "characteristic_length", "length")
        meta_area = _plate_attr(where, attrs, "area", "area")
        d = resolve_direction(
            where, direction, _text(attrs.get("direction")), "attribute 'direction'"
        )
        tables = _read_file(h5py, where, fh, d, columns)
    parts = [(cols, [name] * cols["time"].size, sample) for name, cols, _, sample in tables]
    notes = [str(_text(attrs["notes"]))] if "notes" in attrs else []
    notes += [f"synthetic: {_text(attrs['synthetic'])}"] if "synthetic" in attrs else []
    return assemble(
        where,
        parts,
        tables[0][2],
        direction=d,
        notes=notes,
        meta={},
        meta_len=meta_len,
        meta_area=meta_area,
        characteristic_length=characteristic_length,
        area=area,
    )


def save_intrusion_hdf5(
    dataset: IntrusionDataset, path: str | os.PathLike[str], *, overwrite: bool = False
) -> Path:
    """Write a dataset to HDF5 in SI units, one group per trial, atomically.

    Parameters
    ----------
    dataset : IntrusionDataset
        The data.
    path, overwrite
        As :meth:`IntrusionDataset.to_csv`: the output file; replace an existing one.

    Returns
    -------
    Path
        The file written.
    """
    h5py = require_extra("h5py", needed_for="save_intrusion_hdf5")
    if not isinstance(dataset, IntrusionDataset):
        raise MudrftError(f"dataset must be an IntrusionDataset, got {type(dataset).__name__}")
    length = dataset._one_length("HDF5")

    def write(tmp: Path) -> None:
        with h5py.File(tmp, "w") as fh:
            fh.attrs["direction"] = dataset.direction
            fh.attrs["characteristic_length"] = length
            if dataset.notes:
                fh.attrs["notes"] = "\n".join(dataset.notes)
            for i, tr in enumerate(dataset.trials):
                g = fh.create_group(f"{i:03d}_{tr.name}".replace("/", "_"))  # in order, no '/'
                g.attrs["trial"] = tr.name  # the label as it is, read back by the loader
                g.create_dataset("time [s]", data=tr.time)
                g.create_dataset("depth [m]", data=tr.depth)
                g.create_dataset("stress [Pa]", data=tr.stress)

    return atomic_write(path, write, overwrite=overwrite, option=OVERWRITE_OPTION)
