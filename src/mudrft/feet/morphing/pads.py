r"""The morphing foot's base and pads in the mud: submerged areas and forces (D33, D38).

Each trapezoidal pad is a thin plate at tilt :math:`\psi_1=\theta` under the plate rule of
eqs. (6)-(7), its areas and forces derived in docs/model.md (D33). Unchecked (:mod:`.foot`
validates), dimensions ``g`` [m, rad] by attribute; the force's functions are element-wise
over ``xp``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._typing import Namespace, XpArray
from ...constitutive.laws import f_n, f_t
from ..base import SurfaceElements, fold_heading, world_force
from .linkage import MorphingFootGeometry

if TYPE_CHECKING:
    from .linkage import MorphingRow

__all__ = [
    "center_height", "coefficients", "footprint_area", "horizontal_area", "morphing_force",
    "pad_area", "pad_corners", "submerged_length", "surface_elements", "vertical_area"
]  # fmt: skip

_FLAT = 1e-12  # sin(theta) below which a pad counts as lying flat at the pivot height [-]
_WALL_SEGMENTS = 16  # elements around the base rim and the column in surface_elements [-]


def pad_area(g: MorphingFootGeometry | MorphingRow, length: XpArray, xp: Namespace = np) -> XpArray:
    """Area of one pad from its pivot to a distance ``length`` [m] along it [m^2]."""
    kappa = (g.pad_outer_width - g.pad_inner_width) / g.pad_length
    return g.pad_inner_width * length + 0.5 * kappa * length * length


def submerged_length(
    g: MorphingFootGeometry | MorphingRow, depth: XpArray, theta: XpArray, xp: Namespace = np
) -> XpArray:
    """Length of each pad below the mud surface from its pivot [m], at tip ``depth`` [m] and
    pad angle ``theta`` [rad]."""
    rise = depth - g.pivot_height
    s = xp.sin(theta)
    flat = s <= _FLAT
    return xp.where(
        flat,
        xp.where(rise > 0.0, g.pad_length, 0.0),
        xp.clip(rise / xp.where(flat, 1.0, s), 0.0, g.pad_length),
    )


def vertical_area(
    g: MorphingFootGeometry | MorphingRow, depth: XpArray, theta: XpArray, xp: Namespace = np
) -> XpArray:
    """Effective vertical area :math:`A_z` of the base and pads [m^2] (D33) at tip ``depth``
    [m] and pad angle ``theta`` [rad]."""
    base = xp.where(depth > 0.0, math.pi * g.base_radius * g.base_radius, 0.0)
    pad = pad_area(g, submerged_length(g, depth, theta, xp=xp), xp=xp)
    weight = f_n(theta, xp=xp) * xp.cos(theta) + f_t(theta, xp=xp) * xp.sin(theta)
    return base + g.n_pads * pad * weight


def horizontal_area(
    g: MorphingFootGeometry | MorphingRow, depth: XpArray, theta: XpArray, heading: XpArray,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """Submerged area projected normal to the ``heading`` [rad], :math:`A_h` [m^2] (D33), at
    tip ``depth`` [m] and pad angle ``theta`` [rad]."""
    col = 2.0 * g.base_radius * xp.clip(depth, 0.0, g.pivot_height) + 2.0 * g.column_radius * (
        xp.clip(depth - g.pivot_height, 0.0, g.height - g.pivot_height)
    )
    pad = pad_area(g, submerged_length(g, depth, theta, xp=xp), xp=xp) * xp.sin(theta)
    n = int(g.n_pads)
    proj = 0.0 * heading  # sum over the pads at azimuths 2 pi k / N
    for k in range(n):
        proj = proj + xp.abs(xp.cos(2.0 * math.pi * k / n - heading))
    return col + pad * proj


def footprint_area(
    g: MorphingFootGeometry, depth: ArrayLike, theta: ArrayLike
) -> NDArray[np.float64]:
    """Horizontal projection of the submerged base and pads [m^2] (D36, D38) at tip
    ``depth`` [m] (``inf``: the whole foot) and pad angle ``theta`` [rad]."""
    d = np.asarray(depth, dtype=float)
    base = np.where(d > 0, math.pi * g.base_radius**2, 0.0)
    whole = np.isinf(d)
    length = np.where(whole, g.pad_length, submerged_length(g, np.where(whole, 0.0, d), theta))
    return np.asarray(base + g.n_pads * pad_area(g, length) * np.cos(theta))


def coefficients(
    g: MorphingFootGeometry | MorphingRow, depth: XpArray, theta: XpArray, phi: XpArray,
    xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray, XpArray, XpArray]:  # fmt: skip
    """Coefficients ``(a_x, b_x, b_y, a_y, a_z)`` [m^2] of the linear force (D33) at tip
    ``depth`` [m], pad angle ``theta`` [rad] and folded heading ``phi`` [rad]."""
    ah = horizontal_area(g, depth, theta, phi, xp=xp)
    zero = 0.0 * ah
    return (ah * xp.cos(phi), zero, zero, ah * xp.sin(phi), vertical_area(g, depth, theta, xp=xp))


def morphing_force(
    g: MorphingFootGeometry | MorphingRow, depth: XpArray, theta: XpArray, sx: XpArray, sy: XpArray,
    sz: XpArray, heading: XpArray, xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray]:  # fmt: skip
    """World force ``(F_x, F_y, F_z)`` [N] of the base and pads at pad angle ``theta`` [rad]:
    :func:`coefficients` at the folded heading, then the heading rule (D9); depth [m], signed
    stresses [Pa], world heading [rad]."""
    co = coefficients(g, depth, theta, fold_heading(heading, xp=xp), xp=xp)
    return world_force(co, sx, sy, sz, heading, xp=xp)


def center_height(
    g: MorphingFootGeometry, depth: ArrayLike, theta: ArrayLike
) -> NDArray[np.float64]:
    """Height above the tip [m] of the center of the vertical pressure: the
    :math:`A_z`-weighted centroid of the submerged base (z = 0) and pad parts, or half the
    submerged height when nothing is submerged; tip ``depth`` [m], pad angle ``theta`` [rad]."""
    d, th = np.broadcast_arrays(np.asarray(depth, dtype=float), np.asarray(theta, dtype=float))
    length = submerged_length(g, d, th)
    kappa = (g.pad_outer_width - g.pad_inner_width) / g.pad_length
    area = pad_area(g, length)
    moment = g.pad_inner_width * length**2 / 2 + kappa * length**3 / 3
    sbar = np.where(area > 0, moment / np.where(area > 0, area, 1.0), 0.0)
    wp = g.n_pads * area * (f_n(th) * np.cos(th) + f_t(th) * np.sin(th))
    wb = np.where(d > 0, math.pi * g.base_radius**2, 0.0)
    zp, tot = g.pivot_height + sbar * np.sin(th), wp + wb
    return np.where(tot > 0, wp * zp / np.where(tot > 0, tot, 1.0), 0.5 * np.minimum(d, g.height))


def pad_corners(g: MorphingFootGeometry, theta: float) -> NDArray[np.float64]:
    """Corners of every pad in the foot frame [m], shape (n_pads, 4, 3), at pad angle
    ``theta`` [rad]: pivot-left, pivot-right, rim-right, rim-left."""
    out = np.empty((g.n_pads, 4, 3))
    for k, a in enumerate(g.azimuths):
        er = np.array([math.cos(a), math.sin(a), 0.0])
        et = np.array([-math.sin(a), math.cos(a), 0.0])
        p0 = g.base_radius * er + np.array([0.0, 0.0, g.pivot_height])
        p1 = p0 + g.pad_length * (math.cos(theta) * er + np.array([0.0, 0.0, math.sin(theta)]))
        out[k] = [
            p0 - 0.5 * g.pad_inner_width * et,
            p0 + 0.5 * g.pad_inner_width * et,
            p1 + 0.5 * g.pad_outer_width * et,
            p1 - 0.5 * g.pad_outer_width * et,
        ]
    return out


def surface_elements(g: MorphingFootGeometry, theta: float, *, strips: int) -> SurfaceElements:
    r"""Surface elements of the base, its rim, the column and both faces of the pads [m] (D159),
    ``strips`` elements each, at pad angle ``theta`` [rad]."""
    edges = np.linspace(0.0, g.pad_length, strips + 1)
    areas_1 = np.diff(pad_area(g, edges))
    mids = 0.5 * (edges[1:] + edges[:-1])
    cen, nor = [np.array([[0.0, 0.0, 0.0]])], [np.array([[0.0, 0.0, -1.0]])]
    ar = [np.array([math.pi * g.base_radius**2])]
    ez = np.array([0.0, 0.0, 1.0])
    # walls: the base pad's rim up to the pivots, the column above them (outward normals)
    az = 2.0 * math.pi * (np.arange(_WALL_SEGMENTS) + 0.5) / _WALL_SEGMENTS
    er_w = np.stack([np.cos(az), np.sin(az), np.zeros_like(az)], axis=-1)
    for radius, z0, z1 in (
        (g.base_radius, 0.0, g.pivot_height),
        (g.column_radius, g.pivot_height, g.height),
    ):
        zs = np.linspace(z0, z1, strips + 1)
        zm = 0.5 * (zs[1:] + zs[:-1])
        cen.append((radius * er_w[:, None, :] + zm[None, :, None] * ez).reshape(-1, 3))
        nor.append(np.repeat(er_w, strips, axis=0))
        area = 2.0 * math.pi * radius * (z1 - z0) / (_WALL_SEGMENTS * strips)
        ar.append(np.full(_WALL_SEGMENTS * strips, area))
    for a in g.azimuths:
        er = np.array([math.cos(a), math.sin(a), 0.0])
        p = (g.base_radius * er + g.pivot_height * ez)[None, :] + mids[:, None] * (
            math.cos(theta) * er + math.sin(theta) * ez
        )[None, :]
        lower = math.sin(theta) * er - math.cos(theta) * ez
        for normal in (lower, -lower):  # a thin plate: both faces
            cen.append(p)
            nor.append(np.tile(normal, (strips, 1)))
            ar.append(areas_1)
    return SurfaceElements(np.concatenate(cen), np.concatenate(nor), np.concatenate(ar))
