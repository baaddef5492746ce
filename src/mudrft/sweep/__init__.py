"""Design sweeps: many feet, muds and motions, labelled xarray results in a resumable Zarr store.

``mudrft.sweep`` is both this package and :func:`~mudrft.sweep.run.run_sweep`::

    import mudrft
    ds = mudrft.sweep("examples/sweep_example.toml", store="maps.zarr", progress=True)
    ds.max_suction.sel(speed=0.2).plot()

A spec (:func:`load_spec`) names the swept parameters of the foot, the mud and the
motion, a grid or a sample, and the metrics. Each chunk of points is one task and one
block of the store, verified when read (:func:`load_result`). :func:`plot_maps` draws a
metric over two parameters; :func:`sensitivity` ranks them. Running a sweep needs
``pip install 'mudrft[sweep]'``; importing this package loads none of it.
"""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING, Any

from .catalog import FOOT_KINDS, METRICS, MOTION_KINDS, PARAMETERS
from .plot import plot_maps, sensitivity
from .run import SweepWarning, run_sweep
from .spec import DESIGNS, Axis, SweepSpec, load_spec
from .store import load_result

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "DESIGNS", "FOOT_KINDS", "METRICS", "MOTION_KINDS", "PARAMETERS", "Axis", "SweepSpec",
    "SweepWarning", "load_result", "load_spec", "plot_maps", "run_sweep", "sensitivity",
]  # fmt: skip


class _CallableModule(types.ModuleType):
    """This package, callable: ``mudrft.sweep(spec, ...)`` runs :func:`run_sweep`."""

    def __call__(self, *args: Any, **kwargs: Any) -> xr.Dataset:
        return run_sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
