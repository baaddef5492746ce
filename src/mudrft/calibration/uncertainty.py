r"""Uncertainty of a fit: covariance in log-parameters, intervals and identifiability.

From the weighted residuals :math:`r` and the Jacobian :math:`J` in log-parameters at
the optimum, two covariances:

* **noise only** (:func:`log_covariance`): :math:`s^2(J^TJ)^{+}` with
  :math:`s^2=\|r\|^2/(m-k)`, right when the model is exact and the residuals are
  independent noise of one size;
* **robust** (:func:`robust_log_covariance`): the sandwich
  :math:`(J^TJ)^{+}\,\Omega\,(J^TJ)^{+}`, with :math:`\Omega` the long-run covariance of
  the scores :math:`J_ir_i` of each trial (Newey and West, Bartlett weights, the lag
  chosen from the residuals' autocorrelation by Andrews' rule), trials independent. It
  takes the residuals as they are: a model slightly off leaves residuals correlated in
  time, which widen it, where the noise-only errors stay as narrow as the noise.

Directions of :math:`J^TJ` whose eigenvalue is below :math:`10^{-10}` of the largest count
as unconstrained, and every parameter loading on them gets an infinite error. The standard
errors of the log-parameters are relative errors, which keeps the intervals
:math:`p\exp(\pm t_q\,\mathrm{se}(\ln p))` positive. Each free parameter gets an
identifiability verdict from the larger of its two errors (rule D44), and a trial that
fits much worse than the others is named (rule D139). The noise-only intervals are each
parameter's own; the robust ones hold for all free parameters at once (Bonferroni), as a
statement that every fitted constant lies in its interval needs.

References
----------
.. [1] W. K. Newey and K. D. West, "A simple, positive semi-definite, heteroskedasticity and
   autocorrelation consistent covariance matrix", Econometrica 55(3), 703-708, 1987.
.. [2] D. W. K. Andrews, "Heteroskedasticity and autocorrelation consistent covariance
   matrix estimation", Econometrica 59(3), 817-858, 1991 (the AR(1) plug-in bandwidth of
   the Bartlett kernel, eq. 6.2 and Sec. 6).
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
    "OUTLYING_TRIAL_FLOOR",
    "OUTLYING_TRIAL_RATIO",
    "LogCovariance",
    "Uncertainty",
    "at_bound",
    "interval",
    "log_covariance",
    "outlying_trials",
    "robust_log_covariance",
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
        Absolute [SI] and relative [-] standard errors, noise only (0 for fixed parameters).
    ci : dict
        ``(low, high)`` interval [SI], noise only, clipped to the bounds.
    robust_rse : dict
        Relative standard errors that admit model error [-]: the larger of the robust
        (sandwich) and the noise-only ones.
    robust_ci : dict
        ``(low, high)`` interval [SI] from ``robust_rse``, clipped to the bounds, for all
        free parameters at once: each at level ``1 - (1 - level)/k`` for ``k`` free
        parameters (Bonferroni), so that together they hold at ``level``.
    verdict : dict
        ``"identified"``, ``"weak"``, ``"not identified"`` or ``"fixed"``, from
        ``robust_rse``.
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
    robust_rse: dict[str, float]
    robust_ci: dict[str, tuple[float, float]]
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
    inv, loose, cond = _scaled_inverse(J)
    cov = s2 * inv
    se_log = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    se_log[loose] = np.inf
    sd = np.where(np.isfinite(se_log) & (se_log > 0), se_log, 1.0)
    corr = cov / np.outer(sd, sd)
    np.fill_diagonal(corr, 1.0)
    corr = np.clip(corr, -1.0, 1.0)
    return LogCovariance(se_log, corr, s2, dof, cond)


def _scaled_inverse(
    J: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.bool_], float]:
    """:math:`(J^TJ)^{+}` on the directions the data constrain, the parameters that load on
    the others, and the condition number of the scaled Jacobian (see :func:`log_covariance`)."""
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
    :math:`A^{+}\Omega A^{+}`, :math:`A=J^TJ`, with :math:`\Omega` the Newey-West long-run
    covariance of the scores :math:`J_ir_i` within each trial (Bartlett weights over
    :func:`bartlett_lag` lags), trials independent, times :math:`m/(m-k)`; plus, for an
    error :math:`s_j` shared by every sample of trial :math:`j` (a subtracted sensor zero),
    :math:`s_j^2\,g_jg_j^T` with :math:`g_j=A^{+}J^T1_j` (the delta method).

    Parameters
    ----------
    r : ndarray, shape (m,)
        Weighted residuals [-].
    J : ndarray, shape (m, k)
        Jacobian of ``r`` in the log-parameters [-].
    trial : ndarray of int, shape (m,)
        The trial of each residual; the residuals of a trial are in time order.
    shift : ndarray, shape (trials,), optional
        Standard error of an error shared by all of a trial's residuals [-].

    Returns
    -------
    ndarray, shape (k,)
        Standard errors (``inf`` where the data do not constrain a parameter).
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
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    se[loose] = np.inf
    return se


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
    trial: NDArray[np.intp] | None = None,
    shift: NDArray[np.float64] | None = None,
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
    trial : ndarray of int, shape (m,), optional
        The trial of each residual, in time order within a trial (default: one trial).
    shift : ndarray, optional
        Per trial, the standard error of an error its residuals share [-]
        (:func:`robust_log_covariance`).
    """
    from scipy.stats import t as student_t

    cov = log_covariance(r, J)
    robust = robust_log_covariance(
        r, J, np.zeros(r.size, dtype=np.intp) if trial is None else trial, shift
    )
    q = float(student_t.ppf(0.5 + level / 2.0, cov.dof))
    # the robust intervals hold for every free parameter at once (Bonferroni)
    q_all = float(student_t.ppf(1.0 - (1.0 - level) / (2.0 * len(free)), cov.dof))
    se, rse, ci, rrse, rci, verdicts = {}, {}, {}, {}, {}, {}
    for name in FIT_PARAMETERS:
        v = values[name]
        if name not in free:
            se[name], rse[name], rrse[name], verdicts[name] = 0.0, 0.0, 0.0, "fixed"
            ci[name] = rci[name] = (v, v)
            continue
        i = free.index(name)
        e, er = float(cov.se_log[i]), max(float(cov.se_log[i]), float(robust[i]))
        rse[name], rrse[name] = e, er
        se[name] = v * e if math.isfinite(e) else math.inf
        # at a bound the interval is the bounds (rule D44): the optimum lies past the bound,
        # so the linearised interval around the bound value would be a confident wrong range
        ci[name] = bounds[name] if bound[name] else interval(v, e, q, bounds[name])
        rci[name] = bounds[name] if bound[name] else interval(v, er, q_all, bounds[name])
        verdicts[name] = verdict(er, bound[name])
    return Uncertainty(
        se,
        rse,
        ci,
        rrse,
        rci,
        verdicts,
        cov.correlation,
        math.sqrt(cov.s2),
        cov.condition_number,
    )


#: A trial whose RMSE exceeds this many times the median of the others', relative to its
#: range and in pascals alike, is flagged as fitting worse than the rest (decision D139) [-].
OUTLYING_TRIAL_RATIO = 2.0
#: ... unless its relative RMSE is below this: such a trial fits well whatever the others
#: do (noise-free logs fit to a few 0.01 %, the ratios then only compare round-off) [-].
OUTLYING_TRIAL_FLOOR = 0.002


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
    mean relative RMSE of 2.2 %. A trial within :data:`OUTLYING_TRIAL_FLOOR` is not named.
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
        if min(ratios) > OUTLYING_TRIAL_RATIO and rmse[j] > OUTLYING_TRIAL_FLOOR:
            bad.append(f"{name!r} ({100 * rmse[j]:.2f} %, {ratios[0]:.1f} times the others')")
    if not bad:
        return None
    return (
        f"trial {', '.join(bad)} fits much worse than the others: a bad run (sensor offset, "
        "depth zero, units, another mud)? every parameter and interval assumes all trials "
        "are of one mud; fit without it to compare"
    )
