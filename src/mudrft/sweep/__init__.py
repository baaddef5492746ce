"""Design sweeps: many feet, muds and motions, labelled xarray results in a resumable Zarr store.

``mudrft.sweep`` is both this package and the function that runs a sweep
(:func:`~mudrft.sweep.run.run_sweep`)::

    import mudrft
    ds = mudrft.sweep("examples/sweep_example.toml", store="maps.zarr", progress=True)
    ds.max_suction.sel(speed=0.2).plot()

A spec (:func:`load_spec`, a TOML file) names the swept parameters of the foot, the mud
and the motion, a grid or a sample (Latin hypercube, Sobol), and the metrics. Points are
cut into chunks; each chunk is one task (in this process, or on Dask) and one block of the
store, written as it finishes and verified when read, so a killed or damaged sweep
resumes without recomputing whole chunks. :func:`plot_maps` draws a metric over two
parameters, one panel per value of a third; :func:`sensitivity` ranks parameters.

Running a sweep needs the ``sweep`` extra (``pip install 'mudrft[sweep]'``: Dask, xarray,
Zarr); importing this package loads none of them, and ``import mudrft`` does not import it.
"""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING, Any

from .catalog import FOOT_KINDS, METRICS, MOTION_KINDS, PARAMETERS
from .design import Axis
from .plot import plot_maps, sensitivity
from .run import SweepWarning, run_sweep
from .spec import DESIGNS, SweepSpec, load_spec
from .store import load_result

if TYPE_CHECKING:
    import xarray as xr

__all__ = [
    "DESIGNS",
    "FOOT_KINDS",
    "METRICS",
    "MOTION_KINDS",
    "PARAMETERS",
    "Axis",
    "SweepSpec",
    "SweepWarning",
    "load_result",
    "load_spec",
    "plot_maps",
    "run_sweep",
    "sensitivity",
]


class _CallableModule(types.ModuleType):
    """This package, callable: ``mudrft.sweep(spec, ...)`` runs :func:`run_sweep`."""

    def __call__(self, *args: Any, **kwargs: Any) -> xr.Dataset:
        return run_sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
