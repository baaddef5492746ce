"""The stages of a calibration on one :class:`~._engine.Engine`: start, one stage per phase
group, joint, and the uncertainty at the optimum (decisions D41, D43)."""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError
from ..parameters.base import MudParameters
from ..parameters.registry import table_rows
from ._engine import Engine
from ._options import check_determined
from ._problem import FIT_PARAMETERS, LINEAR_PARAMETERS, PHASES, Packed
from .result import StageReport
from .uncertainty import Uncertainty, at_bound, uncertainty

if TYPE_CHECKING:
    from scipy.optimize import OptimizeResult


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
#: Phases whose samples the joint stage fits (all but "out").
ALL_PHASES = (PHASES["intrusion"], PHASES["hold"], PHASES["retraction"])


def stage_note(report: StageReport, suffix: str = "") -> str:
    """The progress line of a finished stage."""
    return (
        f"calibrate: stage {report.name:<10} free {list(report.free)}: cost {report.cost:.4g}, "
        f"{report.simulations} simulations, {report.seconds:.2f} s{suffix}"
    )


def _paper_start(
    engine: Engine, direction: str, note: Callable[[str], object], free: tuple[str, ...]
) -> dict[str, float]:
    """The paper row of ``direction`` that fits best once its free linear parameters are
    rescaled (decision D43); those not fitted keep the row's values."""
    rows = table_rows(direction)
    ws = sorted(rows)
    cands = [{k: float(rows[w][k]) for k in FIT_PARAMETERS} for w in ws]
    mask = engine.packed.mask(ALL_PHASES)
    lin = tuple(k for k in LINEAR_PARAMETERS if k in free)
    cost, point = engine.grid_start("start", mask, lin, cands, len(cands))[0]
    nonlinear = [k for k in FIT_PARAMETERS if k not in LINEAR_PARAMETERS]
    w = next(w for w, c in zip(ws, cands, strict=True) if all(c[k] == point[k] for k in nonlinear))
    note(
        f"calibrate: start from the paper's {direction} row W = {100 * w:g} % "
        f"(free linear parameters rescaled), cost {cost:.4g}"
    )
    return point


def start_engine(
    packed: Packed,
    base: MudParameters,
    *,
    from_paper: bool,
    direction: str,
    free: tuple[str, ...],
    fixed: dict[str, float],
    bounds: dict[str, tuple[float, float]],
    trace_limit: int,
    note: Callable[[str], object],
) -> tuple[Engine, StageReport]:
    """The "start" stage: an engine at ``base``'s values [SI] (or the best rescaled paper
    row of ``direction`` with ``from_paper``), the ``fixed`` values applied."""
    t0 = time.perf_counter()
    check_determined(int(np.count_nonzero(packed.valid)), free)
    engine = Engine(
        packed, {k: float(getattr(base, k)) for k in FIT_PARAMETERS}, bounds, trace_limit
    )
    if from_paper:
        engine.values.update(_paper_start(engine, direction, note, free))
    engine.values.update({k: float(v) for k, v in fixed.items()})
    for k in free:
        engine.values[k] = engine.clip(k, engine.values[k])
    try:  # validate the starting set (with the fixed values) once
        packed.parameters({k: np.array([v]) for k, v in engine.values.items()})
    except MudrftError as exc:
        raise MudrftError(f"invalid starting or fixed parameter values: {exc}") from None
    sims = packed.simulations  # those of the start point; the cost below is not counted
    cost = engine.cost(packed.mask(ALL_PHASES))
    message = "paper row" if from_paper else "initial"
    return engine, StageReport("start", (), sims, cost, time.perf_counter() - t0, message)


def _grid(engine: Engine, stage: Stage, free: tuple[str, ...]) -> list[dict[str, float]]:
    """The stage's grid of starting points (with the current values added), in bounds."""
    axes = {
        k: np.unique(np.append(np.clip(v, *engine.bounds[k]), engine.values[k]))
        for k, v in stage.grid.items()
        if k in free
    }
    return [dict(zip(axes, combo, strict=True)) for combo in itertools.product(*axes.values())]


def _message(sol: OptimizeResult | None) -> str:
    return "linear parameters solved exactly" if sol is None else str(sol.message)


def phase_stage(
    engine: Engine, stage: Stage, free: tuple[str, ...], *, starts: int, max_nfev: int
) -> StageReport | None:
    """Fit one group on the samples of its phase from the ``starts`` best points of its
    grid; None if the stage has nothing to do."""
    if not any(k in free for k in stage.own):
        return None  # none of the stage's own group is fitted
    stage_free = tuple(
        k for k in FIT_PARAMETERS if k in free and (k in stage.own or k in stage.linear)
    )
    mask = engine.packed.mask(stage.phases)
    if not mask.any():
        return None
    t0, n0 = time.perf_counter(), engine.packed.simulations
    saved = dict(engine.values)
    best: tuple[float, dict[str, float], OptimizeResult | None] | None = None
    starting = engine.grid_start(
        stage.name, mask, stage_free, _grid(engine, stage, stage_free), starts
    )
    for _, point in starting:
        engine.values = dict(saved)
        c, sol = engine.fit(stage.name, mask, stage_free, max_nfev, start=point, project=stage_free)
        if best is None or c < best[0]:
            best = (c, dict(engine.values), sol)
    assert best is not None
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
    cost, sol = engine.fit("joint", mask, free, max_nfev, project=free)
    cost, sol_full = engine.fit("joint", mask, free, max_nfev)
    sol = sol_full if sol_full is not None else sol
    sims = engine.packed.simulations - n0
    report = StageReport("joint", free, sims, cost, time.perf_counter() - t0, _message(sol))
    if sol is None or sol.status > 0:
        return report, "converged"
    return report, "max_evaluations" if sol.status == 0 else "failed"


def uncertainty_at_optimum(
    engine: Engine, free: tuple[str, ...], level: float, *, tare: tuple[float, ...] | None = None
) -> Uncertainty:
    """Standard errors, intervals and verdicts at the engine's values, at ``level`` [-];
    ``tare`` is the standard error [Pa] of each trial's subtracted sensor zero."""
    mask = engine.packed.mask(ALL_PHASES)
    r, J = engine.jacobian(mask, free)
    bound = at_bound(engine.values, free, engine.bounds)
    _, trial = np.nonzero(mask)  # the residuals' order: time, then trial
    order = np.argsort(trial, kind="stable")  # each trial's residuals together, in time order
    shift = None if tare is None else np.asarray(tare) * engine.packed.weight
    return uncertainty(
        r[order], J[order], free, bound, level, engine.values, engine.bounds, trial[order], shift
    )
