"""The result store: a labelled Dataset in Zarr v3, written a chunk at a time, verified
when read: a chunk is trusted only when it decodes and matches its ``checksum`` (CRC-32);
else it is *damaged*, named by :func:`load_result` and computed again on resume."""

from __future__ import annotations

import json
import math
import os
import shutil
import zlib
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeAlias, cast

import numpy as np

from .. import __version__
from .._validation import MudrftError
from .catalog import METRICS
from .evaluate import ChunkResult
from .spec import SweepSpec, block

if TYPE_CHECKING:
    import xarray as xr
    import zarr
    import zarr.abc.store

#: Where a sweep is stored: a ``.zarr`` directory path or a zarr store object.
StoreLike: TypeAlias = "str | os.PathLike[str] | zarr.abc.store.Store"

#: Version of the store layout (attribute ``mudrft_sweep_format``); 2 added the checksums.
FORMAT = 2
_AGAIN = "start again with overwrite=True (CLI: --force)"


def _sources(spec: SweepSpec) -> str:
    if spec.mud_sets:
        parts = [f"mud set {k}: {v['source']}" for k, v in spec.mud_sets.items()]
    else:
        parts = [
            "mud: mudrft.paper_mud: Chen et al. 2026, supplementary Tables S1 (vertical) and "
            "S2 (horizontal), rows interpolated in water content (docs/model.md)"
        ]
    if any(k.endswith("_scale") for k in (*spec.fixed, *(a.name for a in spec.axes))):
        parts.append("*_scale: factors on both directions' values of that field")
    parts.append("feet: mudrft.feet defaults (the paper's dimensions) unless swept or fixed here")
    return "; ".join(parts)


def _param_attrs(name: str, spec: SweepSpec) -> dict[str, Any]:
    if name == "foot":
        return {"long_name": "foot kind", "units": "-", "section": "foot"}
    p = spec.parameter(name)
    return {"long_name": p.doc, "units": p.unit, "section": p.section}


def _template(spec: SweepSpec) -> xr.Dataset:
    import dask.array as da
    import xarray as xr

    dims, shape, chunks = spec.dims, spec.shape, spec.chunks
    coords: dict[str, xr.Variable] = {}
    for a, (name, (d, v)) in zip(spec.axes, spec.coords().items(), strict=True):
        coords[name] = xr.Variable(d, v, attrs=_param_attrs(name, spec))
        if a.low is not None:
            coords[name].attrs.update(range=[a.low, a.high], log=int(a.log))
    if spec.design != "grid":
        coords["point"] = xr.Variable("point", np.arange(spec.n_points), {"long_name": "sample point"})  # fmt: skip
    for name, v in spec.fixed.items():
        value = np.array(v, dtype=object) if isinstance(v, str) else v
        coords[name] = xr.Variable((), value, attrs=_param_attrs(name, spec))
    data: dict[str, xr.Variable] = {}
    for m in spec.metrics:
        meta = METRICS[spec.motion][m]
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


def _root_attrs(path: Path) -> dict[str, Any] | None:
    """The attributes of the group at ``path``, or None without a readable ``zarr.json``."""
    try:
        meta = json.loads((path / "zarr.json").read_text())
        return dict(meta.get("attributes", {}))
    except (OSError, ValueError, AttributeError):
        return None


def create_store(store: StoreLike, spec: SweepSpec, *, overwrite: bool = False) -> zarr.Group:
    """Create an empty store for ``spec`` (a ``.zarr`` path or a zarr store); its group.
    An existing path is replaced only with ``overwrite`` and only if it is a sweep store."""
    import zarr

    if isinstance(store, str | os.PathLike):
        path = Path(store)
        if path.exists():
            if not overwrite:
                raise MudrftError(
                    f"store {str(path)!r} exists; pass resume=True (CLI: --resume) to continue "
                    f"it or overwrite=True (CLI: --force) to start again"
                )
            if "mudrft_sweep_format" not in (_root_attrs(path) or {}):
                raise MudrftError(
                    f"store {str(path)!r} exists and is not a mudrft sweep store; refusing to "
                    f"replace it (remove it yourself, or choose another store)"
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
    group.create_array(
        "checksum",
        shape=(spec.n_chunks,),
        chunks=(1,),
        dtype="uint32",
        fill_value=0,
        dimension_names=["chunk"],
        attributes={"long_name": "CRC-32 of each chunk's metrics and errors", "units": "-"},
    )
    group.attrs["arrays"] = sorted(group.array_keys())
    return group


def _open(store: StoreLike, mode: Literal["r", "r+"]) -> tuple[zarr.Group, str]:
    """A sweep's store opened, its format and the metadata of every array checked."""
    import zarr

    where = repr(str(store)) if isinstance(store, str | os.PathLike) else "the store"
    if isinstance(store, str | os.PathLike):
        path = Path(store)
        if not path.is_dir():
            raise MudrftError(f"store {where}: no such directory")
        attrs = _root_attrs(path)
        if attrs is None:
            raise MudrftError(
                f"store {where} has no readable zarr.json: it is not a Zarr store, or its root "
                f"metadata is gone; it cannot be read or resumed: if it was a sweep, remove the "
                f"directory and run the sweep again"
            )
        if "mudrft_sweep_format" not in attrs:
            raise MudrftError(f"store {where} is not a mudrft sweep store")
        store = str(path)
    try:
        group = zarr.open_group(store, mode=mode)
    except Exception as exc:  # zarr's FileNotFoundError, JSON or metadata errors
        raise MudrftError(f"store {where} cannot be opened as a sweep store ({exc}); {_AGAIN}") from None  # fmt: skip
    fmt = group.attrs.get("mudrft_sweep_format")
    if fmt != FORMAT:
        raise MudrftError(
            f"store {where} has store format {fmt!r} (this mudrft reads {FORMAT}: format 1 "
            f"stores have no chunk checksums and cannot be verified); {_AGAIN} "
            f"(xarray.open_zarr still reads it, unverified)"
        )
    if "arrays" not in group.attrs:  # written last by create_store
        raise MudrftError(f"store {where} was not completely created (its making was interrupted); {_AGAIN}")  # fmt: skip
    for name in cast("list[str]", group.attrs["arrays"]):
        try:
            group[name]
        except Exception:  # KeyError (zarr.json gone) or a JSON error (garbled)
            raise MudrftError(
                f"store {where}: the metadata of its array {name!r} ({name}/zarr.json) is gone "
                f"or unreadable, so the store cannot be read or resumed; {_AGAIN}"
            ) from None
    return group, where


def open_store(store: StoreLike, spec: SweepSpec) -> zarr.Group:
    """Open an existing store to resume ``spec``; raise if it was made from another spec."""
    group, where = _open(store, "r+")
    if group.attrs.get("spec_identity") != spec.identity():
        raise MudrftError(
            f"{where} was made from another spec ({group.attrs.get('spec_source')}); resume it "
            f"with that spec, or start again (overwrite=True, CLI: --force)"
        )
    return group


def _array(group: zarr.Group, name: str) -> zarr.Array:
    return cast("zarr.Array", group[name])


def _blocks(shape: tuple[int, ...], chunks: tuple[int, ...]) -> list[tuple[slice, ...]]:
    n = math.prod(math.ceil(s / c) for s, c in zip(shape, chunks, strict=True))
    return [block(shape, chunks, i) for i in range(n)]


def _checksum(values: list[np.ndarray], errors: np.ndarray) -> int:
    crc = 0
    for v in values:  # NaN made canonical: zarr may store an all-NaN chunk as its fill value
        crc = zlib.crc32(np.where(np.isnan(v), np.nan, v).astype("<f8").tobytes(), crc)
    return zlib.crc32("\0".join(str(e) for e in np.ravel(errors)).encode(), crc)


def write_chunk(group: zarr.Group, spec: SweepSpec, i: int, result: ChunkResult) -> None:
    """Write chunk ``i``: metrics and errors, then its checksum, then ``done``."""
    sl = spec.chunk_slices(i)
    shape = spec.chunk_shape(i)
    values = [result.values[:, k].reshape(shape) for k in range(len(spec.metrics))]
    errors = np.array(result.errors, dtype=object).reshape(shape)
    for m, v in zip(spec.metrics, values, strict=True):
        _array(group, m)[sl] = v
    _array(group, "error")[sl] = errors
    _array(group, "checksum")[i] = _checksum(values, errors)
    _array(group, "done")[sl] = np.ones(shape, dtype=np.uint8)


def chunk_status(group: zarr.Group) -> tuple[np.ndarray, dict[int, str], dict[str, np.ndarray]]:
    """The chunks stored whole (bool, shape (chunks,)), the damaged ones (chunk -> why)
    and every array as read (fill values where damaged)."""
    metrics = cast("list[str]", group.attrs["metrics"])
    first = _array(group, metrics[0])
    blocks = _blocks(first.shape, first.chunks)
    data: dict[str, np.ndarray] = {}
    damaged: dict[int, str] = {}
    for name in [*metrics, "error", "done", "checksum"]:
        arr = _array(group, name)
        try:
            data[name] = np.asarray(arr[...])
        except Exception:  # any failure to decode is damage: found chunk by chunk
            dtype = object if name == "error" else arr.dtype
            out = np.full(arr.shape, arr.fill_value, dtype=dtype)
            for i, sl in enumerate(blocks):
                sl = (slice(i, i + 1),) if name == "checksum" else sl
                try:
                    out[sl] = arr[sl]
                except Exception as exc:
                    why = f"{name} does not decode ({type(exc).__name__}: {exc})"
                    damaged.setdefault(i, why)
            data[name] = out
    complete = bool(group.attrs.get("complete"))
    done = np.zeros(len(blocks), dtype=bool)
    for i, sl in enumerate(blocks):
        flags = data["done"][sl]
        if i in damaged:
            continue
        if np.all(flags == 1):
            crc = _checksum([data[m][sl] for m in metrics], data["error"][sl])
            if crc == data["checksum"][i]:
                done[i] = True
            else:
                damaged[i] = "its values do not match their checksum (a chunk file changed or is missing)"  # fmt: skip
        elif np.any(flags != 0) or complete:
            damaged[i] = "its done flags are missing or partial"
    return done, damaged, data


def _points(ds: xr.Dataset, sl: tuple[slice, ...]) -> str:
    parts = []
    for dim, s in zip(ds["error"].dims, sl, strict=True):
        v = [f"{x:g}" if isinstance(x, float) else str(x) for x in ds[dim].values[s].tolist()]
        parts.append(f"{dim} = {v[0]}" + (f"..{v[-1]}" if len(v) > 1 else ""))
    return ", ".join(parts)


def load_result(
    store: StoreLike, *, keep_done: bool = False, on_damage: str = "raise"
) -> xr.Dataset:
    """The sweep's Dataset from a store, loaded into memory, every chunk verified.

    Parameters
    ----------
    store : path or zarr store
        A store written by :func:`mudrft.sweep`.
    keep_done : bool, keyword-only
        Keep the ``done`` variable (default: drop it when the sweep is complete).
    on_damage : {"raise", "mask"}, keyword-only
        A damaged chunk (one that does not decode or match its checksum) raises, naming
        it and its points, or is returned masked: NaN metrics, ``done`` 0 and an
        ``error`` saying so (attribute ``damaged_chunks``).

    Raises
    ------
    MudrftError
        For a path that is not a sweep store, a store of another format or whose metadata
        is gone, and damaged chunks (``on_damage="raise"``).
    """
    import xarray as xr

    if on_damage not in ("raise", "mask"):
        raise MudrftError(f"on_damage must be 'raise' or 'mask', got {on_damage!r}")
    group, where = _open(store, "r")
    _, damaged, data = chunk_status(group)
    blocks = _blocks(data["error"].shape, _array(group, "error").chunks)
    try:
        ds = xr.open_zarr(group.store, consolidated=False, chunks=None, drop_variables=["checksum"])  # fmt: skip
        for c in ds.coords.values():
            c.load()
        labels = {i: _points(ds, blocks[i]) for i in list(damaged)[:5]}
    except Exception as exc:  # a damaged coordinate: the points cannot be labelled
        raise MudrftError(f"store {where}: its coordinates cannot be read ({type(exc).__name__}: {exc}); {_AGAIN}") from None  # fmt: skip
    if damaged and on_damage == "raise":
        listed = "; ".join(f"chunk {i} ({labels[i]}): {damaged[i]}" for i in labels)
        more = f"; and {len(damaged) - len(labels)} more" if len(damaged) > len(labels) else ""
        raise MudrftError(
            f"store {where} is damaged: {len(damaged)} of {len(blocks)} chunks cannot be "
            f"trusted: {listed}{more}. resume=True (CLI: --resume) recomputes them; "
            f"load_result(..., on_damage='mask') reads the rest"
        )
    data["error"] = data["error"].astype(object)
    for i, why in damaged.items():
        for name, value in data.items():
            if name not in ("checksum", "done", "error"):
                value[blocks[i]] = np.nan
        data["done"][blocks[i]] = 0
        data["error"][blocks[i]] = f"damaged: chunk {i} of the store, {why}"
    ds = ds.assign({k: ds[k].copy(data=v) for k, v in data.items() if k != "checksum"})
    for name in list(ds.variables):
        if ds[name].dtype.kind in "OT":  # numpy StringDType, as zarr reads strings
            values = np.asarray(ds[name].values, dtype=object).astype(str)
            if name in ds.coords:
                ds = ds.assign_coords({name: (ds[name].dims, values, ds[name].attrs)})
            else:
                ds[name] = (ds[name].dims, values, ds[name].attrs)
    ds.attrs.pop("arrays", None)
    if damaged:
        ds.attrs["damaged_chunks"] = sorted(damaged)
    metrics = [str(m) for m in np.atleast_1d(ds.attrs.get("metrics", [])) if m in ds]
    drop = ds.attrs.get("complete") and not keep_done and not damaged
    return ds[[*metrics, "error", *([] if drop else ["done"])]]
