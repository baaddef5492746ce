"""The outcome of a calibration: :class:`FitResult` and its :class:`StageReport` entries."""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..io import IntrusionDataset, atomic_write, json_text
from ..io.atomic import finite_or_none
from ..io.dataset import OVERWRITE_OPTION
from ..parameters.base import PARAMETER_UNITS, MudParameters
from ._problem import FIT_PARAMETERS, PHASES, as_dataset, pack, segment, values_of
from .persistence import FIT_FORMAT, FIT_VERSION, parameters_from_json, read_json
from .rate import check_window, smooth_dataset
from .stages import StageReport
from .uncertainty import IDENTIFIED_SE, NOT_IDENTIFIED_SE, PER_PARAMETER, outlying_trials

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["POOR_FIT_HINT", "POOR_FIT_RMSE", "FitResult"]

#: Relative RMSE above which a fit is flagged as not describing the data [-].
POOR_FIT_RMSE = 0.25
#: The line that flags such a fit (in :meth:`FitResult.summary` and the fit's notes).
POOR_FIT_HINT = (
    "warning: the model does not describe these data (relative RMSE above "
    f"{100 * POOR_FIT_RMSE:g} %); check the units (stress [Pa], depth [m]), the "
    "signs (depth and stress positive while the plate intrudes), the plate area, the "
    "characteristic length and the direction"
)
#: Fields of :class:`FitResult` written to JSON as they are, in the file's order.
_ERROR_FIELDS = tuple(
    "standard_error relative_standard_error confidence_interval confidence_level "
    "robust_standard_error robust_interval".split()
)
_PLAIN_FIELDS = tuple(
    "relative_rmse trial_relative_rmse noise status message condition_number acceleration "
    "thixotropy clock xi0 data_warnings rate depth_notes bounds".split()
)


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
        Standard error of each parameter [its SI unit], :math:`p\,\mathrm{se}(\ln p)`
        (``inf`` where the data do not constrain it, ``0`` for fixed ones).
    relative_standard_error : dict
        :math:`\mathrm{se}(\ln p)` [-], the relative error for small values.
    confidence_interval : dict
        ``(low, high)`` [SI] at ``confidence_level``,
        :math:`p\exp(\pm t_{q}\,\mathrm{se}(\ln p))`, clipped to the bounds (noise only).
    confidence_level : float
        Two-sided level of the intervals [-].
    robust_standard_error, robust_interval : dict
        Relative error [-] and ``(low, high)`` [SI] that admit model error, jointly for all
        free parameters; the verdicts use them.
    correlation : ndarray, shape (k, k)
        Correlation matrix of the log-parameters, in the order of ``free``.
    identifiability : dict
        ``"identified"``, ``"weak"``, ``"not identified"`` or ``"fixed"`` (rule D44).
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
        Every model evaluation: ``{"stage", "evaluation", "cost", "parameters"}``.
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
        What the checks of the log found before the fit.
    rate : str or int
        How the rate came from the logged depth (the ``rate`` option of :func:`calibrate`).
    depth_notes : tuple of str
        Per trial, how its depth was read.
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
        """The warning naming the trials that fit much worse than the others, or None."""
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
        row = "{:<12}{:>11}{:>5} {:>8} {:>7} {:>22} {:>22}  {}".format
        head = ("parameter", "value", "unit", "rel. SE", "robust", "noise interval")
        lines.append(row(*head, "robust interval", "verdict"))
        robust_e = self.robust_standard_error or self.relative_standard_error
        robust_i = self.robust_interval or self.confidence_interval
        for k in FIT_PARAMETERS:
            cells = ["-", "-", "-", "-"]
            if k in self.free:
                cells = [
                    "inf" if not math.isfinite(e) else f"{e:.3g}"
                    for e in (self.relative_standard_error[k], robust_e[k])
                ] + [
                    f"[{lo:.4g}, {hi:.4g}]" for lo, hi in (self.confidence_interval[k], robust_i[k])
                ]
            value = f"{float(getattr(self.parameters, k)):.4g}"
            lines.append(row(k, value, PARAMETER_UNITS[k], *cells, self.identifiability[k]))
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (
            f"FitResult(status={self.status!r}, relative_rmse={self.relative_rmse:.4g}, "
            f"identified={list(self.identified())})"
        )

    def predict(self, dataset: IntrusionDataset | None = None) -> list[NDArray[np.float64]]:
        """Model stress [Pa] at the samples of each trial of ``dataset`` (SI; default the
        fitted data), its depth read with the fit's ``rate`` option: one array per trial."""
        ds = self.dataset if dataset is None else as_dataset(dataset)
        if ds is None:
            raise MudrftError("predict needs a dataset: this FitResult was loaded without data")
        if dataset is not None:  # its depth read as the fitted data's were
            ds = smooth_dataset(ds, self.rate)[0]
        model = {k: getattr(self, k) for k in ("acceleration", "xi0", "thixotropy", "clock")}
        packed = pack(ds, self.parameters, direction=self.direction, **model)
        sim = packed.simulate(values_of(self.parameters, batch=1))[:, 0, :]
        return [sim[: len(tr), j].copy() for j, tr in enumerate(ds.trials)]

    def plot(
        self,
        dataset: IntrusionDataset | None = None,
        *,
        axes: Sequence[Axes] | NDArray[np.object_] | None = None,
    ) -> Figure:
        """Stress [kPa] against time [s], data and fit, one panel per trial of ``dataset``
        (SI; default the fitted data), on ``axes`` (one per trial; default a new figure);
        needs matplotlib."""
        from ..plotting import require_matplotlib

        ds = self.dataset if dataset is None else as_dataset(dataset)
        if ds is None:
            raise MudrftError("plot needs a dataset: pass the data this fit was made from")
        plt = require_matplotlib()
        if axes is None:
            size = (3.6 * len(ds) + 0.6, 3.2)
            fig, axes = plt.subplots(1, len(ds), figsize=size, squeeze=False, layout="constrained")
        else:
            fig = np.ravel(axes)[0].figure  # type: ignore[arg-type]
        axs = np.ravel(axes)  # type: ignore[arg-type]
        for j, (tr, yp) in enumerate(zip(ds.trials, self.predict(ds), strict=True)):
            ax = axs[j]
            used = segment(tr) != PHASES["out"]
            ax.plot(tr.time[used], tr.stress[used] / 1e3, ".", ms=2.5, color="0.55", label="data")
            if not used.all():
                out = {"ms": 4, "color": "0.55", "label": "not fitted (out of the mud)"}
                ax.plot(tr.time[~used], tr.stress[~used] / 1e3, "x", **out)
            ax.plot(tr.time[used], yp[used] / 1e3, "C3", lw=1.5, label="fit")
            ax.axhline(0.0, color="0.8", lw=0.6)
            ax.set_title(f"{tr.name}: {1e3 * tr.speed:.3g} mm/s", fontsize=9)
            ax.set_xlabel("time [s]")
            if j == 0:
                ax.set_ylabel("stress [kPa]")
                ax.legend(fontsize=8, loc="lower left")
        title = f"calibration ({self.direction}); relative RMSE {100 * self.relative_rmse:.2f} %"
        fig.suptitle(title, fontsize=10)
        return fig

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (SI values with the field names of :class:`~mudrft.MudParameters`;
        an infinite or undefined number is None)."""
        ds = self.dataset
        data = None
        if ds is not None:
            trials = [t.name for t in ds.trials]
            data = {"source": ds.source, "trials": trials, "synthetic": ds.synthetic}
        return finite_or_none(
            {
                "format": FIT_FORMAT,
                "version": FIT_VERSION,
                "direction": self.direction,
                "parameters": self.parameters.as_dict(),
                "units": dict(PARAMETER_UNITS),
                "free": list(self.free),
                **{k: getattr(self, k) for k in _ERROR_FIELDS},
                "correlation": {
                    "parameters": list(self.free),
                    "matrix": np.asarray(self.correlation, dtype=float).tolist(),
                },
                "identifiability": dict(self.identifiability),
                "identifiability_rule": (
                    f"identified: robust relative SE <= {IDENTIFIED_SE}; weak: <= "
                    f"{NOT_IDENTIFIED_SE}; not identified: larger, infinite "
                    "(Jacobian rank-deficient) or at a bound"
                ),
                **{k: getattr(self, k) for k in _PLAIN_FIELDS},
                "stages": [asdict(s) for s in self.stages],
                "trace": self.trace,
                "data": data,
            }
        )

    def to_json(self, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
        """Save to the JSON file ``path`` atomically and return its Path; an existing file is
        replaced only with ``overwrite=True``."""
        text = json_text(self.to_dict(), indent=1)
        return atomic_write(path, text, overwrite=overwrite, option=OVERWRITE_OPTION)

    @classmethod
    def from_dict(cls, data: dict[str, Any], *, where: str = "fit") -> FitResult:
        """Rebuild a result (without its dataset) from :meth:`to_dict` output, read from
        ``where`` (named in errors)."""

        def f(x: Any) -> float:
            return float("inf") if x is None else float(x)

        try:
            params = parameters_from_json(data, where=where)
            if not isinstance(data["free"], list):  # a string would read as its letters
                raise MudrftError(f"{where}: free must be a list of names, got {data['free']!r}")
            free = tuple(data["free"])
            se = {k: f(v) for k, v in data["standard_error"].items()}
            rse = {k: f(v) for k, v in data["relative_standard_error"].items()}
            ci = {k: (f(a), f(b)) for k, (a, b) in data["confidence_interval"].items()}
            # a file without robust errors: the noise's
            rrse = {k: f(v) for k, v in data.get("robust_standard_error", {}).items()} or rse
            rci = {k: (f(a), f(b)) for k, (a, b) in data.get("robust_interval", {}).items()} or ci
            verdicts = dict(data["identifiability"])
            per_parameter: dict[str, dict[str, Any]] = dict(
                zip(PER_PARAMETER, (se, rse, ci, rrse, rci, verdicts), strict=True)
            )
            for key, entries in per_parameter.items():
                if set(entries) != set(FIT_PARAMETERS):
                    raise MudrftError(
                        f"{where}: {key} must have one entry per parameter "
                        f"{list(FIT_PARAMETERS)}, got {list(entries)}"
                    )
            if not set(free) <= set(FIT_PARAMETERS):
                raise MudrftError(f"{where}: free must name parameters of {list(FIT_PARAMETERS)}")
            matrix = data["correlation"]["matrix"]
            corr = np.array([[np.nan if c is None else c for c in row] for row in matrix], float)
            stages = tuple(
                StageReport(**{**s, "free": tuple(s["free"]), "cost": f(s["cost"])})
                for s in data.get("stages", [])
            )
            return cls(
                parameters=params,
                free=free,
                correlation=corr.reshape(len(free), len(free)),
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
                confidence_level=float(data["confidence_level"]),
                data_warnings=tuple(str(w) for w in data.get("data_warnings", [])),
                rate=check_window(data.get("rate", "auto")),
                depth_notes=tuple(str(w) for w in data.get("depth_notes", [])),
                **per_parameter,  # type: ignore[arg-type]
            )
        except MudrftError:
            raise
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise MudrftError(
                f"{where}: not a mudrft fit file ({type(exc).__name__}: {exc})"
            ) from None

    @classmethod
    def from_json(cls, path: str | os.PathLike[str]) -> FitResult:
        """Load a result saved by :meth:`to_json` from the JSON file ``path``."""
        p = Path(os.fspath(path))
        return cls.from_dict(read_json(p), where=str(p))
