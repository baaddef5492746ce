"""The sweep spec: a TOML file (or a dict of the same shape) read, checked and resolved.

A spec names a design (a grid, or a Latin hypercube or Sobol sample), the parameters of the
foot, the mud and the motion (each fixed, or swept), the metrics and how the result is
plotted. Every mistake is reported before anything runs, naming the key::

    [sweep]
    design = "grid"                     # or "lhs", "sobol" (then n = ..., seed = ...)
    metrics = ["peak_support", "max_suction"]

    [foot]
    kind = "semi-cylinder"
    radius = [0.03, 0.045, 0.06]        # a list: grid values

    [mud]
    water_content = { low = 0.25, high = 0.45, num = 5 }   # a range

    [motion]
    kind = "gait"
    speed = 0.2                         # a scalar: fixed

See the README's library section and ``examples/sweep_example.toml`` for every option.

>>> spec = load_spec({"foot": {"kind": "flat", "width": [0.05, 0.065]},
...                   "mud": {"water_content": {"low": 0.25, "high": 0.45, "num": 3}}})
>>> spec.dims, spec.shape, spec.n_points
(('width', 'water_content'), (2, 3), 6)
"""

from __future__ import annotations

import difflib
import hashlib
import json
import math
import os
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import MudrftError
from ..feet import MeshFoot
from ..feet.mesh import UP_AXES
from ..units import SCALE
from . import catalog as C
from .design import Axis, Design

if TYPE_CHECKING:
    from .evaluate import SweepContext

__all__ = ["DESIGNS", "SweepSpec", "load_spec"]

#: The designs of a sweep.
DESIGNS = ("grid", "lhs", "sobol")
_SECTIONS = ("sweep", "foot", "mud", "motion", "plot")
_SWEEP_KEYS = ("design", "n", "seed", "metrics", "points_per_task")
_PLOT_KEYS = ("x", "y", "panels", "metrics")
#: Largest number of points of one sweep (1e7; the issue's maps have 1e4-1e6).
MAX_POINTS = 10_000_000
_INT_MIN, _INT_MAX = -(2**53), 2**53  # integer values an int64 coordinate and a float hold


@dataclass(frozen=True, eq=False)
class SweepSpec(Design):
    """A checked, resolved sweep spec (made by :func:`load_spec`).

    Attributes
    ----------
    design : {"grid", "lhs", "sobol"}
        How points are chosen.
    axes : tuple of Axis
        The swept parameters, in spec order (foot, mud, motion).
    fixed : dict
        The fixed parameters by name (SI; ``foot`` is the foot kind).
    motion : {"gait", "load", "walk"}
        What the foot does at every point.
    metrics : tuple of str
        The metrics measured.
    n, seed : int or None
        Sample size and seed (sample designs).
    points_per_task : int
        Target number of points per task (and per chunk of the store).
    mud_sets : dict
        Calibrated sets by name: ``{"vertical": {...}, "horizontal": {...}, "source": str}``.
    mesh : MeshFoot or None
        The mesh foot when ``[foot] kind`` is a mesh file.
    plot : dict
        ``x``, ``y``, ``panels``, ``metrics`` of the maps (names; may be absent).
    text : str
        The spec as given (TOML text, or JSON of a dict), kept in the result.
    where : str
        Where it came from (a path or ``"<dict>"``), for messages.
    """

    motion: str = "gait"
    metrics: tuple[str, ...] = ()
    fixed: dict[str, Any] = field(default_factory=dict)
    mud_sets: dict[str, dict[str, Any]] = field(default_factory=dict)
    mesh: MeshFoot | None = None
    plot: dict[str, Any] = field(default_factory=dict)
    text: str = ""
    where: str = "<dict>"

    def context(self) -> SweepContext:
        """What a task needs besides its points: plain data (and the mesh), no Dask."""
        return {
            "fixed": dict(self.fixed),
            "motion": self.motion,
            "metrics": self.metrics,
            "mud_sets": self.mud_sets,
            "mesh": self.mesh,
        }

    def identity(self) -> str:
        """A hash of everything that decides the values (not the plot): equal specs, equal
        stores; a store made from another spec is not resumed."""
        mesh = None
        if self.mesh is not None:
            h = hashlib.sha256(np.ascontiguousarray(self.mesh.vertices).tobytes())
            h.update(np.ascontiguousarray(self.mesh.faces).tobytes())
            mesh = h.hexdigest()
        doc = {
            "design": self.design,
            "n": self.n,
            "seed": self.seed,
            "axes": [a.as_json() for a in self.axes],
            "fixed": self.fixed,
            "motion": self.motion,
            "metrics": self.metrics,
            "points_per_task": self.points_per_task,
            "chunks": self.chunks,
            "mud_sets": {k: {d: v[d] for d in ("vertical", "horizontal")} for k, v in self.mud_sets.items()},
            "mesh": mesh,
        }  # fmt: skip
        return hashlib.sha256(json.dumps(doc, sort_keys=True, default=str).encode()).hexdigest()


# -- reading --------------------------------------------------------------------------------
def load_spec(spec: str | os.PathLike[str] | Mapping[str, Any] | SweepSpec) -> SweepSpec:
    """Read and check a sweep spec.

    Parameters
    ----------
    spec : path-like, dict or SweepSpec
        A TOML file, a dict of the same shape (``{"foot": {...}, "mud": {...}, ...}``) or
        an already loaded spec (returned as is).

    Returns
    -------
    SweepSpec

    Raises
    ------
    MudrftError
        For an unreadable or malformed file, an unknown section, parameter or metric, a
        value of the wrong type, an empty range, ... naming the key.
    """
    if isinstance(spec, SweepSpec):
        return spec
    if isinstance(spec, Mapping):
        data = dict(spec)
        text = json.dumps(data, indent=1, sort_keys=False, default=str)
        return _resolve(data, text=text, where="<dict>", base=Path.cwd())
    if not isinstance(spec, str | os.PathLike):
        raise MudrftError(
            f"spec must be a TOML file path, a dict or a SweepSpec, got {type(spec).__name__}"
        )
    path = Path(os.fspath(spec))
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise MudrftError(f"spec {str(path)!r}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise MudrftError(f"spec {str(path)!r}: cannot read it ({exc})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise MudrftError(f"spec {str(path)!r} is not valid TOML: {exc}") from None
    return _resolve(data, text=text, where=str(path), base=path.parent)


def _unknown(where: str, key: str, allowed: Iterable[str]) -> MudrftError:
    near = difflib.get_close_matches(key, list(allowed), n=1)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    return MudrftError(f"{where} {key}: unknown key{hint}; expected one of {', '.join(allowed)}")


def _table(data: Mapping[str, Any], name: str) -> dict[str, Any]:
    value = data.get(name, {})
    if not isinstance(value, Mapping):
        raise MudrftError(f"[{name}] must be a table, got {type(value).__name__}: {value!r}")
    return dict(value)


def _resolve(data: dict[str, Any], *, text: str, where: str, base: Path) -> SweepSpec:
    for key in data:
        if key not in _SECTIONS:
            near = difflib.get_close_matches(str(key), _SECTIONS, n=1)
            hint = f" (did you mean [{near[0]}]?)" if near else ""
            raise MudrftError(f"unknown section [{key}]{hint}; expected {', '.join(f'[{s}]' for s in _SECTIONS)}")  # fmt: skip
    run, foot, mud, motion, plot = (_table(data, s) for s in _SECTIONS)
    for key in run:
        if key not in _SWEEP_KEYS:
            raise _unknown("[sweep]", key, _SWEEP_KEYS)
    design = run.get("design", "grid")
    if design not in DESIGNS:
        raise MudrftError(f"[sweep] design must be one of {', '.join(DESIGNS)}, got {design!r}")
    n, seed = _sample_size(run, design)
    motion_kind = motion.pop("kind", "gait")
    if motion_kind not in C.MOTION_KINDS:
        raise MudrftError(f"[motion] kind must be one of {', '.join(C.MOTION_KINDS)}, got {motion_kind!r}")  # fmt: skip
    metrics = _metrics(run.get("metrics"), motion_kind, "[sweep] metrics")

    fixed: dict[str, Any] = {}
    axes: list[Axis] = []
    kinds, mesh = _foot_kind(foot, design, base, fixed, axes)
    allowed = sorted({p for k in kinds for p in C.foot_parameters(k)})
    for key in ("unit", "up") if mesh is not None else ():
        foot.pop(key, None)  # read by _foot_kind
    for key, raw in foot.items():
        if key not in allowed:
            what = f"the {kinds[0]} foot" if len(kinds) == 1 else f"the feet {', '.join(kinds)}"
            if not allowed:
                raise MudrftError(f"[foot] {key}: a mesh foot has no parameters (only unit and up)")
            raise MudrftError(
                f"[foot] {key}: not a parameter of {what}; expected one of {', '.join(allowed)}"
            )
        _add("foot", key, raw, design, fixed, axes)
    mud_sets = _mud_sets(mud.pop("sets", None), base)
    mud_allowed = [p.name for p in C.PARAMETERS.values() if p.section == "mud"]
    for key, raw in mud.items():
        if key not in mud_allowed:
            raise _unknown("[mud]", key, [*mud_allowed, "sets"])
        _add("mud", key, raw, design, fixed, axes)
    _check_mud_source(fixed, axes, mud_sets)
    motion_allowed = C.motion_parameters(motion_kind)
    for key, raw in motion.items():
        if key not in motion_allowed:
            raise _unknown(f"[motion] ({motion_kind})", key, ["kind", *motion_allowed])
        _add("motion", key, raw, design, fixed, axes, motion_kind=motion_kind)
    if motion_kind == "load" and "weight" not in motion:
        raise MudrftError(
            "[motion] weight is required for kind = 'load' (the load on the foot [N])"
        )
    if design != "grid" and not axes:
        raise MudrftError(f"[sweep] design = {design!r} needs at least one range to sample")
    ppt = _points_per_task(run.get("points_per_task"), motion_kind)
    spec = SweepSpec(
        design=design,
        axes=tuple(axes),
        n=n,
        seed=seed,
        points_per_task=ppt,
        motion=motion_kind,
        metrics=metrics,
        fixed=fixed,
        mud_sets=mud_sets,
        mesh=mesh,
        plot=_plot(plot, axes, metrics),
        text=text,
        where=where,
    )
    if spec.n_points > MAX_POINTS:
        raise MudrftError(
            f"the sweep has {spec.n_points:.3g} points, more than the limit {MAX_POINTS:.0e}; "
            f"split it into several sweeps"
        )
    return spec


def _integer(where: str, value: object, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise MudrftError(f"{where} must be an integer >= {low}, got {value!r}")
    return int(value)


def _sample_size(run: dict[str, Any], design: str) -> tuple[int | None, int | None]:
    if design == "grid":
        for key in ("n", "seed"):
            if key in run:
                raise MudrftError(f"[sweep] {key} is for sample designs (lhs, sobol), not a grid")
        return None, None
    if "n" not in run:
        raise MudrftError(f"[sweep] n (the number of points) is required for design = {design!r}")
    n = _integer("[sweep] n", run["n"], 1)
    if design == "sobol" and n & (n - 1):
        raise MudrftError(
            f"[sweep] n must be a power of 2 for a Sobol sample (its balance properties), got "
            f"{n}; use {1 << (n - 1).bit_length()} or design = 'lhs'"
        )
    return n, _integer("[sweep] seed", run.get("seed", 0), 0)


def _metrics(value: object, motion: str, where: str) -> tuple[str, ...]:
    known = C.metric_names(motion)
    if value is None:
        return known
    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise MudrftError(f"{where} must be a non-empty list of metric names, got {value!r}")
    for v in value:
        if v not in known:
            raise MudrftError(
                f"{where}: unknown metric {v!r} for motion {motion!r}; expected {', '.join(known)}"
            )
    if len(set(value)) != len(value):
        raise MudrftError(f"{where} lists a metric twice: {value!r}")
    return tuple(value)


def _points_per_task(value: object, motion: str) -> int:
    if value is not None:
        return _integer("[sweep] points_per_task", value, 1)
    return 0 if motion != "walk" else 1  # 0: chosen from the size (Design.points_per_task)


def _foot_kind(
    foot: dict[str, Any], design: str, base: Path, fixed: dict[str, Any], axes: list[Axis]
) -> tuple[tuple[str, ...], MeshFoot | None]:
    if "kind" not in foot:
        raise MudrftError(
            "[foot] kind is required: flat, semi-cylinder, semi-sphere, morphing or a mesh "
            "file (.stl/.obj/.ply), or a list of the named feet"
        )
    kind = foot.pop("kind")
    names = tuple(C.FOOT_KINDS)
    if isinstance(kind, str) and kind.lower().endswith((".stl", ".obj", ".ply")):
        unit = foot.get("unit", "m")
        if not isinstance(unit, str) or unit.strip() not in SCALE["length"]:
            raise MudrftError(f'[foot] unit must be the length unit of the mesh file, a string such as "m" or "mm" (one of {", ".join(sorted(SCALE["length"]))}), got {unit!r}')  # fmt: skip
        up = foot.get("up", "z")
        if not isinstance(up, str) or up not in UP_AXES:
            axes_ = ", ".join(f'"{a}"' for a in UP_AXES)
            raise MudrftError(f"[foot] up must be the mesh file's up axis, a string, one of {axes_} (y for a y-up export), got {up!r}")  # fmt: skip
        path = Path(kind) if Path(kind).is_absolute() else base / kind
        try:
            mesh = MeshFoot.from_file(path, unit=unit, up=up)
        except MudrftError as exc:
            raise MudrftError(f"[foot] kind: {exc}") from None
        fixed["foot"] = str(path)
        return ("mesh",), mesh
    for key in ("unit", "up"):
        if key in foot:
            raise MudrftError(f"[foot] {key} applies to mesh files only (.stl/.obj/.ply)")
    values = kind if isinstance(kind, list) else [kind]
    if not values or not all(isinstance(v, str) and v in names for v in values):
        raise MudrftError(f"[foot] kind must be one of {', '.join(names)} or a mesh file, or a list of the named feet, got {kind!r}")  # fmt: skip
    if isinstance(kind, list):
        if design != "grid":
            raise MudrftError(f"[foot] kind: a list of feet is for grids; design = {design!r} samples ranges only")  # fmt: skip
        if len(set(values)) != len(values):
            raise MudrftError(f"[foot] kind lists a foot twice: {kind!r}")
        axes.append(Axis("foot", "str", values=np.array(values, dtype=object)))
    else:
        fixed["foot"] = kind
    return tuple(values), None


def _mud_sets(value: object, base: Path) -> dict[str, dict[str, Any]]:
    if value is None:
        return {}
    if not isinstance(value, Mapping) or not value:
        raise MudrftError(f"[mud.sets] must be a table of named sets, got {value!r}")
    from ..calibration.persistence import load_parameters

    out: dict[str, dict[str, Any]] = {}
    for name, entry in value.items():
        where = f"[mud.sets.{name}]"
        if not isinstance(entry, Mapping):
            raise MudrftError(f"{where} must be a table with vertical = FILE and horizontal = FILE, got {entry!r}")  # fmt: skip
        for key in entry:
            if key not in ("vertical", "horizontal"):
                raise _unknown(where, key, ("vertical", "horizontal"))
        sets: dict[str, Any] = {}
        sources = []
        for d in ("vertical", "horizontal"):
            if not isinstance(entry.get(d), str):
                raise MudrftError(f"{where} {d} must be the path of a parameter JSON (mudrft calibrate --out), got {entry.get(d)!r}")  # fmt: skip
            path = Path(entry[d]) if Path(entry[d]).is_absolute() else base / entry[d]
            try:
                p = load_parameters(path)
            except FileNotFoundError:
                raise MudrftError(f"{where} {d}: {str(path)!r}: no such file") from None
            except (MudrftError, OSError) as exc:
                raise MudrftError(f"{where} {d}: {exc}") from None
            if p.direction not in ("", d):
                raise MudrftError(
                    f"{where} {d}: {str(path)!r} holds a {p.direction} parameter set, expected "
                    f"a {d} one (were vertical and horizontal swapped?)"
                )
            sets[d] = {k: float(v) for k, v in p.as_dict().items()}
            sources.append(f"{d}: {p.source or path}")
        sets["source"] = "; ".join(sources)
        out[str(name)] = sets
    return out


def _check_mud_source(fixed: dict[str, Any], axes: list[Axis], sets: dict[str, Any]) -> None:
    names = set(fixed) | {a.name for a in axes}
    if "mud_set" in names and "water_content" in names:
        raise MudrftError(
            "[mud] give water_content (the paper's mud) or mud_set (calibrated sets in "
            "[mud.sets]), not both"
        )
    if "mud_set" in names:
        used = [fixed["mud_set"]] if "mud_set" in fixed else []
        used += [str(v) for a in axes if a.name == "mud_set" for v in a.values]  # type: ignore[union-attr]
        for u in used:
            if u not in sets:
                raise MudrftError(f"[mud] mud_set: no set {u!r} in [mud.sets]; defined: {', '.join(sets) or 'none'}")  # fmt: skip
    elif sets:
        raise MudrftError("[mud.sets] defines sets, but [mud] mud_set does not use any")
    elif "water_content" not in names:
        fixed["water_content"] = 0.25


def _add(
    section: str,
    key: str,
    raw: object,
    design: str,
    fixed: dict[str, Any],
    axes: list[Axis],
    *,
    motion_kind: str = "gait",
) -> None:
    p = C.motion_parameter(motion_kind, key) if section == "motion" else C.PARAMETERS[key]
    where = f"[{section}] {key}"
    if isinstance(raw, Mapping):
        axes.append(_range(where, p, dict(raw), design))
    elif isinstance(raw, list):
        if not p.sweepable:
            raise MudrftError(f"{where} cannot be swept; give one value")
        if design != "grid":
            raise MudrftError(f"{where}: a list of values is for grids; design = {design!r} draws from ranges: give {{low = ..., high = ...}}")  # fmt: skip
        if not raw:
            raise MudrftError(f"{where}: empty list; give at least one value")
        values = [_scalar(where, p, v) for v in raw]
        if len(set(values)) != len(values):
            raise MudrftError(f"{where} lists a value twice: {raw!r}")
        dtype = object if p.kind == "str" else (np.int64 if p.kind == "int" else float)
        axes.append(Axis(key, p.kind, values=np.array(values, dtype=dtype)))
    else:
        fixed[key] = _scalar(where, p, raw)


def _scalar(where: str, p: C.Parameter, v: object) -> Any:
    if p.kind == "bool":
        if not isinstance(v, bool):
            raise MudrftError(f"{where} must be true or false, got {v!r}")
        return v
    if p.kind == "str":
        if not isinstance(v, str):
            raise MudrftError(f"{where} must be a string, got {v!r}")
        if p.choices and v not in p.choices:
            raise MudrftError(f"{where} must be one of {', '.join(p.choices)}, got {v!r}")
        return v
    if isinstance(v, bool) or not isinstance(v, int | float):
        kinds = "an integer" if p.kind == "int" else "a number"
        raise MudrftError(f"{where} must be {kinds} [{p.unit}], a list of them or a table {{low, high, num}}, got {v!r}")  # fmt: skip
    if p.kind == "int" and not isinstance(v, int):
        raise MudrftError(f"{where} must be an integer, got {v!r}")
    if p.kind == "int" and not _INT_MIN <= v <= _INT_MAX:  # int64 coordinates, exact in float64
        raise MudrftError(f"{where} must be an integer of magnitude at most 2**53, got {v!r}")
    if not math.isfinite(v):
        raise MudrftError(f"{where} must be finite [{p.unit}], got {v!r}")
    return int(v) if p.kind == "int" else float(v)


def _range(where: str, p: C.Parameter, raw: dict[str, Any], design: str) -> Axis:
    if p.kind not in ("float", "int") or not p.sweepable:
        raise MudrftError(f"{where}: only numeric parameters take a range {{low, high}}")
    for key in raw:
        if key not in ("low", "high", "num", "log"):
            raise _unknown(where, key, ("low", "high", "num", "log"))
    for key in ("low", "high"):
        if key not in raw:
            raise MudrftError(f"{where}: a range needs low and high, {key} is missing")
    low = _scalar(f"{where} low", p, raw["low"])
    high = _scalar(f"{where} high", p, raw["high"])
    if not high > low:
        raise MudrftError(f"{where}: empty range, high ({high!r}) must be > low ({low!r})")
    if not math.isfinite(high - low):  # points drawn or spaced in it would be inf or NaN
        raise MudrftError(f"{where}: the range is too wide, high - low ({high!r} - {low!r}) is not a finite number")  # fmt: skip
    log = raw.get("log", False)
    if not isinstance(log, bool):
        raise MudrftError(f"{where} log must be true or false, got {log!r}")
    if log and p.kind == "int":  # drawn uniformly: log = true was ignored
        raise MudrftError(f"{where}: log applies to real ranges; an integer range is drawn uniformly")  # fmt: skip
    if log and low <= 0:
        raise MudrftError(f"{where}: a log range needs low > 0, got {low!r}")
    if design == "grid":
        if p.kind == "int":
            raise MudrftError(f"{where}: an integer parameter takes a list of values in a grid")
        if "num" not in raw:
            raise MudrftError(f"{where}: a grid range needs num (the number of values)")
        num = _integer(f"{where} num", raw["num"], 2)
        if num > MAX_POINTS:  # before the values are made (num = 1e12 took 7 TiB)
            raise MudrftError(f"{where} num = {num:.3g} values, more than a sweep's limit of {MAX_POINTS:.0e} points; split it into several sweeps")  # fmt: skip
        values = np.geomspace(low, high, num) if log else np.linspace(low, high, num)
        return Axis(p.name, p.kind, values=values, low=low, high=high, log=log)
    if "num" in raw:
        raise MudrftError(f"{where}: num is for grids; a {design} sample has [sweep] n points")
    return Axis(p.name, p.kind, low=low, high=high, log=log)


def _plot(plot: dict[str, Any], axes: list[Axis], metrics: tuple[str, ...]) -> dict[str, Any]:
    names = [a.name for a in axes]
    out: dict[str, Any] = {}
    for key, value in plot.items():
        if key not in _PLOT_KEYS:
            raise _unknown("[plot]", key, _PLOT_KEYS)
        if key == "metrics":
            bad = [m for m in (value if isinstance(value, list) else [value]) if m not in metrics]
            if bad or not value:
                raise MudrftError(f"[plot] metrics must name measured metrics ({', '.join(metrics)}), got {value!r}")  # fmt: skip
            out[key] = tuple(value) if isinstance(value, list) else (value,)
        elif value not in names:
            raise MudrftError(f"[plot] {key} must be a swept parameter ({', '.join(names) or 'none'}), got {value!r}")  # fmt: skip
        else:
            out[key] = value
    used = [k for k in ("x", "y", "panels") if k in out]
    for i, key in enumerate(used):
        for other in used[:i]:
            if out[key] == out[other]:
                raise MudrftError(f"[plot] {other} and {key} are both {out[key]!r}; a map needs a different parameter for each")  # fmt: skip
    return out
