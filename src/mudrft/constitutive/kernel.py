r"""The constitutive step, :func:`channel_step`: the one definition of how a stress channel
advances in time (eqs. 1-5, or the closed forms 9-11, decision D15), in the element-wise
subset of :mod:`mudrft._xp`, the namespace every ``xp`` argument here names."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from .._typing import Namespace, XpArray
from . import laws
from .state import ChannelState, ChannelStress

__all__ = [
    "ChannelConstants", "channel_constants", "channel_step", "channel_update",
    "channel_update_quasi_static", "expm1_over_x", "relaxation_convolution",
]  # fmt: skip


class ChannelConstants(NamedTuple):
    """The numbers a channel step needs, floats or arrays: ``alpha``, ``sigma_y`` [Pa];
    ``n``, ``epsilon``, ``k_r`` [-]; ``lam``, ``tau_build``, ``tau_leak`` [s]; ``eta_m``,
    ``eta_inf`` [Pa s]; ``k_a``, ``nu`` [1/s]."""

    alpha: XpArray
    n: XpArray
    lam: XpArray
    eta_m: XpArray
    eta_inf: XpArray
    k_a: XpArray
    k_r: XpArray
    tau_build: XpArray
    tau_leak: XpArray
    epsilon: XpArray
    sigma_y: XpArray
    nu: XpArray


def channel_constants(params: Any) -> ChannelConstants:  # MudParameters or JaxParams
    """The constants of :func:`channel_update` from ``params``, a
    :class:`~mudrft.parameters.base.MudParameters` or JaxParams (SI fields, floats or arrays).

    Examples
    --------
    >>> import mudrft
    >>> c = channel_constants(mudrft.paper_parameters(0.25))
    >>> c.lam, c.sigma_y
    (1.9, 7100.0)
    """
    return ChannelConstants(*(getattr(params, f) for f in ChannelConstants._fields))


def expm1_over_x(x: XpArray, xp: Namespace = np) -> XpArray:
    """(exp(x) - 1) / x, accurate near 0 and safe under JAX autodiff [-]."""
    small = xp.abs(x) < 1e-6
    xs = xp.where(small, 1.0, x)
    return xp.where(small, 1.0 + 0.5 * x + x * x / 6.0, xp.expm1(xs) / xs)


def relaxation_convolution(
    t: XpArray, lam: XpArray, tau: XpArray, e_lam: XpArray, e_tau: XpArray, xp: Namespace = np
) -> XpArray:
    r"""The factor of :math:`B(\xi(0)-\xi_{ss})` in supplementary eq. (S2) [-], in the two forms
    docs/model.md, section 4, gives (exact at :math:`\tau=\lambda`, erratum E5). ``t`` [s] >= 0
    is the elapsed time, ``lam`` and ``tau`` [s] > 0 the two relaxation times, ``e_lam`` and
    ``e_tau`` [-] their :math:`e^{-t/\lambda}` and :math:`e^{-t/\tau}`.
    """
    x = t * (1.0 / lam - 1.0 / tau)
    near = e_lam * (t / lam) * expm1_over_x(xp.minimum(x, 1.0), xp=xp)
    return xp.where(x > 1.0, (t / lam) * (e_tau - e_lam) / xp.maximum(x, 1.0), near)


def channel_update(
    c: ChannelConstants, state: ChannelState, gamma: XpArray, gamma_dot: XpArray, dt: XpArray,
    seal: XpArray = 1.0, kappa: XpArray = 1.0, xp: Namespace = np,
) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
    r"""Advance one stress channel by ``dt``, exactly at a constant rate (docs/model.md,
    section 4); no validation.

    Parameters and returns as :func:`~mudrft.constitutive.dynamics.step`, with ``c`` the
    constants (SI) of :func:`channel_constants` and ``kappa`` [-]: 1.0 keeps the acceleration
    term of :math:`f_\xi`, 0.0 drops it.
    """
    gw_new, direction, r_start, r_end = _retraction(state, gamma, gamma_dot, xp=xp)
    clock, clock_w = _clocks(state, r_end, dt, xp=xp)
    xi, s_th, sig_s = state.xi, state.s_th, state.sigma_s

    # structure parameter, eq. (3b): exact exponential update
    tau = laws.tau_xi(gamma_dot, c.k_a, c.k_r, xp=xp)
    xi_ss = c.k_a * tau
    e_tau = xp.exp(-dt / tau)
    xi_new = xi_ss + (xi - xi_ss) * e_tau

    # lagged thixotropic stress, eq. (3a) driven by A + B xi(t): exact (eq. S2, any xi(0))
    a_drive, b_drive = (1.0 - kappa) * c.eta_inf * gamma_dot, c.eta_m * gamma_dot
    e_lam = xp.exp(-dt / c.lam)
    conv = relaxation_convolution(dt, c.lam, tau, e_lam, e_tau, xp=xp)
    s_new = (
        s_th * e_lam + (a_drive + b_drive * xi_ss) * (1.0 - e_lam) + b_drive * (xi - xi_ss) * conv
    )

    # suction, eq. (5): exact exponential with the sealing state at mid-step (decision D4)
    phi = seal * laws.sealing(0.5 * (r_start + r_end), c.epsilon, xp=xp)
    a = laws.suction_rate(phi, c.tau_build, c.tau_leak)
    target = direction * laws.suction_steady_at_rate(phi, a, c.tau_build, c.sigma_y)  # eq. (11)
    sig_new = target + (sig_s - target) * xp.exp(-a * dt)

    new_state = ChannelState(gamma, gw_new, xi_new, s_new, sig_new, clock, clock_w)
    sigma_th = s_new + kappa * c.eta_inf * gamma_dot
    return new_state, _stresses(c, new_state, sigma_th, direction, gamma_dot, r_end, xp=xp)


def channel_update_quasi_static(
    c: ChannelConstants, state: ChannelState, gamma: XpArray, gamma_dot: XpArray, dt: XpArray,
    seal: XpArray = 1.0, restart: bool = False, xp: Namespace = np,
) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
    r"""The paper's quasi-static evaluation of a channel, eqs. (1), (2), (9)-(11) (decision D15):
    eq. (9) with the clock :math:`t` from first contact, or from :math:`t_w` with ``restart``,
    and eqs. (10)-(11) with :math:`\phi` at the current retraction (times ``seal``).

    Parameters and returns as :func:`channel_update`, with ``restart`` (bool) in place of
    ``kappa``; ``gamma_dot`` [1/s] is the rate at the end of the step.
    """
    gw_new, direction, _r_start, r_end = _retraction(state, gamma, gamma_dot, xp=xp)
    clock, clock_w = _clocks(state, r_end, dt, xp=xp)
    t9 = xp.where(clock_w > 0.0, clock_w, clock) if restart else clock
    gamma_dot_c = c.k_a / c.k_r
    # eq. (9) with eq. (4); 1 - exp(-t/lambda) written as -expm1(-t/lambda)
    sigma_ss = laws.thixotropic_steady(gamma_dot, c.eta_inf, c.eta_m, gamma_dot_c, xp=xp)
    sigma_th = -xp.expm1(-t9 / c.lam) * sigma_ss
    # eqs. (10)-(11) at the current sealing state
    phi = seal * laws.sealing(r_end, c.epsilon, xp=xp)
    a = laws.suction_rate(phi, c.tau_build, c.tau_leak)
    steady = direction * laws.suction_steady_at_rate(phi, a, c.tau_build, c.sigma_y)
    sig_s = -xp.expm1(-a * clock_w) * steady
    xi = laws.xi_steady(gamma_dot, gamma_dot_c, xp=xp)
    new_state = ChannelState(gamma, gw_new, xi, sigma_th, sig_s, clock, clock_w)
    return new_state, _stresses(c, new_state, sigma_th, direction, gamma_dot, r_end, xp=xp)


def channel_step(
    c: ChannelConstants, state: ChannelState, gamma: XpArray, gamma_dot: XpArray, dt: XpArray,
    seal: XpArray = 1.0, kappa: XpArray = 1.0, quasi_static: bool = False, restart: bool = False,
    xp: Namespace = np,
) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
    """One channel step: :func:`channel_update_quasi_static` when ``quasi_static`` (a static
    bool, as ``restart``), else :func:`channel_update`; no validation (decision D15)."""
    if quasi_static:
        return channel_update_quasi_static(c, state, gamma, gamma_dot, dt, seal, restart, xp=xp)
    return channel_update(c, state, gamma, gamma_dot, dt, seal, kappa, xp=xp)


def _stresses(
    c: ChannelConstants, state: ChannelState, sigma_th: XpArray, direction: XpArray,
    gamma_dot: XpArray, r_end: XpArray, xp: Namespace = np,
) -> ChannelStress:  # fmt: skip
    r"""Eq. (1) at the end of a step [Pa]: :math:`\sigma_b(1-\phi)+\sigma_{th}+H_\nu\sigma_s`."""
    bed = laws.bed_contact(r_end, c.epsilon, xp=xp)
    sigma_b = laws.elastic_stress(state.gamma, c.alpha, c.n, xp=xp) * bed
    suction = laws.switch(direction * gamma_dot, c.nu, xp=xp) * state.sigma_s
    return ChannelStress(sigma_b + sigma_th + suction, sigma_b, sigma_th, suction)


def _retraction(
    state: ChannelState, gamma: XpArray, gamma_dot: XpArray, xp: Namespace = np
) -> XpArray:
    r"""``(gamma_w, direction, r_start, r_end)``: deepest displacement [-], its sign, and
    :math:`r=|\gamma_w|-|\gamma|` at the step's ends [-]; a sign change starts anew."""
    g_old, gw_old = state.gamma, state.gamma_w
    ag, agw = xp.abs(gamma), xp.abs(gw_old)
    flipped = xp.sign(gamma) * xp.sign(gw_old) < 0
    deeper = (ag >= agw) | flipped
    gw_new = xp.where(deeper, gamma, gw_old)
    direction = xp.where(
        gw_new != 0, xp.sign(gw_new), xp.where(gamma_dot != 0, xp.sign(gamma_dot), 1.0)
    )
    r_start = xp.where(flipped, 0.0, xp.maximum(agw - xp.abs(g_old), 0.0))
    r_end = xp.maximum(xp.abs(gw_new) - ag, 0.0)
    return gw_new, direction, r_start, r_end


def _clocks(state: ChannelState, r_end: XpArray, dt: XpArray, xp: Namespace = np) -> XpArray:
    r"""``(clock, clock_w)`` after the step [s]: since first contact, and since :math:`r`
    left 0 (0 while not retracted)."""
    return state.clock + dt, xp.where(r_end > 0.0, state.clock_w + dt, 0.0)
