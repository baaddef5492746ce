r"""Surface-element integration of the 3D force law (Chen et al. 2026, eqs. 6-7) on triangles.

Triangles (..., m, 3, 3) [m] are in the foot frame (tip at :math:`z=0`, z up), clipped
exactly by the mud surface :math:`z=d` (the tip ``depth``); the rule of one facet is
:mod:`mudrft.feet.facet`. Every function takes an ``xp`` namespace (``numpy`` by default,
``jax.numpy``); batch axes broadcast.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._typing import Namespace, XpArray
from .facet import (
    clip_constants,
    clip_facet,
    facet_factors,
    facet_force,
    facet_frame,
    safe_div,
    sort_by_height,
)
from .facet import submerged_area as facet_submerged_area

__all__ = [
    "PreparedTriangles", "Wrench", "clip_below", "element_forces", "integrate_prepared",
    "integrate_triangles", "integrate_wrench", "prepare_triangles", "submerged_area"
]  # fmt: skip


class PreparedTriangles(NamedTuple):
    """Per-facet data independent of depth, stress and heading (:func:`prepare_triangles`):
    vertices ``lo, mid, hi`` sorted by height [m], outward unit ``normal`` [-], ``area``
    [m^2], clipping constants (:func:`~mudrft.feet.facet.clip_constants`), the weights of
    :func:`~mudrft.feet.facet.facet_frame` [-] and sorted heights ``za, zb, zc`` [m]."""

    lo: XpArray
    mid: XpArray
    hi: XpArray
    normal: XpArray
    area: XpArray
    k_low: XpArray
    k_high: XpArray
    nh: XpArray
    hx: XpArray
    hy: XpArray
    wz: XpArray
    za: XpArray
    zb: XpArray
    zc: XpArray
    flat_area: XpArray


class Wrench(NamedTuple):
    """Resultant of the element forces: ``force`` (..., 3) [N], ``moment`` about the
    reference point (..., 3) [N m] and ``center_of_pressure`` (..., 3) [m] (D24; the
    reference point when no force acts)."""

    force: XpArray
    moment: XpArray
    center_of_pressure: XpArray


def prepare_triangles(triangles: XpArray, xp: Namespace = np) -> PreparedTriangles:
    """Per-facet data of ``triangles`` (..., m, 3, 3) [m], wound outward (right-hand rule).

    >>> tri = np.array([[[0, 0, 0], [0, 1, 0], [1, 0, 0]]], dtype=float)  # faces down
    >>> p = prepare_triangles(tri)
    >>> p.normal[0].tolist(), float(p.area[0])
    ([0.0, 0.0, -1.0], 0.5)
    """
    tri = xp.asarray(triangles)
    v0, v1, v2 = tri[..., 0, :], tri[..., 1, :], tri[..., 2, :]
    v = (v0[..., 0], v0[..., 1], v0[..., 2], v1[..., 0], v1[..., 1], v1[..., 2],
         v2[..., 0], v2[..., 1], v2[..., 2])  # fmt: skip
    nx, ny, nz, area, nh, hx, hy, wz = facet_frame(*v, xp=xp)
    srt = sort_by_height(*v, xp=xp)
    za, zb, zc = srt[2], srt[5], srt[8]
    k_low, k_high, flat_area = clip_constants(za, zb, zc, area, xp=xp)
    return PreparedTriangles(
        xp.stack(srt[0:3], axis=-1),
        xp.stack(srt[3:6], axis=-1),
        xp.stack(srt[6:9], axis=-1),
        xp.stack([nx, ny, nz], axis=-1),
        area, k_low, k_high, nh, hx, hy, wz, za, zb, zc, flat_area,
    )  # fmt: skip


def submerged_area(prepared: PreparedTriangles, depth: XpArray, xp: Namespace = np) -> XpArray:
    """Exact submerged area of each facet [m^2], shape (..., m), at tip ``depth`` [m]."""
    p, d = prepared, xp.asarray(depth)[..., None]
    return facet_submerged_area(p.za, p.zb, p.zc, p.k_low, p.k_high, p.flat_area, d, xp=xp)


def clip_below(
    prepared: PreparedTriangles, depth: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray]:
    """Area [m^2] (..., m) and centroid [m] (..., m, 3) of each facet's part below the plane
    ``z = depth`` [m]; the centroid is the facet's where nothing is submerged.

    >>> tri = np.array([[[0, 0, 0], [1, 0, 1], [-1, 0, 1]]], dtype=float)  # vertical, 1 m tall
    >>> a, c = clip_below(prepare_triangles(tri), 0.5)
    >>> float(a[0]), c[0].round(4).tolist()
    (0.25, [0.0, 0.0, 0.3333])
    """
    p, d = prepared, xp.asarray(depth)[..., None]
    a, b, c = p.lo, p.mid, p.hi
    area, cx, cy, cz = clip_facet(
        a[..., 0], a[..., 1], a[..., 2], b[..., 0], b[..., 1], b[..., 2],
        c[..., 0], c[..., 1], c[..., 2], p.k_low, p.k_high, p.flat_area, d, xp=xp,
    )  # fmt: skip
    return area, xp.stack(xp.broadcast_arrays(cx, cy, cz), axis=-1)


def _facet_forces(
    p: PreparedTriangles, area: XpArray, stress: XpArray, heading: XpArray, trailing: bool,
    xp: Namespace,
) -> tuple[XpArray, XpArray, XpArray]:  # fmt: skip
    """The force components (..., m) [N] on facets of submerged ``area`` [m^2]."""
    s, h = xp.asarray(stress), xp.asarray(heading)[..., None]
    fn, ft = facet_factors(p.hx, p.hy, xp.cos(h), xp.sin(h), trailing, xp=xp)
    sx, sy, sz = (s[..., k][..., None] for k in range(3))
    return facet_force(area, p.nh, p.hx, p.hy, p.wz, sx, sy, sz, fn, ft, xp=xp)


def element_forces(
    prepared: PreparedTriangles, depth: XpArray, stress: XpArray, heading: XpArray, *,
    trailing: bool = False, xp: Namespace = np,
) -> tuple[XpArray, XpArray]:  # fmt: skip
    """Force of the mud on each facet [N] (..., m, 3) and the centroid of its submerged
    polygon [m] (..., m, 3); arguments as in :func:`integrate_triangles`."""
    area, cen = clip_below(prepared, depth, xp=xp)
    f = _facet_forces(prepared, 1.0, stress, heading, trailing, xp)
    return xp.stack(xp.broadcast_arrays(*f), axis=-1) * area[..., None], cen


def integrate_prepared(
    prepared: PreparedTriangles, depth: XpArray, stress: XpArray, heading: XpArray, *,
    trailing: bool = False, xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """:func:`integrate_triangles` on facets from :func:`prepare_triangles` [N]."""
    area = submerged_area(prepared, depth, xp=xp)
    f = _facet_forces(prepared, area, stress, heading, trailing, xp)
    fx, fy, fz = (xp.sum(c, axis=-1) for c in f)
    return xp.stack(xp.broadcast_arrays(fx, fy, fz), axis=-1) + 0.0  # -0.0 -> 0.0


def integrate_triangles(
    triangles: XpArray, depth: XpArray, stress: XpArray, heading: XpArray, *,
    trailing: bool = False, xp: Namespace = np,
) -> XpArray:  # fmt: skip
    r"""Force of the mud on a triangulated foot: the element rule integrated and summed.

    Parameters
    ----------
    triangles : array_like, shape (..., m, 3, 3)
        Triangles in the foot frame, tip at :math:`z=0` [m]; outward winding.
    depth : array_like, shape (...)
        Tip depth [m]: the mud surface is the plane :math:`z=` ``depth``.
    stress : array_like, shape (..., 3)
        Signed channel stresses (sx, sy, sz) [Pa]; sx > 0 resists motion toward +x.
    heading : array_like, shape (...)
        Heading of the horizontal motion from the x axis [rad], any angle.
    trailing : bool, optional
        Let facets that trail the motion resist too (the sphere's derivation, D23).

    Returns
    -------
    array, shape (..., 3)
        (Fx, Fy, Fz) [N] in the foot frame; Fz > 0 is support.

    Notes
    -----
    .. math::
       :label: chen2026-eq-6

       dF_x=(-\sigma_h^n\cos\varphi+\sigma_h^t\sin\varphi)\,dS_h,\quad
       dF_y=-(\sigma_h^n\sin\varphi+\sigma_h^t\cos\varphi)\,dS_h,\quad
       dF_z=(\sigma_v^n\cos\psi_1+\sigma_v^t\sin\psi_1)\,dS \tag{6}

    with :math:`f_n=\cos^2`, :math:`f_t=\sin^2` (eq. 7), per facet by
    :func:`mudrft.feet.facet.facet_force` (erratum E24: the sign of dF_y).

    Examples
    --------
    >>> sq = np.array([[[0, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 0, 0], [1, 1, 0], [1, 0, 0]]], float)
    >>> integrate_triangles(sq, 0.01, [0.0, 0.0, 5.0], 0.0).tolist()
    [0.0, 0.0, 5.0]
    """
    return integrate_prepared(
        prepare_triangles(triangles, xp=xp), depth, stress, heading, trailing=trailing, xp=xp
    )


def integrate_wrench(
    triangles: XpArray, depth: XpArray, stress: XpArray, heading: XpArray, *, point: XpArray = None,
    trailing: bool = False, xp: Namespace = np, prepared: PreparedTriangles | None = None,
) -> Wrench:  # fmt: skip
    r"""Force, moment about ``point`` and center of pressure of the mud on a triangulated foot.

    Each facet's force acts at its submerged centroid; the center of pressure is the point of
    the wrench's central axis nearest to their :math:`|d\mathbf F|`-weighted centroid (D24).

    Parameters
    ----------
    triangles : array_like, shape (..., m, 3, 3)
        Triangles in the foot frame [m] (ignored when ``prepared`` is given).
    depth, stress, heading, trailing
        As in :func:`integrate_triangles`: depth [m], stresses [Pa], heading [rad].
    point : array_like, shape (..., 3), optional
        Reference point for the moment, in the foot frame [m]; default the tip.
    prepared : PreparedTriangles, optional
        Facet data from :func:`prepare_triangles`, to skip that step.

    Examples
    --------
    >>> sq = np.array([[[0, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 0, 0], [1, 1, 0], [1, 0, 0]]], float)
    >>> w = integrate_wrench(sq, 0.01, [0.0, 0.0, 5.0], 0.0)
    >>> w.moment.tolist(), w.center_of_pressure.tolist()
    ([2.5, -2.5, 0.0], [0.5, 0.5, 0.0])
    """
    p = prepare_triangles(triangles, xp=xp) if prepared is None else prepared
    df, cen = element_forces(p, depth, stress, heading, trailing=trailing, xp=xp)
    force = xp.sum(df, axis=-2)
    pt = (xp.zeros(3) if point is None else xp.asarray(point)) + 0.0 * force  # batch shape
    moment = xp.sum(xp.cross(cen - pt[..., None, :], df), axis=-2)
    w = xp.sqrt(xp.sum(df * df, axis=-1))
    wsum = xp.sum(w, axis=-1)
    cbar = safe_div(xp.sum(w[..., None] * cen, axis=-2), wsum[..., None], xp)
    cbar = xp.where(wsum[..., None] > 0, cbar, pt)
    f2 = xp.sum(force * force, axis=-1)
    has_f = f2 > (1e-24 * wsum * wsum)  # the element forces do not cancel out
    f2_safe = xp.where(has_f, f2, 1.0)[..., None]
    r0 = pt + xp.cross(force, moment) / f2_safe
    along = xp.sum((cbar - r0) * force, axis=-1)[..., None] / f2_safe
    return Wrench(force, moment, xp.where(has_f[..., None], r0 + along * force, cbar))
