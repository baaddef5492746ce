r"""Offline calibration: fit the mud model to intrusion logs, with uncertainty.

:func:`calibrate` fits the constants of eqs. (1)-(5) of Chen et al. (2026) to one
or several plate-intrusion trials by bounded nonlinear least squares
(:func:`scipy.optimize.least_squares`) in log-parameters, phase by phase and then
jointly:

1. **intrusion** (:math:`\Pi_b=\{\alpha,n\}` and :math:`\eta_\infty`) on the intrusion
   samples: the paper's :math:`\sigma\approx\alpha\gamma^n+\eta_\infty\dot\gamma`;
2. **relaxation** (:math:`\Pi_{th}=\{\lambda,\eta_m,\eta_\infty,\dot\gamma_c\}`) on
   the intrusion and hold samples;
3. **retraction** (:math:`\Pi_s=\{\tau_{build},\tau_{leak},\varepsilon\}` and
   :math:`\sigma_Y`) on the retraction samples;
4. **joint**: every free parameter on every sample.

Each stage starts from the best point of a small grid over its nonlinear
parameters, on which the parameters the model is *linear* in
(:math:`\alpha,\eta_\infty,\eta_m,\sigma_Y`) are solved exactly by non-negative
least squares (variable projection), all grid points in one batched simulation.
Standard errors come from the Jacobian at the optimum in log-parameters
(:math:`\mathrm{cov}=s^2(J^TJ)^{-1}`), which makes them relative errors and keeps
confidence intervals positive; each parameter gets an identifiability verdict
(decision D44). See docs/model.md for the decisions D40-D48.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError, check_choice, check_in_range, number_in_range
from ..constitutive.dynamics import evaluation
from ..io import IntrusionDataset, Trial
from ..metrics import relative_rmse
from ..parameters.base import MudParameters
from ..parameters.registry import paper_parameters
from ._engine import Engine
from ._options import (
    DEFAULT_BOUNDS,
    GROUPS,
    as_dataset,
    auto_decimate,
    check_count,
    resolve_bounds,
    resolve_fixed,
    resolve_groups,
    thin_trials,
)
from ._problem import FIT_PARAMETERS, values_of
from ._problem import LINEAR_PARAMETERS as LINEAR_PARAMETERS  # importable here, as before
from ._problem import PHASES as PHASES
from ._problem import Packed as Packed
from ._report import Reporter, ordinal
from .persistence import load_parameters
from .rate import Smoothing, check_window, smooth_dataset
from .result import POOR_FIT_HINT, POOR_FIT_RMSE, FitResult, StageReport
from .sensors import check_clipped, check_zero
from .stages import (
    STAGES,
    joint_stage,
    phase_stage,
    stage_note,
    start_engine,
    uncertainty_at_optimum,
)
from .uncertainty import IDENTIFIED_SE, NOT_IDENTIFIED_SE, Uncertainty

__all__ = [
    "DEFAULT_BOUNDS",
    "GROUPS",
    "IDENTIFIED_SE",
    "NOT_IDENTIFIED_SE",
    "FitResult",
    "StageReport",
    "calibrate",
    "load_parameters",
]


@dataclass(frozen=True)
class _Setup:
    """The checked inputs of one fit."""

    dataset: IntrusionDataset
    direction: str
    free: tuple[str, ...]
    fixed: dict[str, float]
    bounds: dict[str, tuple[float, float]]
    exclude: list[NDArray[np.bool_]] | None = None
    data_warnings: tuple[str, ...] = ()
    smoothing: tuple[Smoothing, ...] = ()
    rate: int | str = "auto"
    tare: tuple[float, ...] | None = None

    @property
    def depth_notes(self) -> tuple[str, ...]:
        """How each trial's depth was read, for the trials with something to say."""
        return tuple(h.note() for h in self.smoothing if h.method != "as logged" or h.depth_noise)


def calibrate(
    dataset: IntrusionDataset | Trial | str | os.PathLike[str] | Sequence[object],
    direction: str | None = None,
    *,
    groups: str | Iterable[str] | None = "all",
    initial: MudParameters | None = None,
    fixed: dict[str, float] | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    phases: bool = True,
    starts: int = 1,
    max_nfev: int = 200,
    confidence_level: float = 0.95,
    acceleration: bool | None = None,
    thixotropy: str = "ode",
    clock: str = "contact",
    xi0: float = 0.0,
    progress: bool | Callable[[str], object] | None = None,
    area: float | None = None,
    characteristic_length: float | None = None,
    trace_limit: int = 2000,
    decimate: int | None = None,
    clipped: str = "exclude",
    zero: str = "check",
    rate: int | str = "auto",
) -> FitResult:
    r"""Fit the mud model to intrusion logs; return parameters with their uncertainty.

    Parameters
    ----------
    dataset : IntrusionDataset, Trial, path or list of them
        The data: one or several trials (several speeds, repetitions), fitted jointly.
        A path (CSV, or HDF5 by suffix) is loaded with :func:`mudrft.io.load_dataset`.
    direction : {"vertical", "horizontal"}, optional
        Loading direction; default the dataset's. It selects the paper rows used to
        start the fit and is stored in the fitted parameters.
    groups : str or sequence of str, keyword-only
        What to fit: ``"all"`` (default), group names ``"b"`` (:math:`\alpha, n`),
        ``"th"`` (:math:`\lambda,\eta_m,\eta_\infty,\dot\gamma_c`), ``"s"``
        (:math:`\tau_{build},\tau_{leak},\varepsilon,\sigma_Y`) or parameter names.
        The others stay at their initial values. ``nu`` and ``k_a`` are never fitted
        (:math:`k_a=1/\lambda` follows :math:`\lambda`, decisions D8, D41).
    initial : MudParameters, optional, keyword-only
        Starting values and values of the fixed parameters. Default: the paper row of
        the direction that best matches the data after rescaling its free linear
        parameters (decision D43); those not fitted keep the row's values.
    fixed : dict, optional, keyword-only
        Parameters to hold at given SI values (removed from the free set).
    bounds : dict, optional, keyword-only
        ``{name: (low, high)}`` in SI, overriding :data:`DEFAULT_BOUNDS`.
    phases : bool, keyword-only
        Run the three phase stages before the joint fit (default). ``False`` goes
        straight to the joint fit from ``initial``.
    starts : int, keyword-only
        Multi-start: number of best grid points refined in each phase stage (>= 1).
    max_nfev : int, keyword-only
        Evaluations allowed to each least-squares solve.
    confidence_level : float, keyword-only
        Level of the confidence intervals, in (0, 1).
    acceleration : bool or None, keyword-only
        Keep the acceleration term of :math:`f_\xi` (decision D6); None keeps it in the ODE.
    thixotropy : {"ode", "quasi-static"}, keyword-only
        Fit the ODE model (default) or the paper's quasi-static closed forms (9)-(11)
        (decision D15), as :class:`mudrft.MudTerrain`.
    clock : {"contact", "retraction"}, keyword-only
        Quasi-static only: the clock of eq. (9) (decision D15).
    xi0 : float, keyword-only
        Initial structure of the mud in every trial [-] (decision D3: 0).
    progress : bool or callable, keyword-only
        Notes (one line per stage) always go to the ``mudrft.calibration`` logger at
        INFO level. ``True`` shows them on stderr with the progress in percent
        (:func:`mudrft._progress.make_progress`); a callable receives each note line.
    area, characteristic_length : float, optional, keyword-only
        Plate area [m^2] and length [m] when ``dataset`` is a path to load (an error
        for a dataset already loaded, which they would not change).
    trace_limit : int, keyword-only
        Most evaluations kept in ``trace``.
    decimate : int or None, keyword-only
        Keep every ``decimate``-th sample of each trial (and its deepest and last
        samples) before fitting; 1 fits every sample. The fit time grows with the samples
        per trial (the model step is exact between samples, so thinning loses data, not
        accuracy of the model). Default ``None``: trials longer than
        :data:`~mudrft.calibration._options.FIT_SAMPLES` (2000) samples are thinned to
        about that many, with a warning naming the factor used (decision D104).
    clipped : {"exclude", "keep"}, keyword-only
        A trial with :data:`~mudrft.calibration.sensors.CLIPPED_SAMPLES` (5) samples or more
        at exactly its largest positive (or smallest negative) stress is a saturated force
        sensor: it is named by a :class:`~mudrft.calibration.CalibrationWarning`, and
        ``"exclude"`` (default) leaves those samples out of the fit (they say only that the
        stress was at least the limit); ``"keep"`` fits them (decision D153).
    zero : {"check", "subtract"}, keyword-only
        The stress [Pa] while the plate is out of the mud (depth <= 0) is the force sensor's
        zero. ``"check"`` (default) warns, naming the trial, when its median is clearly off 0
        (above 2 % of the trial's range, at least 5 samples); ``"subtract"`` subtracts each
        trial's median out of the mud before the fit, and needs 5 such samples in every
        trial; a vertical test only: a horizontal plate at zero travel is still in the mud
        (decision D154).
    rate : "auto", "raw" or int, keyword-only
        How the model's rate comes from the logged depth (:mod:`.rate`). ``"auto"``
        (default): the depth is smoothed over the fewest samples that bring the rate's noise
        to 1 % of the trial's speed (none for a clean depth); ``"raw"``: the difference of
        the logged depths; an odd int: smoothed over that many samples. Samples whose rate
        spans a change of speed are not fitted. The window of each trial is in
        ``fit.rate_notes``.

    Returns
    -------
    FitResult
        Parameters, standard errors, confidence intervals, correlation, verdicts, RMSE,
        status and trace. ``fit.parameters`` is a :class:`~mudrft.MudParameters`.

    Raises
    ------
    MudrftError
        For invalid arguments or data, and for a fit with no more fitted samples than
        free parameters (decision D104).

    Notes
    -----
    Residuals of each trial are divided by the trial's peak-to-peak stress, so that
    trials of different speeds weigh equally and the residual scale is the relative
    RMSE of decision D12 (decision D45). Samples after the plate is back at the
    surface are not fitted (decision D42). The covariance of the log-parameters is
    :math:`s^2(J^TJ)^{+}` with :math:`s^2=\|r\|^2/(m-k)`; directions of :math:`J^TJ`
    whose eigenvalue is below :math:`10^{-10}` of the largest are treated as
    unconstrained, and every parameter loading on them gets an infinite error.

    Identifiability rule (decision D44): a free parameter is *identified* if its
    relative standard error :math:`\mathrm{se}(\ln p)\le 0.05` and it is not at a
    bound; *weak* if :math:`0.05<\mathrm{se}(\ln p)\le 0.5`; *not identified* if the
    error is larger or infinite, or the parameter ends at a bound.

    References
    ----------
    .. [1] X. Chen, L. Wang, X. Huang, J. Shan, Y. Shen and J. Yi, "A Foot Resistive Force
       Model for Legged Locomotion on Muddy Terrains", 2026 (preprint with supplementary
       materials), supplementary Sec. III (identification of the mud constants).

    Examples
    --------
    >>> import mudrft
    >>> from mudrft.calibration import calibrate, synthetic_dataset
    >>> true = mudrft.paper_parameters(0.25, "vertical")
    >>> data = synthetic_dataset(true, speeds=(0.02,), noise=0.01, seed=1, dt=0.02)
    >>> fit = calibrate(data, groups="b")
    >>> abs(fit.parameters.alpha / true.alpha - 1) < 0.05
    True
    """
    t_start = time.perf_counter()
    _qs, _restart, kappa = evaluation(thixotropy, clock, acceleration)
    # the options that are one number or a flag, checked before any work (a list of xi0
    # failed inside the fit; phases="no" ran the phases, a negative trace_limit kept none)
    xi0 = number_in_range("xi0", xi0, 0.0, 1.0)
    if not isinstance(phases, (bool, np.bool_)):
        raise MudrftError(f"phases must be True or False, got {phases!r}")
    if (
        isinstance(trace_limit, (bool, np.bool_))
        or not isinstance(trace_limit, (int, np.integer))
        or trace_limit < 0
    ):
        raise MudrftError(f"trace_limit must be an integer >= 0, got {trace_limit!r}")
    acceleration = kappa == 1.0
    clipped = check_choice("clipped", clipped, ("exclude", "keep"))
    zero = check_choice("zero", zero, ("check", "subtract"))
    rate = check_window(rate)
    reporter = Reporter(progress, label="calibrate", steps=len(STAGES) + 3)
    setup = _prepare(
        dataset,
        direction,
        reporter=reporter,
        groups=groups,
        initial=initial,
        fixed=fixed,
        bounds=bounds,
        starts=starts,
        max_nfev=max_nfev,
        confidence_level=confidence_level,
        area=area,
        characteristic_length=characteristic_length,
        decimate=decimate,
        clipped=clipped,
        zero=zero,
        rate=rate,
    )
    ds, free = setup.dataset, setup.free
    reporter.note(
        f"calibrate: {len(ds)} trial(s), {sum(len(t) for t in ds.trials)} samples, "
        f"direction {setup.direction}, free {list(free)}"
    )
    for line in setup.depth_notes:
        reporter.note(f"calibrate: depth of {line}")
    engine, start = start_engine(
        ds,
        initial if initial is not None else paper_parameters(0.25, setup.direction),
        from_paper=initial is None,
        direction=setup.direction,
        free=free,
        fixed=setup.fixed,
        bounds=setup.bounds,
        acceleration=acceleration,
        xi0=xi0,
        trace_limit=trace_limit,
        reporter=reporter,
        thixotropy=thixotropy,
        clock=clock,
        exclude=setup.exclude,
    )
    reporter.step()
    stages = [start]
    for stage in STAGES:
        report = (
            phase_stage(engine, stage, free, starts=starts, max_nfev=max_nfev) if phases else None
        )
        if report is not None:
            stages.append(report)
            reporter.note(stage_note(report))
        reporter.step()
    joint, status = joint_stage(engine, free, max_nfev=max_nfev)
    stages.append(joint)
    reporter.note(stage_note(joint, f" ({status})"))
    reporter.step()
    unc = uncertainty_at_optimum(engine, free, confidence_level, tare=setup.tare)
    fit = _assemble(
        engine,
        setup,
        unc,
        stages=tuple(stages),
        status=status,
        confidence_level=confidence_level,
        acceleration=acceleration,
        xi0=xi0,
    )
    if fit.relative_rmse > POOR_FIT_RMSE:
        reporter.warn(POOR_FIT_HINT.removeprefix("warning: "))
    outliers = fit.outlying_trials()
    if outliers is not None:
        reporter.warn(outliers)
    reporter.note(
        f"calibrate: done in {time.perf_counter() - t_start:.2f} s, relative RMSE "
        f"{100 * fit.relative_rmse:.2f} %, identified {list(fit.identified())}"
    )
    reporter.step()
    return fit


def _prepare(
    dataset: IntrusionDataset | Trial | str | os.PathLike[str] | Sequence[object],
    direction: str | None,
    *,
    reporter: Reporter,
    groups: str | Iterable[str] | None,
    initial: MudParameters | None,
    fixed: dict[str, float] | None,
    bounds: dict[str, tuple[float, float]] | None,
    starts: int,
    max_nfev: int,
    confidence_level: float,
    area: float | None,
    characteristic_length: float | None,
    decimate: int | None,
    clipped: str,
    zero: str,
    rate: int | str,
) -> _Setup:
    """Check the inputs of :func:`calibrate`; load, merge, smooth and thin the data."""
    k = None if decimate is None else check_count("decimate", decimate)
    ds = as_dataset(dataset, area=area, characteristic_length=characteristic_length)
    d = (
        ds.direction
        if direction is None
        else check_choice("direction", direction, ("vertical", "horizontal"))
    )
    ds, smoothing, rate_warnings = smooth_dataset(ds, check_window(rate))
    # the sensor's zero on every sample: the tare's error is then as small as the log allows
    ds, tare, data_warnings, notes = check_zero(ds, zero=zero, direction=d)
    if k is None:
        k = auto_decimate(ds)
        if k > 1:
            longest = max(len(t) for t in ds.trials)
            reporter.warn(
                f"the longest trial has {longest} samples; fitting every {ordinal(k)} sample "
                f"(about {longest // k} per trial, decision D104) to keep the fit to minutes; "
                "pass decimate=1 (CLI: --decimate 1) to fit every sample"
            )
    if k > 1:
        ds = thin_trials(ds, k)
    exclude, clip_warnings = check_clipped(ds, clipped=clipped)
    data_warnings += clip_warnings
    for line in notes:
        reporter.note(line)
    for line in data_warnings + rate_warnings:
        reporter.warn(line)
    # samples whose step spans a change of speed are not fitted (module rate)
    near = [how.excluded(tr.time) for how, tr in zip(smoothing, ds.trials, strict=True)]
    exclude = [m if exclude is None else m | exclude[j] for j, m in enumerate(near)]
    check_in_range("confidence_level", confidence_level, 1e-6, 1 - 1e-9)
    check_count("starts", starts)
    check_count("max_nfev", max_nfev)
    if initial is not None and not isinstance(initial, MudParameters):
        raise MudrftError(f"initial must be a MudParameters, got {type(initial).__name__}")
    if initial is not None and initial.shape != ():
        raise MudrftError(
            f"initial must be a single parameter set, got a batch of shape {initial.shape}"
        )
    selected = resolve_groups(groups)
    bnds = resolve_bounds(bounds)
    held = resolve_fixed(fixed)
    free = tuple(k for k in selected if k not in held)
    if not free:
        raise MudrftError("every parameter is fixed: nothing to fit")
    return _Setup(
        ds,
        d,
        free,
        held,
        bnds,
        exclude,
        tuple(data_warnings + rate_warnings),
        tuple(smoothing),
        check_window(rate),
        None if tare is None else tuple(off.error for off in tare),
    )


def _assemble(
    engine: Engine,
    setup: _Setup,
    unc: Uncertainty,
    *,
    stages: tuple[StageReport, ...],
    status: str,
    confidence_level: float,
    acceleration: bool,
    xi0: float,
) -> FitResult:
    """The :class:`FitResult` at the engine's optimum, with the RMSE of each trial."""
    packed, ds = engine.packed, setup.dataset
    params = MudParameters(
        **{k: engine.values[k] for k in FIT_PARAMETERS},
        nu=packed.nu,
        k_a=packed.k_a,
        direction=setup.direction,
        source=f"fit: {ds.source or 'data'} ({len(ds)} trials)",
    )
    # relative RMSE of each trial over its fitted samples (decision D12)
    sim = packed.simulate(values_of(params, batch=1))[:, 0, :]
    trmse = []
    for j, n in enumerate(packed.lengths):
        m = packed.valid[:n, j]
        trmse.append(relative_rmse(sim[:n, j][m], packed.data[:n, j][m]))
    return FitResult(
        parameters=params,
        free=setup.free,
        standard_error=unc.se,
        relative_standard_error=unc.rse,
        confidence_interval=unc.ci,
        confidence_level=float(confidence_level),
        robust_standard_error=unc.robust_rse,
        robust_interval=unc.robust_ci,
        correlation=unc.corr,
        identifiability=unc.verdict,
        relative_rmse=float(np.mean(trmse)),
        trial_relative_rmse=tuple(float(x) for x in trmse),
        noise=unc.noise,
        status=status,
        message=str(stages[-1].message),
        stages=stages,
        trace=tuple(engine.trace),
        direction=setup.direction,
        bounds={k: setup.bounds[k] for k in setup.free},
        condition_number=unc.cond,
        acceleration=bool(acceleration),
        xi0=float(xi0),
        dataset=ds,
        thixotropy=packed.thixotropy,
        clock=packed.clock,
        data_warnings=setup.data_warnings,
        rate=setup.rate,
        depth_notes=setup.depth_notes,
    )
