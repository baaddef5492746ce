r"""What the compiled kernel and MJX's array form of the coupling share: the channel
weights of a facet and a ball's channels integrated exactly (D60a), a foot's triangles, its
pose on a tangent plane of uneven ground (D175), and two steps of the implicit update (D62c,
D63).

The compiled kernel (:mod:`.compiled`, :mod:`.linalg`) sums the weights over the submerged
facets and takes the implicit step on floats; :mod:`mudrft.integrations.mjx.pose` and
:mod:`~mudrft.integrations.mjx.wrench` do so on arrays.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, cast

import numpy as np

from ..._typing import FloatArray, Namespace, XpArray
from ...feet import Flat
from ...terrains.field import plane_frame

if TYPE_CHECKING:
    from ...feet.base import Foot
    from ...feet.morphing import MorphingFoot

__all__ = [
    "ball_channels", "channel_weights", "foot_triangles", "matvec", "morphing_triangles",
    "on_planes", "passivity_scale", "secant_steps",
]  # fmt: skip


#: Mesh resolution of the curved closed-form feet in the coupling (segments tip to rim).
POSE_RESOLUTION = 6
#: Segments of the morphing foot's base disk and column.
_SEGMENTS = 16
#: Gauss-Legendre nodes on [-1, 1] and weights of :func:`ball_channels` (exact to round-off
#: for its integrands, trigonometric polynomials of degree 6 on at most a quarter turn).
_GL_X, _GL_W = (tuple(float(v) for v in a) for a in np.polynomial.legendre.leggauss(16))


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


def secant_steps(vel: XpArray, dv_min: float, xp: Namespace = np) -> XpArray:
    r"""Velocity steps [m/s] of the secant derivative toward rest (D63, D119), element-wise:
    :math:`-u` for channel velocities ``vel`` [m/s], ``dv_min`` [m/s] across rest near it.
    """
    across = xp.where(vel > 0.0, -dv_min, dv_min)
    return xp.where(xp.abs(vel) > dv_min, -vel, across)


def passivity_scale(
    work_lin: XpArray, work_quad: XpArray, tank: XpArray, xp: Namespace = np
) -> XpArray:
    r"""Largest :math:`s\in[0,1]` with :math:`s\,l+s^2q\le T` (the passivity bound, D62c).

    ``work_lin`` :math:`l` and ``work_quad`` :math:`q\ge0` [J]: the linear and quadratic
    parts of the wrench's work over the step; ``tank`` :math:`T\ge0` [J]: the energy the mud
    has taken and may give back. Element-wise in ``xp``.
    """
    full = work_lin + work_quad <= tank
    disc = xp.sqrt(xp.maximum(work_lin * work_lin + 4.0 * work_quad * tank, 0.0))
    # the positive root of q s^2 + l s - T = 0, in the form without cancellation
    taking = (disc - work_lin) / (2.0 * xp.where(work_quad > 0.0, work_quad, 1.0))
    den = work_lin + disc  # > 0 unless l = 0 and q T = 0, where the root is 0
    giving = 2.0 * tank / xp.where(den > 0.0, den, 1.0)
    root = xp.where(work_lin < 0.0, taking, giving)
    return xp.where(full, 1.0, xp.minimum(xp.maximum(root, 0.0), 1.0))
