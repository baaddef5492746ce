r"""Uncertainty of a fit: covariances of the log-parameters, intervals, identifiability.

The noise-only covariance is :math:`s^2(J^TJ)^{+}`, :math:`s^2=\|r\|^2/(m-k)`; the robust
one (:func:`robust_log_covariance`) admits residuals correlated in time.

References
----------
.. [1] W. K. Newey and K. D. West, Econometrica 55(3), 703-708, 1987.
.. [2] D. W. K. Andrews, Econometrica 59(3), 817-858, 1991 (eq. 6.2 and Sec. 6).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ._problem import ALL_PHASES, FIT_PARAMETERS

if TYPE_CHECKING:
    from .sensors import Offset
    from .stages import Engine

#: The per-parameter entries of a fit (:class:`~mudrft.calibration.FitResult` fields).
PER_PARAMETER = tuple(
    "standard_error relative_standard_error confidence_interval robust_standard_error "
    "robust_interval identifiability".split()
)
#: Relative standard error at or below which a parameter counts as identified (D44).
IDENTIFIED_SE = 0.05
#: Relative standard error above which a parameter counts as not identified (D44).
NOT_IDENTIFIED_SE = 0.5
#: Eigenvalues of the scaled normal matrix below this fraction of the largest are
#: directions the data do not constrain.
_RANK_TOLERANCE = 1e-10
#: Distance in log-parameter from a bound within which a parameter is at the bound.
_AT_BOUND = 1e-3


def _scaled_inverse(J: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_], float]:
    """:math:`(J^TJ)^{+}` on the directions the data constrain (scaled to unit diagonal, so
    that the rank test ignores units), the parameters loading on the others, and the
    condition number of the scaled Jacobian."""
    F = J.T @ J
    d = np.sqrt(np.diag(F))
    d_safe = np.where(d > 0, d, 1.0)
    w, V = np.linalg.eigh(F / np.outer(d_safe, d_safe))
    wmax = float(w.max()) if w.size else 0.0
    keep = w > _RANK_TOLERANCE * wmax if wmax > 0 else np.zeros_like(w, dtype=bool)
    inv = (V[:, keep] / w[keep]) @ V[:, keep].T / np.outer(d_safe, d_safe)
    loose = np.any(np.abs(V[:, ~keep]) > 0.1, axis=1) | (d == 0)
    cond = float(math.sqrt(wmax / w.min())) if w.size and w.min() > 0 else math.inf
    return inv, loose, cond


def bartlett_lag(r: NDArray[np.float64], trial: NDArray[np.intp]) -> int:
    """The lag [samples] of the Bartlett weights for residuals ``r`` of ``trial``s (in time
    order within each): Andrews' AR(1) plug-in :math:`1.1447(\\alpha m)^{1/3}`,
    :math:`\\alpha=4\\rho^2/((1-\\rho)^2(1+\\rho)^2)`, with :math:`\\rho` the residuals' lag-1
    autocorrelation within the trials and :math:`m` the samples of the longest trial."""
    same = trial[1:] == trial[:-1]
    num = float(r[1:][same] @ r[:-1][same])
    rho = min(max(num / float(r @ r), 0.0), 0.97) if float(r @ r) > 0 else 0.0
    alpha = 4.0 * rho**2 / ((1.0 - rho) ** 2 * (1.0 + rho) ** 2)
    m = int(np.bincount(trial).max())
    return min(int(1.1447 * (alpha * m) ** (1.0 / 3.0)), m // 2)


def robust_log_covariance(
    r: NDArray[np.float64],
    J: NDArray[np.float64],
    trial: NDArray[np.intp],
    shift: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    r"""Standard errors [-] of the log-parameters that admit model error: the sandwich
    :math:`A^{+}\Omega A^{+}`, :math:`A=J^TJ`, :math:`\Omega` the Newey-West covariance of
    the scores within each trial, times :math:`m/(m-k)`, plus :math:`s_j^2g_jg_j^T`,
    :math:`g_j=A^{+}J^T1_j`, for an error ``shift[j]`` shared by trial :math:`j` (a
    subtracted sensor zero). ``r`` (m,) weighted residuals, ``J`` (m, k) their Jacobian,
    ``trial`` (m,) the trial of each, in time order within a trial.
    """
    m, k = J.shape
    inv, loose, _ = _scaled_inverse(J)
    lag = bartlett_lag(r, trial)
    omega = np.zeros((k, k))
    for j in np.unique(trial):
        S = J[trial == j] * r[trial == j, None]
        omega += S.T @ S
        for lg in range(1, min(lag, S.shape[0] - 1) + 1):
            G = S[lg:].T @ S[:-lg]
            omega += (1.0 - lg / (lag + 1.0)) * (G + G.T)
    cov = inv @ omega @ inv * (m / max(m - k, 1))
    for j, s_j in enumerate(() if shift is None else shift):
        g = inv @ J[trial == j].sum(axis=0)
        cov += s_j**2 * np.outer(g, g)
    return np.where(loose, np.inf, np.sqrt(np.clip(np.diag(cov), 0.0, None)))


def interval(v: float, e: float, q: float, bounds: tuple[float, float]) -> tuple[float, float]:
    """Interval :math:`v\\exp(\\pm q e)` [SI] of a value ``v`` with log-error ``e`` [-] and
    quantile ``q`` [-], clipped to ``bounds``; the bounds themselves if ``e`` is infinite."""
    lo_b, hi_b = bounds
    if not math.isfinite(e):
        return lo_b, hi_b
    return max(v * math.exp(-min(q * e, 700.0)), lo_b), min(v * math.exp(min(q * e, 700.0)), hi_b)


def verdict(e: float, bound: bool) -> str:
    """Identifiability verdict of a free parameter with log-error ``e`` [-] (rule D44)."""
    if bound or not math.isfinite(e) or e > NOT_IDENTIFIED_SE:
        return "not identified"
    return "identified" if e <= IDENTIFIED_SE else "weak"


def at_bound(
    values: dict[str, float], free: tuple[str, ...], bounds: dict[str, tuple[float, float]]
) -> dict[str, bool]:
    """Whether each free parameter ends within 0.1 % (in log) of one of its bounds."""
    out = {}
    for k in free:
        lo, hi = bounds[k]
        x = math.log(values[k])
        out[k] = bool(x - math.log(lo) < _AT_BOUND or math.log(hi) - x < _AT_BOUND)
    return out


def uncertainty(
    engine: Engine, free: tuple[str, ...], level: float, *, tare: Sequence[Offset] | None = None
) -> dict[str, Any]:
    """The :class:`~mudrft.calibration.FitResult` fields of the uncertainty (errors,
    intervals at ``level`` [-], verdicts, correlation, noise, condition number) at the
    ``engine``'s values, from the weighted residuals and their Jacobian in the log of the
    ``free`` parameters; ``tare`` holds each trial's subtracted sensor zero, with its
    standard error [Pa]."""
    from scipy.stats import t as student_t

    mask = engine.packed.mask(ALL_PHASES)
    r, J = engine.jacobian(mask, free)
    values, bounds = engine.values, engine.bounds
    bound = at_bound(values, free, bounds)
    _, trial = np.nonzero(mask)  # the residuals' order: time, then trial
    order = np.argsort(trial, kind="stable")  # each trial's residuals together, in time order
    r, J, trial = r[order], J[order], trial[order]
    shift = None if tare is None else np.array([t.error for t in tare]) * engine.packed.weight
    m, k = J.shape
    dof = max(m - k, 1)
    s2 = float(r @ r) / dof
    inv, loose, cond = _scaled_inverse(J)
    cov = s2 * inv
    se_log = np.where(loose, np.inf, np.sqrt(np.clip(np.diag(cov), 0.0, None)))
    sd = np.where(np.isfinite(se_log) & (se_log > 0), se_log, 1.0)
    corr = np.clip(cov / np.outer(sd, sd), -1.0, 1.0)
    np.fill_diagonal(corr, 1.0)
    robust = robust_log_covariance(r, J, trial, shift)
    q = float(student_t.ppf(0.5 + level / 2.0, dof))
    q_all = float(student_t.ppf(1.0 - (1.0 - level) / (2.0 * len(free)), dof))  # Bonferroni
    se, rse, ci, rrse, rci, verdicts = {}, {}, {}, {}, {}, {}
    for name in FIT_PARAMETERS:
        v = values[name]
        if name not in free:
            se[name], rse[name], rrse[name], verdicts[name] = 0.0, 0.0, 0.0, "fixed"
            ci[name] = rci[name] = (v, v)
            continue
        i = free.index(name)
        e, er = float(se_log[i]), max(float(se_log[i]), float(robust[i]))
        rse[name], rrse[name] = e, er
        se[name] = v * e if math.isfinite(e) else math.inf
        # at a bound the interval is the bounds (rule D44): the optimum may lie past it
        ci[name] = bounds[name] if bound[name] else interval(v, e, q, bounds[name])
        rci[name] = bounds[name] if bound[name] else interval(v, er, q_all, bounds[name])
        verdicts[name] = verdict(er, bound[name])
    return {
        **dict(zip(PER_PARAMETER, (se, rse, ci, rrse, rci, verdicts), strict=True)),
        "correlation": corr,
        "noise": math.sqrt(s2),
        "condition_number": cond,
    }


#: A trial whose RMSE exceeds this many times the median of the others', relative to its
#: range and in pascals alike, fits worse than the rest (decision D139) [-] ...
OUTLYING_TRIAL_RATIO = 2.0
#: ... unless its relative RMSE is below this [-].
OUTLYING_TRIAL_FLOOR = 0.002


def outlying_trials(
    rmse: Sequence[float], ranges: Sequence[float], names: Sequence[str]
) -> str | None:
    """The warning naming the trials whose relative ``rmse`` [-] and RMSE in pascals (times
    their stress ``ranges`` [Pa]) are both outliers (decision D139), or None."""
    if len(rmse) < 3:
        return None
    absolute = [r * g for r, g in zip(rmse, ranges, strict=True)]
    bad = []
    for j, name in enumerate(names):
        ratios = [
            x[j] / float(np.median([v for i, v in enumerate(x) if i != j]))
            for x in (rmse, absolute)
        ]
        if min(ratios) > OUTLYING_TRIAL_RATIO and rmse[j] > OUTLYING_TRIAL_FLOOR:
            bad.append(f"{name!r} ({100 * rmse[j]:.2f} %, {ratios[0]:.1f} times the others')")
    if not bad:
        return None
    return (
        f"trial {', '.join(bad)} fits much worse than the others: a bad run (sensor offset, "
        "depth zero, units, another mud)? every parameter and interval assumes all trials "
        "are of one mud; fit without it to compare"
    )
