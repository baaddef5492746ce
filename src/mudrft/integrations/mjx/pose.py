r"""The array form of the posed foot: where each channel of the mud acts on it (D60a).

Per channel :math:`c\in\{x,y,z\}` of the foot's yaw frame, the submerged elements weigh

.. math:: w_{x}=|\mathbf n_h|\hat n_x^2\,dS,\quad w_{y}=|\mathbf n_h|\hat n_y^2\,dS,\quad
          w_{z}=(\cos^3\psi_1+\sin^3\psi_1)\,dS\ (n_z<0),

their sums :math:`A_c`, centroids :math:`\mathbf p_c` and second moments
:math:`\mathbf J_c=\sum_i w_{ic}\,(\mathbf r_i\times\mathbf e_c)(\mathbf r_i\times\mathbf e_c)^T`
(:class:`ChannelGeometry`). MJX runs these functions on JAX arrays; the compiled MuJoCo
kernel (:mod:`mudrft.integrations.mujoco.compiled`) takes the same steps on floats, and the
tests hold the two equal.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..._typing import FloatArray, Namespace, XpArray
from ...feet.facet import submerged_area
from ...feet.surface import PreparedTriangles, clip_below, prepare_triangles
from ..mujoco.pose import ball_channels, channel_weights, matvec

__all__ = ["ChannelGeometry", "channel_geometry", "posed_channels", "rowdot", "upright_area"]


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


def rowdot(a: FloatArray, b: FloatArray) -> FloatArray:
    """Dot product over the last axis, summed from the first element on (fixed order)."""
    acc = a[..., 0] * b[..., 0]
    for i in range(1, a.shape[-1]):
        acc = acc + a[..., i] * b[..., i]
    return acc
