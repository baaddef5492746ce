"""The sweep spec: a TOML file (or a dict of the same shape) read into dataclasses, every
mistake an error naming the key before anything runs (``examples/sweep_example.toml``).

>>> spec = load_spec({"foot": {"kind": "flat", "width": [0.05, 0.065]},
...                   "mud": {"water_content": {"low": 0.25, "high": 0.45, "num": 3}}})
>>> spec.dims, spec.shape, spec.n_points
(('width', 'water_content'), (2, 3), 6)

The spec's points and chunks (one chunk = one task = one block of the store): a grid has
one dimension per swept parameter, cut into blocks of about ``points_per_task`` points; a
sample (Latin hypercube or scrambled Sobol, :mod:`scipy.stats.qmc`, seeded) has one
dimension ``point``. The same spec gives the same points and chunks on any machine.

>>> d = SweepSpec("grid", (Axis("a", "float", values=np.arange(5.0)),
...                        Axis("b", "float", values=np.arange(4.0))), points_per_task=3)
>>> d.chunks, d.n_chunks
((1, 2), 10)
>>> d.chunk_points(1)
[{'a': 0.0, 'b': 2.0}, {'a': 0.0, 'b': 3.0}]
"""

from __future__ import annotations

import difflib
import hashlib
import inspect
import json
import math
import os
import tomllib
import typing
from collections.abc import Iterable, Mapping
from dataclasses import MISSING, dataclass, field, fields
from functools import cached_property
from itertools import product
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar, cast

import numpy as np

from .._validation import MudrftError
from ..feet import MeshFoot
from ..feet.mesh import UP_AXES
from ..units import SCALE
from .catalog import FOOT_KINDS, METRICS, MOTION_KINDS, MOTIONS, PARAMETERS, Parameter
from .plot import check_names

if TYPE_CHECKING:
    from .evaluate import SweepContext

#: The designs of a sweep.
DESIGNS = ("grid", "lhs", "sobol")
#: Largest number of points of one sweep.
MAX_POINTS = 10_000_000
_MESH_SUFFIXES = (".stl", ".obj", ".ply")
#: With ``points_per_task`` unset, a sweep is cut into about this many tasks of at most
#: ``MAX_POINTS_PER_TASK`` points (a few seconds of a closed-form foot's gaits).
AUTO_TASKS = 32
MAX_POINTS_PER_TASK = 64


@dataclass(frozen=True, eq=False)
class Axis:
    """A swept parameter ``name`` of ``kind`` ("float", "int", "str"): grid ``values``, or
    a range ``[low, high]`` [SI] a sample draws from (a grid range keeps it for the
    record), spaced or drawn uniformly in the logarithm with ``log``."""

    name: str
    kind: str
    values: np.ndarray | None = None
    low: float | None = None
    high: float | None = None
    log: bool = False

    def as_json(self) -> dict[str, Any]:
        """The axis as plain data."""
        out: dict[str, Any] = {"name": self.name, "kind": self.kind}
        if self.values is not None:
            out["values"] = self.values.tolist()
        if self.low is not None:
            out.update(low=self.low, high=self.high, log=self.log)
        return out

    def draw(self, u: np.ndarray) -> np.ndarray:
        """Map uniform numbers ``u`` in [0, 1) onto the range."""
        lo, hi = float(self.low), float(self.high)  # type: ignore[arg-type]
        if self.kind == "int":
            return np.minimum(np.floor(lo + u * (hi - lo + 1)), hi).astype(np.int64)
        if self.log:
            return np.exp(math.log(lo) + u * (math.log(hi) - math.log(lo)))
        return lo + u * (hi - lo)


def block(shape: tuple[int, ...], chunks: tuple[int, ...], i: int) -> tuple[slice, ...]:
    """The block of chunk ``i`` of an array of ``shape`` cut into ``chunks`` (C order)."""
    index = np.unravel_index(int(i), [math.ceil(s / c) for s, c in zip(shape, chunks, strict=True)])  # fmt: skip
    return tuple(slice(int(k) * c, min((int(k) + 1) * c, s)) for k, c, s in zip(index, chunks, shape, strict=True))  # fmt: skip


# -- the tables of a spec, as dataclasses -----------------------------------------------------
# A field's type is checked by _table; ``metadata={"ge": k}`` bounds an integer.
@dataclass(frozen=True)
class Options:
    """``[sweep]``: the design, sample size and seed, metrics, points per task."""

    design: Literal["grid", "lhs", "sobol"] = "grid"
    n: int | None = field(default=None, metadata={"ge": 1})
    seed: int | None = field(default=None, metadata={"ge": 0})
    metrics: list[str] | str | None = None
    points_per_task: int | None = field(default=None, metadata={"ge": 1})

    def __post_init__(self) -> None:
        if self.design == "grid":
            for key in ("n", "seed"):
                if getattr(self, key) is not None:
                    raise MudrftError(f"[sweep] {key} is for sample designs (lhs, sobol), not a grid")  # fmt: skip
        elif self.n is None:
            raise MudrftError(f"[sweep] n (the number of points) is required for design = {self.design!r}")  # fmt: skip
        elif self.design == "sobol" and self.n & (self.n - 1):
            raise MudrftError(
                f"[sweep] n must be a power of 2 for a Sobol sample (its balance properties), got "
                f"{self.n}; use {1 << (self.n - 1).bit_length()} or design = 'lhs'"
            )


@dataclass(frozen=True)
class Range:
    """A parameter's range ``{low, high, num, log}``; low and high are checked as its values."""

    low: Any
    high: Any
    num: int | None = field(default=None, metadata={"ge": 2})
    log: bool = False


@dataclass(frozen=True)
class MudSet:
    """``[mud.sets.NAME]``: parameter JSON files of ``mudrft calibrate --out``."""

    vertical: str
    horizontal: str


@dataclass(frozen=True)
class PlotOptions:
    """``[plot]``: the maps' swept parameters and metrics (names)."""

    x: str | None = None
    y: str | None = None
    panels: str | None = None
    metrics: list[str] | str | None = None


_SECTIONS = ("sweep", "foot", "mud", "motion", "plot")
_T = TypeVar("_T")


def _unknown(where: str, key: str, allowed: Iterable[str]) -> MudrftError:
    near = difflib.get_close_matches(str(key), list(allowed), n=1)
    hint = f" (did you mean {near[0]!r}?)" if near else ""
    return MudrftError(f"{where} {key}: unknown key{hint}; expected one of {', '.join(allowed)}")


def _check_type(where: str, value: object, hint: Any, ge: int | None) -> None:
    options = [h for h in typing.get_args(hint) if h is not type(None)] or [hint]
    if typing.get_origin(hint) is Literal:
        if value not in options:
            raise MudrftError(f"{where} must be one of {', '.join(options)}, got {value!r}")
        return
    for h in options:
        if h is Any or (h is bool and isinstance(value, bool)):
            return
        if h is int and isinstance(value, int) and not isinstance(value, bool):
            if ge is not None and value < ge:
                break
            return
        if h is str and isinstance(value, str):
            return
        if typing.get_origin(h) is list and isinstance(value, list) and value:
            if all(isinstance(v, str) for v in value):
                return
    names = {int: "an integer", bool: "true or false", str: "a string"}
    what = " or ".join(names.get(h, "a non-empty list of strings") for h in options)
    bound = f" >= {ge}" if ge is not None else ""
    raise MudrftError(f"{where} must be {what}{bound}, got {value!r}")


def _section(raw: object, where: str) -> dict[str, Any]:
    if not isinstance(raw, Mapping):
        raise MudrftError(f"{where} must be a table, got {type(raw).__name__}: {raw!r}")
    return dict(raw)


def _table(cls: type[_T], raw: object, where: str) -> _T:
    """``raw`` (a TOML table) as a ``cls``: unknown keys, missing keys and types named."""
    table = _section(raw, where)
    hints = typing.get_type_hints(cls)
    names = [f.name for f in fields(cls)]  # type: ignore[arg-type]
    for key in table:
        if key not in names:
            raise _unknown(where, key, names)
    for f in fields(cls):  # type: ignore[arg-type]
        if f.name in table:
            _check_type(f"{where} {f.name}", table[f.name], hints[f.name], f.metadata.get("ge"))
        elif f.default is MISSING:
            raise MudrftError(f"{where} needs {f.name}, it is missing")
    return cls(**table)


# -- the resolved spec ------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SweepSpec:
    """A checked, resolved sweep spec (made by :func:`load_spec`): a ``design`` ("grid",
    "lhs", "sobol") over ``axes`` (in spec order), ``n`` points from ``seed`` for a sample,
    about ``points_per_task`` points a chunk (0: ``ceil(points / AUTO_TASKS)`` clipped to [1,
    MAX_POINTS_PER_TASK]); the ``motion`` and ``metrics``, the ``fixed`` parameters (SI;
    ``foot`` is the kind or mesh file), calibrated ``mud_sets`` (``{"vertical": {...},
    "horizontal": {...}, "source": str}``), the ``mesh`` foot, the maps' ``plot`` names, and
    the spec's ``text`` and where it came from."""

    design: str
    axes: tuple[Axis, ...]
    n: int | None = None
    seed: int | None = None
    points_per_task: int = 0
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
        names = ("motion", "metrics", "mud_sets", "mesh")
        return cast(
            "SweepContext", {"fixed": dict(self.fixed)} | {k: getattr(self, k) for k in names}
        )

    def parameter(self, name: str) -> Parameter:
        """The catalog entry of a parameter of this spec (a motion's own for motion names)."""
        return MOTIONS[self.motion].get(name) or PARAMETERS[name]

    def identity(self) -> str:
        """A hash of everything that decides the values (not the plot): a store made from
        another spec is not resumed."""
        mesh = None
        if self.mesh is not None:
            h = hashlib.sha256(np.ascontiguousarray(self.mesh.vertices).tobytes())
            h.update(np.ascontiguousarray(self.mesh.faces).tobytes())
            mesh = h.hexdigest()
        names = ("design", "n", "seed", "fixed", "motion", "metrics", "points_per_task", "chunks")
        doc = {k: getattr(self, k) for k in names} | {
            "axes": [a.as_json() for a in self.axes],
            "mud_sets": {k: {d: v[d] for d in ("vertical", "horizontal")} for k, v in self.mud_sets.items()},
            "mesh": mesh,
        }  # fmt: skip
        return hashlib.sha256(json.dumps(doc, sort_keys=True, default=str).encode()).hexdigest()

    @property
    def dims(self) -> tuple[str, ...]:
        """Dimensions of the result: the swept parameters (grid) or ``("point",)``."""
        return tuple(a.name for a in self.axes) if self.design == "grid" else ("point",)

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the result."""
        if self.design == "grid":
            return tuple(len(a.values) for a in self.axes)  # type: ignore[arg-type]
        return (int(self.n),)  # type: ignore[arg-type]

    @property
    def n_points(self) -> int:
        """Number of points."""
        return math.prod(self.shape)

    @cached_property
    def sample(self) -> dict[str, np.ndarray]:
        """A sample design's points: the values of every swept parameter, shape (n,)."""
        if self.design == "grid":
            return {}
        from scipy.stats import qmc

        d, n = len(self.axes), int(self.n)  # type: ignore[arg-type]
        # scipy names the generator rng= from 1.15 and seed= before (mudrft supports 1.10)
        key = "rng" if "rng" in inspect.signature(qmc.LatinHypercube).parameters else "seed"
        gen = {key: np.random.default_rng(self.seed)}
        if self.design == "lhs":
            u = qmc.LatinHypercube(d, **gen).random(n)
        else:
            u = qmc.Sobol(d, scramble=True, **gen).random_base2(int(math.log2(n)))
        return {a.name: a.draw(u[:, i]) for i, a in enumerate(self.axes)}

    def coords(self) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Coordinates of the swept parameters: ``name -> (dims, values)``."""
        if self.design == "grid":
            return {a.name: ((a.name,), a.values) for a in self.axes}  # type: ignore[misc]
        return {name: (("point",), v) for name, v in self.sample.items()}

    @property
    def chunk_size(self) -> int:
        """Target points per chunk (and per task)."""
        if self.points_per_task:
            return int(self.points_per_task)
        return min(max(math.ceil(self.n_points / AUTO_TASKS), 1), MAX_POINTS_PER_TASK)

    @cached_property
    def chunks(self) -> tuple[int, ...]:
        """Chunk shape: blocks filled from the last dimension, balanced within each."""
        budget = self.chunk_size
        if self.design != "grid":
            return (min(budget, self.n_points),)
        out = [1] * len(self.shape)
        for d in reversed(range(len(self.shape))):
            size = self.shape[d]
            if budget <= 1:
                break
            blocks = math.ceil(size / budget)
            out[d] = math.ceil(size / blocks)
            budget //= out[d]
        return tuple(out)

    @property
    def n_chunks(self) -> int:
        """Number of chunks (tasks)."""
        return math.prod(math.ceil(s / c) for s, c in zip(self.shape, self.chunks, strict=True))

    def chunk_slices(self, i: int) -> tuple[slice, ...]:
        """The block of chunk ``i`` (C order over the chunk grid)."""
        return block(self.shape, self.chunks, i)

    def chunk_shape(self, i: int) -> tuple[int, ...]:
        """Shape of the block of chunk ``i``."""
        return tuple(s.stop - s.start for s in self.chunk_slices(i))

    def chunk_points(self, i: int) -> list[dict[str, Any]]:
        """The points of chunk ``i`` (C order within the block), as plain Python values."""
        sl = self.chunk_slices(i)
        if self.design == "grid":
            names = [a.name for a in self.axes]
            cols = [a.values[s].tolist() for a, s in zip(self.axes, sl, strict=True)]  # type: ignore[index]
            return [dict(zip(names, combo, strict=True)) for combo in product(*cols)]
        cols2 = {k: arr[sl[0]].tolist() for k, arr in self.sample.items()}
        return [dict(zip(cols2, row, strict=True)) for row in zip(*cols2.values(), strict=True)]


def load_spec(spec: str | os.PathLike[str] | Mapping[str, Any] | SweepSpec) -> SweepSpec:
    """Read and check a sweep spec: a TOML file, a dict of the same shape
    (``{"foot": {...}, "mud": {...}, ...}``) or a loaded spec (returned as is); a
    :class:`~mudrft.MudrftError` naming the key for any mistake."""
    if isinstance(spec, SweepSpec):
        return spec
    if isinstance(spec, Mapping):
        text = json.dumps(dict(spec), indent=1, default=str)
        return _resolve(dict(spec), text=text, where="<dict>", base=Path.cwd())
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


def _resolve(data: dict[str, Any], *, text: str, where: str, base: Path) -> SweepSpec:
    for key in data:
        if key not in _SECTIONS:
            near = difflib.get_close_matches(str(key), _SECTIONS, n=1)
            hint = f" (did you mean [{near[0]}]?)" if near else ""
            raise MudrftError(f"unknown section [{key}]{hint}; expected {', '.join(f'[{s}]' for s in _SECTIONS)}")  # fmt: skip
    opts = _table(Options, data.get("sweep", {}), "[sweep]")
    foot, mud, motion = (_section(data.get(s, {}), f"[{s}]") for s in ("foot", "mud", "motion"))
    motion_kind = motion.pop("kind", "gait")
    if motion_kind not in MOTION_KINDS:
        raise MudrftError(f"[motion] kind must be one of {', '.join(MOTION_KINDS)}, got {motion_kind!r}")  # fmt: skip
    known = tuple(METRICS[motion_kind])
    chosen = [opts.metrics] if isinstance(opts.metrics, str) else opts.metrics or []
    for v in chosen:
        if v not in known:
            raise MudrftError(f"[sweep] metrics: unknown metric {v!r} for motion {motion_kind!r}; expected {', '.join(known)}")  # fmt: skip
    if len(set(chosen)) != len(chosen):
        raise MudrftError(f"[sweep] metrics lists a metric twice: {opts.metrics!r}")
    metrics = tuple(chosen) or known

    fixed: dict[str, Any] = {}
    axes: list[Axis] = []
    kinds, mesh = _foot_kind(foot, opts.design, base, fixed, axes)
    allowed = sorted({p for k in kinds for p in FOOT_KINDS.get(k, ())})
    for key, raw in foot.items():
        if key not in allowed:
            if mesh is not None:
                raise MudrftError(f"[foot] {key}: a mesh foot has no parameters (only unit and up)")
            what = f"the {kinds[0]} foot" if len(kinds) == 1 else f"the feet {', '.join(kinds)}"
            raise MudrftError(f"[foot] {key}: not a parameter of {what}; expected one of {', '.join(allowed)}")  # fmt: skip
        _add(f"[foot] {key}", PARAMETERS[key], raw, opts.design, fixed, axes)
    sets = mud.pop("sets", None)
    if sets is not None and (not isinstance(sets, Mapping) or not sets):
        raise MudrftError(f"[mud.sets] must be a table of named sets, got {sets!r}")
    mud_sets = {str(k): _mud_set(f"[mud.sets.{k}]", v, base) for k, v in (sets or {}).items()}
    mud_allowed = [p.name for p in PARAMETERS.values() if p.section == "mud"]
    for key, raw in mud.items():
        if key not in mud_allowed:
            raise _unknown("[mud]", key, [*mud_allowed, "sets"])
        _add(f"[mud] {key}", PARAMETERS[key], raw, opts.design, fixed, axes)
    _check_mud_source(fixed, axes, mud_sets)
    for key, raw in motion.items():
        if key not in MOTIONS[motion_kind]:
            raise _unknown(f"[motion] ({motion_kind})", key, ["kind", *MOTIONS[motion_kind]])
        _add(f"[motion] {key}", MOTIONS[motion_kind][key], raw, opts.design, fixed, axes)
    if motion_kind == "load" and "weight" not in motion:
        raise MudrftError("[motion] weight is required for kind = 'load' (the load on the foot [N])")  # fmt: skip
    if opts.design != "grid" and not axes:
        raise MudrftError(f"[sweep] design = {opts.design!r} needs at least one range to sample")
    spec = SweepSpec(
        design=opts.design,
        axes=tuple(axes),
        n=opts.n,
        seed=None if opts.design == "grid" else opts.seed or 0,
        points_per_task=opts.points_per_task or (1 if motion_kind == "walk" else 0),
        motion=motion_kind,
        metrics=metrics,
        fixed=fixed,
        mud_sets=mud_sets,
        mesh=mesh,
        plot=_plot(_table(PlotOptions, data.get("plot", {}), "[plot]"), axes, metrics),
        text=text,
        where=where,
    )
    if spec.n_points > MAX_POINTS:
        raise MudrftError(
            f"the sweep has {spec.n_points:.3g} points, more than the limit {MAX_POINTS:.0e}; "
            f"split it into several sweeps"
        )
    return spec


def _foot_kind(
    foot: dict[str, Any], design: str, base: Path, fixed: dict[str, Any], axes: list[Axis]
) -> tuple[tuple[str, ...], MeshFoot | None]:
    if "kind" not in foot:
        raise MudrftError(
            "[foot] kind is required: flat, semi-cylinder, semi-sphere, morphing or a mesh "
            "file (.stl/.obj/.ply), or a list of the named feet"
        )
    kind = foot.pop("kind")
    if isinstance(kind, str) and kind.lower().endswith(_MESH_SUFFIXES):
        unit, up = foot.pop("unit", "m"), foot.pop("up", "z")
        if not isinstance(unit, str) or unit.strip() not in SCALE["length"]:
            raise MudrftError(f'[foot] unit must be the length unit of the mesh file, a string such as "m" or "mm" (one of {", ".join(sorted(SCALE["length"]))}), got {unit!r}')  # fmt: skip
        if not isinstance(up, str) or up not in UP_AXES:
            axes_ = ", ".join(f'"{a}"' for a in UP_AXES)
            raise MudrftError(f"[foot] up must be the mesh file's up axis, a string, one of {axes_} (y for a y-up export), got {up!r}")  # fmt: skip
        path = base / kind  # an absolute kind replaces base
        try:
            mesh = MeshFoot.from_file(path, unit=unit, up=up)
        except MudrftError as exc:
            raise MudrftError(f"[foot] kind = {kind!r}: {exc}") from None
        fixed["foot"] = str(path)
        return ("mesh",), mesh
    for key in ("unit", "up"):
        if key in foot:
            raise MudrftError(f"[foot] {key} applies to mesh files only (.stl/.obj/.ply)")
    values = kind if isinstance(kind, list) else [kind]
    if not values or not all(isinstance(v, str) and v in FOOT_KINDS for v in values):
        raise MudrftError(f"[foot] kind must be one of {', '.join(FOOT_KINDS)} or a mesh file, or a list of the named feet, got {kind!r}")  # fmt: skip
    if isinstance(kind, list):
        if design != "grid":
            raise MudrftError(f"[foot] kind: a list of feet is for grids; design = {design!r} samples ranges only")  # fmt: skip
        if len(set(values)) != len(values):
            raise MudrftError(f"[foot] kind lists a foot twice: {kind!r}")
        axes.append(Axis("foot", "str", values=np.array(values, dtype=object)))
    else:
        fixed["foot"] = kind
    return tuple(values), None


def _mud_set(where: str, entry: object, base: Path) -> dict[str, Any]:
    from ..calibration.persistence import load_parameters

    files = _table(MudSet, entry, where)
    out: dict[str, Any] = {}
    sources = []
    for d in ("vertical", "horizontal"):
        path = base / getattr(files, d)
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
        out[d] = {k: float(v) for k, v in p.as_dict().items()}
        sources.append(f"{d}: {p.source or path}")
    out["source"] = "; ".join(sources)
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
    where: str, p: Parameter, raw: object, design: str, fixed: dict[str, Any], axes: list[Axis]
) -> None:
    """A parameter's value: a scalar (fixed), a list (grid values) or a range."""
    if not isinstance(raw, Mapping | list):
        fixed[p.name] = p.check(where, raw)
        return
    if not p.sweepable:
        raise MudrftError(f"{where} cannot be swept; give one value")
    if isinstance(raw, list):
        if design != "grid":
            raise MudrftError(f"{where}: a list of values is for grids; design = {design!r} draws from ranges: give {{low = ..., high = ...}}")  # fmt: skip
        if not raw:
            raise MudrftError(f"{where}: empty list; give at least one value")
        values = [p.check(where, v) for v in raw]
        if len(set(values)) != len(values):
            raise MudrftError(f"{where} lists a value twice: {raw!r}")
        dtype = {"str": object, "int": np.int64}.get(p.kind, float)
        axes.append(Axis(p.name, p.kind, values=np.array(values, dtype=dtype)))
        return
    if p.kind not in ("float", "int"):
        raise MudrftError(f"{where}: only numeric parameters take a range {{low, high}}")
    r = _table(Range, raw, where)
    low, high = p.check(f"{where} low", r.low), p.check(f"{where} high", r.high)
    if not high > low:
        raise MudrftError(f"{where}: empty range, high ({high!r}) must be > low ({low!r})")
    if not math.isfinite(high - low):  # points drawn or spaced in it would be inf or NaN
        raise MudrftError(f"{where}: the range is too wide, high - low ({high!r} - {low!r}) is not a finite number")  # fmt: skip
    if r.log and p.kind == "int":
        raise MudrftError(f"{where}: log applies to real ranges; an integer range is drawn uniformly")  # fmt: skip
    if r.log and low <= 0:
        raise MudrftError(f"{where}: a log range needs low > 0, got {low!r}")
    if design != "grid":
        if r.num is not None:
            raise MudrftError(f"{where}: num is for grids; a {design} sample has [sweep] n points")
        axes.append(Axis(p.name, p.kind, low=low, high=high, log=r.log))
        return
    if p.kind == "int":
        raise MudrftError(f"{where}: an integer parameter takes a list of values in a grid")
    if r.num is None:
        raise MudrftError(f"{where}: a grid range needs num (the number of values)")
    if r.num > MAX_POINTS:  # before the values are made (num = 1e12 took 7 TiB)
        raise MudrftError(f"{where} num = {r.num:.3g} values, more than a sweep's limit of {MAX_POINTS:.0e} points; split it into several sweeps")  # fmt: skip
    grid = (np.geomspace if r.log else np.linspace)(low, high, r.num)
    axes.append(Axis(p.name, p.kind, values=grid, low=low, high=high, log=r.log))


def _plot(plot: PlotOptions, axes: list[Axis], metrics: tuple[str, ...]) -> dict[str, Any]:
    names = {k: getattr(plot, k) for k in ("x", "y", "panels")}
    check_names(names, [a.name for a in axes], "[plot] ")
    out: dict[str, Any] = {k: v for k, v in names.items() if v is not None}
    if plot.metrics is not None:
        chosen = [plot.metrics] if isinstance(plot.metrics, str) else plot.metrics
        if any(m not in metrics for m in chosen):
            raise MudrftError(f"[plot] metrics must name measured metrics ({', '.join(metrics)}), got {plot.metrics!r}")  # fmt: skip
        out["metrics"] = tuple(chosen)
    return out
