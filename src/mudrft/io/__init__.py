"""Intrusion logs and foot paths: read them from CSV or HDF5 in SI, write them atomically.

A log holds one or more trials (a ``trial`` column tells them apart) with the columns
``time``, ``depth`` and ``stress`` or a force, each named with its unit (``time [ms]``);
the format is described in docs/guide/calibrate.md. Every problem in a file raises
:class:`~mudrft._validation.MudrftError` naming the file, the line and the column.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .atomic import atomic_write, json_text
    from .csv_log import load_dataset, load_intrusion_csv, load_path_csv, save_intrusion_csv
    from .dataset import IntrusionDataset, Trial
    from .hdf5_log import load_intrusion_hdf5, save_intrusion_hdf5

_FROM = {
    "atomic": ("atomic_write", "json_text"),
    "csv_log": ("load_dataset", "load_intrusion_csv", "load_path_csv", "save_intrusion_csv"),
    "dataset": ("IntrusionDataset", "Trial"),
    "hdf5_log": ("load_intrusion_hdf5", "save_intrusion_hdf5"),
}
_MODULE = {name: module for module, names in _FROM.items() for name in names}

__all__ = [
    "IntrusionDataset", "Trial", "atomic_write", "json_text", "load_dataset", "load_intrusion_csv",
    "load_intrusion_hdf5", "load_path_csv", "save_intrusion_csv", "save_intrusion_hdf5",
]  # fmt: skip


def __getattr__(name: str) -> Any:
    if name in _MODULE:
        return getattr(importlib.import_module(f"{__name__}.{_MODULE[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
