r"""The paper's three feet in closed form: flat, semi-cylindrical, semi-spherical (Sec. III-A).

Each is the integral of eqs. (6)-(7) over the foot (supplementary Sec. II), corrected where
the printed final differs (errata E20-E23; ``printed_*``), as the coefficients [m^2] of its
linear form (:func:`~mudrft.feet.base.world_force`), on the array namespace ``xp``. With
:math:`z` the tip depth capped at the height, :math:`\varphi` the folded heading,
:math:`\varphi_c=\pi/2-\varphi`, :math:`\theta_c=\cos^{-1}(1-z/R)`, :math:`s=\sin\theta_c`,
:math:`c=\cos\theta_c`.
"""

from __future__ import annotations

import math

import numpy as np

from .._typing import ArrayLike, FloatArray, FloatOrArray, Namespace, XpArray
from ..constitutive.laws import f_n, f_t
from .base import fold_heading, magnitudes, world_force

__all__ = [
    "closed_form_coefficients", "closed_form_force", "flat_coefficients", "flat_forces",
    "printed_semicylinder_fz", "printed_semisphere_fxy", "printed_semisphere_fz",
    "semicylinder_coefficients", "semicylinder_forces", "semisphere_coefficients",
    "semisphere_forces"
]  # fmt: skip

#: Segments from tip to rim of a closed-form foot's mesh (elements, center of pressure).
DEFAULT_RESOLUTION = 48

Coefficients = tuple[XpArray, XpArray, XpArray, XpArray, XpArray]


def _theta(z: XpArray, radius: float, xp: Namespace = np) -> XpArray:
    r""":math:`\theta_c=\cos^{-1}(1-z/R)` [rad], with a zero derivative where the argument
    is +-1 (finite JAX gradients with the tip at the surface, D107)."""
    x = xp.clip(1.0 - z / radius, -1.0, 1.0)
    inside = xp.abs(x) < 1.0
    edge = xp.where(x > 0.0, 0.0, math.pi)  # arccos(1) = 0, arccos(-1) = pi, exactly
    return xp.where(inside, xp.arccos(xp.where(inside, x, 0.0)), edge)


def flat_coefficients(
    depth: XpArray, phi: XpArray, length: float, width: float, height: float, xp: Namespace = np
) -> Coefficients:
    r"""Flat foot, eq. (12): the coefficients [m^2] (:math:`a_z=LW` once submerged).

    Parameters
    ----------
    depth, phi : array_like
        Tip depth [m] (capped at ``height``; 0 gives :math:`a_z=0`); heading in [0, pi/2] [rad].
    length, width, height : float
        :math:`L` (along y), :math:`W` (along x) and height [m].

    Notes
    -----
    .. math::
       :label: chen2026-eq-12

       F_x=z\left[L f_n(\varphi)\sigma_x+W f_t(\varphi_c)\sigma_y\right],\quad
       F_y=z\left[L f_t(\varphi)\sigma_x+W f_n(\varphi_c)\sigma_y\right],\quad F_z=LW\sigma_z \tag{12}
    """
    z = xp.minimum(depth, height)
    phic = 0.5 * math.pi - phi
    ax, by = z * length * f_n(phi, xp=xp), z * length * f_t(phi, xp=xp)
    bx, ay = z * width * f_t(phic, xp=xp), z * width * f_n(phic, xp=xp)
    az = xp.where(depth > 0, length * width, 0.0)
    return ax, bx, by, ay, az


def semicylinder_coefficients(
    depth: XpArray, phi: XpArray, radius: float, width: float, height: float, xp: Namespace = np
) -> Coefficients:
    r"""Semi-cylindrical foot, eq. (13) with :math:`F_z` corrected (E20): the coefficients [m^2].

    Parameters
    ----------
    depth, phi : array_like
        Tip depth [m] (capped at ``height``); heading from the axis (x) in [0, pi/2] [rad].
    radius, width, height : float
        :math:`R`, :math:`W` (axis length, along x) and height (<= R) [m].

    Notes
    -----
    .. math::
       :label: chen2026-eq-13

       \begin{aligned}F_x&=R^2(\theta_c-sc)\,f_n(\varphi)\sigma_x+WR(1-c)\,f_t(\varphi_c)\sigma_y,\\
       F_y&=R^2(\theta_c-sc)\,f_t(\varphi)\sigma_x+WR(1-c)\,f_n(\varphi_c)\sigma_y,\\
       F_z&=2WR\,\sigma_z\left[s-\tfrac{s^3}{3}+\tfrac{(1-c)^2(2+c)}{3}\right]\end{aligned} \tag{13}
    """
    z = xp.minimum(depth, height)
    th = _theta(z, radius, xp=xp)
    s, c = xp.sin(th), xp.cos(th)
    phic = 0.5 * math.pi - phi
    seg = radius * radius * (th - s * c)  # end-cap segment area (x projection)
    side = width * radius * (1.0 - c)  # = W z (y projection)
    # 2/3 - c + c^3/3 = (1 - c)^2 (2 + c)/3 with 1 - c = z/R: no cancellation near z = 0
    u = z / radius
    az = 2.0 * width * radius * (s - s * s * s / 3.0 + u * u * (2.0 + c) / 3.0)
    ax, by = seg * f_n(phi, xp=xp), seg * f_t(phi, xp=xp)
    bx, ay = side * f_t(phic, xp=xp), side * f_n(phic, xp=xp)
    return ax, bx, by, ay, az


def semisphere_coefficients(
    depth: XpArray, phi: XpArray, radius: float, height: float, xp: Namespace = np
) -> Coefficients:
    r"""Semi-spherical foot (a cap), eq. (14) corrected (E21-E23): the coefficients [m^2], with
    :math:`a_z=2\pi R^2\int_0^{\theta_c}(\cos^3\sin+\sin^4)` and no shear terms.

    Parameters
    ----------
    depth, phi : array_like
        Tip depth [m] (capped at ``height``); heading in [0, pi/2] [rad].
    radius, height : float
        :math:`R` and cap height (<= R) [m].

    Notes
    -----
    .. math::
       :label: chen2026-eq-14

       F_x=\tfrac83R^2(\theta_c-sc)\cos\varphi\,\sigma_x,\quad F_y=\tfrac83R^2(\theta_c-sc)\sin\varphi\,\sigma_y,
       \quad F_z=\tfrac{S_e}{4}\left(2+2c^2+\tfrac{2c^3}{s}-\tfrac{5c}{s}+\tfrac{3\theta_c}{s^2}\right)\sigma_z \tag{14}
    """
    z = xp.minimum(depth, height)
    th = _theta(z, radius, xp=xp)
    s, c = xp.sin(th), xp.cos(th)
    side = 8.0 / 3.0 * radius * radius * (th - s * c)
    u = z / radius  # = 1 - c, exact
    # int_0^tc (cos^3 sin + sin^4); 1 - c^4 = (1 - c)(1 + c)(1 + c^2)
    ring = u * (1.0 + c) * (1.0 + c * c) / 4.0 + 3.0 * th / 8.0 - xp.sin(2.0 * th) / 4.0
    ring = ring + xp.sin(4.0 * th) / 32.0
    az = 2.0 * math.pi * radius * radius * ring
    return side * xp.cos(phi), 0.0 * side, 0.0 * side, side * xp.sin(phi), az


def closed_form_coefficients(
    kind: int, g0: float, g1: float, g2: float, depth: XpArray, phi: XpArray, xp: Namespace = np
) -> Coefficients:
    """The coefficients [m^2] of the closed-form foot ``kind``: 0 flat ``(L, W, H)``, 1
    semi-cylinder ``(R, W, H)``, 2 semi-sphere ``(R, H, -)`` [m]; depth [m], phi [rad]."""
    if kind == 0:
        return flat_coefficients(depth, phi, g0, g1, g2, xp=xp)
    if kind == 1:
        return semicylinder_coefficients(depth, phi, g0, g1, g2, xp=xp)
    return semisphere_coefficients(depth, phi, g0, g1, xp=xp)


def closed_form_force(
    kind: int, g0: float, g1: float, g2: float, depth: XpArray, sx: XpArray, sy: XpArray,
    sz: XpArray, heading: XpArray, xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray]:  # fmt: skip
    """World force [N] of the closed-form foot ``kind`` (:func:`closed_form_coefficients`,
    then :func:`~mudrft.feet.base.world_force`); depth [m], stresses [Pa], heading [rad]."""
    co = closed_form_coefficients(kind, g0, g1, g2, depth, fold_heading(heading, xp=xp), xp=xp)
    return world_force(co, sx, sy, sz, heading, xp=xp)


def flat_forces(
    depth: XpArray, stress: XpArray, heading: XpArray, *, length: float, width: float,
    height: float, xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """Flat foot, eq. (12): magnitudes (Fx, Fy, Fz) [N] at tip depth [m], channel stresses
    (..., 3) [Pa] and heading in [0, pi/2] [rad]; dimensions [m] as :func:`flat_coefficients`.

    >>> f = flat_forces(0.01, [1e3, 0.0, 1e3], 0.0, length=0.08, width=0.065, height=0.026)
    >>> f.round(4).tolist()
    [0.8, 0.0, 5.2]
    """
    co = flat_coefficients(xp.asarray(depth), xp.asarray(heading), length, width, height, xp=xp)
    return magnitudes(co, stress, xp)


def semicylinder_forces(
    depth: XpArray, stress: XpArray, heading: XpArray, *, radius: float, width: float,
    height: float, xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """Semi-cylindrical foot, eq. (13) corrected (E20): magnitudes (Fx, Fy, Fz) [N]; arguments
    as :func:`flat_forces`, dimensions [m] as :func:`semicylinder_coefficients`.

    >>> kw = dict(radius=0.045, width=0.065, height=0.045)
    >>> f = semicylinder_forces(0.045, [0.0, 0.0, 1.0], 0.0, **kw)
    >>> round(float(f[2]) / (2 * 0.045 * 0.065), 6)  # half-cylinder: 2WR[1 - 1/3 + 2/3]
    1.333333
    """
    d, h = xp.asarray(depth), xp.asarray(heading)
    return magnitudes(semicylinder_coefficients(d, h, radius, width, height, xp=xp), stress, xp)


def semisphere_forces(
    depth: XpArray, stress: XpArray, heading: XpArray, *, radius: float, height: float,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """Semi-spherical foot, eq. (14) corrected (E21-E23): magnitudes (Fx, Fy, Fz) [N];
    arguments as :func:`flat_forces`, dimensions [m] as :func:`semisphere_coefficients`.

    >>> f = semisphere_forces(0.045, [1.0, 1.0, 1.0], 0.0, radius=0.045, height=0.045)
    >>> round(float(f[0]) / 0.045**2, 6), round(float(f[2]) / (np.pi * 0.045**2), 6)
    (4.18879, 1.678097)
    """
    co = semisphere_coefficients(xp.asarray(depth), xp.asarray(heading), radius, height, xp=xp)
    return magnitudes(co, stress, xp)


# -- the printed finals, kept to show the errata (E20-E23) ---------------------------------
def printed_semicylinder_fz(
    depth: ArrayLike, sz: FloatOrArray, *, radius: float, width: float
) -> FloatOrArray:
    r"""Printed eq. (13c): :math:`F_z=\tfrac13S_e(2+c^2)\sigma_z` [N] (see erratum E20)."""
    th = _theta(np.asarray(depth, dtype=float), radius)
    se = 2 * radius * width * np.sin(th)
    return se / 3.0 * (2.0 + np.cos(th) ** 2) * sz


def printed_semisphere_fz(depth: ArrayLike, sz: FloatOrArray, *, radius: float) -> FloatOrArray:
    r"""Printed eq. (14b) final, with "2 + c^2" [N] (see erratum E21); needs depth > 0."""
    th = _theta(np.asarray(depth, dtype=float), radius)
    s, c = np.sin(th), np.cos(th)
    se = math.pi * radius**2 * s**2
    return se / 4.0 * (2 + c**2 + 2 * c**3 / s - 5 * c / s + 3 * th / s**2) * sz


def printed_semisphere_fxy(
    depth: ArrayLike, sx: FloatOrArray, sy: FloatOrArray, heading: FloatOrArray, *, radius: float
) -> FloatArray:
    r"""Printed eq. (14a): :math:`\tfrac{4S_e}{3\pi s}(\tfrac{2\theta_c}{s}-1)` (E22, E23) [N].

    Returns ``(Fx, Fy)`` stacked on the last axis; equal to :math:`\tfrac13R^2(8\theta_c
    -4\sin\theta_c)(\cos\varphi\,\sigma_x,\sin\varphi\,\sigma_y)`.
    """
    th = _theta(np.asarray(depth, dtype=float), radius)
    s = np.sin(th)
    se = math.pi * radius**2 * s**2
    k = 4 * se / (3 * math.pi * s) * (2 * th / s - 1)
    return np.stack([k * np.cos(heading) * sx, k * np.sin(heading) * sy], axis=-1)
