r"""The paper's printed closed-form finals, kept to show the errata (E20-E23 in docs/model.md).

The model uses the corrected forms of :mod:`mudrft.feet.closed_form`; these reproduce what
eqs. (13c), (14a) and (14b) print, for the erratum tests and the docs.
"""

from __future__ import annotations

import math

import numpy as np

from .._typing import ArrayLike, FloatArray, FloatOrArray

__all__ = ["printed_semicylinder_fz", "printed_semisphere_fxy", "printed_semisphere_fz"]


def _theta(z: FloatArray, radius: float) -> FloatArray:
    return np.arccos(np.clip(1.0 - z / radius, -1.0, 1.0))


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
