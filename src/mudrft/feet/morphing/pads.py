r"""The morphing foot's base and pads in the mud: submerged areas and forces (D33, D38).

Given the pad angle :math:`\theta` (from :mod:`.linkage`) and the tip depth :math:`d`, each
trapezoidal pad (widths :math:`w_i` at its pivot, :math:`w_o` at its rim, length
:math:`\ell`) is submerged from its pivot up to the length
:math:`s(d,\theta)=\operatorname{clip}((d-h_A)/\sin\theta, 0, \ell)`, of area
:math:`a_p(s)=w_is+\tfrac12\kappa s^2`, :math:`\kappa=(w_o-w_i)/\ell`. With uniform channel
stresses the plate rule of the paper's eq. (6)-(7), pad tilt :math:`\psi_1=\theta`, gives

.. math:: F_z = \sigma_zA_z,\qquad A_z = \pi r_A^2 + N a_p(s)\,
          \bigl(f_n(\theta)\cos\theta + f_t(\theta)\sin\theta\bigr),

.. math:: F_x = \sigma_xA_h(\varphi)\cos\varphi,\quad F_y = \sigma_yA_h(\varphi)\sin\varphi,
          \qquad A_h = A_{column}(d) + a_p(s)\sin\theta\sum_k|\cos(2\pi k/N-\varphi)|,

first-quadrant magnitudes as in :meth:`mudrft.feet.base.Foot.resultant`. All functions here
are vectorized and unchecked: the foot (:mod:`.foot`) validates its inputs.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...constitutive.laws import f_n, f_t
from ..base import SurfaceElements
from .linkage import MorphingFootGeometry

__all__ = [
    "center_height",
    "footprint_area",
    "horizontal_area",
    "magnitudes",
    "pad_area",
    "pad_corners",
    "submerged_length",
    "surface_elements",
    "vertical_area",
]

_FLAT = 1e-12  # sin(theta) below which a pad counts as lying flat at the pivot height [-]


def pad_area(g: MorphingFootGeometry, length: ArrayLike) -> NDArray[np.float64]:
    """Area of one pad from its pivot to a distance ``length`` along it [m^2].

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    length : float or array_like
        Distance from the pivot along the pad [m], in [0, pad_length].
    """
    s = np.asarray(length, dtype=float)
    kappa = (g.pad_outer_width - g.pad_inner_width) / g.pad_length
    return np.asarray(g.pad_inner_width * s + 0.5 * kappa * s**2)


def submerged_length(
    g: MorphingFootGeometry, depth: ArrayLike, theta: ArrayLike
) -> NDArray[np.float64]:
    """Length of each pad below the mud surface, from its pivot [m].

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    depth : float or array_like
        Tip depth [m], >= 0.
    theta : float or array_like
        Pad angle [rad].
    """
    rise = np.asarray(depth, dtype=float) - g.pivot_height
    s = np.sin(theta)
    safe = np.where(s > _FLAT, s, 1.0)
    return np.where(
        s > _FLAT,
        np.clip(rise / safe, 0.0, g.pad_length),
        np.where(rise > 0, g.pad_length, 0.0),
    )


def vertical_area(
    g: MorphingFootGeometry, depth: ArrayLike, theta: ArrayLike
) -> NDArray[np.float64]:
    """Effective vertical area :math:`A_z` of the base and the pads [m^2] (D33).

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    depth : float or array_like
        Tip depth [m], >= 0.
    theta : float or array_like
        Pad angle [rad].
    """
    d = np.asarray(depth, dtype=float)
    base = np.where(d > 0, math.pi * g.base_radius**2, 0.0)
    pad = pad_area(g, submerged_length(g, d, theta))
    weight = f_n(theta) * np.cos(theta) + f_t(theta) * np.sin(theta)
    return np.asarray(base + g.n_pads * pad * weight)


def horizontal_area(
    g: MorphingFootGeometry, depth: ArrayLike, theta: ArrayLike, heading: ArrayLike
) -> NDArray[np.float64]:
    """Submerged area projected normal to the heading, :math:`A_h` [m^2] (D33).

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    depth : float or array_like
        Tip depth [m], >= 0.
    theta : float or array_like
        Pad angle [rad].
    heading : float or array_like
        Heading of the motion from the x axis [rad].
    """
    d = np.asarray(depth, dtype=float)
    col = 2.0 * g.base_radius * np.clip(d, 0.0, g.pivot_height) + 2.0 * g.column_radius * np.clip(
        d - g.pivot_height, 0.0, g.height - g.pivot_height
    )
    pad = pad_area(g, submerged_length(g, d, theta)) * np.sin(theta)
    h = np.asarray(heading, dtype=float)
    proj = np.abs(np.cos(g.azimuths - h[..., None])).sum(-1)
    return np.asarray(col + pad * proj)


def footprint_area(
    g: MorphingFootGeometry, depth: ArrayLike, theta: ArrayLike
) -> NDArray[np.float64]:
    """Horizontal projection of the submerged base and pads [m^2] (D36, D38).

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    depth : float or array_like
        Tip depth [m], >= 0; ``inf`` counts the whole foot.
    theta : float or array_like
        Pad angle [rad].
    """
    d = np.asarray(depth, dtype=float)
    base = np.where(d > 0, math.pi * g.base_radius**2, 0.0)
    whole = np.isinf(d)
    length = np.where(whole, g.pad_length, submerged_length(g, np.where(whole, 0.0, d), theta))
    return np.asarray(base + g.n_pads * pad_area(g, length) * np.cos(theta))


def magnitudes(
    g: MorphingFootGeometry,
    depth: ArrayLike,
    stress: ArrayLike,
    heading: ArrayLike,
    theta: ArrayLike,
) -> NDArray[np.float64]:
    """First-quadrant force magnitudes (Fx, Fy, Fz) [N] at a pad angle (D33).

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    depth : float or array_like
        Tip depth [m], >= 0.
    stress : array_like, shape (..., 3)
        Channel stresses (sx, sy, sz) [Pa].
    heading : float or array_like
        Heading in [0, pi/2] [rad].
    theta : float or array_like
        Pad angle [rad].

    Returns
    -------
    ndarray, shape (..., 3)
        (Fx, Fy, Fz) [N].
    """
    s = np.asarray(stress, dtype=float)
    h = np.asarray(heading, dtype=float)
    ah = horizontal_area(g, depth, theta, h)
    az = vertical_area(g, depth, theta)
    fx = ah * np.cos(h) * s[..., 0]
    fy = ah * np.sin(h) * s[..., 1]
    fz = az * s[..., 2]
    return np.stack(np.broadcast_arrays(fx, fy, fz), axis=-1)


def center_height(
    g: MorphingFootGeometry, depth: ArrayLike, theta: ArrayLike
) -> NDArray[np.float64]:
    """Height of the center of the vertical pressure above the tip [m].

    The :math:`A_z`-weighted centroid of the submerged base (at z = 0) and pad parts; half
    the submerged height when nothing is submerged.

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    depth : float or array_like
        Tip depth [m], >= 0.
    theta : float or array_like
        Pad angle [rad].
    """
    d, th = np.broadcast_arrays(np.asarray(depth, dtype=float), np.asarray(theta, dtype=float))
    length = submerged_length(g, d, th)
    kappa = (g.pad_outer_width - g.pad_inner_width) / g.pad_length
    area = pad_area(g, length)
    moment = g.pad_inner_width * length**2 / 2 + kappa * length**3 / 3
    sbar = np.where(area > 0, moment / np.where(area > 0, area, 1.0), 0.0)
    wp = g.n_pads * area * (f_n(th) * np.cos(th) + f_t(th) * np.sin(th))
    wb = np.where(d > 0, math.pi * g.base_radius**2, 0.0)
    zp = g.pivot_height + sbar * np.sin(th)
    tot = wp + wb
    return np.where(tot > 0, wp * zp / np.where(tot > 0, tot, 1.0), 0.5 * np.minimum(d, g.height))


def pad_corners(g: MorphingFootGeometry, theta: float) -> NDArray[np.float64]:
    """Corners of every pad in the foot frame [m], shape (n_pads, 4, 3).

    Order: pivot-left, pivot-right, rim-right, rim-left.

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    theta : float
        Pad angle [rad].
    """
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
    """Surface elements of the base (one downward disk) and the pads (thin plates) [m].

    Parameters
    ----------
    g : MorphingFootGeometry
        Foot dimensions [m].
    theta : float
        Pad angle [rad].
    strips : int, keyword-only
        Elements along each pad [-]; a pad element's normal is the plate's upward-outward
        normal.
    """
    edges = np.linspace(0.0, g.pad_length, strips + 1)
    areas_1 = np.diff(pad_area(g, edges))
    mids = 0.5 * (edges[1:] + edges[:-1])
    cen = [np.array([[0.0, 0.0, 0.0]])]
    nor = [np.array([[0.0, 0.0, -1.0]])]
    ar = [np.array([math.pi * g.base_radius**2])]
    ez = np.array([0.0, 0.0, 1.0])
    for a in g.azimuths:
        er = np.array([math.cos(a), math.sin(a), 0.0])
        p = (g.base_radius * er + g.pivot_height * ez)[None, :] + mids[:, None] * (
            math.cos(theta) * er + math.sin(theta) * ez
        )[None, :]
        cen.append(p)
        nor.append(np.tile(-math.sin(theta) * er + math.cos(theta) * ez, (strips, 1)))
        ar.append(areas_1)
    return SurfaceElements(
        centroids=np.concatenate(cen), normals=np.concatenate(nor), areas=np.concatenate(ar)
    )
