r"""The outcome of a calibration: :class:`FitResult` and its :class:`StageReport` entries.

A :class:`FitResult` holds the fitted :class:`~mudrft.MudParameters`, their standard
errors, confidence intervals, correlation and identifiability verdicts, the fit quality
(relative RMSE, noise), the solver status and a trace of every evaluation. It predicts
and plots the fitted data, and saves to / loads from JSON.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..io import IntrusionDataset, atomic_write
from ..parameters.base import PARAMETER_UNITS, MudParameters
from ._options import as_dataset
from ._plot import plot_fit
from ._problem import FIT_PARAMETERS, pack, values_of
from .persistence import FIT_FORMAT, FIT_VERSION, parameters_from_json, read_json
from .rate import check_window, smooth_dataset
from .uncertainty import IDENTIFIED_SE, NOT_IDENTIFIED_SE, outlying_trials

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["POOR_FIT_HINT", "POOR_FIT_RMSE", "FitResult", "StageReport"]

#: Relative RMSE above which a fit is flagged as not describing the data [-].
POOR_FIT_RMSE = 0.25
#: The line that flags such a fit (in :meth:`FitResult.summary` and the fit's notes).
POOR_FIT_HINT = (
    "warning: the model does not describe these data (relative RMSE above "
    f"{100 * POOR_FIT_RMSE:g} %); check the units (stress [Pa], depth [m]), the "
    "signs (depth and stress positive while the plate intrudes), the plate area, the "
    "characteristic length and the direction"
)


@dataclass(frozen=True)
class StageReport:
    """Summary of one stage of a fit.

    Attributes
    ----------
    name : str
        ``"start"``, ``"intrusion"``, ``"relaxation"``, ``"retraction"`` or ``"joint"``.
    free : tuple of str
        Parameters freed in the stage.
    simulations : int
        Batched simulations of all trials run in the stage (a batch holds a grid of
        starting points, or a point and its finite-difference neighbours).
    cost : float
        Half the sum of squared weighted residuals of the stage's samples [-].
    seconds : float
        Wall time of the stage [s].
    message : str
        Outcome of the solver.
    """

    name: str
    free: tuple[str, ...]
    simulations: int
    cost: float
    seconds: float
    message: str = ""


@dataclass(frozen=True, eq=False)
class FitResult:
    r"""Outcome of :func:`calibrate`: parameters, uncertainty, diagnostics, trace.

    Attributes
    ----------
    parameters : MudParameters
        The fitted set (SI), usable anywhere in the library.
    free : tuple of str
        Fitted parameters; the others were held fixed.
    standard_error : dict
        Absolute standard error of each parameter [its SI unit] (``inf`` where the
        data do not constrain it, ``0`` for fixed ones), from the delta method
        :math:`\mathrm{se}(p)=p\,\mathrm{se}(\ln p)`.
    relative_standard_error : dict
        :math:`\mathrm{se}(\ln p)` [-], the relative error for small values.
    confidence_interval : dict
        ``(low, high)`` [SI] at ``confidence_level``:
        :math:`p\exp(\pm t_{q}\,\mathrm{se}(\ln p))`, clipped to the bounds. It covers
        the noise only: it assumes the model exact and the residuals independent.
    confidence_level : float
        Two-sided level of the intervals [-].
    robust_standard_error, robust_interval : dict
        Relative error [-] and ``(low, high)`` [SI] that admit model error (residuals
        correlated in time, :mod:`~mudrft.calibration.uncertainty`), never narrower than the
        noise's; the intervals hold for all free parameters at once. The verdicts use them.
    correlation : ndarray, shape (k, k)
        Correlation matrix of the log-parameters, in the order of ``free``.
    identifiability : dict
        Verdict per parameter: ``"identified"``, ``"weak"``, ``"not identified"``
        or ``"fixed"`` (rule D44 on ``robust_standard_error``, see :func:`calibrate`).
    relative_rmse : float
        Mean over trials of the relative RMSE (RMSE / peak-to-peak, decision D12) [-].
    trial_relative_rmse : tuple of float
        Relative RMSE of each trial [-].
    noise : float
        Estimated standard deviation of the residuals relative to each trial's range [-].
    status : str
        ``"converged"``, ``"max_evaluations"`` or ``"failed"``.
    message : str
        Solver message of the joint stage.
    stages : tuple of StageReport
        One entry per stage.
    trace : tuple of dict
        Every model evaluation: ``{"stage", "evaluation", "cost", "parameters"}``
        (like ``mujoco.minimize``'s trace).
    direction : str
        Loading direction of the data.
    bounds : dict
        Bounds used [SI].
    condition_number : float
        Condition number of the Jacobian in log-parameters [-].
    acceleration : bool
        Whether the model kept the acceleration term (decision D6).
    thixotropy, clock : str
        Evaluation of the model that was fitted (decision D15).
    xi0 : float
        Initial structure of every trial [-].
    dataset : IntrusionDataset or None
        The data that were fitted (not saved to JSON).
    data_warnings : tuple of str
        What the checks of the log's sensor found before the fit: a saturated sensor's
        trial (decision D153), an unzeroed one (D154), a depth too noisy for the rate
        (:mod:`~mudrft.calibration.rate`); shown by :meth:`summary`.
    rate : str or int
        How the rate came from the logged depth (the ``rate`` option of :func:`calibrate`).
    depth_notes : tuple of str
        Per trial, how its depth was read: noise, segments or window, rate noise.
    """

    parameters: MudParameters
    free: tuple[str, ...]
    standard_error: dict[str, float]
    relative_standard_error: dict[str, float]
    confidence_interval: dict[str, tuple[float, float]]
    confidence_level: float
    correlation: NDArray[np.float64]
    identifiability: dict[str, str]
    relative_rmse: float
    trial_relative_rmse: tuple[float, ...]
    noise: float
    status: str
    message: str
    stages: tuple[StageReport, ...] = ()
    trace: tuple[dict, ...] = ()
    direction: str = "vertical"
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    condition_number: float = float("nan")
    acceleration: bool = True
    xi0: float = 0.0
    dataset: IntrusionDataset | None = None
    thixotropy: str = "ode"
    clock: str = "contact"
    data_warnings: tuple[str, ...] = ()
    robust_standard_error: dict[str, float] = field(default_factory=dict)
    robust_interval: dict[str, tuple[float, float]] = field(default_factory=dict)
    rate: str | int = "auto"
    depth_notes: tuple[str, ...] = ()

    @property
    def success(self) -> bool:
        """True if the joint stage converged."""
        return self.status == "converged"

    def to_parameters(self) -> MudParameters:
        """The fitted :class:`~mudrft.MudParameters` (same as ``fit.parameters``)."""
        return self.parameters

    def trial_names(self) -> tuple[str, ...]:
        """Names of the fitted trials (numbers ``"1"``, ``"2"``, ... without the dataset)."""
        n = len(self.trial_relative_rmse)
        if self.dataset is not None and len(self.dataset.trials) == n:
            return tuple(t.name for t in self.dataset.trials)
        return tuple(str(i + 1) for i in range(n))

    def outlying_trials(self) -> str | None:
        """The warning naming the trials that fit much worse than the others (rule D139:
        :func:`~mudrft.calibration.uncertainty.outlying_trials`), or None; None without the
        dataset (a fit loaded from JSON)."""
        ds = self.dataset
        if ds is None or len(ds.trials) != len(self.trial_relative_rmse):
            return None
        ranges = [float(np.ptp(t.stress)) for t in ds.trials]
        return outlying_trials(self.trial_relative_rmse, ranges, self.trial_names())

    def identified(self) -> tuple[str, ...]:
        """Names of the parameters the data identify (verdict ``"identified"``)."""
        return tuple(k for k, v in self.identifiability.items() if v == "identified")

    def summary(self) -> str:
        """A table of the parameters with standard errors, intervals and verdicts."""
        lines = [
            f"mudrft fit ({self.direction}): status {self.status}, relative RMSE "
            f"{100 * self.relative_rmse:.2f} %, noise {100 * self.noise:.2f} %"
        ]
        if self.relative_rmse > POOR_FIT_RMSE:
            lines.append(POOR_FIT_HINT)
        rmse = zip(self.trial_names(), self.trial_relative_rmse, strict=True)
        if len(self.trial_relative_rmse) > 1:
            lines.append(
                "relative RMSE per trial: " + ", ".join(f"{n} {100 * r:.2f} %" for n, r in rmse)
            )
        outliers = self.outlying_trials()
        if outliers is not None:
            lines.append(f"warning: {outliers}")
        lines.extend(f"warning: {w}" for w in self.data_warnings)
        lines.extend(f"depth of {n}" for n in self.depth_notes)
        pct = round(100 * self.confidence_level)
        lines.append(
            f"{pct} % intervals: 'noise' is each parameter's own and assumes the model exact "
            "and the residuals independent noise; 'robust' takes the residuals as they are "
            "(correlated in time, a model slightly off), holds for all free parameters at "
            "once, and its errors decide the verdict"
        )
        lines.append(
            f"{'parameter':<12}{'value':>11}{'unit':>5} {'rel. SE':>8} {'robust':>7} "
            f"{'noise interval':>22} {'robust interval':>22}  verdict"
        )
        robust_e = self.robust_standard_error or self.relative_standard_error
        robust_i = self.robust_interval or self.confidence_interval
        for k in FIT_PARAMETERS:
            v = float(getattr(self.parameters, k))
            cells = ["-", "-", "-", "-"]
            if k in self.free:
                cells = [
                    "inf" if not math.isfinite(e) else f"{e:.3g}"
                    for e in (self.relative_standard_error[k], robust_e[k])
                ] + [
                    f"[{lo:.4g}, {hi:.4g}]" for lo, hi in (self.confidence_interval[k], robust_i[k])
                ]
            lines.append(
                f"{k:<12}{v:>11.4g}{PARAMETER_UNITS[k]:>5} {cells[0]:>8} {cells[1]:>7} "
                f"{cells[2]:>22} {cells[3]:>22}  {self.identifiability[k]}"
            )
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (
            f"FitResult(status={self.status!r}, relative_rmse={self.relative_rmse:.4g}, "
            f"identified={list(self.identified())})"
        )

    # -- prediction and plots ---------------------------------------------------------
    def predict(self, dataset: IntrusionDataset | None = None) -> list[NDArray[np.float64]]:
        """Model stress [Pa] at the samples of each trial.

        Parameters
        ----------
        dataset : IntrusionDataset, optional
            Trials to predict (SI), their depth read with the fit's ``rate`` option; default
            the fitted data. The stress is exactly 0 while a vertical plate is above the
            surface.

        Returns
        -------
        list of ndarray
            One array of stresses [Pa] per trial, at its samples.
        """
        ds = self.dataset if dataset is None else as_dataset(dataset)
        if ds is None:
            raise MudrftError("predict needs a dataset: this FitResult was loaded without data")
        if dataset is not None:  # its depth read as the fitted data's were
            ds = smooth_dataset(ds, self.rate)[0]
        packed = pack(
            ds,
            self.parameters,
            acceleration=self.acceleration,
            xi0=self.xi0,
            thixotropy=self.thixotropy,
            clock=self.clock,
            direction=self.direction,
        )
        sim = packed.simulate(values_of(self.parameters, batch=1))[:, 0, :]
        return [sim[:n, j].copy() for j, n in enumerate(packed.lengths)]

    def plot(
        self,
        dataset: IntrusionDataset | None = None,
        *,
        axes: Sequence[Axes] | NDArray[np.object_] | None = None,
    ) -> Figure:
        """Fit against data: stress against time, one panel per trial (needs matplotlib).

        Parameters
        ----------
        dataset : IntrusionDataset, optional
            Data to plot (SI); default the fitted data.
        axes : array of matplotlib Axes, optional, keyword-only
            One per trial; default a new figure.

        Returns
        -------
        matplotlib.figure.Figure
        """
        ds = self.dataset if dataset is None else as_dataset(dataset)
        if ds is None:
            raise MudrftError("plot needs a dataset: pass the data this fit was made from")
        title = f"calibration ({self.direction}); relative RMSE {100 * self.relative_rmse:.2f} %"
        return plot_fit(ds, self.predict(ds), title=title, axes=axes)

    # -- persistence --------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (SI values with the field names of :class:`~mudrft.MudParameters`)."""

        def num(x: float) -> float | None:
            return float(x) if math.isfinite(float(x)) else None

        corr = [[num(c) for c in row] for row in np.asarray(self.correlation, dtype=float)]
        return {
            "format": FIT_FORMAT,
            "version": FIT_VERSION,
            "direction": self.direction,
            "parameters": self.parameters.as_dict(),
            "units": dict(PARAMETER_UNITS),
            "free": list(self.free),
            "standard_error": {k: num(v) for k, v in self.standard_error.items()},
            "relative_standard_error": {k: num(v) for k, v in self.relative_standard_error.items()},
            "confidence_interval": {
                k: [num(a), num(b)] for k, (a, b) in self.confidence_interval.items()
            },
            "confidence_level": self.confidence_level,
            "robust_standard_error": {k: num(v) for k, v in self.robust_standard_error.items()},
            "robust_interval": {k: [num(a), num(b)] for k, (a, b) in self.robust_interval.items()},
            "correlation": {"parameters": list(self.free), "matrix": corr},
            "identifiability": dict(self.identifiability),
            "identifiability_rule": (
                f"identified: robust relative SE <= {IDENTIFIED_SE}; weak: <= "
                f"{NOT_IDENTIFIED_SE}; not identified: larger, infinite "
                "(Jacobian rank-deficient) or at a bound"
            ),
            "relative_rmse": self.relative_rmse,
            "trial_relative_rmse": list(self.trial_relative_rmse),
            "noise": self.noise,
            "status": self.status,
            "message": self.message,
            "condition_number": num(self.condition_number),
            "acceleration": self.acceleration,
            "thixotropy": self.thixotropy,
            "clock": self.clock,
            "xi0": self.xi0,
            "data_warnings": list(self.data_warnings),
            "rate": self.rate,
            "depth_notes": list(self.depth_notes),
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "stages": [asdict(s) | {"free": list(s.free)} for s in self.stages],
            "trace": [dict(t) for t in self.trace],
            "data": None
            if self.dataset is None
            else {
                "source": self.dataset.source,
                "trials": [t.name for t in self.dataset.trials],
                "synthetic": self.dataset.synthetic,
            },
        }

    def to_json(self, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
        """Save to JSON, atomically; never replaces an existing file unless ``overwrite=True``.

        Parameters
        ----------
        path : str or path-like
            Output file (written through :func:`mudrft.io.atomic_write`).
        overwrite : bool, keyword-only
            Replace an existing file.

        Returns
        -------
        Path
            The file written.
        """
        text = json.dumps(self.to_dict(), indent=1, allow_nan=False)
        return atomic_write(
            path, text + "\n", overwrite=overwrite, option="overwrite=True (CLI: --force)"
        )

    @classmethod
    def from_dict(cls, data: dict[str, Any], *, where: str = "fit") -> FitResult:
        """Rebuild a result from :meth:`to_dict` output (without the dataset).

        Parameters
        ----------
        data : dict
            Output of :meth:`to_dict` (SI values).
        where : str, keyword-only
            Where the data come from (a path), named in errors.
        """
        try:
            params = parameters_from_json(data, where=where)
            if not isinstance(data["free"], list):  # a string would read as its letters
                raise MudrftError(f"{where}: free must be a list of names, got {data['free']!r}")
            free = tuple(data["free"])

            def f(x: Any) -> float:
                return float("inf") if x is None else float(x)

            se = {k: f(v) for k, v in data["standard_error"].items()}
            rse = {k: f(v) for k, v in data["relative_standard_error"].items()}
            ci = {k: (f(a), f(b)) for k, (a, b) in data["confidence_interval"].items()}
            # files written before the robust errors (issue 39) have none: the noise's
            rrse = {k: f(v) for k, v in data.get("robust_standard_error", {}).items()} or rse
            rci = {k: (f(a), f(b)) for k, (a, b) in data.get("robust_interval", {}).items()} or ci
            for key, per_free in (
                ("standard_error", se),
                ("relative_standard_error", rse),
                ("confidence_interval", ci),
                ("robust_standard_error", rrse),
                ("robust_interval", rci),
                ("identifiability", data["identifiability"]),
            ):
                if set(per_free) != set(FIT_PARAMETERS):
                    raise MudrftError(
                        f"{where}: {key} must have one entry per parameter "
                        f"{list(FIT_PARAMETERS)}, got {list(per_free)}"
                    )
            if not set(free) <= set(FIT_PARAMETERS):
                raise MudrftError(f"{where}: free must name parameters of {list(FIT_PARAMETERS)}")
            corr = np.array(
                [
                    [np.nan if c is None else c for c in row]
                    for row in data["correlation"]["matrix"]
                ],
                dtype=float,
            )
            stages = tuple(
                StageReport(
                    s["name"],
                    tuple(s["free"]),
                    int(s["simulations"]),
                    float(s["cost"]),
                    float(s["seconds"]),
                    s.get("message", ""),
                )
                for s in data.get("stages", [])
            )
            return cls(
                parameters=params,
                free=free,
                standard_error=se,
                relative_standard_error=rse,
                confidence_interval=ci,
                confidence_level=float(data["confidence_level"]),
                correlation=corr.reshape(len(free), len(free)),
                identifiability=dict(data["identifiability"]),
                relative_rmse=float(data["relative_rmse"]),
                trial_relative_rmse=tuple(float(x) for x in data["trial_relative_rmse"]),
                noise=float(data["noise"]),
                status=str(data["status"]),
                message=str(data.get("message", "")),
                stages=stages,
                trace=tuple(data.get("trace", [])),
                direction=str(data["direction"]),
                bounds={k: (float(a), float(b)) for k, (a, b) in data.get("bounds", {}).items()},
                condition_number=f(data.get("condition_number")),
                acceleration=bool(data.get("acceleration", True)),
                thixotropy=str(data.get("thixotropy", "ode")),
                clock=str(data.get("clock", "contact")),
                xi0=float(data.get("xi0", 0.0)),
                data_warnings=tuple(str(w) for w in data.get("data_warnings", [])),
                robust_standard_error=rrse,
                robust_interval=rci,
                rate=check_window(data.get("rate", "auto")),
                depth_notes=tuple(str(w) for w in data.get("depth_notes", [])),
            )
        except MudrftError:
            raise
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise MudrftError(
                f"{where}: not a mudrft fit file ({type(exc).__name__}: {exc})"
            ) from None

    @classmethod
    def from_json(cls, path: str | os.PathLike[str]) -> FitResult:
        """Load a result saved by :meth:`to_json`.

        Parameters
        ----------
        path : str or path-like
            The JSON file.
        """
        p = Path(os.fspath(path))
        return cls.from_dict(read_json(p), where=str(p))
