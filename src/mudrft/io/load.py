"""Load one or several intrusion logs, CSV or HDF5 by suffix, into one dataset."""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from .._validation import MudrftError
from .csv_log import load_intrusion_csv
from .dataset import IntrusionDataset
from .hdf5_log import load_intrusion_hdf5

__all__ = ["HDF5_SUFFIXES", "load_dataset"]

#: File suffixes read as HDF5; every other file is read as CSV.
HDF5_SUFFIXES = (".h5", ".hdf5", ".hdf")


def load_dataset(
    path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    *,
    area: float | None = None,
    characteristic_length: float | None = None,
    direction: str | None = None,
) -> IntrusionDataset:
    """Load one or several logs (CSV, or HDF5 by suffix ``.h5``/``.hdf5``) into one dataset.

    Parameters
    ----------
    path : path or sequence of paths
        Files to read; several files are merged (same direction).
    area : float, optional, keyword-only
        Plate area [m^2], needed when a file logs a force.
    characteristic_length : float, optional, keyword-only
        Plate characteristic length [m].
    direction : {"vertical", "horizontal"}, optional, keyword-only
        Loading direction, overriding the files'.

    Returns
    -------
    IntrusionDataset
    """
    if isinstance(path, (str, os.PathLike)):
        paths = [path]
    else:
        items: list[Any] = list(path) if isinstance(path, Iterable) else [None]
        if not all(isinstance(q, (str, os.PathLike)) for q in items):
            raise MudrftError(
                f"path must be a file path or a sequence of file paths, got {type(path).__name__}"
            )
        paths = items
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
    sets = []
    for pth in paths:
        hdf5 = Path(os.fspath(pth)).suffix.lower() in HDF5_SUFFIXES
        loader = load_intrusion_hdf5 if hdf5 else load_intrusion_csv
        sets.append(
            loader(pth, area=area, characteristic_length=characteristic_length, direction=direction)
        )
    return sets[0].merge(*sets[1:]) if len(sets) > 1 else sets[0]
