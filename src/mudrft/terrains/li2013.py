r"""Li, Zhang & Goldman (Science 2013): the Fourier fit of granular RFT and its media; the
stress per unit depth on a plate element is :math:`\zeta\,\alpha^{fit}(\beta,\gamma)` (D50).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .._validation import check_broadcast, check_finite

__all__ = [
    "DEFAULT_ZETA", "GRANULAR_MEDIA", "LI2013_GENERIC", "PLAUSIBLE_ZETA", "FourierCoefficients",
    "li2013_alpha"
]  # fmt: skip


@dataclass(frozen=True)
class FourierCoefficients:
    r"""Coefficients of Li et al.'s (2013) first-order Fourier fit of :math:`\alpha_{z,x}`
    (:meth:`alpha`; docs/model.md, section 8), with :math:`\beta\in[-\pi/2,\pi/2]` the attack
    angle (0: horizontal) and :math:`\gamma\in[-\pi/2,\pi/2]` the velocity's angle below the
    horizontal."""

    A00: float
    A10: float
    B01: float
    B11: float
    Bm11: float
    C01: float
    C11: float
    Cm11: float
    D10: float

    @property
    def plate(self) -> float:
        r""":math:`\alpha_z(0,\pi/2)`, a horizontal plate pushed straight down (units of the fit).

        >>> round(LI2013_GENERIC.plate, 12)
        1.0
        """
        return float(self.alpha(0.0, np.pi / 2)[1])

    def alpha(self, beta: ArrayLike, gamma: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """``(alpha_x, alpha_z)`` at attack angle ``beta`` and intrusion angle ``gamma`` [rad]."""
        b2, g = 2.0 * np.asarray(beta, dtype=float), np.asarray(gamma, dtype=float)
        az = (
            self.A00
            + self.A10 * np.cos(b2)
            + self.B01 * np.sin(g)
            + self.B11 * np.sin(b2 + g)
            + self.Bm11 * np.sin(-b2 + g)
        )
        ax = (
            self.C01 * np.cos(g)
            + self.C11 * np.cos(b2 + g)
            + self.Cm11 * np.cos(-b2 + g)
            + self.D10 * np.sin(b2)
        )
        return ax, az


#: Li, Zhang & Goldman (2013), generic coefficients (dimensionless; alpha_z(0, pi/2) = 1).
LI2013_GENERIC = FourierCoefficients(
    A00=0.206, A10=0.169, B01=0.358, B11=0.212, Bm11=0.055,  # alpha_z
    C01=0.253, C11=-0.124, Cm11=0.007, D10=0.088,  # alpha_x
)  # fmt: skip

#: Scale zeta [N/m^3] of loosely and closely packed poppy seeds, alpha_z(0, pi/2) of Li et
#: al.'s (2013) per-medium fits (decision D50).
GRANULAR_MEDIA: dict[str, float] = {"poppy-lp": 0.254e6, "poppy-cp": 0.464e6}

#: Default scale: loosely packed poppy seeds [N/m^3].
DEFAULT_ZETA = GRANULAR_MEDIA["poppy-lp"]

#: Plausible scales of a granular medium [N/m^3]; below, most likely N/cm^3 read as N/m^3.
PLAUSIBLE_ZETA = (1.0e3, 1.0e8)


def li2013_alpha(
    beta: ArrayLike, gamma: ArrayLike, *, coefficients: FourierCoefficients = LI2013_GENERIC
) -> tuple[np.ndarray, np.ndarray]:
    r"""Generic RFT stress per unit depth of Li et al. (2013), :math:`(\alpha_x, \alpha_z)` in the
    fit's units: :math:`\alpha_x` > 0 resists the motion, :math:`\alpha_z` > 0 lifts.

    Parameters
    ----------
    beta : array_like
        Attack angle of the element [rad] (0: horizontal plate).
    gamma : array_like
        Angle of the velocity below the horizontal [rad], in :math:`[-\pi/2, \pi/2]`.
    coefficients : FourierCoefficients, keyword-only
        The fit (default: the generic one, dimensionless).

    Examples
    --------
    >>> ax, az = li2013_alpha(0.0, np.pi / 2)     # horizontal plate pushed straight down
    >>> round(float(ax), 12), round(float(az), 3)
    (0.0, 1.0)
    """
    b, g = check_finite("beta", beta), check_finite("gamma", gamma)
    check_broadcast(beta=b.shape, gamma=g.shape)
    return coefficients.alpha(b, g)
