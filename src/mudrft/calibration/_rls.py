r"""Recursive least squares with forgetting, for banks of filters, and the stream of samples
it reads (internal).

:func:`rls_update` advances any number of independent filters (a bank: one per value of
a grid) by one sample; :func:`refined_argmin` picks the best bank member between grid
points; :class:`SampleStream` checks each sample of a stream and gives the step from the
previous one (decision D46).
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import LENGTH_LIMITS, MudrftError, warn_implausible
from ..io._build import PLAUSIBLE_DEPTH, PLAUSIBLE_PEAK_STRESS

__all__ = ["MAX_STRESS", "Sample", "SampleStream", "refined_argmin", "rls_update"]

#: Largest stress magnitude a streamed sample may have [Pa]: far above any mud (a few
#: hundred kPa) and any material; 1e300 overflowed the filters' squared errors to inf.
MAX_STRESS = 1e12


def rls_update(
    theta: NDArray[np.float64],
    P: NDArray[np.float64],
    phi: NDArray[np.float64],
    y: ArrayLike,
    lam: float,
    p_max: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    r"""One RLS step with exponential forgetting, for a bank of filters.

    Parameters
    ----------
    theta : ndarray, shape (..., p)
        Estimates of each filter [-] (normalised).
    P : ndarray, shape (..., p, p)
        Covariances [-].
    phi : ndarray, shape (..., p)
        Regressors of the sample [-].
    y : array_like, shape (...)
        Measurement [-].
    lam : float
        Forgetting factor in (0, 1] [-].
    p_max : float
        Cap of the trace of ``P``, so that directions the data do not excite cannot wind
        up (decision D46) [-].

    Returns
    -------
    theta, P : ndarray
        Updated estimates and covariances.
    increment : ndarray, shape (...)
        Increment of the weighted least-squares cost,
        :math:`\lambda e^2/(\lambda+\phi^TP\phi)` with :math:`e` the a-priori error (so
        that :math:`V_k=\lambda V_{k-1}+\text{increment}` is the minimised cost).
    """
    Pphi = np.einsum("...ij,...j->...i", P, phi)
    denom = lam + np.einsum("...i,...i->...", phi, Pphi)
    K = Pphi / denom[..., None]
    err = y - np.einsum("...i,...i->...", phi, theta)
    theta = theta + K * err[..., None]
    P = (P - K[..., :, None] * Pphi[..., None, :]) / lam
    P = 0.5 * (P + np.swapaxes(P, -1, -2))  # keep symmetric against round-off
    tr = np.trace(P, axis1=-2, axis2=-1)
    over = tr > p_max
    if np.any(over):
        P = P * np.where(over, p_max / tr, 1.0)[..., None, None]
    return theta, P, lam * err * err / denom


def refined_argmin(e: NDArray[np.float64]) -> float:
    """Index of the smallest of ``e``, refined by the vertex of the parabola through it and
    its neighbours (within half a grid step) [grid steps]."""
    i = int(np.argmin(e))
    if 0 < i < e.size - 1:
        den = e[i - 1] - 2 * e[i] + e[i + 1]
        if den > 0:
            return i + float(np.clip(0.5 * (e[i - 1] - e[i + 1]) / den, -0.5, 0.5))
    return float(i)


class Sample(NamedTuple):
    """One checked sample of a stream and the step from the previous one.

    Attributes
    ----------
    time : float
        Sample time [s].
    gamma : float
        Dimensionless displacement :math:`q/L_c` [-].
    stress : float
        Measured stress [Pa].
    dt : float or None
        Time since the previous sample [s]; None for the first sample.
    rate : float or None
        Mean :math:`\\dot\\gamma` since the previous sample [1/s]; None for the first.
    previous_time : float or None
        Time of the previous sample [s]; None for the first.
    """

    time: float
    gamma: float
    stress: float
    dt: float | None = None
    rate: float | None = None
    previous_time: float | None = None


class SampleStream:
    """The last sample of a stream; checks each new one (finite, time increasing).

    Parameters
    ----------
    characteristic_length : float
        Plate length :math:`L_c` [m] (already checked > 0).
    """

    def __init__(self, characteristic_length: float) -> None:
        self.L = float(characteristic_length)
        self.last: tuple[float, float] | None = None
        self.warned = False  # one plausibility warning a stream, not one a sample

    def reset(self) -> None:
        """Forget the previous sample."""
        self.last = None

    def push(self, time: float, depth: float, stress: float) -> Sample:
        """Check one sample (time [s], depth [m], stress [Pa]) and step to it."""
        t, q, s = _number("time", time), _number("depth", depth), _number("stress", stress)
        if not (math.isfinite(t) and math.isfinite(q) and math.isfinite(s)):
            raise MudrftError(
                f"update needs finite time, depth and stress, got {time!r}, {depth!r}, {stress!r}"
            )
        for what, given, v, limit, unit in (
            ("stress", stress, s, MAX_STRESS, "Pa"), ("depth", depth, q, LENGTH_LIMITS[1], "m")
        ):  # fmt: skip
            if abs(v) > limit:
                raise MudrftError(
                    f"update: {what} must be at most {limit:g} {unit} in magnitude (no mud "
                    f"test reaches it: a unit mistake?), got {given!r}"
                )
        if not self.warned and (
            abs(q) > PLAUSIBLE_DEPTH[1] or abs(s) > PLAUSIBLE_PEAK_STRESS[1]
        ):  # a depth in mm or a stress in a wrong unit, as the log loader warns (D105)
            big_depth = abs(q) > PLAUSIBLE_DEPTH[1]
            self.warned = warn_implausible(
                f"update: {'depth' if big_depth else 'stress'} of",
                abs(q) if big_depth else abs(s),
                PLAUSIBLE_DEPTH if big_depth else PLAUSIBLE_PEAK_STRESS,
                unit="m" if big_depth else "Pa",
                hint="stream SI values (depth in m, stress in Pa, time in s); "
                "this warning is shown once a stream",
            )
        g = q / self.L
        if self.last is None:
            self.last = (t, g)
            return Sample(t, g, s)
        t0, g0 = self.last
        if not t > t0:
            raise MudrftError(
                f"update: time must increase between updates, got {t!r} [s] after {t0!r} [s]; "
                "a trial whose clock starts again: add the previous trial's last time to its "
                "times (the estimates carry on), or call reset() first (they start again from "
                "the prior)"
            )
        dt = t - t0
        self.last = (t, g)
        return Sample(t, g, s, dt, (g - g0) / dt, t0)


def _number(name: str, value: Any) -> float:
    """``float(value)`` for a sample, or an error naming it (a string, None, a list)."""
    if isinstance(value, str | bytes | bool) or value is None:
        raise MudrftError(f"update: {name} must be a number, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise MudrftError(
            f"update: {name} must be a number, got {type(value).__name__} {value!r}"
        ) from None
