r"""A field of mud: patches of different mud, and rigid ground, on the plane of the surface.

The plane is cut into a grid of cells, each holding one region: a mud, or rigid ground (no
mud force; MuJoCo's own contact acts). A tip at :math:`(x, y)` feels the regions over the
square of side :math:`b` (the border width) centered there, each weighted by the share
:math:`w_r` of the square it covers: the constants are the mud regions' weighted mean, the
force is scaled by the mud's share :math:`m=\sum_{mud}w_r` (decision D174, continuous across
borders). The surface may be uneven (:func:`surface_at`, decision D175).
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from os import PathLike
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray, IndexArray, Namespace, XpArray
from .._validation import MudrftError, plain, positive_number
from .._xp import pyfloat
from ..parameters.base import Mud, MudParameters
from ..parameters.registry import paper_mud
from .mud import MudTerrain
from .rows import N_CONST, constant_row

__all__ = [
    "RIGID",
    "MudField",
    "cell_overlap",
    "field_blend",
    "field_row",
    "plane_frame",
    "same_options",
    "surface_at",
    "surface_blend",
    "uniform",
]

#: The region value of rigid ground.
RIGID = "rigid"


def cell_overlap(
    t: XpArray, t0: float, h: float, half: float, i: XpArray, xp: Namespace
) -> XpArray:
    """Share [-] of ``[t - half, t + half]`` in cell ``i`` of cells of width ``h`` from
    ``t0`` [m], element-wise."""
    lo = xp.maximum(t0 + i * h, t - half)
    hi = xp.minimum(t0 + (i + 1) * h, t + half)
    return xp.maximum(hi - lo, 0.0) / (2.0 * half)


def field_row(
    x: float, y: float, grid: FloatArray, cells: IndexArray, rows: FloatArray, out: FloatArray
) -> float:
    """Blend into ``out`` (N_CONST,) the mud constants under a tip at ``(x, y)`` [m]; return
    the mud's share [-] (see the module docstring).

    ``grid``: ``(x0, y0, hx, hy, b)`` [m], the grid's corner, cell sizes and border width
    (``0 < b <= min(hx, hy)``); ``cells`` (ny, nx): the region of each cell (outside the
    grid, the nearest cell's); ``rows`` (R, N_CONST + 1): each region's constants and
    1 for mud, 0 for rigid ground (its constants: any mud's).
    """
    x0, y0, hx, hy, half = grid[0], grid[1], grid[2], grid[3], 0.5 * grid[4]
    ny, nx = cells.shape[0], cells.shape[1]
    ix = math.floor((x - half - x0) / hx)
    iy = math.floor((y - half - y0) / hy)
    for q in range(N_CONST):
        out[q] = 0.0
    wm, wr, first, mixed = 0.0, 0.0, -1, False  # mud and rigid weights
    for a in range(2):
        wy = cell_overlap(y, y0, hy, half, iy + a, pyfloat)
        for c in range(2):
            w = wy * cell_overlap(x, x0, hx, half, ix + c, pyfloat)
            r = cells[min(max(iy + a, 0), ny - 1), min(max(ix + c, 0), nx - 1)]
            if w <= 0.0:
                continue
            if rows[r, N_CONST] == 0.0:
                wr += w
                continue
            wm += w
            mixed = mixed or (first >= 0 and r != first)
            first = r if first < 0 else first
            for q in range(N_CONST):
                out[q] += w * rows[r, q]
    if not mixed:  # one mud (or none: any mud's constants, no force), to the bit
        for q in range(N_CONST):
            out[q] = rows[max(first, 0), q]
    else:
        for q in range(N_CONST):
            out[q] /= wm
    return 1.0 if wr == 0.0 else wm / (wm + wr)


def _triangle(
    h00: XpArray, h01: XpArray, h10: XpArray, h11: XpArray, fx: XpArray, fy: XpArray, xp: Namespace
) -> tuple[XpArray, XpArray, XpArray]:
    """Height and rises per node spacing in x and y of a cell of corner heights ``h00``
    (lower left), ``h01`` (lower right), ``h10``, ``h11`` [m] at fractions ``fx``, ``fy``
    [-]: MuJoCo's heightfield, two planar triangles split along the diagonal from the lower
    left node. Element-wise."""
    lower = fx >= fy  # the triangle of the nodes (0, 0), (1, 0), (1, 1)
    sx = xp.where(lower, h01 - h00, h11 - h10)
    sy = xp.where(lower, h11 - h01, h10 - h00)
    return h00 + fx * sx + fy * sy, sx, sy


def surface_at(
    x: float, y: float, grid: FloatArray, ny: int, nx: int, heights: FloatArray
) -> tuple[float, float, float]:
    """The surface's height [m] (over the coupling's ``surface``) and slopes dh/dx, dh/dy
    [-] at ``(x, y)`` [m]. ``heights`` (nyh, nxh) are sampled at the nodes of the rectangle
    of ``ny`` x ``nx`` cells of ``grid`` (:func:`field_row`); between them the surface is
    MuJoCo's heightfield's (:func:`_triangle`); outside the rectangle the edge's height,
    with no slope across it. One sample is a flat surface at that height."""
    nyh, nxh = heights.shape[0], heights.shape[1]
    if nyh == 1 and nxh == 1:
        return heights[0, 0], 0.0, 0.0
    dx, dy = grid[2] * nx / (nxh - 1), grid[3] * ny / (nyh - 1)  # node spacings [m]
    u, v = (x - grid[0]) / dx, (y - grid[1]) / dy
    in_x, in_y = 0.0 <= u <= nxh - 1, 0.0 <= v <= nyh - 1
    u, v = min(max(u, 0.0), nxh - 1.0), min(max(v, 0.0), nyh - 1.0)
    i, j = min(math.floor(u), nxh - 2), min(math.floor(v), nyh - 2)
    h, sx, sy = _triangle(
        heights[j, i], heights[j, i + 1], heights[j + 1, i], heights[j + 1, i + 1],
        u - i, v - j, pyfloat,
    )  # fmt: skip
    return h, sx / dx if in_x else 0.0, sy / dy if in_y else 0.0


def surface_blend(
    x: XpArray, y: XpArray, grid: XpArray, ny: int, nx: int, heights: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray, XpArray]:
    """:func:`surface_at` on arrays (numpy or JAX) of points ``x``, ``y`` (...) [m]; the
    heights at least 2 x 2 nodes."""
    nyh, nxh = heights.shape
    dx, dy = grid[2] * nx / (nxh - 1), grid[3] * ny / (nyh - 1)
    u, v = (x - grid[0]) / dx, (y - grid[1]) / dy
    in_x, in_y = (u >= 0.0) & (u <= nxh - 1), (v >= 0.0) & (v <= nyh - 1)
    u, v = xp.clip(u, 0.0, nxh - 1.0), xp.clip(v, 0.0, nyh - 1.0)
    i = xp.minimum(xp.floor(u), nxh - 2).astype(int)
    j = xp.minimum(xp.floor(v), nyh - 2).astype(int)
    h, sx, sy = _triangle(
        heights[j, i], heights[j, i + 1], heights[j + 1, i], heights[j + 1, i + 1],
        u - i, v - j, xp,
    )  # fmt: skip
    return h, xp.where(in_x, sx / dx, 0.0), xp.where(in_y, sy / dy, 0.0)


def plane_frame(gx: XpArray, gy: XpArray, xp: Namespace = pyfloat) -> tuple[XpArray, ...]:
    """The frame of a plane of slopes dh/dx = ``gx``, dh/dy = ``gy`` [-]: the rows of the
    rotation from world to it (9 values), its x axis ``t1`` in the world's xz plane, then
    ``t2``, then the upward unit normal ``n``; the identity for a level plane. Element-wise."""
    a, c = xp.sqrt(1.0 + gx * gx), xp.sqrt(1.0 + gx * gx + gy * gy)
    ac = a * c
    zero = 0.0 * gx + 0.0  # (not -0.0)
    return (
        1.0 / a, zero, gx / a,
        -gx * gy / ac, (1.0 + gx * gx) / ac, gy / ac,
        -gx / c, -gy / c, 1.0 / c,
    )  # fmt: skip


def _terrain(name: str, value: object) -> MudTerrain | None:
    if isinstance(value, str) and value == RIGID:
        return None
    if isinstance(value, MudTerrain):
        return value
    if isinstance(value, Mud):
        return MudTerrain(value)
    if isinstance(value, int | float) and not isinstance(value, bool):
        return MudTerrain(paper_mud(float(value)))
    raise MudrftError(
        f"region {name!r} must be a water content [-], a Mud, a MudTerrain or {RIGID!r}, "
        f"got {value!r}"
    )


@dataclass(frozen=True, eq=False)
class MudField:
    """Patches of mud and rigid ground on the surface, for :func:`~mudrft.integrations.mujoco.attach`.

    Parameters
    ----------
    regions : mapping
        ``{name: region}``: a water content [-] (:func:`mudrft.paper_mud`), a
        :class:`~mudrft.Mud` (from :func:`mudrft.paper_mud` or ``mudrft calibrate``), a
        :class:`~mudrft.MudTerrain` or ``"rigid"``. Mud terrains share their options
        (evaluation, characteristic length, ...); at least one region is mud.
    cells : sequence of sequences of str
        Region names, ``cells[j][i]`` the cell from ``origin + (i hx, j hy)`` to
        ``origin + ((i+1) hx, (j+1) hy)``; outside the grid the nearest cell holds.
        A string row is split on white space: ``["wet dry", "rock wet"]``.
    cell_size : float or (float, float)
        Cell sizes ``hx``, ``hy`` [m].
    origin : (float, float)
        World position of the grid's corner [m].
    border : float
        Width [m] over which a foot crossing a border blends the regions, in
        ``(0, min(hx, hy)]``.
    heights : array_like (nyh, nxh) or None
        The surface's height [m] over the coupling's ``surface`` at ``nxh`` x ``nyh``
        (each at least 2) evenly spaced nodes from the grid's corner to its far corner,
        ``heights[j][i]`` at ``x`` node ``i`` and ``y`` node ``j``, between them MuJoCo's
        heightfield's triangles (:func:`surface_at`); None: a plane. :meth:`from_hfield` reads a MuJoCo heightfield.

    Examples
    --------
    >>> import mudrft
    >>> f = MudField({"firm": 0.25, "soft": 0.35}, ["firm soft"], cell_size=0.5)
    >>> f.names, f.cells.tolist()
    (('firm', 'soft'), [[0, 1]])
    >>> share, c = f.blend(0.5, 0.3)  # on the border: half of each
    >>> rows = f.arrays()[2]
    >>> share, bool(c[0] == (rows[0, 0] + rows[1, 0]) / 2)
    (1.0, True)
    """

    regions: Mapping[str, object]
    cells: Any
    cell_size: float | tuple[float, float] = 1.0
    origin: tuple[float, float] = (0.0, 0.0)
    border: float = 0.05
    heights: Any = None
    terrains: tuple[MudTerrain | None, ...] = field(init=False, repr=False)
    names: tuple[str, ...] = field(init=False, repr=False)
    grid: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.regions, Mapping) or not self.regions:
            raise MudrftError(f"regions must be a non-empty mapping {{name: mud}}, got {self.regions!r}")  # fmt: skip
        names = tuple(str(k) for k in self.regions)
        terrains = tuple(_terrain(k, v) for k, v in zip(names, self.regions.values(), strict=True))
        muds = [t for t in terrains if t is not None]
        if not muds:
            raise MudrftError("regions: at least one region must be mud, got only rigid ground")
        for n, t in zip(names, terrains, strict=True):
            if t is not None and not same_options(t, muds[0]):
                raise MudrftError(
                    f"region {n!r}: its MudTerrain options differ from the first mud's; the regions "
                    "of a field share them (evaluation, characteristic length, ...)"
                )
        try:
            rows = [r.split() if isinstance(r, str) else list(r) for r in self.cells]
        except TypeError:
            rows = []
        if not rows or not rows[0] or any(len(r) != len(rows[0]) for r in rows):
            raise MudrftError(f"cells must be a non-empty grid of rows of equal length, got {self.cells!r}")  # fmt: skip
        index = {n: i for i, n in enumerate(names)}
        unknown = sorted({str(c) for r in rows for c in r} - set(index))
        if unknown:
            raise MudrftError(f"cells name regions {unknown} that regions does not define ({list(names)})")  # fmt: skip
        size = self.cell_size
        hx, hy = (size, size) if isinstance(size, int | float) else tuple(size)
        hx, hy = positive_number("cell_size", hx, unit="m"), positive_number("cell_size", hy, unit="m")  # fmt: skip
        b = positive_number("border", self.border, unit="m")
        if b > min(hx, hy):
            raise MudrftError(f"border must be at most the cell size ({plain(min(hx, hy))} m), got {plain(b)} m")  # fmt: skip
        x0, y0 = (float(v) for v in self.origin)
        if not (math.isfinite(x0) and math.isfinite(y0)):
            raise MudrftError(f"origin must be two finite numbers [m], got {self.origin!r}")
        cells = np.array([[index[str(c)] for c in r] for r in rows], dtype=np.int64)
        h = np.zeros((1, 1)) if self.heights is None else np.array(self.heights, dtype=float)
        if h.shape != (1, 1) and (h.ndim != 2 or min(h.shape) < 2 or not np.all(np.isfinite(h))):
            raise MudrftError(f"heights must be None or finite heights [m] on a grid of at least 2 x 2 nodes, got shape {h.shape}")  # fmt: skip
        object.__setattr__(self, "heights", h)
        object.__setattr__(self, "cells", cells)
        object.__setattr__(self, "names", names)
        object.__setattr__(self, "terrains", terrains)
        object.__setattr__(self, "grid", np.array([x0, y0, hx, hy, b]))

    @classmethod
    def from_toml(cls, path: str | PathLike[str]) -> MudField:
        """A field from a TOML file: ``cell_size``, ``origin``, ``border`` and ``cells`` at
        the top, the regions in a ``[regions]`` table (water contents or ``"rigid"``)."""
        try:
            with open(path, "rb") as fh:
                spec = tomllib.load(fh)
        except (OSError, tomllib.TOMLDecodeError) as exc:
            raise MudrftError(f"{path}: cannot be read as a field spec ({exc})") from None
        extra = sorted(set(spec) - {"regions", "cells", "cell_size", "origin", "border", "heights"})
        if extra or "regions" not in spec or "cells" not in spec:
            raise MudrftError(
                f"{path}: a field spec has regions and cells (and cell_size, origin, border, "
                f"heights); got keys {sorted(spec)}"
            )
        return cls(**spec)

    @classmethod
    def from_polygons(
        cls,
        regions: Mapping[str, object],
        polygons: Sequence[tuple[str, ArrayLike]],
        *,
        outside: str,
        bounds: tuple[float, float, float, float],
        cell_size: float,
        border: float | None = None,
    ) -> MudField:
        """A field from polygons, rasterized on cells of ``cell_size`` [m]: each cell takes
        the region of the last polygon (``(name, vertices (k, 2) [m])``) that holds its
        center, else ``outside``; ``bounds`` ``(x0, y0, x1, y1)`` [m]. A border thus follows
        the cells, within ``cell_size`` of the polygon's edge; ``border`` defaults to
        ``cell_size``. Needs matplotlib (extra ``plot``) for the point-in-polygon test.
        """
        try:
            from matplotlib.path import Path
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise ImportError("MudField.from_polygons needs matplotlib: pip install 'mudrft[plot]'") from exc  # fmt: skip
        h = positive_number("cell_size", cell_size, unit="m")
        x0, y0, x1, y1 = (float(v) for v in bounds)
        if not (x1 > x0 and y1 > y0):
            raise MudrftError(f"bounds must be (x0, y0, x1, y1) with x1 > x0 and y1 > y0 [m], got {bounds!r}")  # fmt: skip
        nx, ny = max(round((x1 - x0) / h), 1), max(round((y1 - y0) / h), 1)
        cx, cy = np.meshgrid(x0 + h * (np.arange(nx) + 0.5), y0 + h * (np.arange(ny) + 0.5))
        centers = np.column_stack([cx.ravel(), cy.ravel()])
        names = np.full(len(centers), outside, dtype=object)
        for i, (name, vertices) in enumerate(polygons):
            v = np.asarray(vertices, dtype=float)
            if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3 or not np.all(np.isfinite(v)):
                raise MudrftError(f"polygons[{i}] ({name!r}) must be three or more finite (x, y) vertices [m], got shape {v.shape}")  # fmt: skip
            names[Path(v).contains_points(centers)] = name
        cells = names.reshape(ny, nx).tolist()
        return cls(regions, cells, h, (x0, y0), h if border is None else border)

    @classmethod
    def from_hfield(
        cls,
        model: Any,
        geom: str | int,
        regions: Mapping[str, object],
        cells: Any = None,
        *,
        surface: float = 0.0,
        border: float | None = None,
    ) -> MudField:
        """A field on a MuJoCo heightfield: the surface of ``model``'s hfield geom ``geom``
        (name or id; not rotated), its heights taken over ``surface`` [m], the coupling's
        ``surface``. ``cells`` as in :class:`MudField` over the heightfield's rectangle
        (None: the first region everywhere); ``border`` [m] defaults to the smaller cell
        size. The geom stays in the model: where the mud is, it must not collide
        (``contype="0" conaffinity="0"``), or MuJoCo's contact carries the feet.
        """
        import mujoco

        g = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, geom) if isinstance(geom, str) else int(geom)  # fmt: skip
        if not 0 <= g < model.ngeom or model.geom_type[g] != mujoco.mjtGeom.mjGEOM_HFIELD:
            raise MudrftError(f"geom must name a heightfield geom (type hfield) of the model, got {geom!r}")  # fmt: skip
        d = mujoco.MjData(model)
        mujoco.mj_kinematics(model, d)
        if not np.allclose(d.geom_xmat[g], np.eye(3).ravel()):
            raise MudrftError(f"the heightfield geom {geom!r} is rotated; mudrft takes an upright, unrotated one")  # fmt: skip
        h = int(model.geom_dataid[g])
        nrow, ncol, adr = int(model.hfield_nrow[h]), int(model.hfield_ncol[h]), int(model.hfield_adr[h])  # fmt: skip
        rx, ry, top = (float(v) for v in model.hfield_size[h][:3])
        data = np.asarray(model.hfield_data[adr : adr + nrow * ncol], dtype=float).reshape(nrow, ncol)  # fmt: skip
        x, y, z = (float(v) for v in d.geom_xpos[g])
        cells = [[next(iter(regions))]] if cells is None else cells
        try:
            ny, nx = len(cells), len(cells[0].split() if isinstance(cells[0], str) else cells[0])
        except (TypeError, IndexError):
            ny, nx = 0, 0  # refused by MudField with its own message
        hx, hy = 2.0 * rx / max(nx, 1), 2.0 * ry / max(ny, 1)
        border = min(hx, hy) if border is None else border
        return cls(regions, cells, (hx, hy), (x - rx, y - ry), border, z - surface + top * data)

    def height(self, x: float, y: float) -> tuple[float, FloatArray]:
        """The surface's height [m] over the coupling's ``surface`` at ``(x, y)`` [m], and
        its upward unit normal (3,) [-] (:func:`surface_at`)."""
        ny, nx = self.cells.shape
        h, gx, gy = surface_at(float(x), float(y), self.grid, ny, nx, self.heights)
        return float(h), np.array([-gx, -gy, 1.0]) / math.sqrt(1.0 + gx * gx + gy * gy)

    @property
    def has_rigid(self) -> bool:
        """Whether a region is rigid ground (a draw of the layout may put it in any cell)."""
        return any(t is None for t in self.terrains)

    @property
    def terrain(self) -> MudTerrain:
        """The first mud region: the options (and initial state) every mud region shares."""
        return next(t for t in self.terrains if t is not None)

    def arrays(self) -> tuple[FloatArray, IndexArray, FloatArray]:
        """``(grid, cells, rows)`` of :func:`field_row`: rows (R, N_CONST + 1), each
        region's constants and its mud flag (rigid ground: the first mud's constants)."""
        first = constant_row(*self.terrain.constants)
        rows = np.array([
            [*(first if t is None else constant_row(*t.constants)), 0.0 if t is None else 1.0]
            for t in self.terrains
        ])  # fmt: skip
        return self.grid, self.cells, rows

    def randomized(
        self,
        seed: int | np.random.Generator,
        *,
        water_content: tuple[float, float] | None = None,
        scale: Mapping[str, tuple[float, float]] | None = None,
        layout: bool = False,
    ) -> MudField:
        """A field drawn from this one, the same for the same ``seed`` (for an environment's
        reset; the shape, and so a compiled MJX step, stays this field's).

        Parameters
        ----------
        seed : int or numpy.random.Generator
            The draw's seed.
        water_content : (float, float) or None, keyword-only
            Each mud region becomes :func:`mudrft.paper_mud` at a water content [-] drawn
            uniformly from this range (outside 0.25-0.45 the paper's table is extrapolated,
            down to 0.15 and up to 0.50); None keeps the regions' muds.
        scale : mapping or None, keyword-only
            ``{parameter: (low, high)}``: each mud region's parameter (of
            :class:`~mudrft.MudParameters`, both directions) times a factor drawn
            log-uniformly from the range [-].
        layout : bool, keyword-only
            Each cell draws its region uniformly from the field's regions.
        """
        rng = np.random.default_rng(seed)
        regions: dict[str, object] = {}
        for name, t in zip(self.names, self.terrains, strict=True):
            if t is None:
                regions[name] = RIGID
                continue
            mud = t.mud
            if water_content is not None:
                lo, hi = (float(v) for v in water_content)
                if not 0.15 <= lo <= hi <= 0.5:
                    raise MudrftError(f"water_content must be (low, high) within [0.15, 0.5], got {water_content!r}")  # fmt: skip
                with warnings.catch_warnings():  # the range was the caller's choice
                    warnings.simplefilter("ignore")
                    mud = paper_mud(float(rng.uniform(lo, hi)), extrapolate=True)
            for key, (lo, hi) in (scale or {}).items():
                if key not in MudParameters.__dataclass_fields__ or not 0 < lo <= hi:
                    raise MudrftError(f"scale must map MudParameters fields to (low, high) > 0, got {key!r}: {(lo, hi)!r}")  # fmt: skip
                f = float(np.exp(rng.uniform(np.log(lo), np.log(hi))))
                mud = type(mud)(
                    mud.vertical.replace(**{key: getattr(mud.vertical, key) * f}),
                    mud.horizontal.replace(**{key: getattr(mud.horizontal, key) * f}),
                    mud.water_content, mud.name,
                )  # fmt: skip
            regions[name] = dataclasses.replace(t, mud=mud)
        cells = self.cells
        if layout:
            cells = rng.integers(0, len(self.names), size=cells.shape)
            if not any(self.terrains[i] is not None for i in np.unique(cells)):
                cells.flat[0] = self.terrains.index(self.terrain)  # the first mud
        names = [[self.names[i] for i in row] for row in cells]
        return dataclasses.replace(self, regions=regions, cells=names)

    def blend(self, x: float, y: float) -> tuple[float, FloatArray]:
        """The mud's share [-] and the constants (N_CONST,) a tip at ``(x, y)`` [m] feels."""
        out = np.zeros(N_CONST)
        return field_row(float(x), float(y), *self.arrays(), out), out


def field_blend(
    x: XpArray, y: XpArray, grid: XpArray, cells: XpArray, rows: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray]:
    """:func:`field_row` on arrays (numpy or JAX): tips at ``x``, ``y`` (...) [m] give the
    mud's share (...) [-] and the constants (..., N_CONST)."""
    x0, y0, hx, hy, half = grid[0], grid[1], grid[2], grid[3], 0.5 * grid[4]
    ny, nx = cells.shape
    ix = xp.floor((x - half - x0) / hx)
    iy = xp.floor((y - half - y0) / hy)
    regions = xp.arange(rows.shape[0])
    weight = 0.0
    for a in range(2):
        wy = cell_overlap(y, y0, hy, half, iy + a, xp)
        j = xp.clip(iy + a, 0, ny - 1).astype(int)
        for c in range(2):
            w = wy * cell_overlap(x, x0, hx, half, ix + c, xp)
            r = cells[j, xp.clip(ix + c, 0, nx - 1).astype(int)]
            weight = weight + w[..., None] * (r[..., None] == regions)  # (..., R)
    mud = rows[:, N_CONST]
    wm_r = weight * mud
    wm, wr = xp.sum(wm_r, axis=-1), xp.sum(weight * (1.0 - mud), axis=-1)
    share = xp.where(wr == 0.0, 1.0, wm / xp.where(wr == 0.0, 1.0, wm + wr))
    blended = (wm_r @ rows[:, :N_CONST]) / xp.where(wm > 0.0, wm, 1.0)[..., None]
    one = rows[xp.argmax(wm_r, axis=-1), :N_CONST]  # one mud (or none: the first row)
    single = xp.sum(wm_r > 0.0, axis=-1) <= 1
    return share, xp.where(single[..., None], one, blended)


def same_options(a: MudTerrain, b: object) -> bool:
    """Whether mud terrains ``a`` and ``b`` share their options (all but the mud)."""
    names = [f.name for f in dataclasses.fields(MudTerrain) if f.init and f.name not in ("mud", "name")]  # fmt: skip
    return isinstance(b, MudTerrain) and all(getattr(a, k) == getattr(b, k) for k in names)


def uniform(terrain: MudTerrain) -> tuple[FloatArray, IndexArray, FloatArray]:
    """The field arrays ``(grid, cells, rows)`` of one mud everywhere."""
    rows = np.append(constant_row(*terrain.constants), 1.0)[None]
    return np.array([0.0, 0.0, 1.0, 1.0, 1.0]), np.zeros((1, 1), dtype=np.int64), rows
