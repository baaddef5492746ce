"""Run any terrain along a trajectory and compare terrains (supplementary Figs. S5, S6)."""

from __future__ import annotations

import csv
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from .. import metrics
from .._progress import make_progress
from .._validation import MudrftError, plain
from ..feet.base import Foot
from ..io.atomic import atomic_write
from ..parameters import Mud, paper_mud
from ..terrains import MudTerrain, Terrain
from ..terrains.base import projected
from ..terrains.granular_rft import GranularRFT
from ..terrains.granular_rft3d import GranularRFT3D
from ..terrains.linear import LinearStiffness
from ..terrains.maxwell import MaxwellMud
from ..terrains.rigid import RigidGround
from ..trajectories import Trajectory, check_unburied

__all__ = [
    "CSV_COLUMNS", "TERRAIN_NAMES", "History", "compare", "default_terrains", "normalized_loop",
    "run_terrain", "summarize", "write_csv"
]  # fmt: skip

#: Columns of ``compare.csv`` (long format: one row per terrain and sample).
CSV_COLUMNS = (
    "trajectory", "terrain", "time [s]", "x [m]", "y [m]", "z [m]", "depth [m]", "Fx [N]",
    "Fy [N]", "Fz [N]", "sigma_z [Pa]",
)  # fmt: skip


@dataclass(frozen=True, eq=False)
class History:
    """A terrain's response along a trajectory: ``name``; ``time`` (n,) [s]; tip ``position``
    (n, 3) [m] and ``velocity`` (n, 3) [m/s]; ``force`` of the terrain on the foot (n, 3) [N],
    world frame; the terrain's own channel (or mean) ``stress`` (n, 3) [Pa]; tip ``depth`` (n,)
    [m]; submerged footprint ``area`` :math:`A_z(d)` (n,) [m^2]."""

    name: str
    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    stress: np.ndarray
    depth: np.ndarray
    area: np.ndarray

    @property
    def sigma_z(self) -> np.ndarray:
        """Vertical stress :math:`F_z/A_z` [Pa] (0 out of the terrain)."""
        safe = np.where(self.area > 0, self.area, 1.0)
        return np.where(self.area > 0, self.force[:, 2] / safe, 0.0)

    def __len__(self) -> int:
        return int(self.time.size)


def _check_foot_trajectory(foot: Any, trajectory: Any) -> None:
    if not isinstance(trajectory, Trajectory):
        raise MudrftError(
            f"trajectory must be a Trajectory (see mudrft.gait), got {type(trajectory).__name__}"
        )
    if not isinstance(foot, Foot):
        raise MudrftError(f"foot must be a Foot (see mudrft.feet), got {type(foot).__name__}")


def run_terrain(
    terrain: Terrain, foot: Foot, trajectory: Trajectory, *,
    progress: Callable[[int, int], None] | None = None,
) -> History:  # fmt: skip
    """Drive ``foot`` along ``trajectory`` through ``terrain`` and record the forces.

    The force at sample ``i`` comes from the step that ends there (D58); ``progress(i, n)``,
    if given, is called every 500 samples.

    >>> import mudrft
    >>> from mudrft.baselines import LinearStiffness
    >>> h = run_terrain(LinearStiffness(), mudrft.feet.Flat(), mudrft.plate_intrusion())
    >>> round(float(h.force[:, 2].max()), 1)      # k d A = 1.09e6 * 0.03 * 0.0052
    170.0
    """
    _check_foot_trajectory(foot, trajectory)
    if not (hasattr(terrain, "initial_state") and hasattr(terrain, "step")):
        raise MudrftError(
            "terrain must have initial_state() and step() (see mudrft.terrains), "
            f"got {type(terrain).__name__}"
        )
    t, pos, vel = trajectory.time, trajectory.position, trajectory.velocity
    n = t.size
    force, stress = np.zeros((n, 3)), np.zeros((n, 3))
    state = terrain.initial_state(foot, pos[0])
    for i in range(n):
        dt = float(t[i] - t[i - 1]) if i > 0 else float(t[1] - t[0])
        state, out = terrain.step(foot, state, pos[i], vel[i], dt)
        force[i], stress[i] = out.force, out.stress
        if progress is not None and (i % 500 == 0 or i == n - 1):
            progress(i + 1, n)
    if not np.all(np.isfinite(force)):
        bad = int(np.argmax(~np.all(np.isfinite(force), axis=1)))
        raise MudrftError(
            f"terrain {getattr(terrain, 'name', terrain)!r} returned a non-finite force "
            f"at t = {plain(t[bad])} s"
        )
    depth = trajectory.depth
    name = str(getattr(terrain, "name", type(terrain).__name__))
    return History(name, t, pos, vel, force, stress, depth, projected(foot, depth)[:, 2])


#: Names of :func:`default_terrains`, in their order.
TERRAIN_NAMES = ("mud", "granular-rft", "granular-rft3d", "linear", "maxwell", "rigid")


def default_terrains(
    water_content: float = 0.25, *, extrapolate: bool = False
) -> dict[str, Terrain]:
    """The mud model and the five baselines with their defaults, by name (:data:`TERRAIN_NAMES`).

    ``water_content`` [-] selects the mud (``extrapolate`` as :func:`mudrft.paper_mud`).
    """
    mud = MudTerrain(paper_mud(water_content, extrapolate=extrapolate))
    terrains = (mud, GranularRFT(), GranularRFT3D(), LinearStiffness(), MaxwellMud(), RigidGround())
    return {t.name: t for t in terrains}


def compare(
    foot: Foot, trajectory: Trajectory,
    terrains: Mapping[str, Terrain] | Iterable[Terrain] | None = None, *,
    water_content: float = 0.25, extrapolate: bool = False,
    progress: bool | Callable[[float], None] = False, strict: bool = False,
) -> dict[str, History]:  # fmt: skip
    """Run several terrains on the same foot and trajectory: ``{name: History}``, in the order
    given.

    Parameters
    ----------
    foot : Foot
        The foot (granular RFT needs ``foot.elements()``).
    trajectory : Trajectory
        Prescribed tip motion, e.g. :func:`mudrft.plate_intrusion` or :func:`mudrft.gait`.
    terrains : mapping name -> terrain, iterable of terrains or names, or None, optional
        Terrains (``GranularRFT(zeta=...)``, a :class:`~mudrft.Mud`, ...) or names of
        :func:`default_terrains`, mixed freely; default: all of them.
    water_content, extrapolate : keyword-only
        Mud water content [-] of the default terrains, and whether it may lie outside the
        tabulated rows (warns).
    progress : bool or callable, keyword-only
        Report the share of terrains run: ``True`` through the ``mudrft.progress`` logger,
        a callable with the fraction done.
    strict : bool, keyword-only
        Refuse a trajectory that takes the foot deeper than its height, instead of warning
        (:class:`~mudrft.trajectories.BuriedFootWarning`), as :func:`mudrft.simulate`.

    Examples
    --------
    >>> import mudrft
    >>> from mudrft.baselines import GranularRFT, LinearStiffness
    >>> foot, plate = mudrft.feet.Flat(), mudrft.plate_intrusion(depth=0.02)
    >>> out = compare(foot, plate, [GranularRFT(), LinearStiffness()])
    >>> list(out)
    ['granular-rft', 'linear']
    >>> list(compare(foot, plate, ["mud", GranularRFT(zeta=0.464e6, name="poppy-cp")]))
    ['mud', 'poppy-cp']
    """
    _check_foot_trajectory(foot, trajectory)
    if terrains is None:
        items = list(default_terrains(water_content, extrapolate=extrapolate).items())
    elif isinstance(terrains, str):
        raise MudrftError(
            f"terrains must be a list of terrains or names, got the string {terrains!r} "
            f"(write [{terrains!r}]; names: {list(TERRAIN_NAMES)})"
        )
    elif isinstance(terrains, Mapping):
        items = [
            (str(k), _terrain(f"terrains[{k!r}]", v, water_content, extrapolate))
            for k, v in terrains.items()
        ]
    else:
        items = []
        for i, t in enumerate(terrains):
            t = _terrain(f"terrains[{i}]", t, water_content, extrapolate)
            items.append((str(getattr(t, "name", type(t).__name__)), t))
    if not items:
        raise MudrftError("terrains must name at least one terrain, got none")
    how, deepest = f"{trajectory.name}: the tip goes", float(trajectory.depth.max())
    check_unburied(foot.name, foot.height, deepest, how=how, strict=bool(strict))
    names = [k for k, _ in items]
    if len(set(names)) != len(names):
        raise MudrftError(f"terrain names must be unique, got {names}")
    out: dict[str, History] = {}
    report = make_progress(progress, f"compare on {trajectory.name}")
    for i, (name, terrain) in enumerate(items):
        out[name] = replace(run_terrain(terrain, foot, trajectory), name=name)
        if report is not None:
            report((i + 1) / len(items))
    return out


def _terrain(label: str, value: Any, water_content: float, extrapolate: bool) -> Terrain:
    """A terrain object from ``value``: a terrain, a Mud, or the name of a default terrain."""
    if isinstance(value, str):
        if value not in TERRAIN_NAMES:
            raise MudrftError(
                f"{label} must be a terrain or one of the names {list(TERRAIN_NAMES)}, "
                f"got {value!r}"
            )
        return default_terrains(water_content, extrapolate=extrapolate)[value]
    if isinstance(value, type):
        raise MudrftError(
            f"{label} must be a terrain object, got the class {value.__name__} "
            f"(write {value.__name__}() with its options)"
        )
    if isinstance(value, Mud):
        return MudTerrain(value)
    if not isinstance(value, Terrain):
        raise MudrftError(
            f"{label} must be a terrain (mudrft.terrains), a Mud or one of the names "
            f"{list(TERRAIN_NAMES)}, got {_what(value)}"
        )
    return value


def _check_history(name: str, value: Any) -> None:
    if not isinstance(value, History):
        raise MudrftError(
            f"{name} must be a History (run_terrain's or compare's result), got {_what(value)}"
        )


def summarize(histories: Mapping[str, History]) -> list[dict[str, Any]]:
    """Per terrain: peak support, max suction [N], impulses [N s], energy [J], peak sigma_z [Pa]."""
    if not isinstance(histories, Mapping):
        raise MudrftError(
            f"histories must be a mapping {{terrain: History}}, got {_what(histories)}"
        )
    rows = []
    for name, h in histories.items():
        _check_history(f"histories[{name!r}]", h)
        imp = metrics.impulse(h.time, h.force)
        rows.append(
            {
                "terrain": name,
                "peak_support [N]": metrics.peak_support(h.force[:, 2]),
                "max_suction [N]": metrics.max_suction(h.force[:, 2]),
                **{f"impulse_{c} [N s]": float(v) for c, v in zip("xyz", imp, strict=True)},
                "energy [J]": metrics.energy(h.time, h.force, h.velocity),
                "peak_sigma_z [Pa]": float(np.max(h.sigma_z)),
            }
        )
    return rows


def write_csv(
    runs: Mapping[str, Mapping[str, History]] | Mapping[str, History], path: str | Path, *,
    overwrite: bool = False,
) -> Path:  # fmt: skip
    """Write histories to ``path`` in long format (:data:`CSV_COLUMNS`), one row per sample,
    atomically; ``runs`` is ``{trajectory label: {terrain: History}}`` or one
    ``{terrain: History}`` (label ``""``); an existing file is replaced only with ``overwrite``."""
    if not isinstance(runs, Mapping) or not runs:
        raise MudrftError(
            "runs must be a non-empty mapping {terrain: History} (compare's result) or "
            f"{{label: {{terrain: History}}}}, got {_what(runs)}"
        )
    nested: Mapping[str, Any] = runs
    if all(isinstance(v, History) for v in runs.values()):
        nested = {"": runs}
    for label, histories in nested.items():
        if (
            not isinstance(histories, Mapping)
            or not histories
            or not all(isinstance(h, History) for h in histories.values())
        ):
            raise MudrftError(
                f"runs[{label!r}] must be a non-empty mapping {{terrain: History}}, got "
                f"{_what(histories)}"
            )

    def write(tmp: Path) -> None:
        with tmp.open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(CSV_COLUMNS)
            for label, histories in nested.items():
                for name, h in histories.items():
                    cols = np.column_stack([h.time, h.position, h.depth, h.force, h.sigma_z])
                    w.writerows([label, name, *(f"{v:.6g}" for v in row)] for row in cols)

    return atomic_write(path, write, overwrite=overwrite, option="overwrite=True (--force)")


def _what(value: Any) -> str:
    """A short description of a wrong argument, for messages."""
    if isinstance(value, Mapping) and not value:
        return "an empty mapping"
    return f"{type(value).__name__} {plain(value)}"[:120]


def normalized_loop(history: History) -> tuple[np.ndarray, np.ndarray]:
    """Fig. S6a axes: depth over its maximum and F_z over max |F_z| [-]."""
    _check_history("history", history)
    d, f = history.depth, history.force[:, 2]
    dmax, fmax = float(d.max()), float(np.abs(f).max())
    return (d / dmax if dmax > 0 else d.copy()), (f / fmax if fmax > 0 else f.copy())
