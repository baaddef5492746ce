r"""The posed foot: its triangles, and where each channel of the mud acts on them (D60a).

Per channel :math:`c\in\{x,y,z\}` of the foot's yaw frame, the submerged elements weigh

.. math:: w_{x}=|\mathbf n_h|\hat n_x^2\,dS,\quad w_{y}=|\mathbf n_h|\hat n_y^2\,dS,\quad
          w_{z}=(\cos^3\psi_1+\sin^3\psi_1)\,dS\ (n_z<0),

their sums :math:`A_c`, centroids :math:`\mathbf p_c` and second moments
:math:`\mathbf J_c=\sum_i w_{ic}\,(\mathbf r_i\times\mathbf e_c)(\mathbf r_i\times\mathbf e_c)^T`
(:class:`ChannelGeometry`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple, cast

import numpy as np
from numpy.typing import NDArray

from ..._typing import FloatArray, Namespace, XpArray
from ...feet import Flat
from ...feet.facet import submerged_area
from ...feet.surface import PreparedTriangles, clip_below, prepare_triangles
from ...terrains.field import plane_frame

if TYPE_CHECKING:
    from ...feet.base import Foot
    from ...feet.morphing import MorphingFoot

__all__ = [
    "ChannelGeometry", "ball_channels", "channel_geometry", "channel_weights", "foot_triangles",
    "matvec", "morphing_triangles", "on_planes", "posed_channels", "rowdot", "upright_area",
]  # fmt: skip


#: Mesh resolution of the curved closed-form feet in the coupling (segments tip to rim).
POSE_RESOLUTION = 6
#: Segments of the morphing foot's base disk and column.
_SEGMENTS = 16
#: Gauss-Legendre nodes on [-1, 1] and weights of :func:`ball_channels` (exact to round-off
#: for its integrands, trigonometric polynomials of degree 6 on at most a quarter turn).
_GL_X, _GL_W = (tuple(float(v) for v in a) for a in np.polynomial.legendre.leggauss(16))


class ChannelGeometry(NamedTuple):
    r"""Where the three channels act on the submerged part of a posed foot.

    Attributes
    ----------
    area : ndarray (..., 3)
        :math:`A_c` of the x, y and z channels [m^2].
    point : ndarray (..., 3, 3)
        :math:`\mathbf p_c` (row ``c``) [m]; the lowest point where :math:`A_c=0`.
    inertia : ndarray (..., 3, 3, 3)
        :math:`\mathbf J_c` (``[..., c, :, :]``) [m^4].
    low : ndarray (..., 3)
        Lowest vertex [m].
    """

    area: FloatArray
    point: FloatArray
    inertia: FloatArray
    low: FloatArray


def channel_weights(
    area: XpArray, nh: XpArray, hx: XpArray, hy: XpArray, wz: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray, XpArray]:
    r"""Weights :math:`(w_x, w_y, w_z)` [m^2] of a facet with submerged area ``area``
    [m^2] and :math:`|\mathbf n_h|`, :math:`\hat n_x`, :math:`\hat n_y`, vertical weight [-]
    (:func:`mudrft.feet.facet.facet_frame`); element-wise.
    """
    a = area * nh
    return a * hx * hx, a * hy * hy, area * wz


def ball_channels(
    radius: XpArray, height: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray, XpArray, XpArray, XpArray, XpArray, XpArray]:
    r"""The channels of a ball of ``radius`` [m] whose center is ``height`` [m] above the
    mud surface: the lower hemisphere below the surface, integrated exactly (D60a).

    Per unit :math:`d\delta` (:math:`\delta` from the lowest point):
    :math:`w_x=w_y=\pi R^2\sin^2\delta`, :math:`w_z=2\pi R^2(\cos^3\delta+\sin^3\delta)\sin\delta`.

    Returns
    -------
    tuple
        ``(A_h, A_z, z_h, z_z, J_hz, J_hh, J_z)``: :math:`A_x=A_y` and :math:`A_z` [m^2],
        the centroids' heights above the surface [m] (the lowest point's where the area is
        0), and the nonzero second moments [m^4]: :math:`J_{x,yy}=J_{y,xx}` (about the
        centroid's height), :math:`J_{x,zz}=J_{y,zz}` and :math:`J_{z,xx}=J_{z,yy}`.
    """
    low = height - radius
    q = xp.clip(-low / (2.0 * radius), 0.0, 0.5)  # sin^2(delta_s / 2), at most a quarter turn
    half = xp.arctan2(xp.sqrt(q), xp.sqrt(1.0 - q))  # delta_s / 2
    # one pass over the nodes: the sums of w, w u, w u^2 and w r^2 (u from the lowest point,
    # r from the axis); J_hz = sum w_h u^2 - A_h u_h^2 loses under a digit, as u starts at 0
    ah = az = mh = mz = m2h = jhh = jz = 0.0 * low
    for i in range(16):
        e = 0.5 * half * (1.0 + _GL_X[i])  # half the node's angle
        sh, ch = xp.sin(e), xp.cos(e)
        s, c, u = 2.0 * sh * ch, 1.0 - 2.0 * sh * sh, 2.0 * radius * sh * sh
        wh = (half * _GL_W[i]) * (math.pi * radius * radius) * s * s
        wz = (half * _GL_W[i]) * (2.0 * math.pi * radius * radius) * (c * c * c + s * s * s) * s
        r2 = radius * radius * s * s
        ah, az, mh, mz = ah + wh, az + wz, mh + wh * u, mz + wz * u
        m2h, jhh, jz = m2h + wh * u * u, jhh + 0.25 * wh * r2, jz + 0.5 * wz * r2
    uh = xp.where(ah > 0.0, mh / xp.where(ah > 0.0, ah, 1.0), 0.0)
    uz = xp.where(az > 0.0, mz / xp.where(az > 0.0, az, 1.0), 0.0)
    jhz = xp.maximum(m2h - ah * uh * uh, 0.0)
    return ah, az, low + uh, low + uz, jhz, jhh, jz


def channel_geometry(triangles: FloatArray, xp: Namespace = np) -> ChannelGeometry:
    """Channel weights, centroids and second moments of the part of ``triangles``
    (..., m, 3, 3) below z = 0 (the foot's yaw frame, heights from the mud surface [m],
    outward winding).
    """
    tri = xp.asarray(triangles, dtype=float) if xp is np else triangles
    prep = prepare_triangles(tri, xp=xp)
    area, cen = clip_below(prep, xp.zeros(tri.shape[:-3]), xp=xp)
    w = xp.stack(channel_weights(area, prep.nh, prep.hx, prep.hy, prep.wz), axis=-1)  # (..., m, 3)
    a = w.sum(axis=-2)
    flat = tri.reshape(*tri.shape[:-3], -1, 3)
    low = xp.take_along_axis(flat, xp.argmin(flat[..., 2], axis=-1)[..., None, None], -2)[..., 0, :]
    has = a > 0.0
    safe = xp.where(has, a, 1.0)
    pts = xp.einsum("...mc,...mk->...ck", w, cen) / safe[..., None]
    pts = xp.where(has[..., None], pts, low[..., None, :])
    r = cen[..., None, :, :] - pts[..., :, None, :]  # (..., c, m, 3)
    rx, ry, rz = r[..., 0], r[..., 1], r[..., 2]
    zero = xp.zeros_like(rx)
    # r x e_c for c = x, y, z
    q = xp.stack(
        [
            xp.stack([zero[..., 0, :], rz[..., 0, :], -ry[..., 0, :]], -1),
            xp.stack([-rz[..., 1, :], zero[..., 1, :], rx[..., 1, :]], -1),
            xp.stack([ry[..., 2, :], -rx[..., 2, :], zero[..., 2, :]], -1),
        ],
        axis=-3,
    )  # (..., c, m, 3)
    wc = xp.moveaxis(w, -1, -2)  # (..., c, m)
    inertia = xp.einsum("...cm,...cmi,...cmj->...cij", wc, q, q)
    return ChannelGeometry(area=a, point=pts, inertia=inertia, low=low)


def upright_area(prepared: PreparedTriangles, depth: XpArray, xp: Namespace = np) -> FloatArray:
    """Channel weights :math:`A_c` [m^2] (..., 3) of the upright foot (its prepared
    triangles) with its tip at ``depth`` [m].
    """
    p = prepared
    d = (np.asarray(depth, dtype=float) if xp is np else depth)[..., None]
    area = submerged_area(p.za, p.zb, p.zc, p.k_low, p.k_high, p.flat_area, d, xp=xp)
    return xp.stack(channel_weights(area, p.nh, p.hx, p.hy, p.wz), axis=-1).sum(axis=-2)


def posed_channels(
    groups: Sequence[tuple[FloatArray, PreparedTriangles, NDArray[np.int_], bool]],
    X: XpArray,
    R: XpArray,
    C: XpArray,
    cs: XpArray,
    surface: float,
    xp: Namespace = np,
) -> tuple[ChannelGeometry, XpArray]:
    """Channel geometry of every posed foot, and its ratio :math:`A_c/A_c^{up}` to the
    upright foot at the same depth (D60a; 0 where the upright foot has none).

    Lengths in the foot's yaw frame, origin at the center of mass horizontally and at the
    mud surface vertically. ``groups``: per foot type, the triangles in the body frames,
    the prepared upright ones, the bodies' indices and whether they are
    balls; ``X``, ``R``, ``C`` (N, nb, ...): body origins [m], orientations, centers of
    mass [m]; ``cs``: yaw cosine and sine; ``surface`` [m].
    """
    N, nb = X.shape[:2]
    origin = xp.concatenate([C[..., :2], xp.full((N, nb, 1), float(surface))], axis=-1)
    c, s = cs[..., 0], cs[..., 1]

    def yaw(d: XpArray, ci: XpArray, si: XpArray) -> XpArray:  # R_z(-psi) d
        return xp.stack(
            [ci * d[..., 0] + si * d[..., 1], -si * d[..., 0] + ci * d[..., 1], d[..., 2]], -1
        )

    # the compiled coupling's order of operations (D68a)
    parts = []
    for tri_b, upright, idx, ball in groups:
        ci, si = c[:, idx], s[:, idx]
        shift = yaw(X[:, idx] - origin[:, idx], ci, si)
        if ball:  # the same from every angle: integrated exactly, ratio 1
            parts.append(_ball_parts(-np.min(np.asarray(tri_b)[..., 2], axis=(-1, -2)), shift, xp))
            continue
        Rg = R[:, idx]
        M = xp.stack(
            [ci[..., None] * Rg[..., 0, :] + si[..., None] * Rg[..., 1, :],
             -si[..., None] * Rg[..., 0, :] + ci[..., None] * Rg[..., 1, :], Rg[..., 2, :]],
            axis=-2,
        )  # fmt: skip
        t = matvec(M[:, :, None, None], xp.asarray(tri_b)[None]) + shift[:, :, None, None, :]
        g = channel_geometry(t, xp=xp)
        up_tri = PreparedTriangles(*(xp.asarray(a) for a in upright))
        up = upright_area(up_tri, xp.maximum(-g.low[..., 2], 0.0), xp=xp)
        ratio = xp.where(up > 0.0, g.area / xp.where(up > 0.0, up, 1.0), 0.0)
        parts.append((*g, ratio))
    inv = np.argsort(np.concatenate([idx for _, _, idx, _ in groups]))
    area, point, inertia, lowest, ratio = (
        xp.concatenate([p[i] for p in parts], axis=1)[:, inv] for i in range(5)
    )
    return ChannelGeometry(area, point, inertia, lowest), ratio


def _ball_parts(
    radius: FloatArray, center: XpArray, xp: Namespace
) -> tuple[XpArray, XpArray, XpArray, XpArray, XpArray]:
    """:func:`posed_channels`' arrays for balls of ``radius`` (nb,) [m] with centers
    ``center`` (N, nb, 3) [m] in their yaw frames: area, points, moments, lowest point, ratio.
    """
    x, y, h = center[..., 0], center[..., 1], center[..., 2]
    ah, az, zh, zz, jhz, jhh, jz = ball_channels(xp.asarray(radius), h, xp=xp)
    o = xp.zeros_like(ah)
    area = xp.stack([ah, ah, az], -1)
    point = xp.stack([xp.stack([x, y, z], -1) for z in (zh, zh, zz)], -2)

    def diag(a: XpArray, b: XpArray, c: XpArray) -> XpArray:
        return xp.stack([a, b, c], -1)[..., None] * xp.eye(3)

    inertia = xp.stack([diag(o, jhz, jhh), diag(jhz, o, jhh), diag(jz, jz, o)], -3)
    low = xp.stack([x, y, h - xp.asarray(radius)], -1)
    return area, point, inertia, low, xp.ones_like(area)


def matvec(R: FloatArray, v: FloatArray) -> FloatArray:
    r""":math:`R v` over the last axes, summed in the compiled coupling's order (D68a)."""
    return (R[..., 0] * v[..., 0, None] + R[..., 1] * v[..., 1, None]) + R[..., 2] * v[..., 2, None]


def on_planes(
    X: XpArray,
    R: XpArray,
    C: XpArray,
    tip: XpArray,
    hs: XpArray,
    gx: XpArray,
    gy: XpArray,
    surface: float,
    xp: Namespace = np,
) -> tuple[XpArray, ...]:
    """Bodies posed on the surface's tangent planes under their tips (D175), as the compiled
    kernel poses them (``linalg._about``): the plane of slopes ``gx``, ``gy`` [-] through
    P = (tip x, tip y, ``surface`` + ``hs``) [m] turned level by its frame Q (rows: its axes,
    :func:`~mudrft.terrains.field.plane_frame`) about P and moved down to P' = (tip x,
    tip y, ``surface``). ``X``, ``C``, ``tip`` (..., 3) [m], ``R`` (..., 3, 3); returns them
    posed, then Q, P and P'."""
    Q = xp.stack(plane_frame(gx, gy, xp), axis=-1).reshape(*gx.shape, 3, 3)
    level = 0.0 * hs + surface
    P = xp.stack([tip[..., 0], tip[..., 1], level + hs], axis=-1)
    Pd = xp.stack([tip[..., 0], tip[..., 1], level], axis=-1)

    def about(a: XpArray) -> XpArray:
        return matvec(Q, a - P) + Pd

    return about(X), Q @ R, about(C), about(tip), Q, P, Pd


def rowdot(a: FloatArray, b: FloatArray) -> FloatArray:
    """Dot product over the last axis, summed from the first element on (fixed order)."""
    acc = a[..., 0] * b[..., 0]
    for i in range(1, a.shape[-1]):
        acc = acc + a[..., i] * b[..., i]
    return acc


def foot_triangles(foot: Foot, *, resolution: int = POSE_RESOLUTION) -> FloatArray | None:
    """Triangles (m, 3, 3) [m] of a foot in its own frame (tip at the origin, z up), a
    closed form's at ``resolution``; None for a foot without a surface."""

    if hasattr(foot, "pad_corners") and hasattr(foot, "geometry"):  # a MorphingFoot
        return morphing_triangles(cast("MorphingFoot", foot))
    if isinstance(foot, Flat):
        return np.asarray(foot.to_mesh(resolution=1).triangles, dtype=float)
    if hasattr(foot, "to_mesh"):
        return np.asarray(foot.to_mesh(resolution=resolution).triangles, dtype=float)
    tri = getattr(foot, "triangles", None)
    return None if tri is None else np.asarray(tri, dtype=float)


def morphing_triangles(foot: MorphingFoot, *, segments: int = _SEGMENTS) -> FloatArray:
    """The morphing foot as triangles (m, 3, 3) [m]: base disk, column wall
    and pads (thin plates) at the angle ``pad_corners()`` draws; ``segments`` around the disk.
    """
    g = foot.geometry
    a = np.linspace(0.0, 2.0 * math.pi, segments + 1)
    ring = np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], axis=-1)
    tris = []
    rb, rc, h = float(g.base_radius), float(g.column_radius), float(foot.height)
    for k in range(segments):
        # base disk facing down: (0, a_{k+1}, a_k)
        tris.append([np.zeros(3), rb * ring[k + 1], rb * ring[k]])
        lo0, lo1 = rc * ring[k], rc * ring[k + 1]
        up = np.array([0.0, 0.0, h])
        hi0, hi1 = lo0 + up, lo1 + up
        tris.append([lo0, lo1, hi1])  # column wall facing out
        tris.append([lo0, hi1, hi0])
    for quad in np.asarray(foot.pad_corners(), dtype=float):
        p0l, p0r, p1r, p1l = quad
        t1, t2 = [p0l, p0r, p1r], [p0l, p1r, p1l]
        n = np.cross(np.subtract(p0r, p0l), np.subtract(p1r, p0l))
        if n[2] > 0:  # make the first pair the bottom face (normal down)
            t1, t2 = [p0l, p1r, p0r], [p0l, p1l, p1r]
        tris += [t1, t2, [t1[0], t1[2], t1[1]], [t2[0], t2[2], t2[1]]]
    return np.asarray(tris, dtype=float)
