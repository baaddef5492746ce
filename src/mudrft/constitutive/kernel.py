r"""The constitutive step: the one definition of how a stress channel advances in time.

:func:`channel_update` is the only place where eqs. (1)-(5) are stepped. Every path calls
it: :func:`mudrft.constitutive.step` (the validated reference), :class:`mudrft.MudTerrain`
(one foot on Python floats, or a batch on numpy arrays), the JAX backend
(``xp=jax.numpy``), calibration, and the numba backend, which compiles this very function
on floats (decision D80). It is written in the element-wise subset of
:mod:`mudrft._xp`: no validation, no shapes, no stacking.

The ODEs (3) and (5) are linear in the state when the rate is held constant over a step,
so the update is their exact exponential solution: unconditionally stable for every time
constant in the tables at any step size, and exact for inputs that are piecewise linear in
time. The only approximation is the sealing function, evaluated at the middle of the step
(second order).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from . import laws
from .state import ChannelState, ChannelStress

__all__ = ["ChannelConstants", "channel_constants", "channel_update", "expm1_over_x"]


class ChannelConstants(NamedTuple):
    """The numbers a channel step needs, as a pytree/tuple that numba and JAX can carry.

    Fields are floats or arrays broadcasting with the channel state: ``alpha``,
    ``sigma_y`` [Pa]; ``n``, ``epsilon``, ``k_r`` [-]; ``lam``, ``tau_build``,
    ``tau_leak`` [s]; ``eta_m``, ``eta_inf`` [Pa s]; ``k_a`` [1/s]; ``nu`` [1/s].
    """

    alpha: Any
    n: Any
    lam: Any
    eta_m: Any
    eta_inf: Any
    k_a: Any
    k_r: Any
    tau_build: Any
    tau_leak: Any
    epsilon: Any
    sigma_y: Any
    nu: Any


def channel_constants(params: Any) -> ChannelConstants:
    """The constants of :func:`channel_update` from a parameter set.

    Parameters
    ----------
    params : MudParameters or JaxParams
        Any object with the fields of :class:`~mudrft.parameters.base.MudParameters`
        (and ``k_a``, ``k_r``); arrays (a batch, or traced JAX values) pass through.

    Examples
    --------
    >>> import mudrft
    >>> c = channel_constants(mudrft.paper_parameters(0.25))
    >>> c.lam, c.sigma_y
    (1.9, 7100.0)
    """
    p = params
    return ChannelConstants(
        alpha=p.alpha,
        n=p.n,
        lam=p.lam,
        eta_m=p.eta_m,
        eta_inf=p.eta_inf,
        k_a=p.k_a,
        k_r=p.k_r,
        tau_build=p.tau_build,
        tau_leak=p.tau_leak,
        epsilon=p.epsilon,
        sigma_y=p.sigma_y,
        nu=p.nu,
    )


def expm1_over_x(x: Any, *, xp: Any = np) -> Any:
    """(exp(x) - 1) / x, accurate near 0 and safe under JAX autodiff [-]."""
    small = xp.abs(x) < 1e-6
    xs = xp.where(small, 1.0, x)
    return xp.where(small, 1.0 + 0.5 * x + x * x / 6.0, xp.expm1(xs) / xs)


def channel_update(
    c: ChannelConstants,
    state: ChannelState,
    gamma: Any,
    gamma_dot: Any,
    dt: Any,
    seal: Any = 1.0,
    kappa: Any = 1.0,
    *,
    xp: Any = np,
) -> tuple[ChannelState, ChannelStress]:
    r"""Advance one stress channel by ``dt``; no validation (see :func:`mudrft.constitutive.step`).

    Structure (eq. 3b), exactly: :math:`\xi\leftarrow\xi_{ss}+(\xi-\xi_{ss})e^{-\Delta t/\tau_\xi}`.
    Lagged thixotropic stress (eq. 3a, driven by :math:`A+B\xi(t)`), exactly; with the
    acceleration term kept (``kappa = 1``, decision D6) the :math:`\lambda\eta_\infty\ddot\gamma`
    impulse makes :math:`\sigma_{th}=\eta_\infty\dot\gamma+s_{th}`. Suction (eq. 5) exactly,
    with the sealing state (decision D4) at mid-step. Total (eq. 1):
    :math:`\sigma_b(1-\phi_{end})+\sigma_{th}+H_\nu\sigma_s`.

    Parameters
    ----------
    c : ChannelConstants
        Model constants (SI), from :func:`channel_constants`.
    state : ChannelState
        State at the start of the step.
    gamma : array_like
        Dimensionless displacement at the end of the step [-].
    gamma_dot : array_like
        Dimensionless rate over the step, held constant [1/s].
    dt : float or array_like
        Step length [s], > 0.
    seal : array_like
        Factor in [0, 1] multiplying the sealing state [-] (1: the foot can seal).
    kappa : float
        1.0 keeps the acceleration term of :math:`f_\xi`, 0.0 drops it [-].
    xp : module, keyword-only
        Element-wise namespace (:mod:`mudrft._xp`).

    Returns
    -------
    state : ChannelState
        State at the end of the step.
    stress : ChannelStress
        Stresses at the end of the step [Pa].
    """
    g_old, gw_old, xi, s_th, sig_s = state
    # deepest point of the current intrusion, and the retraction from it
    ag = xp.abs(gamma)
    agw = xp.abs(gw_old)
    flipped = xp.sign(gamma) * xp.sign(gw_old) < 0
    deeper = (ag >= agw) | flipped
    gw_new = xp.where(deeper, gamma, gw_old)
    direction = xp.where(
        gw_new != 0, xp.sign(gw_new), xp.where(gamma_dot != 0, xp.sign(gamma_dot), 1.0)
    )
    r_start = xp.where(flipped, 0.0, xp.maximum(agw - xp.abs(g_old), 0.0))
    r_end = xp.maximum(xp.abs(gw_new) - ag, 0.0)

    # structure parameter, eq. (3b): exact exponential update
    tau = laws.tau_xi(gamma_dot, c.k_a, c.k_r, xp=xp)
    xi_ss = c.k_a * tau
    xi_new = xi_ss + (xi - xi_ss) * xp.exp(-dt / tau)

    # lagged thixotropic stress, eq. (3a) driven by A + B xi(t): exact (supplementary eq. S2
    # generalised to any xi(0) and to tau_xi == lambda)
    a_drive = (1.0 - kappa) * c.eta_inf * gamma_dot
    b_drive = c.eta_m * gamma_dot
    e_lam = xp.exp(-dt / c.lam)
    conv = e_lam * (dt / c.lam) * expm1_over_x(dt * (1.0 / c.lam - 1.0 / tau), xp=xp)
    s_new = (
        s_th * e_lam + (a_drive + b_drive * xi_ss) * (1.0 - e_lam) + b_drive * (xi - xi_ss) * conv
    )

    # suction, eq. (5): exact exponential with the sealing state at mid-step (decision D4)
    phi = seal * laws.sealing(0.5 * (r_start + r_end), c.epsilon, xp=xp)
    a = laws.suction_rate(phi, c.tau_build, c.tau_leak)
    target = -direction * phi * c.sigma_y / (a * c.tau_build)
    sig_new = target + (sig_s - target) * xp.exp(-a * dt)

    # stresses at the end of the step, eq. (1); the bed-contact factor is decision D2
    sigma_b = laws.elastic_stress(gamma, c.alpha, c.n, xp=xp) * laws.bed_contact(
        r_end, c.epsilon, xp=xp
    )
    sigma_th = s_new + kappa * c.eta_inf * gamma_dot
    suction = laws.switch(direction * gamma_dot, c.nu, xp=xp) * sig_new
    new_state = ChannelState(gamma=gamma, gamma_w=gw_new, xi=xi_new, s_th=s_new, sigma_s=sig_new)
    stress = ChannelStress(
        total=sigma_b + sigma_th + suction, elastic=sigma_b, thixotropic=sigma_th, suction=suction
    )
    return new_state, stress
