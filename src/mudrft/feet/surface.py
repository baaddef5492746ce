r"""Surface-element integration of the 3D force law (Chen et al. 2026, eqs. 6-7) on triangles.

The surface is a set of triangles in the foot frame (tip at :math:`z=0`, :math:`z` up);
the mud surface is the plane :math:`z=d` (the tip ``depth``), and each triangle is clipped
exactly by that plane, so only its submerged polygon counts. The element rule of each
facet is written once in :mod:`mudrft.feet.facet` (decisions D21-D23, erratum E24).

Every function is pure and takes an ``xp`` array namespace (``numpy`` by default, or
``jax.numpy``). Shapes: ``triangles`` (..., m, 3, 3) [m]; ``depth`` (...) [m];
``stress`` (..., 3) [Pa]; ``heading`` (...) [rad]; leading batch dimensions broadcast.
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
    fold_stresses,
    safe_div,
    sort_by_height,
)
from .facet import (
    submerged_area as facet_submerged_area,
)

__all__ = [
    "ClippedElements",
    "LocalFrame",
    "PreparedTriangles",
    "Wrench",
    "clip_below",
    "clip_elements",
    "element_forces",
    "integrate_prepared",
    "integrate_triangles",
    "integrate_wrench",
    "local_frame",
    "prepare_triangles",
    "submerged_area",
]


class PreparedTriangles(NamedTuple):
    r"""Per-facet data that do not depend on depth, stress or heading (:func:`prepare_triangles`).

    Attributes
    ----------
    lo, mid, hi : array (..., m, 3)
        Vertices sorted by height [m].
    normal : array (..., m, 3)
        Outward unit normal from the winding [-] (zero for zero-area facets).
    area : array (..., m)
        Facet area [m^2].
    k_low, k_high : array (..., m)
        Clipping constants of :func:`mudrft.feet.facet.clip_constants` [-].
    nh : array (..., m)
        :math:`|\mathbf n_h|=\sin\psi_1` [-].
    hx, hy : array (..., m)
        Unit horizontal normal [-] (zero for horizontal facets).
    wz : array (..., m)
        Vertical weight :math:`\cos^3\psi_1+\sin^3\psi_1` on facets facing down, else 0 [-].
    za, zb, zc : array (..., m)
        Sorted vertex heights [m].
    flat_area : array (..., m)
        Area of horizontal facets, else 0 [m^2].
    """

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


class ClippedElements(NamedTuple):
    """Submerged parts of the facets at one depth.

    Attributes
    ----------
    centroids : array (..., m, 3)
        Centroid of each submerged polygon [m] (the facet centroid when nothing is submerged).
    normals : array (..., m, 3)
        Outward unit normals [-].
    areas : array (..., m)
        Submerged areas [m^2].
    depths : array (..., m)
        Depth of each centroid below the mud surface [m] (negative above it).
    """

    centroids: XpArray
    normals: XpArray
    areas: XpArray
    depths: XpArray


class LocalFrame(NamedTuple):
    r"""Local plate frame and angles of eq. (6) for each facet and heading.

    Attributes
    ----------
    e1, e2, e3 : array (..., m, 3)
        Unit vectors :math:`\mathbf e_1=\mathbf n\times\mathbf e_3/\|\cdot\|`,
        :math:`\mathbf e_2=\mathbf e_3\times\mathbf e_1` (the horizontal normal),
        :math:`\mathbf e_3=\mathbf e_z`; e1, e2 are zero for horizontal facets [-].
    psi1 : array (..., m)
        Angle between the normal and :math:`-\mathbf e_z` [rad], in [0, pi].
    psi2 : array (..., m)
        Signed angle from :math:`\mathbf e_2` to the motion direction [rad], in (-pi, pi].
    varphi : array (..., m)
        Azimuth of :math:`\mathbf e_2` from the x axis [rad], in (-pi, pi].
    """

    e1: XpArray
    e2: XpArray
    e3: XpArray
    psi1: XpArray
    psi2: XpArray
    varphi: XpArray


class Wrench(NamedTuple):
    """Resultant of the element forces.

    Attributes
    ----------
    force : array (..., 3)
        Force of the mud on the foot [N].
    moment : array (..., 3)
        Moment of the element forces about ``point`` [N m].
    center_of_pressure : array (..., 3)
        Center of pressure [m] (decision D24, :func:`integrate_wrench`); ``point`` when no
        force acts.
    """

    force: XpArray
    moment: XpArray
    center_of_pressure: XpArray


def prepare_triangles(triangles: XpArray, xp: Namespace = np) -> PreparedTriangles:
    """Per-facet data that do not depend on depth, stress or heading.

    Parameters
    ----------
    triangles : array_like, shape (..., m, 3, 3)
        Vertices of each triangle in the foot frame [m]; the winding (right-hand rule)
        gives the outward normal.
    xp : module, optional
        Array namespace (``numpy`` or ``jax.numpy``).

    Returns
    -------
    PreparedTriangles

    Examples
    --------
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
    p = prepared
    d = xp.asarray(depth)[..., None]
    return facet_submerged_area(p.za, p.zb, p.zc, p.k_low, p.k_high, p.flat_area, d, xp=xp)


def clip_below(
    prepared: PreparedTriangles, depth: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray]:
    """Exact area and centroid of the part of each facet below the plane ``z = depth``.

    Parameters
    ----------
    prepared : PreparedTriangles
        From :func:`prepare_triangles`.
    depth : array_like, shape (...)
        Tip depth [m], the height of the mud surface in the foot frame.
    xp : module, optional
        Array namespace.

    Returns
    -------
    area : array (..., m)
        Submerged area [m^2].
    centroid : array (..., m, 3)
        Centroid of the submerged polygon [m]; the facet centroid where nothing is submerged.

    Examples
    --------
    >>> tri = np.array([[[0, 0, 0], [1, 0, 1], [-1, 0, 1]]], dtype=float)  # vertical, 1 m tall
    >>> a, c = clip_below(prepare_triangles(tri), 0.5)
    >>> float(a[0]), c[0].round(4).tolist()
    (0.25, [0.0, 0.0, 0.3333])
    """
    p = prepared
    d = xp.asarray(depth)[..., None]
    a, b, c = p.lo, p.mid, p.hi
    area, cx, cy, cz = clip_facet(
        a[..., 0], a[..., 1], a[..., 2], b[..., 0], b[..., 1], b[..., 2],
        c[..., 0], c[..., 1], c[..., 2], p.k_low, p.k_high, p.flat_area, d, xp=xp,
    )  # fmt: skip
    return area, xp.stack(xp.broadcast_arrays(cx, cy, cz), axis=-1)


def clip_elements(triangles: XpArray, depth: XpArray, xp: Namespace = np) -> ClippedElements:
    """Submerged surface elements (centroid, normal, area, depth) at a tip depth.

    Parameters
    ----------
    triangles : array_like, shape (..., m, 3, 3)
        Triangles in the foot frame [m].
    depth : array_like, shape (...)
        Tip depth [m].
    xp : module, optional
        Array namespace.

    Returns
    -------
    ClippedElements

    Examples
    --------
    >>> tri = np.array([[[0, 0, 0], [0, 1, 0], [1, 0, 0]]], dtype=float)
    >>> float(clip_elements(tri, 0.1).areas[0])
    0.5
    """
    p = prepare_triangles(triangles, xp=xp)
    area, cen = clip_below(p, depth, xp=xp)
    normals = xp.broadcast_to(p.normal, cen.shape)
    return ClippedElements(cen, normals, area, xp.asarray(depth)[..., None] - cen[..., 2])


def local_frame(normals: XpArray, heading: XpArray, xp: Namespace = np) -> LocalFrame:
    """The local frame (e1, e2, e3) and the angles psi1, psi2, varphi of eq. (6).

    Parameters
    ----------
    normals : array_like, shape (..., m, 3)
        Outward unit normals [-].
    heading : array_like, shape (...)
        Direction of the horizontal motion from the x axis [rad].
    xp : module, optional
        Array namespace.

    Returns
    -------
    LocalFrame

    Examples
    --------
    >>> f = local_frame(np.array([[1.0, 0.0, 0.0]]), np.pi / 4)
    >>> f.e2[0].tolist(), round(float(f.psi2[0]), 6), round(float(f.psi1[0]), 6)
    ([1.0, 0.0, 0.0], 0.785398, 1.570796)
    """
    n = xp.asarray(normals)
    h = xp.asarray(heading)[..., None]
    r = xp.sqrt(n[..., 0] ** 2 + n[..., 1] ** 2)
    nx, ny = safe_div(n[..., 0], r, xp), safe_div(n[..., 1], r, xp)
    zero = xp.zeros_like(r)
    e2 = xp.stack([nx, ny, zero], axis=-1)
    e1 = xp.stack([ny, -nx, zero], axis=-1)
    e3 = xp.stack([zero, zero, zero + 1.0], axis=-1)
    ux, uy = xp.cos(h), xp.sin(h)
    psi1 = xp.arctan2(r, -n[..., 2])
    psi2 = xp.arctan2(nx * uy - ny * ux, nx * ux + ny * uy)
    varphi = xp.arctan2(ny, nx)
    return LocalFrame(e1, e2, e3, psi1, psi2, varphi)


def _heading_factors(
    p: PreparedTriangles, stress: XpArray, heading: XpArray, trailing: bool, xp: Namespace
) -> tuple[XpArray, ...]:
    """Stresses (..., 1) and the factors f_n, f_t of each facet (..., m)."""
    s = xp.asarray(stress)
    h = xp.asarray(heading)
    sqx, sqy, ux, uy = fold_stresses(s[..., 0], s[..., 1], h, xp=xp)
    fn, ft = facet_factors(p.hx, p.hy, ux[..., None], uy[..., None], trailing, xp=xp)
    return sqx[..., None], sqy[..., None], s[..., 2][..., None], fn, ft


def element_forces(
    prepared: PreparedTriangles,
    depth: XpArray,
    stress: XpArray,
    heading: XpArray,
    *,
    trailing: bool = False,
    xp: Namespace = np,
) -> tuple[XpArray, XpArray]:
    """Force on each submerged facet and its point of application.

    Parameters
    ----------
    prepared : PreparedTriangles
        From :func:`prepare_triangles`.
    depth, stress, heading, trailing, xp
        Tip depth [m], channel stresses (..., 3) [Pa], heading [rad], and the options, as
        in :func:`integrate_triangles`.

    Returns
    -------
    force : array (..., m, 3)
        Force of the mud on each facet [N].
    centroid : array (..., m, 3)
        Centroid of each submerged polygon [m].
    """
    p = prepared
    area, cen = clip_below(p, depth, xp=xp)
    sqx, sqy, sz, fn, ft = _heading_factors(p, stress, heading, trailing, xp)
    f = facet_force(1.0, p.nh, p.hx, p.hy, p.wz, sqx, sqy, sz, fn, ft, xp=xp)
    return xp.stack(xp.broadcast_arrays(*f), axis=-1) * area[..., None], cen


def integrate_prepared(
    prepared: PreparedTriangles,
    depth: XpArray,
    stress: XpArray,
    heading: XpArray,
    *,
    trailing: bool = False,
    xp: Namespace = np,
) -> XpArray:
    """:func:`integrate_triangles` on facets from :func:`prepare_triangles` [N].

    Parameters
    ----------
    prepared : PreparedTriangles
        From :func:`prepare_triangles`.
    depth, stress, heading, trailing, xp
        Tip depth [m], channel stresses (..., 3) [Pa], heading [rad], and the options, as
        in :func:`integrate_triangles`.

    Returns
    -------
    array, shape (..., 3)
        (Fx, Fy, Fz) [N] in the foot frame.
    """
    p = prepared
    area = submerged_area(p, depth, xp=xp)
    sqx, sqy, sz, fn, ft = _heading_factors(p, stress, heading, trailing, xp)
    f = facet_force(area, p.nh, p.hx, p.hy, p.wz, sqx, sqy, sz, fn, ft, xp=xp)
    fx, fy, fz = (xp.sum(c, axis=-1) for c in f)
    return xp.stack(xp.broadcast_arrays(fx, fy, fz), axis=-1) + 0.0  # -0.0 -> 0.0


def integrate_triangles(
    triangles: XpArray,
    depth: XpArray,
    stress: XpArray,
    heading: XpArray,
    *,
    trailing: bool = False,
    xp: Namespace = np,
) -> XpArray:
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
        Let facets that trail the motion resist too, with the supplementary's full-range
        factors (as in the sphere's derivation); default ``False``, leading facets only (as
        in the flat and semi-cylindrical feet's), decision D23.
    xp : module, optional
        Array namespace (``numpy``, ``jax.numpy``).

    Returns
    -------
    array, shape (..., 3)
        (Fx, Fy, Fz) [N] in the foot frame: horizontal components oppose the motion for
        resisting stresses; Fz > 0 is support.

    Notes
    -----
    .. math::
       :label: chen2026-eq-6

       dF_x=(-\sigma_h^n\cos\varphi+\sigma_h^t\sin\varphi)\,dS_h,\quad
       dF_y=-(\sigma_h^n\sin\varphi+\sigma_h^t\cos\varphi)\,dS_h,\quad
       dF_z=(\sigma_v^n\cos\psi_1+\sigma_v^t\sin\psi_1)\,dS \tag{6}

    with :math:`f_n=\cos^2`, :math:`f_t=\sin^2` (eq. 7), applied per facet by
    :func:`mudrft.feet.facet.facet_force`.

    References
    ----------
    .. [1] Chen et al. (2026), "A Foot Resistive Force Model for Legged Locomotion on Muddy
       Terrains", eqs. (6)-(7), supplementary Sec. II-C (erratum E24: the sign of dF_y).

    Examples
    --------
    A 1 m x 1 m downward-facing square at any positive depth carries sz x 1 m^2:

    >>> sq = np.array([[[0, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 0, 0], [1, 1, 0], [1, 0, 0]]], float)
    >>> integrate_triangles(sq, 0.01, [0.0, 0.0, 5.0], 0.0).tolist()
    [0.0, 0.0, 5.0]
    """
    return integrate_prepared(
        prepare_triangles(triangles, xp=xp), depth, stress, heading, trailing=trailing, xp=xp
    )


def integrate_wrench(
    triangles: XpArray,
    depth: XpArray,
    stress: XpArray,
    heading: XpArray,
    *,
    point: XpArray = None,
    trailing: bool = False,
    xp: Namespace = np,
    prepared: PreparedTriangles | None = None,
) -> Wrench:
    r"""Force, moment about ``point`` and center of pressure of the mud on a triangulated foot.

    Each facet's force acts at the centroid of its submerged polygon. The center of
    pressure (decision D24) is the point of the wrench's central axis
    :math:`\mathbf r_0+t\hat{\mathbf F}`, :math:`\mathbf r_0=\mathbf p+\mathbf F\times
    \mathbf M_p/|\mathbf F|^2`, nearest to the :math:`|d\mathbf F|`-weighted centroid of the
    submerged surface.

    Parameters
    ----------
    triangles : array_like, shape (..., m, 3, 3)
        Triangles in the foot frame [m] (ignored when ``prepared`` is given).
    depth, stress, heading, trailing, xp
        Tip depth [m], channel stresses (..., 3) [Pa], heading [rad], and the options, as
        in :func:`integrate_triangles`.
    point : array_like, shape (..., 3), optional
        Reference point for the moment, in the foot frame [m]; default the tip (origin).
    prepared : PreparedTriangles, optional
        Facet data from :func:`prepare_triangles`, to skip that step.

    Returns
    -------
    Wrench

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
