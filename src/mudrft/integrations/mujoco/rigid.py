"""Rigid ground in a field of mud: a box geom per cell of a :class:`~mudrft.MudField`, which
MuJoCo's contact uses where the cell is rigid (the coupling gives no mud force there) and
ignores where it is mud; a new draw of the field switches them (an environment's reset)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..._validation import MudrftError, positive_number
from ._lazy import _mujoco

if TYPE_CHECKING:
    import mujoco

    from ...terrains.field import MudField

#: Names of the cell boxes: ``f"{RIGID_CELL}_{j}_{i}"`` for cell ``cells[j][i]``.
RIGID_CELL = "mudrft_rigid_cell"
#: How far an edge cell's box reaches beyond the grid [m].
FAR = 100.0
#: The colour of a rigid cell (a mud cell's box is transparent).
ROCK = (0.45, 0.45, 0.45, 1.0)


def add_rigid_cells(
    spec: Any, field: MudField, *, surface: float = 0.0, thickness: float = 0.05
) -> None:
    """Add to ``spec`` (a ``mujoco.MjSpec``) a box under each cell of ``field``'s grid: the
    cell's size (an edge cell's reaching :data:`FAR` beyond the grid, where the field's
    nearest cell holds), ``thickness`` [m] deep, its top at the surface [m] (``surface`` plus
    the field's height at the cell's center). Boxes collide with geoms of ``contype`` 1 (the
    default); :func:`set_rigid_cells` on the compiled model makes only the rigid ones do.
    """
    from ...terrains.field import surface_at

    box = _mujoco().mjtGeom.mjGEOM_BOX
    t = positive_number("thickness", thickness, unit="m")
    x0, y0, hx, hy, _ = (float(v) for v in field.grid)
    ny, nx = field.cells.shape

    # the cells' edges: an edge cell reaches FAR beyond the grid, as the field's nearest cell
    xs, ys = x0 + np.arange(nx + 1) * hx, y0 + np.arange(ny + 1) * hy
    xs[[0, -1]] += (-FAR, FAR)
    ys[[0, -1]] += (-FAR, FAR)
    for j, i in np.ndindex(ny, nx):
        (xa, xb), (ya, yb) = xs[i : i + 2], ys[j : j + 2]
        cx, cy = x0 + (i + 0.5) * hx, y0 + (j + 0.5) * hy
        top = float(surface) + float(surface_at(cx, cy, field.grid, ny, nx, field.heights)[0])
        g = spec.worldbody.add_geom()
        g.name = f"{RIGID_CELL}_{j}_{i}"
        g.type = box
        g.size = [(xb - xa) / 2, (yb - ya) / 2, t / 2]
        g.pos = [(xa + xb) / 2, (ya + yb) / 2, top - t / 2]
        # colliding as compiled: MuJoCo keeps a body's contact bits from its geoms then
        g.contype, g.conaffinity = 1, 1


def set_rigid_cells(model: mujoco.MjModel, field: MudField) -> int:
    """Make ``model``'s cell boxes (:func:`add_rigid_cells`) collide and show where
    ``field``'s cell is rigid, and neither where it is mud; the number of rigid cells.
    ``field`` has the shape of the one the boxes were added for (a draw of it)."""
    mj = _mujoco()
    ny, nx = field.cells.shape
    rigid = np.array([t is None for t in field.terrains])[field.cells]
    for j, i in np.ndindex(ny, nx):
        g = mj.mj_name2id(model, mj.mjtObj.mjOBJ_GEOM, f"{RIGID_CELL}_{j}_{i}")
        if g < 0:
            raise MudrftError(
                f"the model has no box for cell ({j}, {i}) of the field: add them with "
                f"add_rigid_cells for a field of this shape ({ny} x {nx} cells)"
            )
        on = bool(rigid[j, i])
        model.geom_contype[g], model.geom_conaffinity[g] = int(on), int(on)
        model.geom_rgba[g] = ROCK if on else (0.0, 0.0, 0.0, 0.0)
    return int(rigid.sum())
