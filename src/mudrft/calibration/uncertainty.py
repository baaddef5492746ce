r"""Uncertainty of a fit: covariance in log-parameters, intervals and identifiability.

From the weighted residuals :math:`r` and the Jacobian :math:`J` in log-parameters at
the optimum, the covariance is :math:`s^2(J^TJ)^{+}` with :math:`s^2=\|r\|^2/(m-k)`;
directions of :math:`J^TJ` whose eigenvalue is below :math:`10^{-10}` of the largest
count as unconstrained, and every parameter loading on them gets an infinite error.
The standard errors of the log-parameters are relative errors, which keeps the
intervals :math:`p\exp(\pm t_q\,\mathrm{se}(\ln p))` positive. Each free parameter gets
an identifiability verdict (rule D44), and a trial that fits much worse than the others
is named (rule D139).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ._problem import FIT_PARAMETERS

__all__ = [
    "IDENTIFIED_SE",
    "NOT_IDENTIFIED_SE",
    "OUTLYING_TRIAL_RATIO",
    "LogCovariance",
    "Uncertainty",
    "at_bound",
    "interval",
    "log_covariance",
    "outlying_trials",
    "uncertainty",
    "verdict",
]

#: Relative standard error at or below which a parameter counts as identified (D44).
IDENTIFIED_SE = 0.05
#: Relative standard error above which a parameter counts as not identified (D44).
NOT_IDENTIFIED_SE = 0.5
#: Eigenvalues of the scaled normal matrix below this fraction of the largest are
#: directions the data do not constrain.
_RANK_TOLERANCE = 1e-10
#: Distance in log-parameter from a bound within which a parameter is at the bound.
_AT_BOUND = 1e-3


class LogCovariance(NamedTuple):
    """Covariance of the log-parameters at an optimum.

    Attributes
    ----------
    se_log : ndarray, shape (k,)
        Standard error of each log-parameter [-] (``inf`` where unconstrained).
    correlation : ndarray, shape (k, k)
        Correlation matrix [-].
    s2 : float
        Residual variance :math:`\\|r\\|^2/(m-k)` [-].
    dof : int
        Degrees of freedom :math:`\\max(m-k, 1)`.
    condition_number : float
        Condition number of the scaled Jacobian [-].
    """

    se_log: NDArray[np.float64]
    correlation: NDArray[np.float64]
    s2: float
    dof: int
    condition_number: float


class Uncertainty(NamedTuple):
    """Per-parameter uncertainty of a fit (every parameter of ``FIT_PARAMETERS``).

    Attributes
    ----------
    se, rse : dict
        Absolute [SI] and relative [-] standard errors (0 for fixed parameters).
    ci : dict
        ``(low, high)`` interval [SI], clipped to the bounds.
    verdict : dict
        ``"identified"``, ``"weak"``, ``"not identified"`` or ``"fixed"``.
    corr : ndarray, shape (k, k)
        Correlation of the free log-parameters [-].
    noise : float
        Standard deviation of the weighted residuals [-].
    cond : float
        Condition number of the scaled Jacobian [-].
    """

    se: dict[str, float]
    rse: dict[str, float]
    ci: dict[str, tuple[float, float]]
    verdict: dict[str, str]
    corr: NDArray[np.float64]
    noise: float
    cond: float


def log_covariance(r: NDArray[np.float64], J: NDArray[np.float64]) -> LogCovariance:
    """Covariance of the log-parameters from residuals ``r`` (m,) and Jacobian ``J`` (m, k).

    The normal matrix is scaled to unit diagonal before its eigen-decomposition, so that
    the rank test does not depend on the parameters' units.
    """
    m, k = J.shape
    dof = max(m - k, 1)
    s2 = float(r @ r) / dof
    F = J.T @ J
    d = np.sqrt(np.diag(F))
    d_safe = np.where(d > 0, d, 1.0)
    w, V = np.linalg.eigh(F / np.outer(d_safe, d_safe))
    wmax = float(w.max()) if w.size else 0.0
    keep = w > _RANK_TOLERANCE * wmax if wmax > 0 else np.zeros_like(w, dtype=bool)
    inv = (V[:, keep] / w[keep]) @ V[:, keep].T
    cov = s2 * inv / np.outer(d_safe, d_safe)
    loose = np.zeros(k, dtype=bool)
    if np.any(~keep):
        loose = np.any(np.abs(V[:, ~keep]) > 0.1, axis=1)
    loose |= d == 0
    se_log = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    se_log[loose] = np.inf
    sd = np.where(np.isfinite(se_log) & (se_log > 0), se_log, 1.0)
    corr = cov / np.outer(sd, sd)
    np.fill_diagonal(corr, 1.0)
    corr = np.clip(corr, -1.0, 1.0)
    cond = float(math.sqrt(wmax / w.min())) if w.size and w.min() > 0 else math.inf
    return LogCovariance(se_log, corr, s2, dof, cond)


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
    r: NDArray[np.float64],
    J: NDArray[np.float64],
    free: tuple[str, ...],
    bound: dict[str, bool],
    level: float,
    values: dict[str, float],
    bounds: dict[str, tuple[float, float]],
) -> Uncertainty:
    """Standard errors, intervals and verdicts of every parameter at an optimum.

    Parameters
    ----------
    r : ndarray, shape (m,)
        Weighted residuals [-].
    J : ndarray, shape (m, k)
        Jacobian of ``r`` in the log of the ``free`` parameters [-].
    free : tuple of str
        The fitted parameters, in the column order of ``J``.
    bound : dict
        Whether each free parameter sits at a bound (:func:`at_bound`).
    level : float
        Two-sided confidence level of the intervals, in (0, 1) [-].
    values : dict
        Value of every parameter [SI].
    bounds : dict
        Bounds of the free parameters [SI].
    """
    from scipy.stats import t as student_t

    cov = log_covariance(r, J)
    q = float(student_t.ppf(0.5 + level / 2.0, cov.dof))
    se, rse, ci, verdicts = {}, {}, {}, {}
    for name in FIT_PARAMETERS:
        v = values[name]
        if name not in free:
            se[name], rse[name], ci[name], verdicts[name] = 0.0, 0.0, (v, v), "fixed"
            continue
        e = float(cov.se_log[free.index(name)])
        rse[name] = e
        se[name] = v * e if math.isfinite(e) else math.inf
        # at a bound the interval is the bounds (rule D44): the optimum lies past the bound,
        # so the linearised interval around the bound value would be a confident wrong range
        ci[name] = bounds[name] if bound[name] else interval(v, e, q, bounds[name])
        verdicts[name] = verdict(e, bound[name])
    return Uncertainty(
        se, rse, ci, verdicts, cov.correlation, math.sqrt(cov.s2), cov.condition_number
    )


#: A trial whose RMSE exceeds this many times the median of the others', relative to its
#: range and in pascals alike, is flagged as fitting worse than the rest (decision D139) [-].
OUTLYING_TRIAL_RATIO = 2.0


def outlying_trials(
    rmse: Sequence[float], ranges: Sequence[float], names: Sequence[str]
) -> str | None:
    """The warning for trials that fit much worse than the others, or None (D139).

    With three trials or more, a trial whose relative RMSE [-] and whose RMSE in pascals
    (relative RMSE times its stress range ``ranges`` [Pa]) are both above
    :data:`OUTLYING_TRIAL_RATIO` times the median of the other trials' is named. Both, so
    that neither a sensor noise of equal size in pascals (larger relative to a slow trial's
    smaller range) nor one of equal relative size flags a good trial; a bad run stands out
    in both: one whose depth zero was 3 mm off, among three good ones, pulled ``alpha``,
    ``n`` and ``sigma_y`` off by up to 21 % with intervals that excluded the truth, at a
    mean relative RMSE of 2.2 %.
    """
    if len(rmse) < 3:
        return None
    absolute = [r * g for r, g in zip(rmse, ranges, strict=True)]
    bad = []
    for j, name in enumerate(names):
        ratios = [
            x[j] / float(np.median([v for i, v in enumerate(x) if i != j]))
            for x in (rmse, absolute)
        ]
        if min(ratios) > OUTLYING_TRIAL_RATIO:
            bad.append(f"{name!r} ({100 * rmse[j]:.2f} %, {ratios[0]:.1f} times the others')")
    if not bad:
        return None
    return (
        f"trial {', '.join(bad)} fits much worse than the others: a bad run (sensor offset, "
        "depth zero, units, another mud)? every parameter and interval assumes all trials "
        "are of one mud; fit without it to compare"
    )
