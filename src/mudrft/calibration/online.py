"""Online estimation by recursive least squares with forgetting, O(1) per sample (D46), and
which known mud a log (:func:`classify`) or a stream (:class:`StreamClassifier`) resembles:
every candidate set runs the full model on the data, and its residuals give a Gaussian
likelihood and, with equal priors, a probability (decision D47)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import (
    LENGTH_LIMITS,
    CalibrationWarning,
    MudrftError,
    check_characteristic_length,
    check_choice,
    check_positive,
    check_shape,
    number_in_range,
    positive_number,
    warn_implausible,
)
from ..constitutive import channel_constants, channel_update, initial_state
from ..constitutive.contact import in_contact
from ..io import IntrusionDataset
from ..io._build import DIRECTIONS, PLAUSIBLE_DEPTH, PLAUSIBLE_PEAK_STRESS
from ..parameters.base import MudParameters
from ..parameters.registry import paper_parameters
from ..plate import DEFAULT_PLATE_LENGTH
from ._problem import FIT_PARAMETERS, PHASES, Packed, basis, free_k_a, pack, values_of

__all__ = ["Classification", "OnlineEstimate", "OnlineEstimator", "StreamClassifier", "classify"]

_EXACT = ("alpha", "eta_inf", "eta_m", "sigma_y")
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
    bank: Filters, x: float, log_grid: NDArray[np.float64]
) -> tuple[NDArray[np.float64], float]:
    r"""Standard errors [-] of a bank's estimates read at ``x`` [grid steps], and of the
    log of the grid value there (decision D138): the profile's, where the cost rises by
    the noise variance :math:`s^2`; ``inf`` at the grid's ends or without curvature.
    """
    theta, cost, weight = bank.theta, bank.cost, bank.weight
    G, p = theta.shape
    i = round(x)
    se = filter_errors(bank.P[i], bank.M[i], float(cost[i]), weight)
    se_log = math.inf
    if 0 < i < G - 1 and weight > p:
        h0, h1 = log_grid[i] - log_grid[i - 1], log_grid[i + 1] - log_grid[i]
        curv = 2.0 * ((cost[i + 1] - cost[i]) / h1 - (cost[i] - cost[i - 1]) / h0) / (h0 + h1)
        if curv > 0:
            s2 = float(cost[i]) / (weight - p)
            se_log = math.sqrt(2.0 * s2 / float(curv) * bank.weight2 / weight)
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
    """``float(value)`` for a sample, or an error naming it (a string, None, a list, nan)."""
    if isinstance(value, str | bytes | bool) or value is None:
        raise MudrftError(f"update: {name} must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise MudrftError(
            f"update: {name} must be a number, got {type(value).__name__} {value!r}"
        ) from None
    if not math.isfinite(v):
        raise MudrftError(f"update: {name} must be finite, got {value!r}")
    return v


class OnlineEstimator:
    r"""Recursive least squares with forgetting of the linear constants and tau_build.

    Feed samples with :meth:`update` and read :attr:`estimate`. Two regressor models:

    ``model="exact"`` (default)
        The full model, stepped alongside the stream, gives the regressors of
        :math:`\alpha,\eta_\infty,\eta_m,\sigma_Y`, the other constants from ``prior``;
        unbiased when the prior's nonlinear constants are right.
    ``model="paper"``
        The supplementary's approximations (Sec. III-A): intrusion
        :math:`\sigma\approx\alpha\gamma^n+\eta_\infty\dot\gamma`, retraction
        :math:`\sigma\approx-(1-e^{-\Delta t/\tau_{build}})\sigma_Y+\eta_\infty\dot\gamma`;
        needs only ``n`` but gives apparent values.

    In both, one filter runs per :math:`\tau_{build}` of a grid; the one with the smallest
    discounted prediction error is read, refined by a parabola in :math:`\ln\tau_{build}`.

    Parameters
    ----------
    prior : MudParameters, optional
        Starting values and fixed constants; default the paper's row W = 35 % of
        ``direction``.
    model : {"exact", "paper"}, keyword-only
        Regressor model (see above).
    direction : {"vertical", "horizontal"}, keyword-only
        Direction of the default prior.
    characteristic_length : float, keyword-only
        Plate length :math:`L_c` [m] (decision D1).
    n : float, optional, keyword-only
        Exponent :math:`n` [-], held fixed; default ``prior.n``.
    forgetting : float, keyword-only
        Forgetting factor :math:`\lambda_f\in[0.5,1]`; memory about
        :math:`1/(1-\lambda_f)` updates (default 0.995: 200).
    tau_build_grid : array_like, optional, keyword-only
        Candidate build-up times [s]; default 25 values from 0.02 to 5 s (log-spaced).
    rate_threshold : float, keyword-only
        Absolute rate below which a sample counts as hold [1/s] (``"paper"`` skips hold samples).
    retraction_skip : float, optional, keyword-only
        ``"paper"`` only: dimensionless retraction skipped at the start of each retraction,
        while the bed contact fades [-]; default ``3 * prior.epsilon``.
    initial_scale : float, keyword-only
        Initial standard deviation of each estimate relative to its prior value [-].

    Examples
    --------
    >>> import mudrft
    >>> true = mudrft.paper_parameters(0.25).replace(alpha=30e3, sigma_y=9e3)
    >>> tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=0.5, dt=0.01)
    >>> res = mudrft.plate_response(tr, true)
    >>> est = OnlineEstimator(mudrft.paper_parameters(0.25))
    >>> for t, q, s in zip(tr.time, res.displacement, res.stress):
    ...     e = est.update(t, q, s)
    >>> abs(e.alpha / 30e3 - 1) < 0.01, abs(e.sigma_y / 9e3 - 1) < 0.01
    (True, True)
    """

    def __init__(
        self,
        prior: MudParameters | None = None,
        *,
        model: str = "exact",
        direction: str = "vertical",
        characteristic_length: float = DEFAULT_PLATE_LENGTH,
        n: float | None = None,
        forgetting: float = 0.995,
        tau_build_grid: ArrayLike | None = None,
        rate_threshold: float = 0.02,
        retraction_skip: float | None = None,
        initial_scale: float = 100.0,
    ) -> None:
        self.model = check_choice("model", model, ("exact", "paper"))
        check_choice("direction", direction, ("vertical", "horizontal"))
        if prior is None:
            prior = paper_parameters(0.35, direction)
        if not isinstance(prior, MudParameters) or prior.shape != ():
            raise MudrftError(f"prior must be a single MudParameters, got {prior!r}")
        self.L = check_characteristic_length("OnlineEstimator", characteristic_length)
        self.n = number_in_range("n", prior.n if n is None else n, 1e-3, 1.0)
        self.forgetting = number_in_range("forgetting", forgetting, 0.5, 1.0)
        grid = np.geomspace(0.02, 5.0, 25) if tau_build_grid is None else tau_build_grid
        g = check_positive("tau_build_grid", grid, unit="s")
        if g.ndim != 1 or g.size < 3:
            raise MudrftError(f"tau_build_grid must hold at least 3 times [s], got {grid!r}")
        self.tau_grid = np.sort(g)
        self.rate_threshold = positive_number("rate_threshold", rate_threshold, unit="1/s")
        if retraction_skip is None:
            retraction_skip = 3.0 * float(prior.epsilon)
        self.retraction_skip = number_in_range("retraction_skip", retraction_skip, 0.0, 10.0)
        self.initial_scale = positive_number("initial_scale", initial_scale)
        self._names = _EXACT if self.model == "exact" else ("sigma_y", "eta_inf")
        self._stream = SampleStream(self.L)
        self.rebase(prior.replace(n=self.n) if n is not None else prior)

    def rebase(self, prior: MudParameters) -> None:
        """Start again around another prior, memory cleared.

        Parameters
        ----------
        prior : MudParameters
            A single set [SI], e.g. a :class:`StreamClassifier`'s best after the mud changed.
        """
        if not isinstance(prior, MudParameters) or prior.shape != ():
            raise MudrftError(f"prior must be a single MudParameters, got {prior!r}")
        self.prior, self.n = prior, float(prior.n)
        if self.model == "exact":
            vals = values_of(prior, batch=self.tau_grid.size)
            vals["tau_build"] = self.tau_grid
            p = MudParameters(**basis(vals, _EXACT), nu=float(prior.nu), k_a=free_k_a(prior))
            self._consts = channel_constants(p)
        self.reset()

    def reset(self) -> None:
        """Forget every sample (back to the prior)."""
        G = self.tau_grid.size
        p = self.prior
        # normalised quantities (parameters / prior, stress / S) keep the filters accurate
        self._scale = np.array([float(getattr(p, k)) for k in self._names])
        self._S = float(max(p.alpha, p.sigma_y))
        self._bank = Filters(G, np.full(self._scale.size, self.initial_scale**2), self.forgetting)
        self._updates = 0
        self._suction_seen = False  # a sample has excited the suction regressor
        self._stream.reset()
        self._gamma_w = 0.0
        self._t_w: float | None = None
        self._phase = "out"
        if self.model == "paper":
            self._scale_i = np.array([float(p.alpha), float(p.eta_inf)])
            self._intrusion = Filters(1, np.full(2, self.initial_scale**2), self.forgetting)
        else:
            self._state = initial_state((G * 5,))

    def update(self, time: float, depth: float, stress: float) -> OnlineEstimate:
        """Add one sample and return the current estimates.

        Parameters
        ----------
        time, depth, stress : float
            Sample time [s] (increasing), intrusion displacement [m], measured stress [Pa].

        Returns
        -------
        OnlineEstimate
        """
        x = self._stream.push(time, depth, stress)
        if x.dt is None or x.rate is None:  # the first sample: a starting point only
            self._phase = "out" if x.gamma <= 0 else "hold"
            if self.model == "exact":
                self._state = initial_state((self.tau_grid.size * 5,), gamma=x.gamma)
            return self.estimate
        if not in_contact(x.gamma):
            self._phase = "out"  # at or above the surface: no mud stress (as plate_response)
        elif abs(x.rate) <= self.rate_threshold:
            self._phase = "hold"
        else:
            self._phase = "intrusion" if x.rate > 0 else "retraction"
        # the deepest point of the current intrusion and the time its retraction began
        if self._phase == "intrusion" and x.gamma >= self._gamma_w:
            self._gamma_w, self._t_w = x.gamma, None
        if self._phase == "retraction" and self._t_w is None:
            self._t_w = x.previous_time  # retraction began at the previous sample
        if self._phase == "out":
            self._gamma_w, self._t_w = 0.0, None
        if self.model == "exact":
            self._update_exact(x.gamma, x.rate, x.dt, x.stress)
        else:
            self._update_paper(x.time, x.gamma, x.rate, x.stress)
        return self.estimate

    def _update_exact(self, g: float, gd: float, dt: float, s: float) -> None:
        G = self.tau_grid.size
        if self._phase == "out":
            # out of the mud: no stress to learn from; the next intrusion starts afresh (D11)
            self._state = initial_state((G * 5,), gamma=g)
            return
        gv, gdv = np.full(G * 5, g), np.full(G * 5, gd)
        self._state, stress = channel_update(self._consts, self._state, gv, gdv, dt)
        tot = np.asarray(stress.total).reshape(G, 5)
        phi = tot[:, 1:] - tot[:, :1]  # exact regressors of alpha, eta_inf, eta_m, sigma_y
        if not np.any(np.abs(phi) > 0):
            return
        # until the plate retracts the suction regressor is 0: nothing tells sigma_y
        self._suction_seen = self._suction_seen or bool(np.any(phi[:, 3] != 0))
        self._bank.step(phi * (self._scale / self._S), np.full(G, s / self._S))
        self._updates += 1

    def _update_paper(self, t: float, g: float, gd: float, s: float) -> None:
        if self._phase == "intrusion":
            phi = np.array([[g**self.n, gd]]) * (self._scale_i / self._S)
            self._intrusion.step(phi, np.array([s / self._S]))
            self._updates += 1
        elif self._phase == "retraction" and self._gamma_w - g >= self.retraction_skip:
            assert self._t_w is not None
            G = self.tau_grid.size
            phi = np.stack(
                [-(1.0 - np.exp(-(t - self._t_w) / self.tau_grid)), np.full(G, gd)], axis=-1
            ) * (self._scale / self._S)
            self._suction_seen = True
            self._bank.step(phi, np.full(G, s / self._S))
            self._updates += 1

    def update_many(
        self, time: ArrayLike, depth: ArrayLike, stress: ArrayLike
    ) -> list[OnlineEstimate]:
        """Feed arrays of samples in order; return the estimate after each.

        Parameters
        ----------
        time, depth, stress : array_like, shape (n,)
            Sample times [s] (increasing), displacements [m], measured stresses [Pa].

        Returns
        -------
        list of OnlineEstimate
        """
        t, q, s = (
            check_shape(name, value, (None,))
            for name, value in (("time", time), ("depth", depth), ("stress", stress))
        )
        if not (t.size == q.size == s.size):
            raise MudrftError(
                f"time, depth and stress must have the same length, got "
                f"{t.size}, {q.size}, {s.size}"
            )
        return [self.update(a, b, c) for a, b, c in zip(t, q, s, strict=True)]

    @property
    def estimate(self) -> OnlineEstimate:
        """The current estimates (``None`` for what no sample has informed yet)."""
        est: dict[str, float | None] = dict.fromkeys((*_EXACT, "tau_build"))
        se: dict[str, float] = {}
        b = self._bank
        if np.any(b.cost > 0):
            x = refined_argmin(b.cost)
            lg = np.log(self.tau_grid)
            tau = float(np.exp(np.interp(x, np.arange(lg.size), lg)))
            est["tau_build"] = tau
            i0 = min(int(np.floor(x)), lg.size - 2)
            w = x - i0
            th = ((1.0 - w) * b.theta[i0] + w * b.theta[i0 + 1]) * self._scale  # linear in ln(tau)
            est.update(zip(self._names, th.tolist(), strict=True))
            se_b, se_log = bank_errors(b, x, lg)
            se.update(zip(self._names, (se_b * self._scale).tolist(), strict=True))
            se["tau_build"] = tau * se_log  # delta method, as the offline fit
        if not self._suction_seen:  # no retraction yet: nothing tells sigma_y or tau_build
            est["sigma_y"] = est["tau_build"] = None
        if self.model == "paper":
            est["eta_inf"] = None
            f = self._intrusion
            if f.count >= 2:
                est["alpha"], est["eta_inf"] = (f.theta[0] * self._scale_i).tolist()
                se_i = filter_errors(f.P[0], f.M[0], float(f.cost[0]), f.weight) * self._scale_i
                se["alpha"], se["eta_inf"] = se_i.tolist()
        return OnlineEstimate(
            **est,
            n=self.n,
            updates=self._updates,
            phase=self._phase,
            standard_error={k: se[k] for k, v in est.items() if v is not None},
        )

    def to_parameters(self, base: MudParameters | None = None) -> MudParameters:
        """``base`` (default the prior) with the estimated fields replaced; an estimate
        not yet available, or not positive, keeps the base value (the latter warns).

        Parameters
        ----------
        base : MudParameters, optional
            The set whose fields are replaced [SI].
        """
        b = base if base is not None else self.prior
        if not isinstance(b, MudParameters):
            raise MudrftError(f"base must be a MudParameters, got {type(b).__name__}")
        est = self.estimate
        changes: dict[str, float] = {"n": self.n}
        kept = []
        for k in (*_EXACT, "tau_build"):
            v = getattr(est, k)
            if v is not None and v > 0:
                changes[k] = v
            elif v is not None:
                kept.append(f"{k} = {v:.4g}")
        if kept:
            warnings.warn(
                f"online estimate not positive ({', '.join(kept)}): the base value is kept; "
                "the prior's fixed constants may not describe this mud (calibrate offline, "
                "then rebase() the estimator on the fit)",
                CalibrationWarning,
                stacklevel=2,
            )
        return b.replace(**changes, source=f"online estimate ({self.model})")

    def __repr__(self) -> str:
        e = self.estimate

        def f(v: float | None) -> str:
            return "None" if v is None else f"{v:.4g}"

        return (
            f"OnlineEstimator(model={self.model!r}, alpha={f(e.alpha)}, "
            f"eta_inf={f(e.eta_inf)}, sigma_y={f(e.sigma_y)}, "
            f"tau_build={f(e.tau_build)}, updates={e.updates})"
        )


def _candidates(
    candidates: MudParameters | Sequence[MudParameters] | None,
    labels: Sequence[Any] | None,
    water_contents: ArrayLike | None,
    direction: str,
) -> tuple[list[MudParameters], list[Any]]:
    """The candidate sets and their labels (default: water contents [-] or sources), checked."""
    if candidates is not None and water_contents is not None:
        raise MudrftError("give either candidates or water_contents, not both")
    if candidates is None:
        ws = [0.25, 0.35, 0.45] if water_contents is None else list(np.atleast_1d(water_contents))
        cands = [paper_parameters(float(w), direction) for w in ws]
        default: list[Any] = [float(w) for w in ws]
    else:
        cands = [candidates] if isinstance(candidates, MudParameters) else list(candidates)
        for i, c in enumerate(cands):
            if not isinstance(c, MudParameters) or c.shape != ():
                raise MudrftError(f"candidates[{i}] must be a single MudParameters, got {c!r}")
        default = [c.source or f"set {i}" for i, c in enumerate(cands)]
    labs = default if labels is None else list(labels)
    if len(labs) != len(cands):
        raise MudrftError(
            f"labels must have one entry per candidate ({len(cands)}), got {len(labs)}"
        )
    if len(cands) < 1:
        raise MudrftError("candidates must hold at least one MudParameters")
    return cands, labs


def _softmax_loglik(
    sse: NDArray[np.float64], count: float, noise_var: float | None
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gaussian log-likelihoods of the residual sums and the probabilities (equal priors)."""
    if noise_var is None:
        noise_var = max(float(np.min(sse)) / max(count, 1.0), 1e-300)
    ll = -0.5 * sse / noise_var
    p = np.exp(ll - ll.max())
    return ll, p / p.sum()


@dataclass(frozen=True)
class Classification:
    """Which candidate parameter set a dataset most resembles.

    Attributes
    ----------
    labels : tuple
        Candidate labels (water contents for the paper's rows).
    relative_rmse, log_likelihood, probabilities : ndarray
        Of each candidate over the fitted samples [-]: relative RMSE (decision D12),
        Gaussian log-likelihood, and probability with equal priors.
    best : object
        Label of the most likely candidate.
    """

    labels: tuple
    relative_rmse: NDArray[np.float64]
    log_likelihood: NDArray[np.float64]
    probabilities: NDArray[np.float64]
    best: Any


def _simulate(
    dataset: IntrusionDataset, cands: list[MudParameters]
) -> tuple[Packed, NDArray[np.float64]]:
    """Total stress [Pa] of every candidate on every trial, shape (n, K, T): one batched
    simulation, or one per candidate when they differ in ``nu`` or ``k_a``."""
    packed = pack(dataset, cands[0], acceleration=True, xi0=0.0)
    if all(free_k_a(c) is None for c in cands) and len({float(c.nu) for c in cands}) == 1:
        vals = {k: np.array([float(getattr(c, k)) for c in cands]) for k in FIT_PARAMETERS}
        return packed, packed.simulate(vals)
    sims = [
        pack(dataset, c, acceleration=True, xi0=0.0).simulate(values_of(c, batch=1)) for c in cands
    ]
    return packed, np.concatenate(sims, axis=1)


def classify(
    dataset: IntrusionDataset,
    candidates: Sequence[MudParameters] | None = None,
    *,
    labels: Sequence[Any] | None = None,
    water_contents: ArrayLike | None = None,
    direction: str | None = None,
    noise: float | None = None,
) -> Classification:
    """Which known parameter set (paper row or user list) an offline dataset resembles,
    from the residuals of each trial relative to its stress range.

    Parameters
    ----------
    dataset : IntrusionDataset
        The data.
    candidates : sequence of MudParameters, optional
        Candidate sets; default the paper's rows (W = 25, 35, 45 %) of the direction.
    labels : sequence, optional, keyword-only
        Label of each candidate (default: the water contents, or the sources).
    water_contents : array_like, optional, keyword-only
        Paper sets interpolated at these water contents [-] as candidates.
    direction : {"vertical", "horizontal"}, optional, keyword-only
        Default the dataset's.
    noise : float, optional, keyword-only
        Standard deviation of the residuals relative to each trial's range [-];
        default estimated from the best candidate.

    Returns
    -------
    Classification

    Examples
    --------
    >>> from mudrft.calibration import example_dataset
    >>> classify(example_dataset("vertical")).best
    0.25
    """
    if not isinstance(dataset, IntrusionDataset):
        raise MudrftError(f"dataset must be an IntrusionDataset, got {type(dataset).__name__}")
    d = check_choice("direction", dataset.direction if direction is None else direction, DIRECTIONS)
    cands, labs = _candidates(candidates, labels, water_contents, d)
    packed, sim = _simulate(dataset, cands)
    mask = packed.mask((PHASES["intrusion"], PHASES["hold"], PHASES["retraction"]))
    R = packed.residuals(sim, mask)  # (m, K), relative to each trial's range
    sse = np.sum(R**2, axis=0)
    m = R.shape[0]
    nv = None if noise is None else positive_number("noise", noise) ** 2
    ll, prob = _softmax_loglik(sse, m, nv)
    return Classification(
        labels=tuple(labs),
        relative_rmse=np.sqrt(sse / m),
        log_likelihood=ll,
        probabilities=prob,
        best=labs[int(np.argmax(ll))],
    )


class StreamClassifier:
    """Which known parameter set a stream of samples most resembles, updated per sample.

    The squared residuals of each candidate's model are discounted by ``1 - 1/window``.

    Parameters
    ----------
    candidates : sequence of MudParameters, optional
        Candidate sets; default the paper's rows (or ``water_contents``) of ``direction``.
    labels : sequence, optional, keyword-only
        Labels of the candidates.
    water_contents : array_like, optional, keyword-only
        Paper sets interpolated at these water contents [-].
    direction : {"vertical", "horizontal"}, keyword-only
        Direction of the paper rows.
    characteristic_length : float, keyword-only
        Plate length [m].
    window : float, keyword-only
        Effective window length [samples] (> 1).
    noise : float, optional, keyword-only
        Stress noise standard deviation [Pa]; default the best candidate's windowed RMS.

    Examples
    --------
    >>> import mudrft
    >>> tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=0.5, dt=0.01)
    >>> res = mudrft.plate_response(tr, mudrft.paper_parameters(0.35))
    >>> clf = StreamClassifier()
    >>> for t, q, s in zip(tr.time, res.displacement, res.stress):
    ...     _ = clf.update(t, q, s)
    >>> clf.best
    0.35
    """

    def __init__(
        self,
        candidates: Sequence[MudParameters] | None = None,
        *,
        labels: Sequence[Any] | None = None,
        water_contents: ArrayLike | None = None,
        direction: str = "vertical",
        characteristic_length: float = DEFAULT_PLATE_LENGTH,
        window: float = 200.0,
        noise: float | None = None,
    ) -> None:
        check_choice("direction", direction, ("vertical", "horizontal"))
        self.candidates, self.labels = _candidates(candidates, labels, water_contents, direction)
        self.L = check_characteristic_length("StreamClassifier", characteristic_length)
        w = positive_number("window", window)
        if w <= 1.0:
            raise MudrftError(f"window must exceed 1 sample, got {window!r}")
        self.decay = 1.0 - 1.0 / w
        self.noise = None if noise is None else positive_number("noise", noise, unit="Pa")
        self.params = MudParameters.stack(self.candidates)
        self._consts = channel_constants(self.params)
        self._stream = SampleStream(self.L)
        self.reset()

    def reset(self) -> None:
        """Forget the stream."""
        K = len(self.candidates)
        self._state = initial_state((K,))
        self._sse = np.zeros(K)
        self._count = 0.0
        self._stream.reset()
        self._inside = False

    def update(self, time: float, depth: float, stress: float) -> Any:
        """Add one sample; return the label of the most likely candidate.

        Parameters
        ----------
        time, depth, stress : float
            The sample: time [s] (increasing), depth [m], stress [Pa].
        """
        x = self._stream.push(time, depth, stress)
        K = len(self.candidates)
        if x.dt is None or x.rate is None:  # the first sample: a starting point only
            self._state = initial_state((K,), gamma=x.gamma)
            return self.best
        if not in_contact(x.gamma):
            # above the surface: nothing to compare; the next intrusion starts afresh (D11)
            if self._inside:
                self._state = initial_state((K,), gamma=x.gamma)
                self._inside = False
            return self.best
        self._inside = True
        gv, gdv = np.full(K, x.gamma), np.full(K, x.rate)
        self._state, model = channel_update(self._consts, self._state, gv, gdv, x.dt)
        r = x.stress - np.asarray(model.total)
        self._sse = self.decay * self._sse + r * r
        self._count = self.decay * self._count + 1.0
        return self.best

    @property
    def log_likelihood(self) -> NDArray[np.float64]:
        """Gaussian log-likelihood of each candidate over the window [-]."""
        nv = None if self.noise is None else self.noise**2
        return _softmax_loglik(self._sse, self._count, nv)[0]

    @property
    def probabilities(self) -> NDArray[np.float64]:
        """Posterior probability of each candidate (equal priors) [-]."""
        nv = None if self.noise is None else self.noise**2
        return _softmax_loglik(self._sse, self._count, nv)[1]

    @property
    def rmse(self) -> NDArray[np.float64]:
        """Windowed RMS residual of each candidate [Pa]."""
        return np.sqrt(self._sse / max(self._count, 1e-300))

    @property
    def best(self) -> Any:
        """Label of the most likely candidate (the first one before any sample)."""
        return self.labels[int(np.argmin(self._sse))]

    def __repr__(self) -> str:
        return f"StreamClassifier(labels={self.labels!r}, best={self.best!r})"
