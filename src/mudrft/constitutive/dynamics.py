r"""Time stepping of the mud constitutive model and the paper's closed-form solutions.

The ODEs (3) and (5) are linear in the state when the rate is held constant over a
step, so :func:`step` advances them with their exact exponential solution: it is
unconditionally stable for every time constant in the tables at any step size,
and exact for inputs that are piecewise linear in time. The only approximation is
the sealing function, evaluated at the middle of the step (second order).

``state, stress = step(params, state, gamma, gamma_dot, dt)`` serves a time loop,
a MuJoCo loop, a batch (arrays everywhere) and, with ``xp=jax.numpy``, a JAX scan.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from .._validation import MudrftError, check_finite, check_increasing, check_positive
from ..parameters.base import MudParameters
from . import laws
from .state import ChannelState, ChannelStress, initial_state

__all__ = [
    "ChannelHistory",
    "run",
    "step",
    "suction_closed_form",
    "thixotropic_approx",
    "thixotropic_exact",
    "xi_exact",
]


def _expm1_over_x(x: Any, xp: Any) -> Any:
    """(exp(x) - 1) / x, accurate near 0 and safe under JAX autodiff."""
    small = xp.abs(x) < 1e-6
    xs = xp.where(small, 1.0, x)
    return xp.where(small, 1.0 + 0.5 * x + x * x / 6.0, xp.expm1(xs) / xs)


def step(
    params: MudParameters,
    state: ChannelState,
    gamma: Any,
    gamma_dot: Any,
    dt: Any,
    *,
    seal: Any = 1.0,
    acceleration: bool = True,
    xp: Any = np,
    validate: bool = True,
) -> tuple[ChannelState, ChannelStress]:
    r"""Advance one stress channel by ``dt`` and return the new state and stresses.

    The rate is held constant over the step; ``gamma`` is the displacement at its
    end. For a prescribed displacement history use ``gamma_dot = (gamma - state.gamma)/dt``
    (what :func:`run` does); in a simulator pass the measured rate.

    Parameters
    ----------
    params : MudParameters
        Constants of the model (SI). Fields may be arrays that broadcast with the state.
    state : ChannelState
        State at the start of the step.
    gamma : array_like
        Dimensionless displacement at the end of the step [-].
    gamma_dot : array_like
        Dimensionless rate over the step [1/s].
    dt : float or array_like
        Step length [s], > 0.
    seal : array_like, keyword-only
        Factor in [0, 1] multiplying the sealing state (1: the foot can seal the cavity;
        the morphing foot lowers it as its pads retract) [-].
    acceleration : bool, keyword-only
        Keep the :math:`\lambda\eta_\infty\ddot\gamma` term of :math:`f_\xi` (default, decision D6).
    xp : module, keyword-only
        Array namespace (``numpy`` or ``jax.numpy``). No validation is done under JAX.
    validate : bool, keyword-only
        Check the inputs (default). Inner loops that already validated pass False.

    Returns
    -------
    state : ChannelState
        State at the end of the step.
    stress : ChannelStress
        Stresses at the end of the step [Pa].

    Examples
    --------
    >>> import mudrft
    >>> from mudrft.constitutive import initial_state, step
    >>> p = mudrft.paper_parameters(0.25, "vertical")
    >>> s, out = step(p, initial_state(), 0.1, 1.0, 0.1)
    >>> bool(out.total > 0)
    True
    """
    if validate and xp is np:
        check_positive("dt", dt, unit="s")
        check_finite("gamma", gamma)
        check_finite("gamma_dot", gamma_dot)
    p = params
    kappa = 1.0 if acceleration else 0.0

    # deepest point of the current intrusion, and the retraction from it
    g_old = state.gamma
    gw_old = state.gamma_w
    flipped = xp.sign(gamma) * xp.sign(gw_old) < 0
    deeper = xp.abs(gamma) >= xp.abs(gw_old)
    gw_new = xp.where(deeper | flipped, gamma, gw_old)
    direction = xp.where(
        gw_new != 0, xp.sign(gw_new), xp.where(gamma_dot != 0, xp.sign(gamma_dot), 1.0)
    )
    r_start = xp.where(flipped, 0.0, xp.maximum(xp.abs(gw_old) - xp.abs(g_old), 0.0))
    r_end = xp.maximum(xp.abs(gw_new) - xp.abs(gamma), 0.0)
    r_mid = 0.5 * (r_start + r_end)

    # structure parameter: exact exponential update
    tau = laws.tau_xi(gamma_dot, p.k_a, p.k_r, xp=xp)
    xi_ss = p.k_a * tau
    e_xi = xp.exp(-dt / tau)
    xi_new = xi_ss + (state.xi - xi_ss) * e_xi

    # lagged thixotropic stress, driven by A + B*xi(t): exact solution (supplementary eq. S2
    # generalised to any xi(0) and to tau_xi == lambda)
    A = (1.0 - kappa) * p.eta_inf * gamma_dot
    B = p.eta_m * gamma_dot
    e_lam = xp.exp(-dt / p.lam)
    x = dt * (1.0 / p.lam - 1.0 / tau)
    conv = e_lam * (dt / p.lam) * _expm1_over_x(x, xp)
    s_new = state.s_th * e_lam + (A + B * xi_ss) * (1.0 - e_lam) + B * (state.xi - xi_ss) * conv

    # suction: exact exponential with the sealing state at mid-step
    phi = seal * laws.sealing(r_mid, p.epsilon, xp=xp)
    a = laws.suction_rate(phi, p.tau_build, p.tau_leak)
    target = -direction * phi * p.sigma_y / (a * p.tau_build)
    sig_s_new = target + (state.sigma_s - target) * xp.exp(-a * dt)

    # stresses at the end of the step, eq. (1)
    sigma_b = laws.elastic_stress(gamma, p.alpha, p.n, xp=xp) * laws.bed_contact(
        r_end, p.epsilon, xp=xp
    )
    sigma_th = s_new + kappa * p.eta_inf * gamma_dot
    H = laws.switch(direction * gamma_dot, p.nu, xp=xp)
    suction = H * sig_s_new
    total = sigma_b + sigma_th + suction

    new_state = ChannelState(gamma=gamma, gamma_w=gw_new, xi=xi_new, s_th=s_new, sigma_s=sig_s_new)
    return new_state, ChannelStress(
        total=total, elastic=sigma_b, thixotropic=sigma_th, suction=suction
    )


class ChannelHistory(NamedTuple):
    """Stresses of a channel along a history; arrays of shape ``(n,) + batch`` [Pa]."""

    time: np.ndarray
    gamma: np.ndarray
    total: np.ndarray
    elastic: np.ndarray
    thixotropic: np.ndarray
    suction: np.ndarray
    xi: np.ndarray


def run(
    params: MudParameters,
    time: Any,
    gamma: Any,
    *,
    state: ChannelState | None = None,
    seal: Any = 1.0,
    acceleration: bool = True,
    xi0: float = 0.0,
) -> ChannelHistory:
    """Run one channel along a displacement history sampled at ``time``.

    The displacement is taken as piecewise linear between samples, so the rate over
    step ``k`` is ``(gamma[k] - gamma[k-1]) / (time[k] - time[k-1])``.

    Parameters
    ----------
    params : MudParameters
        Model constants (SI).
    time : array_like, shape (n,)
        Strictly increasing sample times [s].
    gamma : array_like, shape (n,) or (n, ...)
        Dimensionless displacement at the samples [-]; trailing axes are a batch.
    state : ChannelState, optional, keyword-only
        Initial state; default undisturbed mud with ``xi0`` and ``gamma[0]``.
    seal : array_like, keyword-only
        Sealing factor, scalar or shape (n, ...) [-].
    acceleration : bool, keyword-only
        Keep the acceleration term (decision D6).
    xi0 : float, keyword-only
        Initial structure when ``state`` is not given [-].

    Returns
    -------
    ChannelHistory
        Stresses [Pa] and structure at every sample (the first sample is the initial state).
    """
    t = check_increasing("time", time)
    g = check_finite("gamma", gamma)
    if g.shape[:1] != t.shape:
        raise MudrftError(
            f"gamma must have the same length as time along its first axis, got gamma shape "
            f"{g.shape} and time shape {t.shape}"
        )
    if t.size < 2:
        raise MudrftError(f"time must have at least 2 samples, got {t.size}")
    seal_arr = np.broadcast_to(np.asarray(seal, dtype=float), g.shape) if np.ndim(seal) else None
    st = state if state is not None else initial_state(g.shape[1:], xi0=xi0, gamma=g[0])
    n = t.size
    out = {k: np.zeros(g.shape) for k in ("total", "elastic", "thixotropic", "suction", "xi")}
    out["xi"][0] = st.xi
    s_const = float(seal) if seal_arr is None else None
    for k in range(1, n):
        dt = t[k] - t[k - 1]
        rate = (g[k] - g[k - 1]) / dt
        sk = s_const if seal_arr is None else seal_arr[k]
        st, s = step(params, st, g[k], rate, dt, seal=sk, acceleration=acceleration, validate=False)
        out["total"][k] = s.total
        out["elastic"][k] = s.elastic
        out["thixotropic"][k] = s.thixotropic
        out["suction"][k] = s.suction
        out["xi"][k] = st.xi
    return ChannelHistory(time=t, gamma=g, **out)


# ---------------------------------------------------------------------------------------
# Closed-form solutions (paper eqs. 9-11 and supplementary Sec. I), for tests and users
# ---------------------------------------------------------------------------------------
def xi_exact(t: Any, gamma_dot: Any, params: MudParameters, *, xi0: float = 0.0) -> Any:
    r"""Structure parameter at constant rate: :math:`\xi_{ss}+(\xi_0-\xi_{ss})e^{-t/\tau_\xi}`.

    The supplementary prints :math:`\xi(t)=(1-e^{t/\tau_\xi})\xi_{ss}` for
    :math:`\xi_0=0`, whose exponent has a sign slip (erratum E4); this is the correct form.

    Parameters
    ----------
    t : array_like
        Time since the start of the constant-rate motion [s].
    gamma_dot : float
        Rate [1/s].
    params : MudParameters
        Model constants.
    xi0 : float, keyword-only
        Structure at t = 0 [-] (the paper uses 0).
    """
    tau = laws.tau_xi(gamma_dot, params.k_a, params.k_r)
    xi_ss = params.k_a * tau
    return xi_ss + (xi0 - xi_ss) * np.exp(-np.asarray(t) / tau)


def thixotropic_exact(
    t: Any, gamma_dot: Any, params: MudParameters, *, xi0: float = 0.0, acceleration: bool = False
) -> Any:
    r"""Thixotropic stress at constant rate from rest, supplementary eq. (S2), exact.

    For :math:`\xi(0)=0` and :math:`\ddot\gamma=0`:

    .. math:: \sigma_{th}=(1-e^{-t/\lambda})(\eta_\infty+\xi_{ss}\eta_m)\dot\gamma
              +(e^{-t/\lambda}-e^{-t/\tau_\xi})\frac{\tau_\xi}{\tau_\xi-\lambda}\xi_{ss}\eta_m\dot\gamma .

    This is what the supplementary prints (checked against ``solve_ivp`` in the tests).
    Its claim that the second term vanishes for :math:`\tau_\xi\approx\lambda` is wrong
    (erratum E5): the term tends to :math:`-(t/\lambda)e^{-t/\lambda}\xi_{ss}\eta_m\dot\gamma`.
    Written here for any :math:`\xi_0`, any :math:`\tau_\xi` (including
    :math:`\tau_\xi=\lambda`) and, with ``acceleration=True``, for a rate that jumps from
    0 at t = 0 (the :math:`\ddot\gamma` impulse adds :math:`\eta_\infty\dot\gamma` at once).

    Parameters
    ----------
    t : array_like
        Time since the start of motion [s].
    gamma_dot : float
        Constant rate [1/s].
    params : MudParameters
        Model constants.
    xi0 : float, keyword-only
        Initial structure [-].
    acceleration : bool, keyword-only
        Include the acceleration term.

    Returns
    -------
    array
        :math:`\sigma_{th}(t)` [Pa].
    """
    t = np.asarray(t, dtype=float)
    tau = laws.tau_xi(gamma_dot, params.k_a, params.k_r)
    xi_ss = params.k_a * tau
    lam = params.lam
    kappa = 1.0 if acceleration else 0.0
    A = (1.0 - kappa) * params.eta_inf * gamma_dot
    B = params.eta_m * gamma_dot
    e_lam = np.exp(-t / lam)
    x = t * (1.0 / lam - 1.0 / tau)
    conv = e_lam * (t / lam) * _expm1_over_x(x, np)
    return (
        (A + B * xi_ss) * (1.0 - e_lam)
        + B * (xi0 - xi_ss) * conv
        + kappa * params.eta_inf * gamma_dot
    )


def thixotropic_approx(t: Any, gamma_dot: Any, params: MudParameters) -> Any:
    r"""The paper's approximation, eq. (9): :math:`(1-e^{-t/\lambda})\sigma_{th,ss}` [Pa].

    Exact only when :math:`\xi` starts at its steady value; the supplementary
    justifies it by :math:`\tau_\xi\approx\lambda`, which does not remove the second
    term of eq. (S2) (see docs/model.md, erratum E5, and the tests that measure the error).
    """
    t = np.asarray(t, dtype=float)
    return (1.0 - np.exp(-t / params.lam)) * laws.thixotropic_steady(
        gamma_dot, params.eta_inf, params.eta_m, params.gamma_dot_c
    )


def suction_closed_form(dt: Any, phi: Any, params: MudParameters, *, sigma_s0: float = 0.0) -> Any:
    r"""Suction at constant sealing state, eqs. (10)-(11).

    .. math:: \sigma_s(t)=\sigma_{s,ss}+(\sigma_s(t_w)-\sigma_{s,ss})e^{-a\Delta t},\quad
              \sigma_{s,ss}=-\frac{\phi\sigma_Y}{a\tau_{build}},\quad
              a=\frac{\phi}{\tau_{build}}+\frac{1-\phi}{\tau_{leak}}

    Parameters
    ----------
    dt : array_like
        Time since retraction began, :math:`\Delta t=t-t_w` [s].
    phi : float
        Constant sealing state in [0, 1] [-].
    params : MudParameters
        Model constants.
    sigma_s0 : float, keyword-only
        Suction at :math:`t_w` [Pa]; the paper uses 0.
    """
    a = laws.suction_rate(phi, params.tau_build, params.tau_leak)
    ss = laws.suction_steady(phi, params.tau_build, params.tau_leak, params.sigma_y)
    return ss + (sigma_s0 - ss) * np.exp(-a * np.asarray(dt, dtype=float))
