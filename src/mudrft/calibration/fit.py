"""Offline calibration: fit the mud model to intrusion logs by bounded least squares in
log-parameters, phase by phase then jointly (decisions D40-D48 in docs/model.md)."""

from __future__ import annotations

import functools
import logging
import os
import time
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np

from .._progress import make_progress
from .._validation import (
    CalibrationWarning,
    MudrftError,
    check_choice,
    check_in_range,
    number_in_range,
    positive_int,
    warn_plausibility,
)
from ..constitutive.dynamics import evaluation
from ..io import IntrusionDataset, Trial
from ..io._build import DIRECTIONS
from ..metrics import relative_rmse
from ..parameters.base import MudParameters
from ..parameters.registry import paper_parameters
from ._problem import (
    FIT_PARAMETERS,
    as_dataset,
    auto_decimate,
    pack,
    resolve_bounds,
    resolve_fixed,
    resolve_groups,
    thin_trials,
    values_of,
)
from .rate import check_window, smooth_dataset
from .result import POOR_FIT_HINT, POOR_FIT_RMSE, FitResult
from .sensors import check_clipped, check_zero
from .stages import STAGES, Engine, joint_stage, phase_stage, stage_note, start_stage
from .uncertainty import uncertainty

__all__ = ["calibrate"]

logger = logging.getLogger("mudrft.calibration")


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
        One or several trials, fitted jointly; a path (CSV, or HDF5 by suffix) is loaded
        with :func:`mudrft.io.load_dataset`.
    direction : {"vertical", "horizontal"}, optional
        Loading direction; default the dataset's.
    groups : str or sequence of str, keyword-only
        What to fit: ``"all"`` (default), group names ``"b"`` (:math:`\alpha, n`),
        ``"th"`` (:math:`\lambda,\eta_m,\eta_\infty,\dot\gamma_c`), ``"s"``
        (:math:`\tau_{build},\tau_{leak},\varepsilon,\sigma_Y`) or parameter names;
        ``nu`` and ``k_a`` are never fitted (decisions D8, D41).
    initial : MudParameters, optional, keyword-only
        Starting values and values of the parameters not fitted. Default: the paper row
        that best matches the data once its free linear parameters are rescaled (D43).
    fixed : dict, optional, keyword-only
        Parameters to hold at given SI values (removed from the free set).
    bounds : dict, optional, keyword-only
        ``{name: (low, high)}`` in SI, overriding :data:`DEFAULT_BOUNDS`.
    phases : bool, keyword-only
        Run the three phase stages before the joint fit (default).
    starts : int, keyword-only
        Number of best grid points refined in each phase stage (>= 1).
    max_nfev : int, keyword-only
        Evaluations allowed to each least-squares solve.
    confidence_level : float, keyword-only
        Level of the confidence intervals, in (0, 1).
    acceleration : bool or None, keyword-only
        Keep the acceleration term of :math:`f_\xi` (decision D6); None keeps it in the ODE.
    thixotropy, clock : str, keyword-only
        The ODE model (``"ode"``, default) or the paper's quasi-static closed forms
        (``"quasi-static"``) and its clock (decision D15), as :class:`mudrft.MudTerrain`.
    xi0 : float, keyword-only
        Initial structure of the mud in every trial [-] (decision D3: 0).
    progress : bool or callable, keyword-only
        Notes go to the ``mudrft.calibration`` logger; ``True`` shows them on stderr with
        the progress; a callable receives each line.
    area, characteristic_length : float, optional, keyword-only
        Plate area [m^2] and length [m] when ``dataset`` is a path to load.
    trace_limit : int, keyword-only
        Most evaluations kept in ``trace``.
    decimate : int or None, keyword-only
        Keep every ``decimate``-th sample of each trial (and its deepest and last samples);
        default: trials longer than 2000 samples are thinned to about that many (warns).
    clipped : {"exclude", "keep"}, keyword-only
        Leave out or fit the samples of a saturated sensor (5 or more at exactly a trial's
        extreme stress; warns either way, decision D153).
    zero : {"check", "subtract"}, keyword-only
        Warn when the stress [Pa] of a vertical plate out of the mud is clearly off 0, or
        subtract each trial's median there (decision D154).
    rate : "auto", "raw" or int, keyword-only
        How the model's rate comes from the logged depth (:mod:`.rate`): ``"auto"``
        smooths a noisy depth, ``"raw"`` differences the logged depths, an odd int smooths
        over that many samples.

    Notes
    -----
    Each trial's residuals are divided by its peak-to-peak stress (decision D45); samples
    out of the mud are not fitted (D42); the verdicts follow rule D44 (docs/model.md).

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
    # how the model is evaluated, checked, as pack and FitResult take it
    model: dict[str, Any] = {"thixotropy": thixotropy, "clock": clock}
    model["acceleration"] = evaluation(thixotropy, clock, acceleration)[2] == 1.0
    model["xi0"] = number_in_range("xi0", xi0, 0.0, 1.0)
    if not isinstance(phases, (bool, np.bool_)):
        raise MudrftError(f"phases must be True or False, got {phases!r}")
    whole = isinstance(trace_limit, int | np.integer) and not isinstance(trace_limit, bool)
    if not whole or trace_limit < 0:
        raise MudrftError(f"trace_limit must be an integer >= 0, got {trace_limit!r}")
    clipped = check_choice("clipped", clipped, ("exclude", "keep"))
    zero = check_choice("zero", zero, ("check", "subtract"))
    rate = check_window(rate)
    k = None if decimate is None else positive_int("decimate", decimate)
    check_in_range("confidence_level", confidence_level, 1e-6, 1 - 1e-9)
    positive_int("starts", starts)
    positive_int("max_nfev", max_nfev)
    if initial is not None and (not isinstance(initial, MudParameters) or initial.shape != ()):
        raise MudrftError(f"initial must be a single MudParameters, got {initial!r}")
    selected = resolve_groups(groups)
    bnds = resolve_bounds(bounds)
    held = resolve_fixed(fixed)
    free = tuple(k for k in selected if k not in held)
    if not free:
        raise MudrftError("every parameter is fixed: nothing to fit")
    reporter = Reporter(progress)

    ds = as_dataset(dataset, area=area, characteristic_length=characteristic_length)
    d = check_choice("direction", ds.direction if direction is None else direction, DIRECTIONS)
    ds, smoothing, rate_warnings = smooth_dataset(ds, rate)
    ds, tare, warned, notes = check_zero(ds, zero=zero, direction=d)
    if k is None:
        k = auto_decimate(ds)
        if k > 1:
            longest = max(len(t) for t in ds.trials)
            warn_plausibility(
                f"the longest trial has {longest} samples; fitting every {ordinal(k)} sample "
                f"(about {longest // k} per trial, decision D104) to keep the fit to minutes; "
                "pass decimate=1 (CLI: --decimate 1) to fit every sample",
                CalibrationWarning,
            )
    if k > 1:
        ds = thin_trials(ds, k)
    clip, clip_warnings = check_clipped(ds, clipped=clipped)
    warned += clip_warnings + rate_warnings
    for line in notes:
        reporter.note(line)
    for line in warned:
        warn_plausibility(line, CalibrationWarning)
    # samples whose step spans a change of speed are not fitted (module rate)
    exclude = [how.excluded(tr.time) for how, tr in zip(smoothing, ds.trials, strict=True)]
    if clip is not None:
        exclude = [m | c for m, c in zip(exclude, clip, strict=True)]
    depth_notes = tuple(h.note() for h in smoothing if h.method != "as logged" or h.depth_noise)
    reporter.note(
        f"calibrate: {len(ds)} trial(s), {sum(len(t) for t in ds.trials)} samples, "
        f"direction {d}, free {list(free)}"
    )
    for line in depth_notes:
        reporter.note(f"calibrate: depth of {line}")
    base = initial if initial is not None else paper_parameters(0.25, d)
    try:
        packed = pack(ds, base, exclude=exclude, direction=d, **model)
    except MudrftError as exc:
        raise MudrftError(f"{ds.source}: {exc}" if ds.source else str(exc)) from None
    engine = Engine(packed, {k: float(getattr(base, k)) for k in FIT_PARAMETERS}, bnds, trace_limit)
    paper = d if initial is None else None
    start = start_stage(engine, free, held, paper=paper, note=reporter.note)
    reporter.step()
    stages = [start]
    for stage in STAGES:
        report = phases and phase_stage(engine, stage, free, starts=starts, max_nfev=max_nfev)
        if report:
            stages.append(report)
            reporter.note(stage_note(report))
        reporter.step()
    joint, status = joint_stage(engine, free, max_nfev=max_nfev)
    stages.append(joint)
    reporter.note(stage_note(joint, f" ({status})"))
    reporter.step()
    unc = uncertainty(engine, free, confidence_level, tare=tare)
    params = MudParameters(
        **{k: engine.values[k] for k in FIT_PARAMETERS},
        nu=packed.nu,
        k_a=packed.k_a,
        direction=d,
        source=f"fit: {ds.source or 'data'} ({len(ds)} trials)",
    )
    sim = packed.simulate(values_of(params, batch=1))[:, 0, :]
    per_trial = zip(sim.T, packed.data.T, packed.valid.T, strict=True)
    trmse = [relative_rmse(s[m], d[m]) for s, d, m in per_trial]
    fit = FitResult(
        parameters=params,
        free=free,
        confidence_level=float(confidence_level),
        **unc,
        relative_rmse=float(np.mean(trmse)),
        trial_relative_rmse=tuple(float(x) for x in trmse),
        status=status,
        message=str(joint.message),
        stages=tuple(stages),
        trace=tuple(engine.trace),
        direction=d,
        bounds={k: bnds[k] for k in free},
        **model,
        dataset=ds,
        data_warnings=tuple(warned),
        rate=rate,
        depth_notes=depth_notes,
    )
    if fit.relative_rmse > POOR_FIT_RMSE:
        warn_plausibility(POOR_FIT_HINT.removeprefix("warning: "), CalibrationWarning)
    outliers = fit.outlying_trials()
    if outliers is not None:
        warn_plausibility(outliers, CalibrationWarning)
    reporter.note(
        f"calibrate: done in {time.perf_counter() - t_start:.2f} s, relative RMSE "
        f"{100 * fit.relative_rmse:.2f} %, identified {list(fit.identified())}"
    )
    reporter.step()
    return fit


class Reporter:
    """Where a fit reports (``progress`` as :func:`~mudrft.calibration.calibrate`'s): each
    line to :attr:`note`, and the fraction done after each of the :attr:`STEPS`."""

    #: Steps of a fit's progress: the start, each phase stage, the joint stage, the result.
    STEPS = len(STAGES) + 3

    def __init__(self, progress: bool | Callable[[str], object] | None) -> None:
        if not (progress is None or isinstance(progress, bool) or callable(progress)):
            raise MudrftError(f"progress must be True, False, None or a callable, got {progress!r}")
        #: The line callable, or the log when there is none (never both).
        self.note = progress if callable(progress) else functools.partial(logger.info, "%s")
        self._fraction = make_progress(True, "calibrate") if progress is True else None
        self._done = 0

    def step(self) -> None:
        """One more step of the fit is done."""
        self._done = min(self._done + 1, self.STEPS)
        if self._fraction is not None:
            self._fraction(self._done / self.STEPS)


def ordinal(k: int) -> str:
    """``2`` -> ``"2nd"``, ``11`` -> ``"11th"``, ``21`` -> ``"21st"``.

    Examples
    --------
    >>> [ordinal(k) for k in (1, 2, 3, 4, 11, 12, 13, 21, 102)]
    ['1st', '2nd', '3rd', '4th', '11th', '12th', '13th', '21st', '102nd']
    """
    if 10 <= k % 100 <= 20:
        return f"{k}th"
    return f"{k}{ {1: 'st', 2: 'nd', 3: 'rd'}.get(k % 10, 'th') }"
