"""Online estimation by recursive least squares with forgetting, O(1) per sample (D46)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from types import MappingProxyType
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import (
    CalibrationWarning,
    MudrftError,
    check_characteristic_length,
    check_choice,
    check_positive,
    check_shape,
    number_in_range,
    positive_number,
    warn_plausibility,
)
from ..constitutive import channel_constants, channel_update, initial_state
from ..constitutive.contact import in_contact
from ..parameters.base import MudParameters
from ..parameters.registry import paper_parameters
from ..plate import DEFAULT_PLATE_LENGTH
from ._problem import LINEAR_PARAMETERS, basis, free_k_a, values_of
from .classification import SampleStream

__all__ = ["OnlineEstimate", "OnlineEstimator"]


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
    sigma_y, tau_build : float or None
        Yield stress :math:`\\sigma_Y` [Pa] and suction build-up time [s]; ``None`` until a
        retraction sample.
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


def filter_errors(bank: Filters, i: int) -> NDArray[np.float64]:
    r"""Standard errors [-] of the estimates of member ``i`` of a bank: the sandwich
    :math:`s^2PMP` of a weighted least-squares estimate (``M`` from :meth:`Filters.step`),
    with :math:`s^2=V/(w-p)` from the discounted cost :math:`V` and count ``weight``
    :math:`w` (decision D138); ``inf`` while :math:`w\le p`."""
    P, M, p = bank.P[i], bank.M[i], bank.P.shape[-1]
    if bank.weight <= p:
        return np.full(p, np.inf)
    return np.sqrt(bank.cost[i] / (bank.weight - p) * np.clip(np.diagonal(P @ M @ P), 0.0, None))


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
    se = filter_errors(bank, i)
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


class OnlineEstimator:
    r"""Recursive least squares with forgetting of the linear constants and tau_build (D46).

    Feed samples with :meth:`update` and read :attr:`estimate`; one filter runs per
    :math:`\tau_{build}` of a grid, and the one that predicts best is read.

    Parameters
    ----------
    prior : MudParameters, optional
        Starting values and fixed constants; default the paper's row W = 35 % of
        ``direction``.
    model : {"exact", "paper"}, keyword-only
        Regressors of the full model stepped alongside the stream, the other constants from
        ``prior`` (unbiased when those are right), or the supplementary's approximations
        (Sec. III-A), which need only ``n`` but give apparent values.
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
        prior = paper_parameters(0.35, direction) if prior is None else prior
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
        skip = 3.0 * float(prior.epsilon) if retraction_skip is None else retraction_skip
        self.retraction_skip = number_in_range("retraction_skip", skip, 0.0, 10.0)
        self.initial_scale = positive_number("initial_scale", initial_scale)
        self._names = LINEAR_PARAMETERS if self.model == "exact" else ("sigma_y", "eta_inf")
        self._stream = SampleStream(self.L)
        self.rebase(prior.replace(n=self.n) if n is not None else prior)

    def rebase(self, prior: MudParameters) -> None:
        """Start again around another single ``prior`` [SI], memory cleared (e.g. a
        :class:`StreamClassifier`'s best after the mud changed)."""
        if not isinstance(prior, MudParameters) or prior.shape != ():
            raise MudrftError(f"prior must be a single MudParameters, got {prior!r}")
        self.prior, self.n = prior, float(prior.n)
        if self.model == "exact":
            vals = values_of(prior, batch=self.tau_grid.size)
            vals["tau_build"] = self.tau_grid
            p = MudParameters(**basis(vals, self._names), nu=float(prior.nu), k_a=free_k_a(prior))
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
        """Add one sample, its ``time`` [s] (increasing), intrusion displacement ``depth`` [m]
        and measured ``stress`` [Pa]; return the current estimates."""
        x = self._stream.push(time, depth, stress)
        if x.step is None:  # the first sample: a starting point only
            self._phase = "out" if x.gamma <= 0 else "hold"
            if self.model == "exact":
                self._state = initial_state((self.tau_grid.size * 5,), gamma=x.gamma)
            return self.estimate
        dt, rate, previous_time = x.step
        if not in_contact(x.gamma):
            self._phase = "out"  # at or above the surface: no mud stress (as plate_response)
        elif abs(rate) <= self.rate_threshold:
            self._phase = "hold"
        else:
            self._phase = "intrusion" if rate > 0 else "retraction"
        # the deepest point of the current intrusion and the time its retraction began
        if self._phase == "intrusion" and x.gamma >= self._gamma_w:
            self._gamma_w, self._t_w = x.gamma, None
        if self._phase == "retraction" and self._t_w is None:
            self._t_w = previous_time  # retraction began at the previous sample
        if self._phase == "out":
            self._gamma_w, self._t_w = 0.0, None
        if self.model == "exact":
            self._update_exact(x.gamma, rate, dt, x.stress)
        else:
            self._update_paper(x.time, x.gamma, rate, x.stress)
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
        """:meth:`update` with each sample of the arrays ``time`` [s], ``depth`` [m] and
        ``stress`` [Pa], shape (n,), in order; return the estimate after each."""
        t = check_shape("time", time, (None,))
        q = check_shape("depth", depth, (None,))
        s = check_shape("stress", stress, (None,))
        if not (t.size == q.size == s.size):
            raise MudrftError(
                f"time, depth and stress must have the same length, got "
                f"{t.size}, {q.size}, {s.size}"
            )
        return [self.update(a, b, c) for a, b, c in zip(t, q, s, strict=True)]

    @property
    def estimate(self) -> OnlineEstimate:
        """The current estimates (``None`` for what no sample has informed yet)."""
        est: dict[str, float | None] = dict.fromkeys((*LINEAR_PARAMETERS, "tau_build"))
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
                se_i = filter_errors(f, 0) * self._scale_i
                se["alpha"], se["eta_inf"] = se_i.tolist()
        return OnlineEstimate(
            **est,
            n=self.n,
            updates=self._updates,
            phase=self._phase,
            standard_error={k: se[k] for k, v in est.items() if v is not None},
        )

    def to_parameters(self, base: MudParameters | None = None) -> MudParameters:
        """The set ``base`` [SI] (default the prior) with the estimated fields replaced; an
        estimate not yet available, or not positive, keeps the base value (the latter warns)."""
        b = base if base is not None else self.prior
        if not isinstance(b, MudParameters):
            raise MudrftError(f"base must be a MudParameters, got {type(b).__name__}")
        est = self.estimate
        changes: dict[str, float] = {"n": self.n}
        kept = []
        for k in (*LINEAR_PARAMETERS, "tau_build"):
            v = getattr(est, k)
            if v is not None and v > 0:
                changes[k] = v
            elif v is not None:
                kept.append(f"{k} = {v:.4g}")
        if kept:
            warn_plausibility(
                f"online estimate not positive ({', '.join(kept)}): the base value is kept; "
                "the prior's fixed constants may not describe this mud (calibrate offline, "
                "then rebase() the estimator on the fit)",
                CalibrationWarning,
            )
        return b.replace(**changes, source=f"online estimate ({self.model})")

    def __repr__(self) -> str:
        e = self.estimate
        shown = {k: getattr(e, k) for k in ("alpha", "eta_inf", "sigma_y", "tau_build")}
        values = ", ".join(f"{k}={'None' if v is None else f'{v:.4g}'}" for k, v in shown.items())
        return f"OnlineEstimator(model={self.model!r}, {values}, updates={e.updates})"
