r"""One triangle of a foot, element-wise over ``xp``: its frame for eq. (6) and its clip by the
mud surface (:mod:`mudrft.feet.surface` applies it to every facet). The element rule, its
angles :math:`\psi_1, \psi_2` and the factors :math:`\tilde f_n, \tilde f_t` are derived in
docs/model.md, Sec. 6 (decisions D21-D23, erratum E24).
"""

from __future__ import annotations

import numpy as np

from .._typing import Namespace, XpArray

__all__ = [
    "TOL", "clip_constants", "clip_facet", "facet_factors", "facet_force", "facet_frame",
    "safe_div", "safe_sqrt", "sort_by_height", "submerged_area"
]  # fmt: skip

#: Tolerance on unit-vector components [-]: a facet with :math:`|n_z|\le` this is a vertical
#: wall, with no vertical force.
TOL = 1e-9


def safe_div(num: XpArray, den: XpArray, xp: Namespace = np) -> XpArray:
    """``num/den`` where ``den > 0``, else 0 (gradient-safe: the divisor is never 0)."""
    ok = den > 0
    return xp.where(ok, num / xp.where(ok, den, 1.0), 0.0)


def safe_sqrt(x: XpArray, xp: Namespace = np) -> XpArray:
    """``sqrt(x)`` of ``x >= 0`` with a zero derivative at 0, so that JAX gradients stay
    finite on horizontal or zero-area facets (decision D107)."""
    pos = x > 0
    return xp.where(pos, xp.sqrt(xp.where(pos, x, 1.0)), 0.0)


def facet_frame(
    ax: XpArray, ay: XpArray, az: XpArray, bx: XpArray, by: XpArray, bz: XpArray,
    cx: XpArray, cy: XpArray, cz: XpArray, xp: Namespace = np,
) -> tuple[XpArray, ...]:  # fmt: skip
    r"""Normal, area and the eq. (6) weights of a triangle (a, b, c) [m].

    Returns
    -------
    tuple
        ``(n_x, n_y, n_z, area, n_h, h_x, h_y, w_z)``: outward unit normal from the winding
        (right-hand rule; zero for a zero-area facet) [-], area [m^2],
        :math:`|\mathbf n_h|=\sin\psi_1` [-], unit horizontal normal :math:`\mathbf e_2`
        (zero for a horizontal facet) [-], and :math:`\cos^3\psi_1+\sin^3\psi_1` on facets
        facing down (:math:`-n_z>` :data:`TOL`), else 0 [-].
    """
    ux, uy, uz = bx - ax, by - ay, bz - az
    vx, vy, vz = cx - ax, cy - ay, cz - az
    rx = uy * vz - uz * vy
    ry = uz * vx - ux * vz
    rz = ux * vy - uy * vx
    norm = safe_sqrt(rx * rx + ry * ry + rz * rz, xp=xp)
    nx, ny, nz = safe_div(rx, norm, xp=xp), safe_div(ry, norm, xp=xp), safe_div(rz, norm, xp=xp)
    nh = safe_sqrt(nx * nx + ny * ny, xp=xp)  # sin(psi1)
    c1 = -nz  # cos(psi1)
    # eq. (6) with f_n = cos^2, f_t = sin^2, on facets facing down only
    wz = xp.where(c1 > TOL, c1 * c1 * c1 + nh * nh * nh, 0.0)
    return nx, ny, nz, 0.5 * norm, nh, safe_div(nx, nh, xp=xp), safe_div(ny, nh, xp=xp), wz


def sort_by_height(
    ax: XpArray, ay: XpArray, az: XpArray, bx: XpArray, by: XpArray, bz: XpArray,
    cx: XpArray, cy: XpArray, cz: XpArray, xp: Namespace = np,
) -> tuple[XpArray, ...]:  # fmt: skip
    """The vertices (lo, mid, hi) ordered by height; equal heights keep their order [m]."""
    ab = az <= bz
    px, py, pz = xp.where(ab, ax, bx), xp.where(ab, ay, by), xp.where(ab, az, bz)
    qx, qy, qz = xp.where(ab, bx, ax), xp.where(ab, by, ay), xp.where(ab, bz, az)
    first = cz < pz  # c below both
    second = (cz < qz) & (cz >= pz)  # c between
    lo = (xp.where(first, cx, px), xp.where(first, cy, py), xp.where(first, cz, pz))
    mid = (
        xp.where(first, px, xp.where(second, cx, qx)),
        xp.where(first, py, xp.where(second, cy, qy)),
        xp.where(first, pz, xp.where(second, cz, qz)),
    )
    hi = (
        xp.where(first | second, qx, cx),
        xp.where(first | second, qy, cy),
        xp.where(first | second, qz, cz),
    )
    return lo[0], lo[1], lo[2], mid[0], mid[1], mid[2], hi[0], hi[1], hi[2]


def clip_constants(
    za: XpArray, zb: XpArray, zc: XpArray, area: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray, XpArray]:
    """Constants of the submerged area of a facet with sorted vertex heights [m].

    Returns ``(k_low, k_high, flat_area)``: the submerged area is ``k_low (d - z_a)^2`` with
    only the lowest vertex submerged and ``area - k_high (z_c - d)^2`` with two [-];
    ``flat_area`` is the area of a facet with no height span (below 1e-100 m), else 0 [m^2].
    """
    span1, span2 = (zb - za) * (zc - za), (zc - za) * (zc - zb)
    k_low = safe_div(area, xp.where(span1 > 1e-200, span1, 0.0), xp=xp)
    k_high = safe_div(area, xp.where(span2 > 1e-200, span2, 0.0), xp=xp)
    flat_area = xp.where((span1 > 1e-200) | (span2 > 1e-200), 0.0, area)
    return k_low, k_high, flat_area


def submerged_area(
    za: XpArray, zb: XpArray, zc: XpArray, k_low: XpArray, k_high: XpArray,
    flat_area: XpArray, depth: XpArray, xp: Namespace = np,
) -> XpArray:  # fmt: skip
    r"""Exact area of a facet below the plane :math:`z=d` [m^2] (sorted heights [m]).

    Piecewise quadratic in the depth, written with clamps rather than branches:
    :math:`k_{lo}\min((d-z_a)^+,z_b-z_a)^2+k_{hi}[(z_c-z_b)^2-\min((z_c-d)^+,z_c-z_b)^2]`,
    plus the whole area of a horizontal facet once the plane is above it (strictly).
    """
    lo = xp.minimum(xp.maximum(depth - za, 0.0), zb - za)
    hi = xp.minimum(xp.maximum(zc - depth, 0.0), zc - zb)
    d2 = zc - zb
    return k_low * lo * lo + k_high * (d2 * d2 - hi * hi) + xp.where(depth > za, flat_area, 0.0)


def clip_facet(
    ax: XpArray, ay: XpArray, az: XpArray, bx: XpArray, by: XpArray, bz: XpArray,
    cx: XpArray, cy: XpArray, cz: XpArray, k_low: XpArray, k_high: XpArray,
    flat_area: XpArray, depth: XpArray, xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray, XpArray]:  # fmt: skip
    r"""Exact area [m^2] and centroid ``(x, y, z)`` [m] of the part of a facet below the plane
    :math:`z=d` (``depth`` [m]); the facet's centroid where nothing is submerged. Vertices
    sorted by height (:func:`sort_by_height`) [m], constants from :func:`clip_constants`.
    """
    d = depth
    area = submerged_area(az, bz, cz, k_low, k_high, flat_area, d, xp=xp)
    one_low = (d > az) & (d <= bz)  # only the lowest vertex submerged: a small triangle
    two_low = (d > bz) & (d < cz)  # two submerged: the facet minus a top triangle
    t_ab, t_ac = safe_div(d - az, bz - az, xp=xp), safe_div(d - az, cz - az, xp=xp)
    s_ca, s_cb = safe_div(cz - d, cz - az, xp=xp), safe_div(cz - d, cz - bz, xp=xp)
    top = s_ca * s_cb
    rest = 1.0 - top
    # one vertex below: triangle (A, A + t_ab (B-A), A + t_ac (C-A))
    # two below: whole facet minus the top triangle (C, C + s_ca (A-C), C + s_cb (B-C))
    fx = (ax + bx + cx) / 3.0
    fy = (ay + by + cy) / 3.0
    fz = (az + bz + cz) / 3.0
    x1 = ax + (t_ab * (bx - ax) + t_ac * (cx - ax)) / 3.0
    y1 = ay + (t_ab * (by - ay) + t_ac * (cy - ay)) / 3.0
    z1 = az + (t_ab * (bz - az) + t_ac * (cz - az)) / 3.0
    x2 = safe_div(fx - top * (cx + (s_ca * (ax - cx) + s_cb * (bx - cx)) / 3.0), rest, xp=xp)
    y2 = safe_div(fy - top * (cy + (s_ca * (ay - cy) + s_cb * (by - cy)) / 3.0), rest, xp=xp)
    z2 = safe_div(fz - top * (cz + (s_ca * (az - cz) + s_cb * (bz - cz)) / 3.0), rest, xp=xp)
    return (
        area,
        xp.where(one_low, x1, xp.where(two_low, x2, fx)),
        xp.where(one_low, y1, xp.where(two_low, y2, fy)),
        xp.where(one_low, z1, xp.where(two_low, z2, fz)),
    )


def facet_factors(
    hx: XpArray, hy: XpArray, ux: XpArray, uy: XpArray, trailing: bool, xp: Namespace = np
) -> tuple[XpArray, XpArray]:
    r"""The factors :math:`(\tilde f_n, \tilde f_t)` [-] of eq. (7) of a facet with unit
    horizontal normal ``(hx, hy)`` for a motion ``(ux, uy)``; 0 on trailing facets unless
    ``trailing`` (D23)."""
    cos2 = hx * ux + hy * uy  # cos(psi2)
    sin2 = hx * uy - hy * ux  # sin(psi2) = t . u with t = e_z x e2
    if trailing:
        return cos2 * xp.abs(cos2), sin2 * xp.abs(sin2)
    lead = (cos2 > TOL) | ((xp.abs(cos2) <= TOL) & (sin2 > 0))
    return xp.where(lead, cos2 * cos2, 0.0), xp.where(lead, sin2 * xp.abs(sin2), 0.0)


def facet_force(
    area: XpArray, nh: XpArray, hx: XpArray, hy: XpArray, wz: XpArray, sqx: XpArray,
    sqy: XpArray, sz: XpArray, fn: XpArray, ft: XpArray, xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray]:  # fmt: skip
    r"""Force ``(Fx, Fy, Fz)`` [N] of the mud on one submerged facet of area :math:`dS` [m^2],
    weights of :func:`facet_frame` and :func:`facet_factors`, stresses [Pa]:
    :math:`dF_z=w_z\sigma_zdS`, :math:`d\mathbf F_h=-\sigma_e[\tilde f_n\hat{\mathbf n}_h
    +\tilde f_t\hat{\mathbf t}]|\mathbf n_h|dS`, :math:`\sigma_e=\sigma_x\hat n_x^2+\sigma_y
    \hat n_y^2`."""
    se = -nh * area * (sqx * hx * hx + sqy * hy * hy)  # -sigma_e |n_h| dS
    return se * (fn * hx - ft * hy), se * (fn * hy + ft * hx), wz * sz * area
