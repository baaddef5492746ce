r"""Intrusion logs and foot paths: read them from CSV or HDF5 in SI, write them atomically.

A log holds one or more *trials* (one intrusion-hold-retraction each), with the columns
``time``, ``depth`` (the intrusion displacement) and either ``stress`` or a force. Each
column name carries its unit as the logger wrote it, ``time [ms]``, ``Time (ms)`` or
``time in ms``, and values are converted to SI on load (:mod:`mudrft.units`). A force is
turned into a stress with the plate area, ``stress = force / area``; the dimensionless
displacement of the model is ``gamma = depth / L_c`` with the characteristic length
``L_c``. Fields are separated by commas, tabs or semicolons (found from the header).

A CSV log (``#`` lines are comments; ``# key: value`` comments are metadata)::

    # direction: vertical
    # characteristic_length [m]: 0.05
    trial,time [s],depth [mm],stress [kPa]
    slow,0.00,0.0,0.0
    slow,0.01,0.1,1.9
    ...

Recognised columns (names are case-insensitive; others are mapped with ``columns=``,
CLI ``--columns``, or ignored and listed in ``IntrusionDataset.meta``):

==========================  ==================  ===============================
column                      quantity            units understood
==========================  ==================  ===============================
``time``, ``t``             time                s, ms, us, min
``depth``, ``displacement`` length              m, cm, mm, um, in
``stress``, ``sigma``       stress              Pa, kPa, MPa, N/m^2
``Fz``, ``force``, ``F``    force               N, kN, mN
``trial`` (no unit)         label of the trial  any text
==========================  ==================  ===============================

The force is the force of the mud on the plate *resisting the intrusion* (positive while
intruding, negative under suction); for a vertical test that is the world ``Fz`` (D40).

Every problem in a file raises :class:`~mudrft._validation.MudrftError` naming the file,
the line and the column. The loaders never write; the writers write atomically and
refuse to replace an existing file unless ``overwrite=True`` (:func:`atomic_write`).
Names load on first use, so that the writer does not bring the readers along.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .atomic import atomic_write, json_text
    from .columns import COLUMN_ALIASES
    from .csv_log import load_dataset, load_intrusion_csv, save_intrusion_csv
    from .dataset import IntrusionDataset, Trial
    from .hdf5_log import load_intrusion_hdf5, save_intrusion_hdf5
    from .path_csv import load_path_csv

_FROM = {
    "atomic": ("atomic_write", "json_text"),
    "columns": ("COLUMN_ALIASES",),
    "csv_log": ("load_dataset", "load_intrusion_csv", "save_intrusion_csv"),
    "dataset": ("IntrusionDataset", "Trial"),
    "hdf5_log": ("load_intrusion_hdf5", "save_intrusion_hdf5"),
    "path_csv": ("load_path_csv",),
}
_MODULE = {name: module for module, names in _FROM.items() for name in names}

__all__ = [
    "COLUMN_ALIASES",
    "IntrusionDataset",
    "Trial",
    "atomic_write",
    "json_text",
    "load_dataset",
    "load_intrusion_csv",
    "load_intrusion_hdf5",
    "load_path_csv",
    "save_intrusion_csv",
    "save_intrusion_hdf5",
]


def __getattr__(name: str) -> Any:
    if name in _MODULE:
        return getattr(importlib.import_module(f"{__name__}.{_MODULE[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
