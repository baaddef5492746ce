"""One point of a sweep, and one chunk of points: plain functions of the library, no Dask.

A point that raises is recorded, not fatal: NaN metrics and ``"ExceptionType: message"``.

>>> import numpy as np
>>> ctx = {"fixed": {"foot": "flat", "water_content": 0.25}, "motion": "gait",
...        "metrics": ("peak_support",), "mud_sets": {}, "mesh": None}
>>> out = evaluate_chunk(ctx, [{"speed": 0.2}, {"speed": -1.0}])
>>> bool(out.values[0, 0] > 0), bool(np.isnan(out.values[1, 0])), out.errors[1][:33]
(True, True, 'MudrftError: speed must be > 0 m/')
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass
from typing import Any, TypedDict

import numpy as np

from .. import feet
from .._validation import MudrftError
from ..parameters import Mud, MudParameters, paper_mud
from ..simulation import LoadControl, simulate
from ..terrains import MudTerrain
from ..trajectories import gait
from .catalog import FOOT_KINDS, METRICS, MOTIONS, PARAMETERS


class SweepContext(TypedDict):
    """What a task needs besides its points: these fields of its
    :class:`~.spec.SweepSpec` (:meth:`~.spec.SweepSpec.context`), described there."""

    fixed: dict[str, Any]
    motion: str
    metrics: tuple[str, ...]
    mud_sets: dict[str, dict[str, Any]]
    mesh: feet.MeshFoot | None


@dataclass(frozen=True)
class ChunkResult:
    """What one task returns: ``values`` (points, metrics), NaN where a point failed;
    ``errors``, ``""`` for a point that ran, else ``"ExceptionType: message"``; the distinct
    ``warnings``; the chunk's wall time ``seconds`` [s]."""

    values: np.ndarray
    errors: list[str]
    warnings: tuple[str, ...]
    seconds: float


def _section(values: dict[str, Any], section: str) -> dict[str, Any]:
    return {k: v for k, v in values.items() if k in PARAMETERS and PARAMETERS[k].section == section}


def build_foot(values: dict[str, Any], *, mesh: feet.Foot | None = None) -> feet.Foot:
    """The foot of a point: ``values["foot"]`` (a kind) with its foot parameters."""
    kind = values["foot"]
    params = _section(values, "foot")
    if mesh is not None:
        return mesh
    allowed = FOOT_KINDS[kind]
    extra = [k for k in params if k not in allowed]
    if extra:
        raise MudrftError(f"the {kind} foot has no parameter {extra[0]!r}; its parameters are {', '.join(allowed)}")  # fmt: skip
    cls = {"flat": feet.Flat, "semi-cylinder": feet.SemiCylinder, "semi-sphere": feet.SemiSphere}
    return feet.MorphingFoot(**params) if kind == "morphing" else cls[kind](**params)


def build_mud(values: dict[str, Any], *, mud_sets: dict[str, Any] | None = None) -> MudTerrain:
    """The mud of a point, as a :class:`mudrft.MudTerrain` with the point's options."""
    params = _section(values, "mud")
    if "mud_set" in params:
        entry = (mud_sets or {})[params["mud_set"]]
        mud = Mud(
            MudParameters(**entry["vertical"], source=entry["source"], direction="vertical"),
            MudParameters(**entry["horizontal"], source=entry["source"], direction="horizontal"),
            name=str(params["mud_set"]),
        )
    else:
        mud = paper_mud(
            params["water_content"],
            extrapolate=bool(params.get("extrapolate", False)),
            labels=params.get("labels", "table"),
        )
    scales = {k[: -len("_scale")]: v for k, v in params.items() if k.endswith("_scale")}
    if scales:

        def scaled(p: MudParameters) -> MudParameters:
            return p.replace(**{f: getattr(p, f) * s for f, s in scales.items()})

        mud = Mud(scaled(mud.vertical), scaled(mud.horizontal), mud.water_content, mud.name)
    options = {k: params[k] for k in ("thixotropy", "clock", "xi0") if k in params}
    return MudTerrain(mud, **options)


def evaluate_point(
    context: SweepContext, point: dict[str, Any], *, cache: dict | None = None
) -> dict[str, float]:
    """The metrics of one point (name -> SI value): the ``context``'s fixed values with the
    ``point``'s swept ones; ``cache`` keeps the feet and muds a task has built."""
    values = {**context["fixed"], **point}
    motion = context["motion"]
    cache = {} if cache is None else cache
    foot_key = ("foot", values["foot"], *sorted(_section(values, "foot").items()))
    mud_key = ("mud", *sorted(_section(values, "mud").items()))
    if foot_key not in cache:
        cache[foot_key] = build_foot(values, mesh=context.get("mesh"))
    if mud_key not in cache:
        cache[mud_key] = build_mud(values, mud_sets=context.get("mud_sets"))
    foot, mud = cache[foot_key], cache[mud_key]
    kw = {k: values[k] for k in MOTIONS[motion] if k in values}
    if motion == "walk":
        from ..integrations.walk import walk

        found = walk(foot, mud, **kw).summary  # keys with units: "distance [m]", ...
    elif motion == "gait":
        speed = kw.pop("speed", 0.2)
        found = simulate(foot, mud, gait(speed, **kw)).metrics()
    else:
        found = simulate(foot, mud, LoadControl(**kw)).metrics()
    return {name: float(found[METRICS[motion][name].key]) for name in context["metrics"]}


def evaluate_chunk(context: SweepContext, points: list[dict[str, Any]]) -> ChunkResult:
    """The metrics of a chunk of ``points``; a point that raises is recorded, not fatal."""
    t0 = time.perf_counter()
    metrics = context["metrics"]
    values = np.full((len(points), len(metrics)), np.nan)
    errors = [""] * len(points)
    seen: dict[str, None] = {}
    cache: dict[str, Any] = {}
    for i, point in enumerate(points):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                out = evaluate_point(context, point, cache=cache)
                values[i] = [out[m] for m in metrics]
            except Exception as exc:  # a bad combination: recorded, the rest goes on
                errors[i] = f"{type(exc).__name__}: {' '.join(str(exc).split())}"
        for w in caught:
            seen.setdefault(f"{w.category.__name__}: {w.message}", None)
    return ChunkResult(values, errors, tuple(seen), time.perf_counter() - t0)
