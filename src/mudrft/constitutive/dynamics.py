"""Validated time stepping of one stress channel: :func:`step` and :func:`run`, over
:func:`mudrft.constitutive.kernel.channel_step`."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._typing import ArrayLike, FloatOrArray, Namespace, XpArray
from .._validation import (
    MudrftError,
    check_choice,
    check_finite,
    check_in_range,
    check_increasing,
    check_positive,
)
from .._xp import pyfloat
from ..parameters.base import PARAMETER_UNITS, MudParameters
from . import kernel
from .state import ChannelState, ChannelStress, initial_state

__all__ = [
    "CLOCKS", "THIXOTROPY", "ChannelHistory", "check_parameter_shapes", "evaluation", "run", "step",
]  # fmt: skip

#: Evaluations of the thixotropy and suction (decision D15).
THIXOTROPY = ("ode", "quasi-static")
#: Clock of eq. (9) in the quasi-static evaluation: from first contact, or the retraction.
CLOCKS = ("contact", "retraction")


def evaluation(
    thixotropy: str = "ode", clock: str = "contact", acceleration: bool | None = None
) -> tuple[bool, bool, float]:
    """Validate the evaluation options; return ``(quasi_static, restart, kappa)``.

    Parameters
    ----------
    thixotropy : {"ode", "quasi-static"}
        Step eqs. (3) and (5), or evaluate the closed forms (9)-(11) (decision D15).
    clock : {"contact", "retraction"}
        Quasi-static only: the clock of eq. (9) runs from first contact, or from the
        start of the retraction.
    acceleration : bool or None
        ODE only: keep the acceleration term (decision D6); None means True for the ODE
        (eq. 9 drops it, so True is refused with ``"quasi-static"``).

    Examples
    --------
    >>> evaluation("quasi-static", "retraction")
    (True, True, 0.0)
    >>> evaluation("ode", "retraction")
    Traceback (most recent call last):
    ...
    mudrft._validation.MudrftError: clock='retraction' (CLI: --clock retraction) applies to thixotropy='quasi-static' (CLI: --thixotropy quasi-static) only (eq. 9); the ODE keeps its own memory
    """
    check_choice("thixotropy", thixotropy, THIXOTROPY)
    check_choice("clock", clock, CLOCKS)
    if acceleration is not None and not isinstance(acceleration, bool | np.bool_):
        raise MudrftError(f"acceleration must be True, False or None, got {acceleration!r}")
    if thixotropy == "quasi-static":
        if acceleration:
            raise MudrftError(
                "acceleration=True cannot be combined with thixotropy='quasi-static': eq. (9) "
                "is the solution of eq. (3a) with the acceleration term dropped"
            )
        return True, clock == "retraction", 0.0
    if clock != "contact":
        raise MudrftError(
            f"clock={clock!r} (CLI: --clock {clock}) applies to thixotropy='quasi-static' "
            "(CLI: --thixotropy quasi-static) only (eq. 9); the ODE keeps its own memory"
        )
    return False, False, 1.0 if acceleration is None or acceleration else 0.0


def step(
    params: MudParameters, state: ChannelState, gamma: XpArray, gamma_dot: XpArray, dt: XpArray, *,
    seal: XpArray = 1.0, acceleration: bool | None = None, thixotropy: str = "ode",
    clock: str = "contact", xp: Namespace = np, validate: bool = True,
) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
    r"""Advance one stress channel by ``dt`` at a rate held constant over the step; return its
    :class:`ChannelState` and :class:`ChannelStress` [Pa] at the end of the step.

    .. math::
       :label: chen2026-eq-3a

       \dot\sigma_{th}=\frac1\lambda f_\xi-\frac1\lambda\sigma_{th},\quad
       f_\xi=(\eta_\infty+\xi\eta_m)\dot\gamma+\lambda\eta_\infty\ddot\gamma \tag{3a}

    .. math::
       :label: chen2026-eq-5

       \dot\sigma_s=-\frac{\phi}{\tau_{build}}(\sigma_s+\sigma_Y)-\frac{1-\phi}{\tau_{leak}}\sigma_s \tag{5}

    Parameters
    ----------
    params : MudParameters
        Constants of the model (SI); array fields broadcast with the state.
    state : ChannelState
        State at the start of the step.
    gamma, gamma_dot : array_like
        Dimensionless displacement at the end of the step [-], and rate over it [1/s].
    dt : float or array_like
        Step length [s], > 0.
    seal : array_like, keyword-only
        Factor in [0, 1] multiplying the sealing state [-] (1: the foot can seal).
    acceleration, thixotropy, clock : keyword-only
        The evaluation (:func:`evaluation`; decisions D6, D15).
    xp : module, keyword-only
        Array namespace (``numpy`` or ``jax.numpy``); no validation under JAX.
    validate : bool, keyword-only
        Check the inputs (default).

    Examples
    --------
    >>> import mudrft
    >>> from mudrft.constitutive import initial_state, step
    >>> p = mudrft.paper_parameters(0.25, "vertical")
    >>> s, out = step(p, initial_state(), 0.1, 1.0, 0.1)
    >>> bool(out.total > 0)
    True
    """
    qs, restart, kappa = evaluation(thixotropy, clock, acceleration)
    if validate and xp is np:
        if not isinstance(state, ChannelState):
            raise MudrftError(
                "state must be a ChannelState (mudrft.constitutive.initial_state(), or the "
                f"state a step returned), got {type(state).__name__}"
            )
        check_in_range("seal", seal, 0.0, 1.0)
    c = kernel.channel_constants(params)
    if xp is np and _one_channel(c, state, gamma, gamma_dot, dt, seal):
        # one channel: the same step on Python floats (faster than numpy on 0-d values)
        g, gd, h, sl = float(gamma), float(gamma_dot), float(dt), float(seal)
        if validate and not (h > 0.0 and math.isfinite(h + g + gd)):
            _check(gamma, gamma_dot, dt)  # raises with the message of the array path
        new, out = kernel.channel_step(
            kernel.ChannelConstants(*map(float, c)),
            ChannelState(*map(float, state)),
            g, gd, h, sl, float(kappa), qs, restart, pyfloat,
        )  # fmt: skip
        return ChannelState(*map(np.float64, new)), ChannelStress(*map(np.float64, out))
    if validate and xp is np:
        _check(gamma, gamma_dot, dt)
    return kernel.channel_step(c, state, gamma, gamma_dot, dt, seal, kappa, qs, restart, xp=xp)


def _check(gamma: object, gamma_dot: object, dt: object) -> None:
    """The inputs of :func:`step`: ``dt`` [s] > 0, ``gamma`` and ``gamma_dot`` finite."""
    check_positive("dt", dt, unit="s")
    check_finite("gamma", gamma)
    check_finite("gamma_dot", gamma_dot)


def _one_channel(*values: object) -> bool:
    """Whether every value (numbers, or named tuples of numbers) is one real number."""
    flat = [x for v in values for x in (v if isinstance(v, tuple) else (v,))]
    return all(
        isinstance(x, (float, int, np.floating, np.integer))
        or (isinstance(x, np.ndarray) and x.ndim == 0 and x.dtype.kind in "fiu")
        for x in flat
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


def check_parameter_shapes(shapes: dict[str, tuple[int, ...]], sample: tuple[int, ...]) -> None:
    """Refuse parameter fields (``shapes``) that do not broadcast to one sample of gamma."""
    for name, shape in shapes.items():
        if np.broadcast_shapes(shape, sample) != sample:
            raise MudrftError(
                f"params.{name} has shape {shape}, which does not broadcast to one sample of "
                f"gamma, shape {sample}: gamma needs a column per parameter set, shape "
                f"(n, {', '.join(map(str, shape))}) (a mud's channel sets are x, y, z)"
            )


def run(
    params: MudParameters, time: ArrayLike, gamma: ArrayLike, *, state: ChannelState | None = None,
    seal: FloatOrArray = 1.0, acceleration: bool | None = None, thixotropy: str = "ode",
    clock: str = "contact", xi0: float = 0.0,
) -> ChannelHistory:  # fmt: skip
    """Run one channel along a displacement history, piecewise linear between samples: the
    :class:`ChannelHistory` of stresses [Pa] and structure at every sample (the first sample is
    the initial state).

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
    acceleration, thixotropy, clock : keyword-only
        The evaluation (:func:`evaluation`; decisions D6, D15).
    xi0 : float, keyword-only
        Initial structure when ``state`` is not given [-].
    """
    t, g = check_increasing("time", time), check_finite("gamma", gamma)
    if g.shape[:1] != t.shape:
        raise MudrftError(
            f"gamma must have the same length as time along its first axis, got gamma shape "
            f"{g.shape} and time shape {t.shape}"
        )
    if t.size < 2:
        raise MudrftError(f"time must have at least 2 samples, got {t.size}")
    check_parameter_shapes({k: np.shape(getattr(params, k)) for k in PARAMETER_UNITS}, g.shape[1:])
    qs, restart, kappa = evaluation(thixotropy, clock, acceleration)
    consts = kernel.channel_constants(params)
    seals = np.broadcast_to(np.asarray(seal, dtype=float), g.shape) if np.ndim(seal) else None
    st = state if state is not None else initial_state(g.shape[1:], xi0=xi0, gamma=g[0])
    out = {k: np.zeros(g.shape) for k in (*ChannelStress._fields, "xi")}
    out["xi"][0] = st.xi
    for k in range(1, t.size):
        dt = t[k] - t[k - 1]
        rate = (g[k] - g[k - 1]) / dt
        sk = float(seal) if seals is None else seals[k]
        st, s = kernel.channel_step(consts, st, g[k], rate, dt, sk, kappa, qs, restart)
        for name, value in zip(ChannelStress._fields, s, strict=True):
            out[name][k] = value
        out["xi"][k] = st.xi
    return ChannelHistory(time=t, gamma=g, **out)
