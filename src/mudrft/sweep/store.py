"""The result store: a labelled xarray Dataset in Zarr, written one chunk at a time.

Layout (see the README's library section):

* dimensions: one per swept parameter of a grid (``radius``, ``water_content``, ...) with
  its values as coordinate; a sample has one dimension ``point`` and every swept
  parameter is a coordinate along it;
* fixed parameters: scalar coordinates (``foot = "flat"``, ``speed = 0.2``);
* variables: one float64 per metric (NaN where the point failed or has not run), ``error``
  (str: ``""`` or ``"ExceptionType: message"``) and ``done`` (uint8: 1 once the point's
  chunk is written);
* attributes of every coordinate and variable: ``units``, ``long_name`` (and ``section``
  for parameters); of the dataset: the mudrft version, the spec (text, identity hash),
  the design, the parameter sources, ``complete`` and ``failed_points``.

One chunk of the store is one task's block of points. The block of every metric and of
``error`` is written first, ``done`` last; zarr-python writes each chunk file atomically
(a temporary file renamed), so a sweep killed at any moment leaves a store in which every
chunk whose ``done`` is set is whole, and a resumed sweep recomputes the others only.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeAlias, cast

import numpy as np
from numpy.typing import NDArray

from .. import __version__
from .._validation import MudrftError
from . import catalog as C
from .evaluate import ChunkResult
from .spec import SweepSpec

if TYPE_CHECKING:
    import xarray as xr
    import zarr
    import zarr.abc.store

#: Where a sweep is stored: a ``.zarr`` directory path or a zarr store object.
StoreLike: TypeAlias = "str | os.PathLike[str] | zarr.abc.store.Store"

__all__ = ["FORMAT", "create_store", "done_chunks", "load_result", "open_store", "write_chunk"]

#: Version of the store layout (attribute ``mudrft_sweep_format``).
FORMAT = 1


def _sources(spec: SweepSpec) -> str:
    parts = []
    if spec.mud_sets:
        parts += [f"mud set {k}: {v['source']}" for k, v in spec.mud_sets.items()]
    else:
        parts.append(
            "mud: mudrft.paper_mud: Chen et al. 2026, supplementary Tables S1 (vertical) and "
            "S2 (horizontal), rows interpolated in water content (docs/model.md)"
        )
    if any(a.name.endswith("_scale") for a in spec.axes) or any(
        k.endswith("_scale") for k in spec.fixed
    ):
        parts.append("*_scale: factors on both directions' values of that field")
    parts.append(
        "feet: mudrft.feet defaults (the paper's dimensions; morphing foot D30-D31) "
        "unless swept or fixed here"
    )
    return "; ".join(parts)


def _param_attrs(name: str, spec: SweepSpec) -> dict[str, Any]:
    if name == "foot":
        return {"long_name": "foot kind", "units": "-", "section": "foot"}
    p = (
        C.motion_parameter(spec.motion, name)
        if name in C.motion_parameters(spec.motion)
        else C.PARAMETERS[name]
    )
    return {"long_name": p.doc, "units": p.unit, "section": p.section}


def _template(spec: SweepSpec) -> xr.Dataset:
    import dask.array as da
    import xarray as xr

    dims, shape, chunks = spec.dims, spec.shape, spec.chunks
    coords: dict[str, xr.Variable] = {}
    for name, (d, v) in spec.coords().items():
        coords[name] = xr.Variable(d, v, attrs=_param_attrs(name, spec))
        for a in spec.axes:
            if a.name == name and a.low is not None:
                coords[name].attrs["range"] = [a.low, a.high]
                coords[name].attrs["log"] = int(a.log)
    if spec.design != "grid":
        coords["point"] = xr.Variable("point", np.arange(spec.n_points), {"long_name": "sample point"})  # fmt: skip
    for name, v in spec.fixed.items():
        value = np.array(v, dtype=object) if isinstance(v, str) else v
        coords[name] = xr.Variable((), value, attrs=_param_attrs(name, spec))
    data: dict[str, xr.Variable] = {}
    for m in spec.metrics:
        meta = C.METRICS[spec.motion][m]
        data[m] = xr.Variable(dims, da.full(shape, np.nan, chunks=chunks), {"units": meta.unit, "long_name": meta.doc})  # fmt: skip
    data["done"] = xr.Variable(
        dims,
        da.zeros(shape, dtype=np.uint8, chunks=chunks),
        {"long_name": "1 once the point's chunk is stored", "units": "-"},
    )
    attrs = {
        "title": "mudrft design sweep",
        "mudrft_version": __version__,
        "mudrft_sweep_format": FORMAT,
        "design": spec.design,
        "motion": spec.motion,
        "metrics": list(spec.metrics),
        "sample_size": spec.n if spec.n is not None else "",
        "seed": spec.seed if spec.seed is not None else "",
        "points_per_task": spec.chunk_size,
        "chunks": list(spec.chunks),
        "axes": json.dumps([a.as_json() for a in spec.axes]),
        "parameter_sources": _sources(spec),
        "citations": ["chen2026mud"],
        "spec": spec.text,
        "spec_source": spec.where,
        "spec_identity": spec.identity(),
        "complete": 0,
        "failed_points": 0,
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _is_store(path: Path) -> bool:
    try:
        meta = json.loads((path / "zarr.json").read_text())
    except (OSError, ValueError):
        return False
    return "mudrft_sweep_format" in meta.get("attributes", {})


def create_store(store: StoreLike, spec: SweepSpec, *, overwrite: bool = False) -> zarr.Group:
    """Create an empty store for ``spec`` (metadata and coordinates only); return its group.

    ``store`` is a directory path (``.zarr``) or a zarr store object; an existing path is
    an error unless ``overwrite``, and is removed only when it is a mudrft sweep store.
    """
    import zarr

    if isinstance(store, str | os.PathLike):
        path = Path(store)
        if path.exists():
            if not overwrite:
                raise MudrftError(
                    f"store {str(path)!r} exists; pass resume=True (CLI: --resume) to continue "
                    f"it or overwrite=True (CLI: --force) to start again"
                )
            if not _is_store(path):
                raise MudrftError(
                    f"store {str(path)!r} exists and is not a mudrft sweep store; refusing to "
                    f"replace it"
                )
            shutil.rmtree(path)
        if not path.parent.is_dir():
            raise MudrftError(f"store {str(path)!r}: the directory {str(path.parent)!r} does not exist")  # fmt: skip
        store = str(path)
    _template(spec).to_zarr(store, mode="w-", compute=False, consolidated=False)
    group = zarr.open_group(store, mode="r+")
    group.create_array(
        "error",
        shape=spec.shape,
        chunks=spec.chunks,
        dtype=str,
        fill_value="",
        dimension_names=list(spec.dims),
        attributes={"long_name": "error of a point that failed ('' where it ran)", "units": "-"},
    )
    return group


def open_store(store: StoreLike, spec: SweepSpec) -> zarr.Group:
    """Open an existing store to resume ``spec``; raise if it was made from another spec."""
    import zarr

    where = str(store) if isinstance(store, str | os.PathLike) else "store"
    if isinstance(store, str | os.PathLike):
        if not _is_store(Path(store)):
            raise MudrftError(f"{where!r} is not a mudrft sweep store")
        store = str(store)
    group = zarr.open_group(store, mode="r+")
    attrs = dict(group.attrs)
    if attrs.get("mudrft_sweep_format") != FORMAT:
        raise MudrftError(f"{where!r} has store format {attrs.get('mudrft_sweep_format')!r}; this mudrft writes {FORMAT}")  # fmt: skip
    if attrs.get("spec_identity") != spec.identity():
        raise MudrftError(
            f"{where!r} was made from another spec ({attrs.get('spec_source')}); resume it "
            f"with that spec, or start again (overwrite=True, CLI: --force)"
        )
    return group


def _array(group: zarr.Group, name: str) -> zarr.Array:
    """The array ``name`` of a sweep's store (every name of the layout is an array, never a
    subgroup; zarr types an item of a group as either)."""
    return cast("zarr.Array", group[name])


def done_chunks(group: zarr.Group, spec: SweepSpec) -> NDArray[np.bool_]:
    """Which chunks are stored whole: bool, shape (n_chunks,)."""
    done = np.asarray(_array(group, "done")[...])
    return np.array(
        [bool(np.all(done[spec.chunk_slices(i)] == 1)) for i in range(spec.n_chunks)], dtype=bool
    )


def write_chunk(group: zarr.Group, spec: SweepSpec, i: int, result: ChunkResult) -> None:
    """Write chunk ``i`` (metrics, then errors, then ``done``)."""
    sl = spec.chunk_slices(i)
    shape = spec.chunk_shape(i)
    for k, m in enumerate(spec.metrics):
        _array(group, m)[sl] = result.values[:, k].reshape(shape)
    _array(group, "error")[sl] = np.array(result.errors, dtype=object).reshape(shape)
    _array(group, "done")[sl] = np.ones(shape, dtype=np.uint8)


def mark_complete(group: zarr.Group, spec: SweepSpec) -> int:
    """Count the failed points, set ``complete`` and ``failed_points``; return the count."""
    failed = int(np.count_nonzero(np.asarray(_array(group, "error")[...], dtype=object) != ""))
    group.attrs.update({"complete": 1, "failed_points": failed})
    return failed


def load_result(store: StoreLike, *, keep_done: bool = False) -> xr.Dataset:
    """The sweep's Dataset from a store (loaded into memory), strings as plain ``str``.

    Parameters
    ----------
    store : path or zarr store
        A store written by :func:`mudrft.sweep`.
    keep_done : bool, keyword-only
        Keep the ``done`` variable (default: drop it when the sweep is complete).
    """
    import xarray as xr

    if isinstance(store, str | os.PathLike):
        if not _is_store(Path(store)):
            raise MudrftError(f"{str(store)!r} is not a mudrft sweep store")
        store = str(store)
    ds = xr.open_zarr(store, consolidated=False).load()
    for name in list(ds.variables):
        if ds[name].dtype.kind == "T":  # numpy StringDType, as zarr reads vlen strings
            values = np.asarray(ds[name].values, dtype=object).astype(str)
            if name in ds.coords:
                ds = ds.assign_coords({name: (ds[name].dims, values, ds[name].attrs)})
            else:
                ds[name] = (ds[name].dims, values, ds[name].attrs)
    metrics = [str(m) for m in np.atleast_1d(ds.attrs.get("metrics", [])) if m in ds]
    order = [*metrics, "error", *([] if ds.attrs.get("complete") and not keep_done else ["done"])]
    return ds[order]
