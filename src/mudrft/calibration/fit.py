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
(decision D44). See docs/model.md for the decisions D40-D49.
"""

from __future__ import annotations

import itertools
import json
import math
import os
import sys
import time as _time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._validation import MudrftError, check_choice, check_in_range
from ..io import IntrusionDataset, Trial, load_dataset
from ..metrics import relative_rmse
from ..parameters.base import PARAMETER_UNITS, MudParameters
from ..parameters.registry import paper_parameters, table_rows
from ._problem import FIT_PARAMETERS, LINEAR_PARAMETERS, PHASES, Packed

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

#: Parameter groups of the supplementary Sec. III-A, as fitted here (decision D41):
#: sigma_Y, which the paper derives from Pi_th, is fitted with the suction group because
#: the model uses the printed sigma_Y (erratum E2) and it sets the suction plateau.
GROUPS: dict[str, tuple[str, ...]] = {
    "b": ("alpha", "n"),
    "th": ("lam", "eta_m", "eta_inf", "gamma_dot_c"),
    "s": ("tau_build", "tau_leak", "epsilon", "sigma_y"),
}
_GROUP_ALIASES = {
    "b": "b", "pi_b": "b", "intrusion": "b", "elastic": "b",
    "th": "th", "pi_th": "th", "relaxation": "th", "thixotropic": "th",
    "s": "s", "pi_s": "s", "retraction": "s", "suction": "s",
}

#: Default bounds of the fitted parameters, SI (wide: two to four decades around the
#: paper's tables); ``n`` is bounded by the model's (0, 1].
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "alpha": (1.0, 1.0e8),
    "n": (0.02, 1.0),
    "lam": (0.01, 1.0e3),
    "eta_m": (1.0, 1.0e9),
    "eta_inf": (1.0e-2, 1.0e9),
    "gamma_dot_c": (1.0e-4, 1.0e2),
    "tau_build": (1.0e-3, 1.0e2),
    "tau_leak": (1.0e-3, 1.0e2),
    "epsilon": (1.0e-4, 1.0),
    "sigma_y": (1.0e-2, 1.0e8),
}

#: Relative RMSE above which a fit is flagged as not describing the data [-].
POOR_FIT_RMSE = 0.25
_POOR_FIT_HINT = ("warning: the model does not describe these data (relative RMSE above "
                  f"{100 * POOR_FIT_RMSE:g} %); check the units (stress [Pa], depth [m]), the "
                  "plate area, the characteristic length and the direction")

#: Relative standard error at or below which a parameter counts as identified (D44).
IDENTIFIED_SE = 0.05
#: Relative standard error above which a parameter counts as not identified (D44).
NOT_IDENTIFIED_SE = 0.5

# stage name -> (phases whose samples are fitted, parameters freed, grid of starting values)
# stage name -> (phases whose samples are fitted, the group's parameters, the linear
# parameters its samples also depend on (re-solved exactly in the stage), grid of starts)
_STAGES: tuple[tuple[str, tuple[int, ...], tuple[str, ...], tuple[str, ...],
                     dict[str, np.ndarray]], ...] = (
    ("intrusion", (PHASES["intrusion"],), ("alpha", "n", "eta_inf"), ("eta_m",),
     {"n": np.linspace(0.1, 1.0, 10)}),
    ("relaxation", (PHASES["intrusion"], PHASES["hold"]),
     ("lam", "eta_m", "eta_inf", "gamma_dot_c"), ("alpha",),
     {"lam": np.geomspace(0.1, 30.0, 8), "gamma_dot_c": np.geomspace(0.01, 1.0, 5)}),
    ("retraction", (PHASES["retraction"],), ("tau_build", "tau_leak", "epsilon", "sigma_y"),
     ("alpha", "eta_inf", "eta_m"),
     {"tau_build": np.geomspace(0.03, 3.0, 7), "epsilon": np.geomspace(0.003, 0.3, 5)}),
)
_ALL_PHASES = (PHASES["intrusion"], PHASES["hold"], PHASES["retraction"])
_FD_STEP = 1e-6  # forward-difference step in log-parameters


# ---------------------------------------------------------------------------------------
# result
# ---------------------------------------------------------------------------------------
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
        :math:`p\exp(\pm t_{q}\,\mathrm{se}(\ln p))`, clipped to the bounds.
    confidence_level : float
        Two-sided level of the intervals [-].
    correlation : ndarray, shape (k, k)
        Correlation matrix of the log-parameters, in the order of ``free``.
    identifiability : dict
        Verdict per parameter: ``"identified"``, ``"weak"``, ``"not identified"``
        or ``"fixed"`` (rule D44, see :func:`calibrate`).
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
    xi0 : float
        Initial structure of every trial [-].
    dataset : IntrusionDataset or None
        The data that were fitted (not saved to JSON).
    """

    parameters: MudParameters
    free: tuple[str, ...]
    standard_error: dict[str, float]
    relative_standard_error: dict[str, float]
    confidence_interval: dict[str, tuple[float, float]]
    confidence_level: float
    correlation: np.ndarray
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

    @property
    def success(self) -> bool:
        """True if the joint stage converged."""
        return self.status == "converged"

    def to_parameters(self) -> MudParameters:
        """The fitted :class:`~mudrft.MudParameters` (same as ``fit.parameters``)."""
        return self.parameters

    def identified(self) -> tuple[str, ...]:
        """Names of the parameters the data identify (verdict ``"identified"``)."""
        return tuple(k for k, v in self.identifiability.items() if v == "identified")

    def summary(self) -> str:
        """A table of the parameters with standard errors, intervals and verdicts."""
        lines = [f"mudrft fit ({self.direction}): status {self.status}, relative RMSE "
                 f"{100 * self.relative_rmse:.2f} %, noise {100 * self.noise:.2f} %"]
        if self.relative_rmse > POOR_FIT_RMSE:
            lines.append(_POOR_FIT_HINT)
        pct = round(100 * self.confidence_level)
        lines.append(f"{'parameter':<12}{'value':>12}{'unit':>6}  {'rel. SE':>9}  "
                     f"{f'{pct} % interval':>25}  verdict")
        for k in FIT_PARAMETERS:
            v = float(getattr(self.parameters, k))
            rse = self.relative_standard_error[k]
            lo, hi = self.confidence_interval[k]
            rs = "-" if k not in self.free else ("inf" if not math.isfinite(rse) else f"{rse:.3g}")
            ci = "-" if k not in self.free else f"[{lo:.4g}, {hi:.4g}]"
            lines.append(f"{k:<12}{v:>12.4g}{PARAMETER_UNITS[k]:>6}  {rs:>9}  {ci:>25}  "
                         f"{self.identifiability[k]}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return (f"FitResult(status={self.status!r}, relative_rmse={self.relative_rmse:.4g}, "
                f"identified={list(self.identified())})")

    # -- prediction and plots ---------------------------------------------------------
    def predict(self, dataset: IntrusionDataset | None = None) -> list[np.ndarray]:
        """Model stress [Pa] at the samples of each trial (default: the fitted data)."""
        ds = self.dataset if dataset is None else _as_dataset(dataset)
        if ds is None:
            raise MudrftError("predict needs a dataset: this FitResult was loaded without data")
        packed = _pack(ds, self.parameters, acceleration=self.acceleration, xi0=self.xi0)
        sim = packed.simulate(_values_of(self.parameters, batch=1))[:, 0, :]
        return [sim[: n, j].copy() for j, n in enumerate(packed.lengths)]

    def plot(self, dataset: IntrusionDataset | None = None, *, axes: Any = None) -> Any:
        """Fit against data: stress against time, one panel per trial (needs matplotlib).

        Returns the matplotlib Figure.
        """
        from ..plotting import require_matplotlib

        plt = require_matplotlib()
        ds = self.dataset if dataset is None else _as_dataset(dataset)
        if ds is None:
            raise MudrftError("plot needs a dataset: pass the data this fit was made from")
        pred = self.predict(ds)
        n = len(ds)
        if axes is None:
            fig, axes = plt.subplots(1, n, figsize=(3.6 * n + 0.6, 3.2), squeeze=False,
                                     constrained_layout=True)
        else:
            fig = np.ravel(axes)[0].figure
        axs = np.ravel(axes)
        from ._problem import PHASES, segment

        for j, (tr, yp) in enumerate(zip(ds.trials, pred, strict=True)):
            ax = axs[j]
            used = segment(tr) != PHASES["out"]
            ax.plot(tr.time[used], tr.stress[used] / 1e3, ".", ms=2.5, color="0.55",
                    label="data")
            if not used.all():
                ax.plot(tr.time[~used], tr.stress[~used] / 1e3, "x", ms=4, color="0.55",
                        label="not fitted (out of the mud)")
            ax.plot(tr.time[used], yp[used] / 1e3, "C3", lw=1.5, label="fit")
            ax.axhline(0.0, color="0.8", lw=0.6)
            ax.set_title(f"{tr.name}: {1e3 * tr.speed:.3g} mm/s", fontsize=9)
            ax.set_xlabel("time [s]")
            if j == 0:
                ax.set_ylabel("stress [kPa]")
                ax.legend(fontsize=8, loc="lower left")
        fig.suptitle(f"calibration ({self.direction}); relative RMSE "
                     f"{100 * self.relative_rmse:.2f} %", fontsize=10)
        return fig

    # -- persistence --------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (SI values with the field names of :class:`~mudrft.MudParameters`)."""

        def num(x: float) -> float | None:
            return float(x) if math.isfinite(float(x)) else None

        corr = [[num(c) for c in row] for row in np.asarray(self.correlation, dtype=float)]
        return {
            "format": "mudrft-fit",
            "version": 1,
            "direction": self.direction,
            "parameters": self.parameters.as_dict(),
            "units": dict(PARAMETER_UNITS),
            "free": list(self.free),
            "standard_error": {k: num(v) for k, v in self.standard_error.items()},
            "relative_standard_error": {k: num(v) for k, v in self.relative_standard_error.items()},
            "confidence_interval": {k: [num(a), num(b)] for k, (a, b) in
                                    self.confidence_interval.items()},
            "confidence_level": self.confidence_level,
            "correlation": {"parameters": list(self.free), "matrix": corr},
            "identifiability": dict(self.identifiability),
            "identifiability_rule": (f"identified: relative SE <= {IDENTIFIED_SE}; weak: <= "
                                     f"{NOT_IDENTIFIED_SE}; not identified: larger, infinite "
                                     "(Jacobian rank-deficient) or at a bound"),
            "relative_rmse": self.relative_rmse,
            "trial_relative_rmse": list(self.trial_relative_rmse),
            "noise": self.noise,
            "status": self.status,
            "message": self.message,
            "condition_number": num(self.condition_number),
            "acceleration": self.acceleration,
            "xi0": self.xi0,
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "stages": [{"name": s.name, "free": list(s.free), "simulations": s.simulations,
                        "cost": s.cost, "seconds": s.seconds, "message": s.message}
                       for s in self.stages],
            "trace": [dict(t) for t in self.trace],
            "data": None if self.dataset is None else {
                "source": self.dataset.source, "trials": [t.name for t in self.dataset.trials],
                "synthetic": self.dataset.synthetic},
        }

    def to_json(self, path: str | os.PathLike, *, overwrite: bool = False) -> Path:
        """Save to JSON; never replaces an existing file unless ``overwrite=True``.

        Parameters
        ----------
        path : str or path-like
            Output file.
        overwrite : bool, keyword-only
            Replace an existing file.
        """
        p = Path(os.fspath(path))
        text = json.dumps(self.to_dict(), indent=1, allow_nan=False)
        try:
            with open(p, "w" if overwrite else "x", encoding="utf-8") as fh:
                fh.write(text + "\n")
        except FileExistsError as exc:
            raise MudrftError(f"{p}: file exists; pass overwrite=True (CLI: --overwrite) to "
                              "replace it") from exc
        except OSError as exc:
            raise MudrftError(f"{p}: cannot be written ({exc.strerror or exc})") from exc
        return p

    @classmethod
    def from_dict(cls, data: dict[str, Any], *, where: str = "fit") -> FitResult:
        """Rebuild a result from :meth:`to_dict` output (without the dataset)."""
        try:
            params = _parameters_from_json(data, where=where)
            free = tuple(data["free"])

            def f(x: Any) -> float:
                return float("inf") if x is None else float(x)

            se = {k: f(v) for k, v in data["standard_error"].items()}
            rse = {k: f(v) for k, v in data["relative_standard_error"].items()}
            ci = {k: (f(a), f(b)) for k, (a, b) in data["confidence_interval"].items()}
            corr = np.array([[np.nan if c is None else c for c in row]
                             for row in data["correlation"]["matrix"]], dtype=float)
            stages = tuple(StageReport(name=s["name"], free=tuple(s["free"]),
                                       simulations=int(s["simulations"]), cost=float(s["cost"]),
                                       seconds=float(s["seconds"]), message=s.get("message", ""))
                           for s in data.get("stages", []))
            return cls(
                parameters=params, free=free, standard_error=se, relative_standard_error=rse,
                confidence_interval=ci, confidence_level=float(data["confidence_level"]),
                correlation=corr.reshape(len(free), len(free)),
                identifiability=dict(data["identifiability"]),
                relative_rmse=float(data["relative_rmse"]),
                trial_relative_rmse=tuple(float(x) for x in data["trial_relative_rmse"]),
                noise=float(data["noise"]), status=str(data["status"]),
                message=str(data.get("message", "")), stages=stages,
                trace=tuple(data.get("trace", [])), direction=str(data["direction"]),
                bounds={k: (float(a), float(b)) for k, (a, b) in data.get("bounds", {}).items()},
                condition_number=f(data.get("condition_number")),
                acceleration=bool(data.get("acceleration", True)),
                xi0=float(data.get("xi0", 0.0)),
            )
        except MudrftError:
            raise
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise MudrftError(
                f"{where}: not a mudrft fit file ({type(exc).__name__}: {exc})") from None

    @classmethod
    def from_json(cls, path: str | os.PathLike) -> FitResult:
        """Load a result saved by :meth:`to_json`."""
        p = Path(os.fspath(path))
        return cls.from_dict(_read_json(p), where=str(p))


def _read_json(p: Path) -> dict[str, Any]:
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError as exc:
        raise MudrftError(f"{p}: no such file") from exc
    except (OSError, UnicodeDecodeError) as exc:
        raise MudrftError(f"{p}: cannot be read ({exc})") from exc
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise MudrftError(f"{p}: line {exc.lineno}, column {exc.colno}: invalid JSON ({exc.msg})") \
            from None
    if not isinstance(data, dict):
        raise MudrftError(f"{p}: expected a JSON object, got {type(data).__name__}")
    return data


def _parameters_from_json(data: dict[str, Any], *, where: str) -> MudParameters:
    fields = data.get("parameters", data)
    if not isinstance(fields, dict):
        raise MudrftError(f"{where}: 'parameters' must be an object of SI values")
    fields = {k: v for k, v in fields.items() if k in PARAMETER_UNITS}
    direction = data.get("direction", "")
    if direction not in ("", "vertical", "horizontal"):
        raise MudrftError(
            f"{where}: direction must be 'vertical' or 'horizontal', got {direction!r}")
    try:
        return MudParameters.from_dict(fields, source=f"fit: {where}", direction=direction)
    except MudrftError as exc:
        raise MudrftError(f"{where}: {exc}") from None
    except TypeError as exc:
        raise MudrftError(f"{where}: bad parameter values ({exc})") from None


def load_parameters(path: str | os.PathLike) -> MudParameters:
    """Read a parameter set from a fit JSON (:meth:`FitResult.to_json`) or a plain JSON object.

    A plain object holds the SI fields of :class:`~mudrft.MudParameters`
    (``alpha``, ``n``, ``lam``, ...; ``nu`` and ``k_a`` optional).

    Parameters
    ----------
    path : str or path-like
        The JSON file.

    Returns
    -------
    MudParameters
    """
    p = Path(os.fspath(path))
    return _parameters_from_json(_read_json(p), where=str(p))


# ---------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------
def _as_dataset(data: Any, **load_options: Any) -> IntrusionDataset:
    if isinstance(data, IntrusionDataset):
        return data
    if isinstance(data, Trial):
        return IntrusionDataset((data,))
    if isinstance(data, (str, os.PathLike)):
        return load_dataset(data, **load_options)
    if isinstance(data, Sequence) and data and all(isinstance(d, IntrusionDataset) for d in data):
        return data[0].merge(*data[1:])
    if isinstance(data, Sequence) and data and all(isinstance(d, Trial) for d in data):
        return IntrusionDataset(tuple(data))
    if isinstance(data, Sequence) and data and all(isinstance(d, (str, os.PathLike)) for d in data):
        return load_dataset(list(data), **load_options)
    raise MudrftError("dataset must be an IntrusionDataset, a Trial, a path or a list of them, "
                      f"got {type(data).__name__}")


def _decimate(ds: IntrusionDataset, k: int) -> IntrusionDataset:
    trials = []
    for tr in ds.trials:
        n = len(tr)
        keep = np.unique(np.r_[np.arange(0, n, k), int(np.argmax(np.abs(tr.depth))), n - 1])
        trials.append(Trial(tr.time[keep], tr.depth[keep], tr.stress[keep], name=tr.name,
                            characteristic_length=tr.characteristic_length,
                            meta={**tr.meta, "decimated": k}))
    return IntrusionDataset(tuple(trials), direction=ds.direction, source=ds.source,
                            notes=ds.notes, meta=dict(ds.meta))


def _values_of(p: MudParameters, *, batch: int) -> dict[str, np.ndarray]:
    return {k: np.full(batch, float(getattr(p, k))) for k in FIT_PARAMETERS}


def _pack(ds: IntrusionDataset, p: MudParameters, *, acceleration: bool, xi0: float) -> Packed:
    tied = bool(np.isclose(float(p.k_a), 1.0 / float(p.lam)))
    return Packed.from_dataset(ds, nu=float(p.nu), k_a=None if tied else float(p.k_a),
                               acceleration=acceleration, xi0=xi0)


def _resolve_groups(groups: Any) -> tuple[str, ...]:
    if groups is None or groups == "all":
        names: Iterable[str] = ("b", "th", "s")
    elif isinstance(groups, str):
        names = [g for g in groups.replace(",", " ").split() if g]
    else:
        names = list(groups)
    free: list[str] = []
    for g in names:
        if not isinstance(g, str):
            raise MudrftError(f"groups must be names, got {g!r}")
        key = g.strip().lower()
        if key == "all":
            free.extend(FIT_PARAMETERS)
        elif key in _GROUP_ALIASES:
            free.extend(GROUPS[_GROUP_ALIASES[key]])
        elif key in FIT_PARAMETERS:
            free.append(key)
        else:
            raise MudrftError(
                f"groups must name parameter groups ('b', 'th', 's', 'all') or parameters "
                f"{list(FIT_PARAMETERS)}, got {g!r}")
    if not free:
        raise MudrftError("groups selects no parameter to fit")
    return tuple(k for k in FIT_PARAMETERS if k in free)


def _resolve_bounds(
    bounds: dict[str, tuple[float, float]] | None,
) -> dict[str, tuple[float, float]]:
    out = dict(DEFAULT_BOUNDS)
    for k, v in (bounds or {}).items():
        if k not in FIT_PARAMETERS:
            raise MudrftError(
                f"bounds has an unknown parameter {k!r}; expected {list(FIT_PARAMETERS)}")
        try:
            lo, hi = (float(v[0]), float(v[1]))
        except (TypeError, ValueError, IndexError):
            raise MudrftError(f"bounds[{k!r}] must be a pair (low, high), got {v!r}") from None
        if not (0 < lo < hi < math.inf):
            raise MudrftError(f"bounds[{k!r}] must satisfy 0 < low < high < inf, got {v!r}")
        if k == "n" and hi > 1.0:
            raise MudrftError(f"bounds['n'] must not exceed 1 (the model needs n <= 1), got {v!r}")
        out[k] = (lo, hi)
    return out


class _Progress:
    def __init__(self, progress: Any) -> None:
        if progress is True:
            self.fn: Callable[[str], None] | None = lambda s: print(s, file=sys.stderr, flush=True)
        elif progress in (None, False):
            self.fn = None
        elif callable(progress):
            self.fn = progress
        else:
            raise MudrftError(f"progress must be True, False, None or a callable, got {progress!r}")

    def __call__(self, msg: str) -> None:
        if self.fn is not None:
            self.fn(msg)


class _Engine:
    """Bookkeeping of one calibration: current values, bounds, trace, evaluation count."""

    def __init__(self, packed: Packed, values: dict[str, float],
                 bounds: dict[str, tuple[float, float]],
                 trace_limit: int) -> None:
        self.packed = packed
        self.values = dict(values)
        self.bounds = bounds
        self.trace: list[dict] = []
        self.trace_limit = trace_limit
        self.evaluations = 0
        self._cache: tuple[bytes, np.ndarray, np.ndarray] | None = None

    # a batch of parameter dicts from a base and per-column overrides
    def batch(self, overrides: dict[str, np.ndarray], size: int) -> dict[str, np.ndarray]:
        out = {k: np.full(size, v) for k, v in self.values.items()}
        for k, arr in overrides.items():
            out[k] = np.broadcast_to(np.asarray(arr, dtype=float), (size,)).copy()
        return out

    def clip(self, name: str, v: float) -> float:
        lo, hi = self.bounds[name]
        return float(min(max(v, lo), hi))

    def record(self, stage: str, cost: float, values: dict[str, float]) -> None:
        self.evaluations += 1
        if len(self.trace) < self.trace_limit:
            self.trace.append({"stage": stage, "evaluation": self.evaluations, "cost": float(cost),
                               "parameters": {k: float(v) for k, v in values.items()}})

    # ---- variable projection ----------------------------------------------------------
    def project(self, R: np.ndarray, lin: list[str]) -> tuple[np.ndarray, list[float]]:
        """Solve the linear parameters exactly from a basis simulation.

        ``R`` (m, 1 + nl) holds the weighted residuals with every parameter of ``lin`` set
        to 1 (column 0) and with parameter j set to 2 (column 1 + j). The model is linear
        in each of them, so column differences are their basis functions. Returns the
        residuals at the non-negative least-squares solution (clipped to the bounds) and
        the solution.
        """
        from scipy.optimize import nnls

        if not lin:
            return R[:, 0], []
        E = R[:, 1:] - R[:, :1]  # weighted basis of each linear parameter
        rest = R[:, 0] - E.sum(axis=1)  # weighted (everything else - data)
        scale = np.linalg.norm(E, axis=0)
        scale[~(scale > 0)] = 1.0
        try:
            coef, _ = nnls(E / scale, -rest, maxiter=50 * E.shape[1])
        except RuntimeError:  # pragma: no cover - nnls iteration limit
            coef = np.zeros(E.shape[1])
        c = [self.clip(k, float(v)) for k, v in zip(lin, coef / scale, strict=True)]
        return rest + E @ np.asarray(c), c

    def grid_start(self, stage: str, mask: np.ndarray, free: tuple[str, ...],
                   candidates: list[dict[str, float]], starts: int
                   ) -> list[tuple[float, dict[str, float]]]:
        """Score candidate points, the linear free parameters of each solved exactly.

        Every candidate fixes some parameters (the others keep their current values);
        the free parameters the model is linear in are then set by non-negative least
        squares (variable projection). All candidates run in one batched simulation.
        Returns the ``starts`` best ``(cost, point)`` pairs.
        """
        lin = [k for k in free if k in LINEAR_PARAMETERS]
        cands = candidates or [{}]
        G, nl = len(cands), len(lin)
        over = {k: np.array([c.get(k, self.values[k]) for c in cands])
                for k in {k for c in cands for k in c}}
        upto = self.packed.upto(mask)
        sim = self.packed.simulate(self._basis(self.batch(over, G), lin), upto)
        res = self.packed.residuals(sim, mask).reshape(-1, G, 1 + nl)  # (m, G, 1+nl)
        scored = []
        for g in range(G):
            if not np.all(np.isfinite(res[:, g, :])):
                continue
            point = {k: float(v) for k, v in cands[g].items()}
            r, coef = self.project(res[:, g, :], lin)
            point.update(zip(lin, coef, strict=True))
            cost = 0.5 * float(r @ r)
            scored.append((cost, point))
            self.record(stage + " grid", cost, {**self.values, **point})
        if not scored:
            return [(math.inf, {})]
        scored.sort(key=lambda t: t[0])
        return scored[: max(1, starts)]

    # ---- least squares in log-parameters --------------------------------------------
    def fit(self, stage: str, mask: np.ndarray, free: tuple[str, ...], max_nfev: int,
            start: dict[str, float] | None = None, project: tuple[str, ...] = ()
            ) -> tuple[float, Any]:
        """Bounded least squares over ``free`` in log-parameters (trust-region reflective).

        With ``project``, those linear parameters are not solver variables: each
        evaluation solves them exactly (variable projection), which removes the
        valleys along which a linear and a nonlinear parameter trade off.
        """
        from scipy.optimize import least_squares

        base = dict(self.values)
        if start:
            base.update(start)
        lin = [k for k in project if k in LINEAR_PARAMETERS]
        names = [k for k in free if k not in lin]
        nl = len(lin)
        upto = self.packed.upto(mask)
        if not names:  # only linear parameters: one projection solves them
            self.values.update(base)
            sim = self.packed.simulate(self._basis(self.batch({}, 1), lin), upto)
            R = self.packed.residuals(sim, mask).reshape(-1, 1, 1 + nl)
            r, c = self.project(R[:, 0, :], lin)
            self.values.update(zip(lin, c, strict=True))
            self.record(stage, 0.5 * float(r @ r), self.values)
            return 0.5 * float(r @ r), None
        lo = np.log([self.bounds[k][0] for k in names])
        hi = np.log([self.bounds[k][1] for k in names])
        x0 = np.clip(np.log([base[k] for k in names]), lo, hi)
        x0 = np.minimum(np.maximum(x0, lo + 1e-12), hi - 1e-12)
        n_free = len(names)
        linear_at: dict[bytes, list[float]] = {}

        def values_at(X: np.ndarray) -> dict[str, np.ndarray]:
            B = X.shape[0]
            out = {k: np.full(B, base[k]) for k in FIT_PARAMETERS}
            for i, k in enumerate(names):
                out[k] = np.exp(X[:, i])
            return out

        def evaluate(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            # residuals and forward-difference Jacobian in one batched simulation: a batch
            # of 1 + k parameter sets costs about as much as one (the time loop dominates)
            key = x.tobytes()
            if self._cache is not None and self._cache[0] == key:
                return self._cache[1], self._cache[2]
            X = np.repeat(x[None, :], 1 + n_free, axis=0)
            h = np.where(x + _FD_STEP > hi, -_FD_STEP, _FD_STEP)  # step inward at a bound
            X[1 + np.arange(n_free), np.arange(n_free)] += h
            sim = self.packed.simulate(self._basis(values_at(X), lin), upto)
            R = self.packed.residuals(sim, mask).reshape(-1, 1 + n_free, 1 + nl)
            cols = [self.project(R[:, i, :], lin) for i in range(1 + n_free)]
            r = cols[0][0]
            if not np.all(np.isfinite(r)):
                r = np.full_like(r, 1e6)
            J = np.stack([c[0] for c in cols[1:]], axis=1)
            J = (J - r[:, None]) / h[None, :]
            J[~np.isfinite(J)] = 0.0
            self._cache = (key, r, J)
            linear_at[key] = cols[0][1]
            point = {k: float(v[0]) for k, v in values_at(x[None, :]).items()}
            point.update(zip(lin, cols[0][1], strict=True))
            self.record(stage, 0.5 * float(r @ r), point)
            return r, J

        def fun(x: np.ndarray) -> np.ndarray:
            return evaluate(x)[0]

        def jac(x: np.ndarray) -> np.ndarray:
            return evaluate(x)[1]

        self._cache = None
        sol = least_squares(fun, x0, jac=jac, bounds=(lo, hi), method="trf", x_scale=1.0,
                            max_nfev=max_nfev, xtol=1e-10, ftol=1e-10, gtol=1e-10)
        self.values.update(base)
        for i, k in enumerate(names):
            self.values[k] = float(np.exp(sol.x[i]))
        if lin:
            if sol.x.tobytes() not in linear_at:
                evaluate(sol.x)
            self.values.update(zip(lin, linear_at[sol.x.tobytes()], strict=True))
        self._cache = None
        return float(sol.cost), sol

    def _basis(self, vals: dict[str, np.ndarray], lin: list[str]) -> dict[str, np.ndarray]:
        """Expand each column of ``vals`` into 1 + len(lin) columns for :meth:`project`."""
        nl = len(lin)
        if not nl:
            return vals
        P = int(np.asarray(vals["alpha"]).size)
        out = {k: np.repeat(np.asarray(v, dtype=float), 1 + nl) for k, v in vals.items()}
        for j, k in enumerate(lin):
            v = np.ones((P, 1 + nl))
            v[:, 1 + j] = 2.0
            out[k] = v.ravel()
        return out

    def cost(self, mask: np.ndarray) -> float:
        sim = self.packed.simulate(self.batch({}, 1), self.packed.upto(mask))
        r = self.packed.residuals(sim, mask)[:, 0]
        return 0.5 * float(r @ r)

    def jacobian(self, mask: np.ndarray, free: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
        """Residuals and Jacobian in log-parameters at the current values: central
        differences, shifted inside the bounds for a parameter that sits on one."""
        names = list(free)
        k = len(names)
        h = 1e-4
        over = {}
        lo_s, hi_s = np.zeros(k), np.zeros(k)
        for i, name in enumerate(names):
            x = math.log(self.values[name])
            lo_b, hi_b = (math.log(b) for b in self.bounds[name])
            a, b = x - h, x + h
            if b > hi_b:
                a, b = hi_b - 2 * h, hi_b
            elif a < lo_b:
                a, b = lo_b, lo_b + 2 * h
            lo_s[i], hi_s[i] = a, b
            col = np.full(1 + 2 * k, self.values[name])
            col[1 + 2 * i] = math.exp(b)
            col[2 + 2 * i] = math.exp(a)
            over[name] = col
        sim = self.packed.simulate(self.batch(over, 1 + 2 * k))
        R = self.packed.residuals(sim, mask)
        J = (R[:, 1::2] - R[:, 2::2]) / (hi_s - lo_s)[None, :]
        return R[:, 0], J


def _message(sol: Any) -> str:
    return "linear parameters solved exactly" if sol is None else str(sol.message)


def _status(sol: Any) -> str:
    if sol is None:
        return "converged"
    if sol.status > 0:
        return "converged"
    if sol.status == 0:
        return "max_evaluations"
    return "failed"


def _start_parameters(
    engine: _Engine, direction: str, progress: _Progress,
) -> tuple[dict[str, float], float, float]:
    """The paper row (of the data's direction) that fits best after its linear parameters
    are rescaled by non-negative least squares; all rows in one batched simulation
    (decision D43). Returns the values, the row's water content and the cost."""
    rows = table_rows(direction)
    ws = sorted(rows)
    cands = [{k: float(rows[w][k]) for k in FIT_PARAMETERS} for w in ws]
    mask = engine.packed.mask(_ALL_PHASES)
    scored = engine.grid_start("start", mask, LINEAR_PARAMETERS, cands, len(cands))
    cost, point = scored[0]
    w = next(w for w, c in zip(ws, cands, strict=True)
             if all(c[k] == point[k] for k in FIT_PARAMETERS if k not in LINEAR_PARAMETERS))
    progress(f"calibrate: start from the paper's {direction} row W = {100 * w:g} % "
             f"(linear parameters rescaled), cost {cost:.4g}")
    return point, w, cost


# ---------------------------------------------------------------------------------------
# the fit
# ---------------------------------------------------------------------------------------
def calibrate(
    dataset: Any,
    direction: str | None = None,
    *,
    groups: Any = "all",
    initial: MudParameters | None = None,
    fixed: dict[str, float] | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    phases: bool = True,
    starts: int = 1,
    max_nfev: int = 200,
    confidence_level: float = 0.95,
    acceleration: bool = True,
    xi0: float = 0.0,
    progress: Any = None,
    area: float | None = None,
    characteristic_length: float | None = None,
    trace_limit: int = 2000,
    decimate: int = 1,
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
        the direction that best matches the data after rescaling its linear parameters
        (decision D43).
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
    acceleration : bool, keyword-only
        Keep the acceleration term of :math:`f_\xi` (decision D6).
    xi0 : float, keyword-only
        Initial structure of the mud in every trial [-] (decision D3: 0).
    progress : bool or callable, keyword-only
        ``True`` prints one line per stage to stderr; a callable receives each line.
    area, characteristic_length : float, optional, keyword-only
        Plate area [m^2] and length [m] when ``dataset`` is a path to load.
    trace_limit : int, keyword-only
        Most evaluations kept in ``trace``.
    decimate : int, keyword-only
        Keep every ``decimate``-th sample of each trial (and its deepest and last
        samples) before fitting. The fit time grows with the samples per trial; logs at
        1 kHz fit in seconds at ``decimate=10`` (the model step is exact between samples,
        so thinning loses data, not accuracy of the model).

    Returns
    -------
    FitResult
        Parameters, standard errors, confidence intervals, correlation, verdicts, RMSE,
        status and trace. ``fit.parameters`` is a :class:`~mudrft.MudParameters`.

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
    t_start = _time.perf_counter()
    prog = _Progress(progress)
    ds = _as_dataset(dataset, area=area, characteristic_length=characteristic_length)
    if isinstance(decimate, bool) or not isinstance(decimate, (int, np.integer)) or decimate < 1:
        raise MudrftError(f"decimate must be an integer >= 1, got {decimate!r}")
    if decimate > 1:
        ds = _decimate(ds, int(decimate))
    d = ds.direction if direction is None else check_choice("direction", direction,
                                                             ("vertical", "horizontal"))
    check_in_range("confidence_level", confidence_level, 1e-6, 1 - 1e-9)
    if isinstance(starts, bool) or not isinstance(starts, (int, np.integer)) or starts < 1:
        raise MudrftError(f"starts must be an integer >= 1, got {starts!r}")
    if isinstance(max_nfev, bool) or not isinstance(max_nfev, (int, np.integer)) or max_nfev < 1:
        raise MudrftError(f"max_nfev must be an integer >= 1, got {max_nfev!r}")
    if initial is not None and not isinstance(initial, MudParameters):
        raise MudrftError(f"initial must be a MudParameters, got {type(initial).__name__}")
    if initial is not None and initial.shape != ():
        raise MudrftError(f"initial must be a single parameter set, got a batch of shape "
                          f"{initial.shape}")
    free = _resolve_groups(groups)
    bnds = _resolve_bounds(bounds)
    fixed = dict(fixed or {})
    for k in fixed:
        if k not in FIT_PARAMETERS:
            raise MudrftError(
                f"fixed has an unknown parameter {k!r}; expected {list(FIT_PARAMETERS)}")
    free = tuple(k for k in free if k not in fixed)
    if not free:
        raise MudrftError("every parameter is fixed: nothing to fit")
    n_samples = sum(len(t) for t in ds.trials)
    prog(f"calibrate: {len(ds)} trial(s), {n_samples} samples, direction {d}, "
         f"free {list(free)}")

    # -- starting values -----------------------------------------------------------------
    t0 = _time.perf_counter()
    base = initial if initial is not None else paper_parameters(0.25, d)
    try:
        packed = _pack(ds, base, acceleration=acceleration, xi0=xi0)
    except MudrftError as exc:
        raise MudrftError(f"{ds.source}: {exc}" if ds.source else str(exc)) from None
    values = {k: float(getattr(base, k)) for k in FIT_PARAMETERS}
    eng = _Engine(packed, values, bnds, trace_limit)
    if initial is None:
        point, _, _ = _start_parameters(eng, d, prog)
        eng.values.update(point)
    for k, v in fixed.items():
        eng.values[k] = float(v)
    for k in free:
        eng.values[k] = eng.clip(k, eng.values[k])
    # validate the starting set (with the fixed values) once
    try:
        packed.parameters({k: np.array([v]) for k, v in eng.values.items()})
    except MudrftError as exc:
        raise MudrftError(f"invalid starting or fixed parameter values: {exc}") from None
    all_mask = packed.mask(_ALL_PHASES)
    stages = [StageReport("start", (), packed.simulations, eng.cost(all_mask),
                          _time.perf_counter() - t0, "paper row" if initial is None else "initial")]

    # -- phase stages --------------------------------------------------------------------
    if phases:
        for name, ph, stage_params, also_linear, grid in _STAGES:
            if not any(k in free for k in stage_params):
                continue  # none of the stage's own group is fitted
            stage_free = tuple(k for k in FIT_PARAMETERS
                               if k in free and (k in stage_params or k in also_linear))
            mask = packed.mask(ph)
            if not mask.any():
                continue
            t0 = _time.perf_counter()
            n0 = packed.simulations
            saved = dict(eng.values)
            best: tuple[float, dict[str, float], Any] | None = None
            axes = {k: np.unique(np.append(np.clip(v, *bnds[k]), eng.values[k]))
                    for k, v in grid.items() if k in stage_free}
            cands = [dict(zip(axes, combo, strict=True))
                     for combo in itertools.product(*axes.values())]
            for _, pt in eng.grid_start(name, mask, stage_free, cands, starts):
                eng.values = dict(saved)
                c, sol = eng.fit(name, mask, stage_free, max_nfev, start=pt,
                                 project=stage_free)
                if best is None or c < best[0]:
                    best = (c, dict(eng.values), sol)
            assert best is not None
            eng.values = best[1]
            stages.append(StageReport(name, stage_free, packed.simulations - n0, best[0],
                                      _time.perf_counter() - t0, _message(best[2])))
            prog(f"calibrate: stage {name:<10} free {list(stage_free)}: cost {best[0]:.4g}, "
                 f"{packed.simulations - n0} simulations, {_time.perf_counter() - t0:.2f} s")

    # -- joint stage ---------------------------------------------------------------------
    t0 = _time.perf_counter()
    n0 = packed.simulations
    cost, sol = eng.fit("joint", all_mask, free, max_nfev, project=free)
    # polish with every free parameter a solver variable (same optimum; it checks that
    # the projected solution is a stationary point of the full problem)
    cost, sol_full = eng.fit("joint", all_mask, free, max_nfev)
    sol = sol_full if sol_full is not None else sol
    status = _status(sol)
    stages.append(StageReport("joint", free, packed.simulations - n0, cost,
                              _time.perf_counter() - t0, sol.message))
    prog(f"calibrate: stage {'joint':<10} free {list(free)}: cost {cost:.4g}, "
         f"{packed.simulations - n0} simulations, {_time.perf_counter() - t0:.2f} s ({status})")

    # -- uncertainty ---------------------------------------------------------------------
    r, J = eng.jacobian(all_mask, free)
    at_bound = {}
    for k in free:
        lo, hi = bnds[k]
        v = eng.values[k]
        at_bound[k] = bool(math.log(v) - math.log(lo) < 1e-3 or math.log(hi) - math.log(v) < 1e-3)
    unc = _uncertainty(r, J, free, at_bound, confidence_level, eng.values, bnds)

    params = MudParameters(**{k: eng.values[k] for k in FIT_PARAMETERS}, nu=packed.nu,
                           k_a=packed.k_a, direction=d,
                           source=f"fit: {ds.source or 'data'} ({len(ds)} trials)")
    # relative RMSE of each trial over its fitted samples (decision D12)
    sim = packed.simulate(_values_of(params, batch=1))[:, 0, :]
    trmse = []
    for j, n in enumerate(packed.lengths):
        m = packed.valid[:n, j]
        trmse.append(relative_rmse(sim[:n, j][m], packed.data[:n, j][m]))
    if float(np.mean(trmse)) > POOR_FIT_RMSE:
        prog(f"calibrate: {_POOR_FIT_HINT}")
    prog(f"calibrate: done in {_time.perf_counter() - t_start:.2f} s, relative RMSE "
         f"{100 * float(np.mean(trmse)):.2f} %, identified "
         f"{[k for k in free if unc['verdict'][k] == 'identified']}")
    return FitResult(
        parameters=params, free=free, standard_error=unc["se"],
        relative_standard_error=unc["rse"], confidence_interval=unc["ci"],
        confidence_level=float(confidence_level), correlation=unc["corr"],
        identifiability=unc["verdict"], relative_rmse=float(np.mean(trmse)),
        trial_relative_rmse=tuple(float(x) for x in trmse), noise=unc["noise"], status=status,
        message=str(sol.message), stages=tuple(stages), trace=tuple(eng.trace), direction=d,
        bounds={k: bnds[k] for k in free}, condition_number=unc["cond"],
        acceleration=bool(acceleration), xi0=float(xi0), dataset=ds,
    )


def _uncertainty(
    r: np.ndarray, J: np.ndarray, free: tuple[str, ...], at_bound: dict[str, bool],
    level: float, values: dict[str, float], bounds: dict[str, tuple[float, float]],
) -> dict[str, Any]:
    from scipy.stats import t as student_t

    m, k = J.shape
    dof = max(m - k, 1)
    s2 = float(r @ r) / dof
    F = J.T @ J
    d = np.sqrt(np.diag(F))
    d_safe = np.where(d > 0, d, 1.0)
    C = F / np.outer(d_safe, d_safe)
    w, V = np.linalg.eigh(C)
    wmax = float(w.max()) if w.size else 0.0
    keep = w > 1e-10 * wmax if wmax > 0 else np.zeros_like(w, dtype=bool)
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
    q = float(student_t.ppf(0.5 + level / 2.0, dof))
    cond = float(math.sqrt(wmax / w.min())) if w.size and w.min() > 0 else math.inf
    se, rse, ci, verdict = {}, {}, {}, {}
    for name in FIT_PARAMETERS:
        v = values[name]
        if name not in free:
            se[name], rse[name], ci[name], verdict[name] = 0.0, 0.0, (v, v), "fixed"
            continue
        i = free.index(name)
        e = float(se_log[i])
        rse[name] = e
        se[name] = v * e if math.isfinite(e) else math.inf
        lo_b, hi_b = bounds[name]
        if math.isfinite(e):
            lo = max(v * math.exp(-min(q * e, 700.0)), lo_b)
            hi = min(v * math.exp(min(q * e, 700.0)), hi_b)
        else:
            lo, hi = lo_b, hi_b
        ci[name] = (lo, hi)
        if at_bound[name] or not math.isfinite(e) or e > NOT_IDENTIFIED_SE:
            verdict[name] = "not identified"
        elif e <= IDENTIFIED_SE:
            verdict[name] = "identified"
        else:
            verdict[name] = "weak"
    return {"se": se, "rse": rse, "ci": ci, "verdict": verdict, "corr": corr,
            "noise": math.sqrt(s2), "cond": cond}
