"""The paper's closed-form solutions of eqs. (3) and (5): eqs. (9)-(11), supplementary Sec. I.

Each takes ``params``, the model constants (:class:`~mudrft.parameters.base.MudParameters`);
``t`` [s] is the time since the start of a motion at the constant rate ``gamma_dot`` [1/s].
"""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike, FloatOrArray
from ..parameters.base import MudParameters
from . import laws
from .kernel import relaxation_convolution

__all__ = ["suction_closed_form", "thixotropic_approx", "thixotropic_exact", "xi_exact"]


def xi_exact(
    t: ArrayLike, gamma_dot: FloatOrArray, params: MudParameters, *, xi0: float = 0.0
) -> FloatOrArray:
    r"""Structure parameter at constant rate, :math:`\xi_{ss}+(\xi_0-\xi_{ss})e^{-t/\tau_\xi}` [-].

    The supplementary's :math:`(1-e^{t/\tau_\xi})\xi_{ss}` has a sign slip (erratum E3).
    ``xi0`` [-] is the structure at t = 0.
    """
    tau = laws.tau_xi(gamma_dot, params.k_a, params.k_r)
    xi_ss = params.k_a * tau
    return xi_ss + (xi0 - xi_ss) * np.exp(-np.asarray(t) / tau)


def thixotropic_exact(
    t: ArrayLike, gamma_dot: FloatOrArray, params: MudParameters, *, xi0: float = 0.0,
    acceleration: bool = False,
) -> FloatOrArray:  # fmt: skip
    r"""Thixotropic stress [Pa] at constant rate from rest, supplementary eq. (S2), exact.

    For :math:`\xi(0)=0` and :math:`\ddot\gamma=0`:

    .. math:: \sigma_{th}=(1-e^{-t/\lambda})(\eta_\infty+\xi_{ss}\eta_m)\dot\gamma
              +(e^{-t/\lambda}-e^{-t/\tau_\xi})\frac{\tau_\xi}{\tau_\xi-\lambda}\xi_{ss}\eta_m\dot\gamma .

    The second term does not vanish for :math:`\tau_\xi\approx\lambda` (erratum E5). Here for
    any :math:`\xi_0` and :math:`\tau_\xi`, and with ``acceleration=True`` for a rate that
    jumps from 0 at t = 0 (adding :math:`\eta_\infty\dot\gamma` at once), from the initial
    structure ``xi0`` [-].
    """
    t = np.asarray(t, dtype=float)
    tau = laws.tau_xi(gamma_dot, params.k_a, params.k_r)
    xi_ss = params.k_a * tau
    lam = params.lam
    kappa = 1.0 if acceleration else 0.0
    A, B = (1.0 - kappa) * params.eta_inf * gamma_dot, params.eta_m * gamma_dot
    e_lam = np.exp(-t / lam)
    conv = relaxation_convolution(t, lam, tau, e_lam, np.exp(-t / tau))
    return (
        (A + B * xi_ss) * (1.0 - e_lam)
        + B * (xi0 - xi_ss) * conv
        + kappa * params.eta_inf * gamma_dot
    )


def thixotropic_approx(
    t: ArrayLike, gamma_dot: FloatOrArray, params: MudParameters
) -> FloatOrArray:
    r"""The paper's approximation, eq. (9) [Pa]; exact only when :math:`\xi` starts steady (E5).

    .. math::
       :label: chen2026-eq-9

       \sigma_{th}=\left(1-e^{-t/\lambda}\right)\sigma_{th,ss} \tag{9}
    """
    t = np.asarray(t, dtype=float)
    steady = laws.thixotropic_steady(gamma_dot, params.eta_inf, params.eta_m, params.gamma_dot_c)
    return (1.0 - np.exp(-t / params.lam)) * steady


def suction_closed_form(
    dt: ArrayLike, phi: FloatOrArray, params: MudParameters, *, sigma_s0: float = 0.0
) -> FloatOrArray:
    r"""Suction [Pa] at constant sealing state, eqs. (10)-(11).

    .. math:: \sigma_s(t)=\sigma_{s,ss}+(\sigma_s(t_w)-\sigma_{s,ss})e^{-a\Delta t}

    with :math:`\sigma_{s,ss}` and :math:`a` of eq. (11). ``dt`` is the time :math:`\Delta t=t-t_w`
    [s] since the retraction began, ``phi`` the sealing state [-], ``sigma_s0`` the suction at
    :math:`t_w` [Pa], which the paper takes 0:

    .. math::
       :label: chen2026-eq-10

       \sigma_s=\left(1-e^{-a\Delta t}\right)\sigma_{s,ss},\qquad \Delta t=t-t_w \tag{10}
    """
    a = laws.suction_rate(phi, params.tau_build, params.tau_leak)
    ss = laws.suction_steady(phi, params.tau_build, params.tau_leak, params.sigma_y)
    return ss + (sigma_s0 - ss) * np.exp(-a * np.asarray(dt, dtype=float))
