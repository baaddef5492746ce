"""What a designer reads off a sweep: maps of a metric, and which parameter matters most."""

from __future__ import annotations

from itertools import pairwise
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import MudrftError

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure


def check_names(names: dict[str, str | None], swept: list[str], where: str = "") -> None:
    """Refuse map parameters (``x``, ``y``, ``panels``) not swept, or one given twice."""
    given = [(k, v) for k, v in names.items() if v is not None]
    for i, (key, value) in enumerate(given):
        if value not in swept:
            raise MudrftError(f"{where}{key} must be a swept parameter ({', '.join(swept) or 'none'}), got {value!r}")  # fmt: skip
        for other, v in given[:i]:
            if v == value:
                raise MudrftError(f"{where}{other} and {key} are both {value!r}; a map needs a different parameter for each")  # fmt: skip


def _check(ds: xr.Dataset, metric: str, names: dict[str, str | None]) -> list[str]:
    if metric not in ds.data_vars or metric in ("error", "done"):
        known = [str(v) for v in ds.data_vars if v not in ("error", "done")]
        raise MudrftError(f"metric must be one of {', '.join(known)}, got {metric!r}")
    if "point" in ds.dims:  # a sample's parameters are its coordinates along ``point``
        swept = [str(c) for c in ds.coords if ds[c].dims == ("point",) and c != "point"]
    else:
        swept = [str(d) for d in ds.dims]
    check_names(names, swept)
    return swept


def _unit(ds: xr.Dataset, name: str) -> str:
    unit = ds[name].attrs.get("units", "")
    return unit if unit != "-" else ""


def _label(ds: xr.Dataset, name: str) -> str:
    return f"{name} [{_unit(ds, name)}]" if _unit(ds, name) else name


def _value(ds: xr.Dataset, name: str, v: object) -> str:
    """``name = value unit`` for a title (``speed = 0.13 m/s``)."""
    text = f"{v:g}" if isinstance(v, float | np.floating) else f"{v}"
    return f"{name} = {text} {_unit(ds, name)}".rstrip()


def _panels(plt: ModuleType, n: int, values: np.ndarray) -> tuple[Figure, Any, tuple[float, float]]:
    """A row of ``n`` panels, and the colour range of the finite ``values``."""
    fig, axes = plt.subplots(
        1, n, figsize=(3.6 * n + 1.2, 3.4), squeeze=False, layout="constrained"
    )
    finite = values[np.isfinite(values)]
    return fig, axes, ((finite.min(), finite.max()) if finite.size else (0.0, 1.0))


def _positions(values: np.ndarray) -> tuple[np.ndarray, list[str] | None]:
    if values.dtype.kind in "fiu":
        return values.astype(float), None
    return np.arange(len(values), dtype=float), [str(v) for v in values]


def plot_maps(
    ds: xr.Dataset,
    metric: str,
    *,
    x: str | None = None,
    y: str | None = None,
    panels: str | None = None,
    select: dict[str, Any] | None = None,
) -> Figure:
    """Maps of ``metric`` over ``x`` and ``y``, one panel per value of ``panels`` (failed
    points grey); a sample's points coloured by the metric, a panel per third of ``panels``.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep's result.
    metric : str
        The variable to map.
    x, y, panels : str or None, keyword-only
        Swept parameters; default the first, second and third swept ones.
    select : dict or None, keyword-only
        Values of the other swept parameters of a grid (default: their first value).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    swept = _check(ds, metric, {"x": x, "y": y, "panels": panels})
    rest = [s for s in swept if s not in (x, y, panels)]
    numeric = [s for s in rest if ds[s].dtype.kind in "fiu" and ds[s].size > 1]
    rest = numeric + [s for s in rest if s not in numeric]  # maps over numbers, panels by kind
    x = x or (rest.pop(0) if rest else None)
    if x is None:
        raise MudrftError("the sweep has no swept parameter to plot against")
    y = y or (rest.pop(0) if rest else None)
    if panels is None and rest:
        named = [s for s in rest if s not in numeric]
        panels = named[0] if named else rest[0]
    if "point" in ds.dims:
        return _sample_maps(ds, metric, x, y, panels, plt)
    held = {d: ds[d].values[0] for d in swept if d not in (x, y, panels)}
    if select is not None and not isinstance(select, dict):
        raise MudrftError(f"select must be a dict of parameter values, got {select!r}")
    for key, value in (select or {}).items():  # silently ignored before, or a KeyError
        if key not in held:
            raise MudrftError(f"select {key!r}: not a parameter these maps hold at one value; expected one of {', '.join(held) or 'none'} (x, y and panels are not held)")  # fmt: skip
        if value not in list(ds[key].values):
            raise MudrftError(f"select {key!r}: {value!r} is not one of its values ({', '.join(map(str, ds[key].values))})")  # fmt: skip
        held[key] = value
    da = ds[metric].sel(held) if held else ds[metric]
    values = list(ds[panels].values) if panels else [None]
    fig, axes, (vmin, vmax) = _panels(plt, len(values), da.values)
    px, xt = _positions(ds[x].values)
    mesh = None
    for ax, v in zip(axes[0], values, strict=True):
        sub = da.sel({panels: v}) if panels else da
        ax.set_facecolor("0.85")  # failed points
        if y is None:
            ax.plot(px, sub.values, "o-")
            ax.set_ylabel(_label(ds, metric))
        else:
            py, yt = _positions(ds[y].values)
            z = sub.transpose(y, x).values
            mesh = ax.pcolormesh(px, py, z, shading="nearest", vmin=vmin, vmax=vmax)
            ax.set_ylabel(_label(ds, y))
            if yt:
                ax.set_yticks(py, yt)
        if xt:
            ax.set_xticks(px, xt)
        ax.set_xlabel(_label(ds, x))
        if panels:
            ax.set_title(_value(ds, panels, v))
    if mesh is not None:
        fig.colorbar(mesh, ax=axes[0].tolist(), label=_label(ds, metric))
    held_text = ", ".join(_value(ds, k, v) for k, v in held.items())
    fig.suptitle(f"{metric}" + (f" at {held_text}" if held_text else "") + " (grey: failed)")
    return fig


def _sample_maps(
    ds: xr.Dataset, metric: str, x: str, y: str | None, panels: str | None, plt: ModuleType
) -> Figure:
    m = ds[metric].values
    groups: list[tuple[str, np.ndarray]] = [("", np.ones(m.shape, dtype=bool))]
    if panels:
        p = ds[panels].values.astype(float)
        edges = np.quantile(p, [0, 1 / 3, 2 / 3, 1])
        groups = [
            (f"{panels} in [{lo:.3g}, {hi:.3g}]", (p >= lo) & (p <= hi if k == 2 else p < hi))
            for k, (lo, hi) in enumerate(pairwise(edges))
        ]
    fig, axes, (vmin, vmax) = _panels(plt, len(groups), m)
    sc = None
    for ax, (title, mask) in zip(axes[0], groups, strict=True):
        xv = ds[x].values[mask]
        yv = ds[y].values[mask] if y else m[mask]
        ok = np.isfinite(m[mask])
        ax.scatter(xv[~ok], yv[~ok], c="0.7", marker="x", s=12)
        sc = ax.scatter(xv[ok], yv[ok], c=m[mask][ok], s=14, vmin=vmin, vmax=vmax)
        ax.set_xlabel(_label(ds, x))
        ax.set_ylabel(_label(ds, y) if y else _label(ds, metric))
        ax.set_title(title)
    if y and sc is not None:
        fig.colorbar(sc, ax=axes[0].tolist(), label=_label(ds, metric))
    fig.suptitle(f"{metric} ({ds.sizes['point']} sampled points; grey x: failed)")
    return fig


def sensitivity(ds: xr.Dataset, metric: str) -> list[tuple[str, float]]:
    """Rank the swept numeric parameters by their effect on ``metric``, largest first.

    For a sample: Spearman's rank correlation of each parameter with the metric over the
    points that ran, in [-1, 1]. For a grid: the spread (max - min) of the main effect
    (the metric averaged over every other dimension), in the metric's unit.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep's result.
    metric : str
        The variable.

    Returns
    -------
    list of (str, float)
        Parameter and score, sorted by the score's magnitude.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> ds = xr.Dataset({"m": (("a", "b"), [[1.0, 2.0], [5.0, 6.0]])},
    ...                 coords={"a": [0.0, 1.0], "b": [0.0, 1.0]})
    >>> sensitivity(ds, "m")
    [('a', 4.0), ('b', 1.0)]
    """
    swept = _check(ds, metric, {})
    m = ds[metric]
    out: list[tuple[str, float]] = []
    if "point" in ds.dims:
        from scipy.stats import spearmanr

        ok = np.isfinite(m.values)
        for name in swept:
            v = ds[name].values
            if v.dtype.kind not in "fiu" or ok.sum() < 3 or np.ptp(v[ok]) == 0:
                continue
            rho = spearmanr(v[ok], m.values[ok]).statistic
            out.append((name, float(rho)))
    else:
        for name in swept:
            if ds.sizes[name] < 2:
                continue
            effect = m.mean([d for d in m.dims if d != name], skipna=True).values
            if np.isfinite(effect).any():
                out.append((name, float(np.nanmax(effect) - np.nanmin(effect))))
    return sorted(out, key=lambda t: -abs(t[1]))
