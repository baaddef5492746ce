r"""Time stepping of the mud constitutive model, validated: :func:`step` and :func:`run`.

:func:`step` checks its inputs and calls :func:`mudrft.constitutive.kernel.channel_update`,
the one definition of the update (exact exponential solution of eqs. 3 and 5 over a step).

``state, stress = step(params, state, gamma, gamma_dot, dt)`` serves a time loop,
a MuJoCo loop, a batch (arrays everywhere) and, with ``xp=jax.numpy``, a JAX scan.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from .._validation import MudrftError, check_finite, check_increasing, check_positive
from ..parameters.base import MudParameters
from . import kernel
from .state import ChannelState, ChannelStress, initial_state

__all__ = ["ChannelHistory", "run", "step"]


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
    kappa = 1.0 if acceleration else 0.0
    return kernel.channel_update(
        kernel.channel_constants(params), state, gamma, gamma_dot, dt, seal, kappa, xp=xp
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
