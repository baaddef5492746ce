"""Banks of recursive least-squares filters with forgetting, the checked stream of samples
they read, and :class:`OnlineEstimate` (internal, D46)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._validation import LENGTH_LIMITS, MudrftError, warn_implausible
from ..io._build import PLAUSIBLE_DEPTH, PLAUSIBLE_PEAK_STRESS

#: Largest stress magnitude a streamed sample may have [Pa] (1e300 overflowed the filters).
MAX_STRESS = 1e12


class OnlineEstimate(NamedTuple):
    """Current estimates of :class:`OnlineEstimator` (SI; ``None`` until informed).

    Attributes
    ----------
    alpha : float or None
        Stiffness :math:`\\alpha` [Pa].
    eta_inf : float or None
        Viscosity :math:`\\eta_\\infty` [Pa s].
    eta_m : float or None
        Structural viscosity :math:`\\eta_m` [Pa s] (``model="exact"`` only).
    sigma_y : float or None
        Yield stress :math:`\\sigma_Y` [Pa]; ``None`` until a retraction sample.
    tau_build : float or None
        Suction build-up time [s]; ``None`` until a retraction sample.
    n : float
        Exponent used (fixed) [-].
    updates : int
        Samples used so far.
    phase : str
        Phase of the last sample: ``"intrusion"``, ``"retraction"``, ``"hold"`` or ``"out"``.
    standard_error : dict
        Standard error of each estimate that is not ``None`` [its unit]; ``inf`` while too
        few samples inform it (decision D138).
    """

    alpha: float | None
    eta_inf: float | None
    eta_m: float | None
    sigma_y: float | None
    tau_build: float | None
    n: float
    updates: int
    phase: str
    standard_error: Mapping[str, float] = MappingProxyType({})  # read-only: one shared default


class Filters:
    """A bank of ``members`` forgetting RLS filters (factor ``lam``) on normalised
    quantities, starting at 1 with variances ``var0`` [-], and the discounted sums behind
    their standard errors (D138)."""

    def __init__(self, members: int, var0: NDArray[np.float64], lam: float) -> None:
        self.theta = np.ones((members, var0.size))
        self.P = np.tile(np.diag(var0), (members, 1, 1))
        self.M = np.zeros_like(self.P)
        self.cost = np.zeros(members)
        self.weight = self.weight2 = 0.0
        self.count = 0
        self.lam, self.p_max = lam, float(var0.sum())

    def step(self, phi: NDArray[np.float64], y: NDArray[np.float64]) -> None:
        """One RLS step on regressors ``phi`` (members, p) and measurements ``y``
        (members,) [-]; the trace of ``P`` is capped against wind-up."""
        lam, P = self.lam, self.P
        Pphi = np.einsum("...ij,...j->...i", P, phi)
        denom = lam + np.einsum("...i,...i->...", phi, Pphi)
        K = Pphi / denom[..., None]
        err = y - np.einsum("...i,...i->...", phi, self.theta)
        self.theta = self.theta + K * err[..., None]
        P = (P - K[..., :, None] * Pphi[..., None, :]) / lam
        P = 0.5 * (P + np.swapaxes(P, -1, -2))  # keep symmetric against round-off
        tr = np.trace(P, axis1=-2, axis2=-1)
        over = tr > self.p_max
        if np.any(over):
            P = P * np.where(over, self.p_max / tr, 1.0)[..., None, None]
        self.P = P
        self.M = lam * lam * self.M + phi[..., :, None] * phi[..., None, :]
        self.cost = lam * self.cost + lam * err * err / denom
        self.weight = self.lam * self.weight + 1.0
        self.weight2 = self.lam**2 * self.weight2 + 1.0
        self.count += 1


def refined_argmin(e: NDArray[np.float64]) -> float:
    """Index of the smallest of ``e``, refined by the vertex of the parabola through it and
    its neighbours (within half a grid step) [grid steps]."""
    i = int(np.argmin(e))
    if 0 < i < e.size - 1:
        den = e[i - 1] - 2 * e[i] + e[i + 1]
        if den > 0:
            return i + float(np.clip(0.5 * (e[i - 1] - e[i + 1]) / den, -0.5, 0.5))
    return float(i)


def filter_errors(
    P: NDArray[np.float64], M: NDArray[np.float64], cost: float, weight: float
) -> NDArray[np.float64]:
    r"""Standard errors [-] of one filter's estimates: the sandwich :math:`s^2PMP` of a
    weighted least-squares estimate (``M`` from :meth:`Filters.step`), with
    :math:`s^2=V/(w-p)` from the discounted ``cost`` :math:`V` and count ``weight``
    :math:`w` (decision D138); ``inf`` while :math:`w\le p`."""
    p = P.shape[-1]
    if weight <= p:
        return np.full(p, np.inf)
    return np.sqrt(cost / (weight - p) * np.clip(np.diagonal(P @ M @ P), 0.0, None))


def bank_errors(
    theta: NDArray[np.float64],
    P: NDArray[np.float64],
    M: NDArray[np.float64],
    cost: NDArray[np.float64],
    weight: float,
    weight2: float,
    x: float,
    log_grid: NDArray[np.float64],
) -> tuple[NDArray[np.float64], float]:
    r"""Standard errors [-] of a bank's estimates read at ``x`` [grid steps], and of the
    log of the grid value there (decision D138): the profile's, where the cost rises by
    the noise variance :math:`s^2`; ``inf`` at the grid's ends or without curvature.
    ``theta`` (G, p), ``P`` and ``M`` (G, p, p), ``cost`` (G,), ``log_grid`` (G,).
    """
    G, p = theta.shape
    i = round(x)
    se = filter_errors(P[i], M[i], float(cost[i]), weight)
    se_log = math.inf
    if 0 < i < G - 1 and weight > p:
        h0, h1 = log_grid[i] - log_grid[i - 1], log_grid[i + 1] - log_grid[i]
        curv = 2.0 * ((cost[i + 1] - cost[i]) / h1 - (cost[i] - cost[i - 1]) / h0) / (h0 + h1)
        if curv > 0:
            s2 = float(cost[i]) / (weight - p)
            se_log = math.sqrt(2.0 * s2 / float(curv) * weight2 / weight)
    if math.isfinite(se_log):
        slope = (theta[i + 1] - theta[i - 1]) / (log_grid[i + 1] - log_grid[i - 1])
        spread = slope * se_log
    else:  # the grid value is anywhere on the grid (or beyond it)
        spread = 0.5 * np.ptp(theta, axis=0)
    return np.sqrt(se**2 + spread**2), se_log


class Sample(NamedTuple):
    """One checked sample: time [s], :math:`\\gamma=q/L_c` [-], stress [Pa], and the step
    from the previous sample (None for the first): ``dt`` [s], mean ``rate`` [1/s] and
    ``previous_time`` [s]."""

    time: float
    gamma: float
    stress: float
    dt: float | None = None
    rate: float | None = None
    previous_time: float | None = None


class SampleStream:
    """The last sample of a stream of plate length ``characteristic_length`` [m] (checked);
    checks each new one (finite, plausible, time increasing)."""

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
        ):  # a depth in mm or a stress in a wrong unit, as the log loader warns
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
