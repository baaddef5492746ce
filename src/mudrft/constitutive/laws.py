r"""Pure, vectorized stress laws of the mud model (Chen et al. 2026, eqs. 1-5, 7).

Every function broadcasts over arrays or floats; ``xp`` selects the array namespace
(``numpy`` by default, ``jax.numpy``, or :data:`mudrft._xp.pyfloat`). The dimensionless
displacement is :math:`\gamma=q/L_c` and its rate :math:`\dot\gamma=\dot q/L_c`, with
:math:`q` [m] the intrusion displacement and :math:`L_c` [m] the characteristic length.
"""

from __future__ import annotations

import numpy as np

from .._typing import Namespace, XpArray

__all__ = [
    "bed_contact", "elastic_stress", "f_n", "f_n_extended", "f_t", "f_t_extended", "sealing",
    "sealing_printed", "suction_rate", "suction_steady", "suction_steady_at_rate", "switch",
    "tau_xi", "thixotropic_steady", "xi_steady", "yield_stress",
]  # fmt: skip


def elastic_stress(gamma: XpArray, alpha: XpArray, n: XpArray, xp: Namespace = np) -> XpArray:
    r"""Immediate (nonlinear elastic) resistance, eq. (2), odd in :math:`\gamma` [Pa], of the
    dimensionless displacement ``gamma`` [-], stiffness ``alpha`` [Pa] and exponent ``n`` in
    (0, 1] [-].

    .. math::
       :label: chen2026-eq-2

       \sigma_b=\alpha\gamma^n \tag{2}

    applied as :math:`\alpha|\gamma|^n\operatorname{sgn}\gamma`.

    Examples
    --------
    >>> float(elastic_stress(0.25, 24e3, 0.5))
    12000.0
    """
    g = xp.abs(gamma)
    # safe power: 0**n = 0 with a finite gradient under JAX
    safe = xp.where(g > 0, g, 1.0)
    return xp.where(g > 0, alpha * safe**n, 0.0) * xp.sign(gamma)


def switch(gamma_dot: XpArray, nu: XpArray, xp: Namespace = np) -> XpArray:
    r"""Intrusion/retraction index :math:`H_\nu` of eq. (1) [-]: about 0 intruding, 1 retracting,
    of the dimensionless rate ``gamma_dot`` along the intrusion direction and the switch width
    ``nu`` [1/s].

    .. math::
       :label: chen2026-eq-1

       \sigma_{tot}=\sigma_b+\sigma_{th}+H_\nu(\dot\gamma)\,\sigma_s,\qquad
       H_\nu(\dot\gamma)=\tfrac12\left(1-\tanh\frac{\dot\gamma}{\nu}\right) \tag{1}

    Examples
    --------
    >>> round(float(switch(-1.0, 0.01)), 6), float(switch(0.0, 0.01))
    (1.0, 0.5)
    """
    return 0.5 * (1.0 - xp.tanh(gamma_dot / nu))


def sealing_printed(
    gamma: XpArray, gamma0: XpArray, epsilon: XpArray, xp: Namespace = np
) -> XpArray:
    r"""The sealing function as printed below eq. (5), for reference (the model uses
    :func:`sealing`, decision D4): :math:`\tfrac12(1-\tanh((\gamma-\gamma_0)/\varepsilon))` [-]
    of the displacement ``gamma``, its value ``gamma0`` at the start of retraction and the
    width ``epsilon`` [-]."""
    return 0.5 * (1.0 - xp.tanh((gamma - gamma0) / epsilon))


def sealing(retraction: XpArray, epsilon: XpArray, xp: Namespace = np) -> XpArray:
    r"""Sealing state of the cavity, :math:`\phi=\tanh(\max(r,0)/\varepsilon)` [-] (decision D4).

    0 while the foot intrudes or rests (pure leak), 1 within a few :math:`\varepsilon` of
    retraction (sealed). ``retraction`` is :math:`r=|\gamma_w|-|\gamma|` since the deepest
    point, ``epsilon`` the width [-].

    Examples
    --------
    >>> float(sealing(0.0, 0.02)), round(float(sealing(0.1, 0.02)), 4)
    (0.0, 0.9999)
    """
    return xp.tanh(xp.maximum(retraction, 0.0) / epsilon)


def bed_contact(retraction: XpArray, epsilon: XpArray, xp: Namespace = np) -> XpArray:
    r"""Fraction :math:`1-\phi` of :math:`\sigma_b` kept during retraction [-] (decision D2),
    of the ``retraction`` :math:`r` and the width ``epsilon`` [-] (:func:`sealing`)."""
    return 1.0 - sealing(retraction, epsilon, xp=xp)


def xi_steady(gamma_dot: XpArray, gamma_dot_c: XpArray, xp: Namespace = np) -> XpArray:
    r"""Steady structure parameter :math:`\xi_{ss}=\dot\gamma_c/(\dot\gamma_c+|\dot\gamma|)` [-]
    of the rate ``gamma_dot`` and the critical rate ``gamma_dot_c`` [1/s].

    .. math::
       :label: chen2026-eq-3b

       \dot\xi=k_a(1-\xi)-k_r|\dot\gamma|\,\xi,\qquad
       \xi_{ss}=\frac{k_a}{k_a+k_r|\dot\gamma|}=\frac{\dot\gamma_c}{\dot\gamma_c+|\dot\gamma|} \tag{3b}

    Examples
    --------
    >>> float(xi_steady(0.14, 0.14))
    0.5
    """
    return gamma_dot_c / (gamma_dot_c + xp.abs(gamma_dot))


def tau_xi(gamma_dot: XpArray, k_a: XpArray, k_r: XpArray, xp: Namespace = np) -> XpArray:
    r"""Time constant of eq. (3b), :math:`\tau_\xi=1/(k_a+k_r|\dot\gamma|)` [s], of the rate
    ``gamma_dot`` [1/s], aging rate ``k_a`` [1/s] and rejuvenation coefficient ``k_r`` [-]."""
    return 1.0 / (k_a + k_r * xp.abs(gamma_dot))


def thixotropic_steady(
    gamma_dot: XpArray, eta_inf: XpArray, eta_m: XpArray, gamma_dot_c: XpArray, xp: Namespace = np
) -> XpArray:
    r"""Steady thixotropic stress, eq. (4) [Pa], of the rate ``gamma_dot`` [1/s], viscosities
    ``eta_inf``, ``eta_m`` [Pa s] and critical rate ``gamma_dot_c`` [1/s].

    .. math::
       :label: chen2026-eq-4

       \sigma_{th,ss}=(\eta_\infty+\xi_{ss}\eta_m)\,\dot\gamma,\qquad
       \sigma_Y=(\eta_m-\eta_\infty)\,\dot\gamma_c \tag{4}
    """
    return (eta_inf + xi_steady(gamma_dot, gamma_dot_c, xp=xp) * eta_m) * gamma_dot


def yield_stress(eta_m: XpArray, eta_inf: XpArray, gamma_dot_c: XpArray) -> XpArray:
    r"""Yield stress from eq. (4), :math:`\sigma_Y=(\eta_m-\eta_\infty)\dot\gamma_c` [Pa]
    (erratum E2: the horizontal table rows break it).

    Examples
    --------
    >>> round(float(yield_stress(0.27e6, 0.0031e6, 0.042)), 1)
    11209.8
    """
    return (eta_m - eta_inf) * gamma_dot_c


def suction_rate(phi: XpArray, tau_build: XpArray, tau_leak: XpArray) -> XpArray:
    r"""Rate :math:`a=\phi/\tau_{build}+(1-\phi)/\tau_{leak}` of eq. (11) [1/s]."""
    return phi / tau_build + (1.0 - phi) / tau_leak


def suction_steady(
    phi: XpArray, tau_build: XpArray, tau_leak: XpArray, sigma_y: XpArray
) -> XpArray:
    r"""Steady suction, eq. (11) [Pa], at the sealing state ``phi`` [-], build-up and leak
    times ``tau_build``, ``tau_leak`` [s] and yield stress ``sigma_y`` [Pa].

    .. math::
       :label: chen2026-eq-11

       \sigma_{s,ss}=-\frac{\phi}{a\,\tau_{build}}\sigma_Y,\qquad
       a=\frac{\phi}{\tau_{build}}+\frac{1-\phi}{\tau_{leak}} \tag{11}

    Examples
    --------
    >>> float(suction_steady(1.0, 0.32, 0.17, 7100.0))
    -7100.0
    >>> float(suction_steady(0.0, 0.32, 0.17, 7100.0))
    -0.0
    """
    return suction_steady_at_rate(phi, suction_rate(phi, tau_build, tau_leak), tau_build, sigma_y)


def suction_steady_at_rate(
    phi: XpArray, rate: XpArray, tau_build: XpArray, sigma_y: XpArray
) -> XpArray:
    r"""Eq. (11) at a given ``rate`` :math:`a` [1/s]: :math:`-\phi\sigma_Y/(a\tau_{build})` [Pa]
    (the other arguments as :func:`suction_steady`).

    Examples
    --------
    >>> float(suction_steady_at_rate(1.0, 1.0 / 0.32, 0.32, 7100.0))
    -7100.0
    """
    return -phi * sigma_y / (rate * tau_build)


def f_n(psi: XpArray, xp: Namespace = np) -> XpArray:
    r"""Normal scaling factor of eq. (7), :math:`f_n(\psi)=\tfrac12(1+\cos2\psi)` [-], of the
    angle ``psi`` [rad].

    .. math::
       :label: chen2026-eq-7

       \sigma_v^i=f_i(\psi_1)\,\sigma_v,\quad \sigma_h^i=f_i(\psi_2)\,\sigma_h,\quad
       f_n(\psi)=\tfrac12(1+\cos2\psi),\quad f_t(\psi)=\tfrac12(1-\cos2\psi) \tag{7}
    """
    return 0.5 * (1.0 + xp.cos(2.0 * psi))


def f_t(psi: XpArray, xp: Namespace = np) -> XpArray:
    r"""Tangential scaling factor of eq. (7), :math:`f_t(\psi)=\tfrac12(1-\cos2\psi)` [-]."""
    return 0.5 * (1.0 - xp.cos(2.0 * psi))


def f_n_extended(psi: XpArray, xp: Namespace = np) -> XpArray:
    r""":math:`f_n` extended to :math:`\psi\in[-\pi,\pi]` (supplementary Sec. II-C),
    :math:`\cos\psi|\cos\psi|` [-]: negative on trailing faces."""
    c = xp.cos(psi)
    return c * xp.abs(c)


def f_t_extended(psi: XpArray, xp: Namespace = np) -> XpArray:
    r""":math:`f_t` extended to :math:`\psi\in[-\pi,\pi]` (supplementary Sec. II-C),
    :math:`\sin\psi|\sin\psi|` [-] (odd in :math:`\psi`)."""
    s = xp.sin(psi)
    return s * xp.abs(s)
