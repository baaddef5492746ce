r"""The solver of a calibration (internal) and its stages: start, one stage per phase
group and joint (decisions D41, D43). Bounded least squares in log-parameters, the
parameters the model is linear in (:math:`\alpha,\eta_\infty,\eta_m,\sigma_Y`) solved
exactly by non-negative least squares (variable projection)."""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..parameters.registry import table_rows
from ._problem import ALL_PHASES, FIT_PARAMETERS, LINEAR_PARAMETERS, PHASES, Packed, basis

if TYPE_CHECKING:
    from scipy.optimize import OptimizeResult

_FD_STEP = 1e-6  # forward-difference step in log-parameters

Values = dict[str, NDArray[np.float64]]


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
        Batched simulations of all trials run in the stage.
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


@dataclass
class Engine:
    """One calibration: the packed data, current values and bounds of every parameter
    [SI], the trace (at most ``trace_limit`` evaluations) and the evaluation count."""

    packed: Packed
    values: dict[str, float]
    bounds: dict[str, tuple[float, float]]
    trace_limit: int
    trace: list[dict[str, Any]] = field(default_factory=list)
    evaluations: int = 0

    def batch(self, overrides: dict[str, NDArray[np.float64]], size: int) -> Values:
        """A batch of ``size`` parameter sets: the current values, with per-column overrides."""
        out = {k: np.full(size, v) for k, v in self.values.items()}
        for k, arr in overrides.items():
            out[k] = np.broadcast_to(np.asarray(arr, dtype=float), (size,)).copy()
        return out

    def clip(self, name: str, v: float) -> float:
        """``v`` [SI] clipped to the bounds of ``name``."""
        lo, hi = self.bounds[name]
        return float(min(max(v, lo), hi))

    def record(self, stage: str, cost: float, values: dict[str, float]) -> None:
        """Count one evaluation and keep it in the trace (up to ``trace_limit``)."""
        self.evaluations += 1
        if len(self.trace) < self.trace_limit:
            point = {k: float(v) for k, v in values.items()}
            entry = {"stage": stage, "evaluation": self.evaluations, "cost": float(cost)}
            self.trace.append({**entry, "parameters": point})

    def project(
        self, R: NDArray[np.float64], lin: list[str], keep: dict[str, float] | None = None
    ) -> tuple[NDArray[np.float64], list[float]]:
        """Residuals at the exact (non-negative, clipped) solution of the linear ``lin``,
        and the solution, from ``R`` (m, 1 + nl): residuals with every one of them 1
        (column 0) and with parameter j at 2 (column 1 + j). One the samples do not depend
        on keeps its value in ``keep`` (default the current values)."""
        from scipy.optimize import nnls

        if not lin:
            return R[:, 0], []
        E = R[:, 1:] - R[:, :1]  # weighted basis of each linear parameter
        rest = R[:, 0] - E.sum(axis=1)  # weighted (everything else - data)
        scale = np.linalg.norm(E, axis=0)
        seen = scale > 0
        scale[~seen] = 1.0
        try:
            coef, _ = nnls(E / scale, -rest, maxiter=50 * E.shape[1])
        except RuntimeError:  # pragma: no cover - nnls iteration limit
            coef = np.zeros(E.shape[1])
        held = self.values if keep is None else keep
        c = [
            self.clip(k, float(v)) if s else float(held[k])
            for k, v, s in zip(lin, coef / scale, seen, strict=True)
        ]
        return rest + E @ np.asarray(c), c

    def grid_start(
        self,
        stage: str,
        mask: NDArray[np.bool_],
        free: tuple[str, ...],
        candidates: list[dict[str, float]],
        starts: int,
    ) -> list[tuple[float, dict[str, float]]]:
        """The ``starts`` best ``(cost, point)`` of the candidate points, the linear free
        parameters of each solved exactly; all in one batched simulation."""
        lin = [k for k in free if k in LINEAR_PARAMETERS]
        G, nl = len(candidates), len(lin)
        over = {
            k: np.array([c.get(k, self.values[k]) for c in candidates])
            for k in {k for c in candidates for k in c}
        }
        res = self.packed.residuals(basis(self.batch(over, G), lin), mask).reshape(-1, G, 1 + nl)
        scored = []
        for g in range(G):
            if not np.all(np.isfinite(res[:, g, :])):
                continue
            point = {k: float(v) for k, v in candidates[g].items()}
            r, coef = self.project(res[:, g, :], lin, {**self.values, **candidates[g]})
            point.update(zip(lin, coef, strict=True))
            cost = 0.5 * float(r @ r)
            scored.append((cost, point))
            self.record(stage + " grid", cost, {**self.values, **point})
        return sorted(scored, key=lambda t: t[0])[:starts] or [(math.inf, {})]

    def fit(
        self,
        stage: str,
        mask: NDArray[np.bool_],
        free: tuple[str, ...],
        max_nfev: int,
        start: dict[str, float] | None = None,
        project: tuple[str, ...] = (),
    ) -> tuple[float, OptimizeResult | None]:
        """Bounded least squares over ``free`` in log-parameters, the linear ones among
        ``project`` solved exactly at each evaluation; the cost and the solver's result
        (None when only linear parameters were free)."""
        from scipy.optimize import least_squares

        self.values.update(start or {})
        base = dict(self.values)
        lin = [k for k in project if k in LINEAR_PARAMETERS]
        names = [k for k in free if k not in lin]
        if not names:  # only linear parameters free: one projection solves them
            r, c = self.project(self.packed.residuals(basis(self.batch({}, 1), lin), mask), lin)
            self.values.update(zip(lin, c, strict=True))
            self.record(stage, 0.5 * float(r @ r), self.values)
            return 0.5 * float(r @ r), None
        lo, hi = np.log([self.bounds[k] for k in names]).T
        x0 = np.clip(np.log([base[k] for k in names]), lo + 1e-12, hi - 1e-12)
        k = len(names)
        last: list[tuple[bytes, NDArray[np.float64], NDArray[np.float64]]] = []
        linear_at: dict[bytes, list[float]] = {}

        def evaluate(x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
            """Residuals (m,) and forward-difference Jacobian (m, k) at the log-point ``x``,
            from one batched simulation of it and its neighbours (the last one cached)."""
            key = x.tobytes()
            if last and last[0][0] == key:
                return last[0][1], last[0][2]
            X = np.repeat(x[None, :], 1 + k, axis=0)
            h = np.where(x + _FD_STEP > hi, -_FD_STEP, _FD_STEP)  # step inward at a bound
            X[1 + np.arange(k), np.arange(k)] += h
            over = {p: np.exp(X[:, i]) for i, p in enumerate(names)}
            R = self.packed.residuals(basis(self.batch(over, 1 + k), lin), mask)
            R = R.reshape(-1, 1 + k, 1 + len(lin))
            cols = [self.project(R[:, i, :], lin, base) for i in range(1 + k)]
            r = cols[0][0]
            if not np.all(np.isfinite(r)):
                r = np.full_like(r, 1e6)
            J = np.stack([c[0] for c in cols[1:]], axis=1)
            J = (J - r[:, None]) / h[None, :]
            J[~np.isfinite(J)] = 0.0
            last[:] = [(key, r, J)]
            linear_at[key] = cols[0][1]
            point = {**base, **{p: float(v[0]) for p, v in over.items()}}
            point.update(zip(lin, cols[0][1], strict=True))
            self.record(stage, 0.5 * float(r @ r), point)
            return r, J

        sol = least_squares(
            lambda x: evaluate(x)[0],
            x0,
            jac=lambda x: evaluate(x)[1],
            bounds=(lo, hi),
            method="trf",
            x_scale=1.0,
            max_nfev=max_nfev,
            xtol=1e-10,
            ftol=1e-10,
            gtol=1e-10,
        )
        self.values.update({p: float(np.exp(sol.x[i])) for i, p in enumerate(names)})
        if lin:
            if sol.x.tobytes() not in linear_at:
                evaluate(sol.x)
            self.values.update(zip(lin, linear_at[sol.x.tobytes()], strict=True))
        return float(sol.cost), sol

    def jacobian(
        self, mask: NDArray[np.bool_], free: tuple[str, ...]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Residuals and Jacobian in log-parameters at the current values: central
        differences, shifted inside the bounds for a parameter that sits on one."""
        k = len(free)
        h = 1e-4
        over = {}
        lo_s, hi_s = np.zeros(k), np.zeros(k)
        for i, name in enumerate(free):
            x = math.log(self.values[name])
            lo_b, hi_b = (math.log(b) for b in self.bounds[name])
            a, b = x - h, x + h
            if b > hi_b:
                a, b = hi_b - 2 * h, hi_b
            elif a < lo_b:
                a, b = lo_b, lo_b + 2 * h
            lo_s[i], hi_s[i] = a, b
            over[name] = np.full(1 + 2 * k, self.values[name])
            over[name][1 + 2 * i : 3 + 2 * i] = math.exp(b), math.exp(a)
        R = self.packed.residuals(self.batch(over, 1 + 2 * k), mask)
        J = (R[:, 1::2] - R[:, 2::2]) / (hi_s - lo_s)[None, :]
        return R[:, 0], J


class Stage(NamedTuple):
    """A phase stage: its name, the phases it fits, its group (``own``; it runs if one is
    free), the linear parameters it re-solves, and a grid of starting values [SI]."""

    name: str
    phases: tuple[int, ...]
    own: tuple[str, ...]
    linear: tuple[str, ...]
    grid: dict[str, NDArray[np.float64]]


#: The phase stages, in order (decision D41).
STAGES: tuple[Stage, ...] = (
    Stage(
        "intrusion",
        (PHASES["intrusion"],),
        ("alpha", "n", "eta_inf"),
        ("eta_m",),
        {"n": np.linspace(0.1, 1.0, 10)},
    ),
    Stage(
        "relaxation",
        (PHASES["intrusion"], PHASES["hold"]),
        ("lam", "eta_m", "eta_inf", "gamma_dot_c"),
        ("alpha",),
        {"lam": np.geomspace(0.1, 30.0, 8), "gamma_dot_c": np.geomspace(0.01, 1.0, 5)},
    ),
    Stage(
        "retraction",
        (PHASES["retraction"],),
        ("tau_build", "tau_leak", "epsilon", "sigma_y"),
        ("alpha", "eta_inf", "eta_m"),
        {"tau_build": np.geomspace(0.03, 3.0, 7), "epsilon": np.geomspace(0.003, 0.3, 5)},
    ),
)


def stage_note(report: StageReport, suffix: str = "") -> str:
    """The progress line of a finished stage."""
    return (
        f"calibrate: stage {report.name:<10} free {list(report.free)}: cost {report.cost:.4g}, "
        f"{report.simulations} simulations, {report.seconds:.2f} s{suffix}"
    )


def start_stage(
    engine: Engine,
    free: tuple[str, ...],
    fixed: dict[str, float],
    *,
    paper: str | None,
    note: Callable[[str], object],
) -> StageReport:
    """The "start" stage: the ``engine`` moved from its values [SI] to the best rescaled
    paper row of direction ``paper`` (unless None), the ``fixed`` values applied."""
    t0, packed = time.perf_counter(), engine.packed
    samples = int(np.count_nonzero(packed.valid))
    if samples <= len(free):
        raise MudrftError(
            f"calibrate: {samples} fitted sample(s) cannot determine {len(free)} free "
            f"parameter(s) {list(free)}; a fit needs more samples than free parameters "
            "(samples after the plate is back at the surface do not count): give a longer "
            "log (or a smaller decimate) or fit fewer parameters (groups=..., CLI --groups)"
        )
    if paper is not None:  # the paper row that fits best, its free linear parameters rescaled (D43)
        rows = table_rows(paper)
        ws = sorted(rows)
        cands = [{k: float(rows[w][k]) for k in FIT_PARAMETERS} for w in ws]
        lin = tuple(k for k in LINEAR_PARAMETERS if k in free)
        cost, point = engine.grid_start("start", packed.mask(ALL_PHASES), lin, cands, len(ws))[0]
        nonlinear = [k for k in FIT_PARAMETERS if k not in LINEAR_PARAMETERS]
        w = next(
            w for w, c in zip(ws, cands, strict=True) if all(c[k] == point[k] for k in nonlinear)
        )
        note(
            f"calibrate: start from the paper's {paper} row W = {100 * w:g} % "
            f"(free linear parameters rescaled), cost {cost:.4g}"
        )
        engine.values.update(point)
    engine.values.update({k: float(v) for k, v in fixed.items()})
    for k in free:
        engine.values[k] = engine.clip(k, engine.values[k])
    try:  # validate the starting set (with the fixed values) once
        packed.parameters({k: np.array([v]) for k, v in engine.values.items()})
    except MudrftError as exc:
        raise MudrftError(f"invalid starting or fixed parameter values: {exc}") from None
    sims = packed.simulations  # those of the start point; the cost below is not counted
    r = packed.residuals(engine.batch({}, 1), packed.mask(ALL_PHASES))[:, 0]
    message = "initial" if paper is None else "paper row"
    return StageReport("start", (), sims, 0.5 * float(r @ r), time.perf_counter() - t0, message)


def _message(sol: OptimizeResult | None) -> str:
    return "linear parameters solved exactly" if sol is None else str(sol.message)


def phase_stage(
    engine: Engine, stage: Stage, free: tuple[str, ...], *, starts: int, max_nfev: int
) -> StageReport | None:
    """Fit one group on the samples of its phase from the ``starts`` best points of its
    grid; None if the stage has nothing to do."""
    mask = engine.packed.mask(stage.phases)
    if not mask.any() or not any(k in free for k in stage.own):
        return None  # no sample of the stage's phases, or none of its own group is fitted
    stage_free = tuple(
        k for k in FIT_PARAMETERS if k in free and (k in stage.own or k in stage.linear)
    )
    t0, n0 = time.perf_counter(), engine.packed.simulations
    saved = dict(engine.values)
    axes = {  # the stage's grid of starting points, in bounds, with the current values
        k: np.unique(np.append(np.clip(v, *engine.bounds[k]), engine.values[k]))
        for k, v in stage.grid.items()
        if k in stage_free
    }
    grid = [dict(zip(axes, combo, strict=True)) for combo in itertools.product(*axes.values())]
    runs = []
    for _, point in engine.grid_start(stage.name, mask, stage_free, grid, starts):
        engine.values = dict(saved)
        c, sol = engine.fit(stage.name, mask, stage_free, max_nfev, start=point, project=stage_free)
        runs.append((c, dict(engine.values), sol))
    best = min(runs, key=lambda run: run[0])  # the first of equal costs
    engine.values = best[1]
    sims = engine.packed.simulations - n0
    return StageReport(
        stage.name, stage_free, sims, best[0], time.perf_counter() - t0, _message(best[2])
    )


def joint_stage(engine: Engine, free: tuple[str, ...], *, max_nfev: int) -> tuple[StageReport, str]:
    """Every free parameter on every sample, the linear ones projected out, then polished
    with all of them solver variables; returns the report and the solver status."""
    t0, n0 = time.perf_counter(), engine.packed.simulations
    mask = engine.packed.mask(ALL_PHASES)
    engine.fit("joint", mask, free, max_nfev, project=free)
    cost, sol = engine.fit("joint", mask, free, max_nfev)  # the polish always runs the solver
    sims = engine.packed.simulations - n0
    report = StageReport("joint", free, sims, cost, time.perf_counter() - t0, _message(sol))
    if sol is None or sol.status > 0:
        return report, "converged"
    return report, "max_evaluations" if sol.status == 0 else "failed"
