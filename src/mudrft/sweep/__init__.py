"""Design sweeps on Dask: many feet, muds and motions, labelled xarray results in Zarr.

``mudrft.sweep`` is both this package and the function that runs a sweep
(:func:`~mudrft.sweep.run.run_sweep`)::

    import mudrft
    ds = mudrft.sweep("examples/sweep_example.toml", store="maps.zarr", progress=True)
    ds.max_suction.sel(speed=0.2).plot()

A spec (:func:`load_spec`, a TOML file) names the swept parameters of the foot, the mud
and the motion, a grid or a sample (Latin hypercube, Sobol), and the metrics. Points are
cut into chunks; each chunk is one Dask task (:func:`~.evaluate.evaluate_chunk`, plain
library code) and one block of the Zarr store, written as it finishes, so a killed sweep
resumes without recomputing finished chunks. A point that raises is recorded (NaN and its
error) and the rest completes. :func:`plot_maps` draws a metric over two parameters, one
panel per value of a third; :func:`sensitivity` ranks parameters by their effect.

The package needs the ``sweep`` extra (``pip install 'mudrft[sweep]'``: dask[distributed],
xarray, zarr); importing it does not import them, and ``import mudrft`` does not import it.
It is an edge layer: it uses the core, the core never imports it.
"""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING, Any

from .catalog import FOOT_KINDS, METRICS, MOTION_KINDS, PARAMETERS
from .design import Axis
from .spec import DESIGNS, SweepSpec, load_spec

__all__ = [
    "DESIGNS",
    "FOOT_KINDS",
    "METRICS",
    "MOTION_KINDS",
    "PARAMETERS",
    "Axis",
    "SweepSpec",
    "load_result",
    "load_spec",
    "plot_maps",
    "run_sweep",
    "sensitivity",
]


if TYPE_CHECKING:
    # Type checkers see the functions themselves, with their signatures; at run time the
    # wrappers below import them on first call, so that importing this package loads
    # neither Dask, xarray nor zarr.
    import xarray as xr
    from matplotlib.figure import Figure

    from .plot import plot_maps, sensitivity
    from .run import run_sweep
    from .store import load_result
else:
    # The wrappers forward whatever they are given: the signatures are the functions'.

    def run_sweep(*args: Any, **kwargs: Any) -> xr.Dataset:
        """Run a sweep; see :func:`mudrft.sweep.run.run_sweep` (loads Dask on first use)."""
        from .run import run_sweep as run

        return run(*args, **kwargs)

    def load_result(*args: Any, **kwargs: Any) -> xr.Dataset:
        """Open a sweep's store as a Dataset; see :func:`mudrft.sweep.store.load_result`."""
        from .store import load_result as load

        return load(*args, **kwargs)

    def plot_maps(*args: Any, **kwargs: Any) -> Figure:
        """Maps of a metric; see :func:`mudrft.sweep.plot.plot_maps`."""
        from .plot import plot_maps as plot

        return plot(*args, **kwargs)

    def sensitivity(*args: Any, **kwargs: Any) -> list[tuple[str, float]]:
        """Rank parameters by their effect on a metric; see :func:`mudrft.sweep.plot.sensitivity`."""
        from .plot import sensitivity as sens

        return sens(*args, **kwargs)


class _CallableModule(types.ModuleType):
    """This package, callable: ``mudrft.sweep(spec, ...)`` runs :func:`run_sweep`."""

    def __call__(self, *args: Any, **kwargs: Any) -> xr.Dataset:
        return run_sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
