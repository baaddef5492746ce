r"""Run a foot through mud (or any terrain): prescribed motion or prescribed load.

>>> import mudrft
>>> m = mudrft.simulate(mudrft.feet.Flat(), mudrft.paper_mud(0.25), mudrft.gait(0.2)).metrics()
>>> m["peak_support"] > 0 and m["energy"] > 0
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import metrics as _m
from ._progress import make_progress
from ._validation import (
    MudrftError,
    check_length,
    check_nonnegative,
    check_positive,
    check_samples,
    plain,
    positive_number,
    warn_plausibility,
)
from ._validation import set_number as _set
from .constitutive import laws
from .feet.base import Foot
from .io.atomic import atomic_write
from .parameters.base import Mud
from .plotting import AxesArg, plot_result
from .terrains import MudTerrain, as_terrain
from .terrains.mud import vertical_viscosity
from .terrains.rows import along_path
from .trajectories import MIN_GAIT_STEPS, Trajectory, check_unburied

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

    from .terrains.base import Terrain

__all__ = ["CSV_COLUMNS", "LoadControl", "Result", "simulate", "static_sinking"]

#: Columns of ``run.csv`` (DESIGN.md).
CSV_COLUMNS = ("time [s]", "x [m]", "y [m]", "z [m]", "Fx [N]", "Fy [N]", "Fz [N]")
G = 9.80665  # standard gravity [m/s^2]


@dataclass(frozen=True, eq=False)
class LoadControl:
    r"""A foot driven by a load: a body rests on it rigidly (:math:`m\ddot z = F_z - W`) or on a
    spring-damper leg, from rest at the surface (x = y = 0). The coupling is explicit:
    :func:`simulate` refuses a ``dt`` that does not resolve the mud's damping.

    Parameters
    ----------
    weight : float
        Load pressing the foot into the mud [N].
    mass : float or None, keyword-only
        Mass of the loaded body [kg]; default ``weight / g``.
    leg_stiffness : float or None, keyword-only
        Stiffness of a spring leg between body and foot [N/m]; None for a rigid leg.
    leg_damping : float, keyword-only
        Damping of the spring leg [N s/m].
    foot_mass : float, keyword-only
        Mass of the foot when a spring leg is used [kg].
    duration, dt : float, keyword-only
        Simulated time and time step [s].
    ramp : float, keyword-only
        Time over which the load rises linearly from 0 to ``weight`` [s]; 0 applies it at once.
    """

    weight: float
    mass: float | None = None
    leg_stiffness: float | None = None
    leg_damping: float = 0.0
    foot_mass: float = 0.5
    duration: float = 10.0
    dt: float = 1e-3
    ramp: float = 0.0

    def __post_init__(self) -> None:
        for name, unit, check in (
            ("weight", "N", check_positive),
            ("mass", "kg", check_positive),
            ("leg_stiffness", "N/m", check_positive),
            ("leg_damping", "N s/m", check_nonnegative),
            ("foot_mass", "kg", check_positive),
            ("duration", "s", check_positive),
            ("dt", "s", check_positive),
            ("ramp", "s", check_nonnegative),
        ):
            value = getattr(self, name)
            if value is not None or name not in ("mass", "leg_stiffness"):
                _set(self, name, check(name, value, unit=unit))
        what = f"LoadControl: duration {self.duration:g} s at dt = {self.dt:g} s"
        hint = "use a larger dt or a shorter duration"
        check_samples(what, self.duration / self.dt + 1, hint=hint)

    @property
    def body_mass(self) -> float:
        """Mass of the loaded body [kg]."""
        return float(self.mass if self.mass is not None else self.weight / G)


@dataclass(frozen=True, eq=False)
class Result:
    """Outcome of :func:`simulate`.

    Attributes
    ----------
    time, depth : ndarray (n,)
        Times [s] and tip depth [m].
    position, velocity : ndarray (n, 3)
        Tip position [m] and velocity [m/s] in the world frame.
    force, stress : ndarray (n, 3)
        Force of the terrain on the foot [N]; channel stresses [Pa] (or zeros).
    foot, terrain : str
        Names.
    areas : ndarray (n, 3) or None
        Submerged areas projected along x, y and z [m^2].
    meta : dict
        Run settings (load control, trajectory name, ...).
    """

    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    stress: np.ndarray
    depth: np.ndarray
    foot: str = ""
    terrain: str = ""
    areas: np.ndarray | None = None
    meta: dict = field(default_factory=dict)

    def metrics(self) -> _m.Metrics:
        """The paper's metrics of this run (:func:`mudrft.metrics.cycle_metrics`)."""
        load = bool(self.meta.get("load_control"))
        return _m.cycle_metrics(self.time, self.force, self.velocity, self.depth, load=load)

    def normalized_stress(self) -> np.ndarray:
        """Force divided by the submerged cross-section areas (Figs. 10-12) [Pa], shape (n, 3)."""
        if self.areas is None:
            raise MudrftError(
                "this result has no areas; run simulate with a foot that provides them"
            )
        return _m.normalized_stress(self.force, self.areas)

    def to_csv(self, path: str | Path, *, overwrite: bool = False) -> Path:
        """Write :data:`CSV_COLUMNS` to ``path`` atomically; overwrite only with ``overwrite``."""
        data = np.column_stack([self.time, self.position, self.force])
        head = ",".join(CSV_COLUMNS)
        return atomic_write(
            path,
            lambda tmp: np.savetxt(tmp, data, delimiter=",", header=head, comments="", fmt="%.9g"),
            overwrite=overwrite,
            option="overwrite=True (CLI: --force)",
        )

    def to_pandas(self) -> pd.DataFrame:
        """The run as a ``pandas.DataFrame`` with the CSV columns plus stresses and depth."""
        try:
            import pandas as pd
        except ImportError as exc:  # pragma: no cover - depends on the environment
            raise ImportError("to_pandas needs pandas: pip install 'mudrft[pandas]'") from exc
        data = np.column_stack([self.time, self.position, self.force, self.stress, self.depth])
        columns = [*CSV_COLUMNS, "sx [Pa]", "sy [Pa]", "sz [Pa]", "depth [m]"]
        return pd.DataFrame(data, columns=columns)

    def plot(self, *, axes: AxesArg = None) -> Figure:
        """Forces against time and Fz against depth (needs matplotlib)."""
        return plot_result(self, axes=axes)

    def __len__(self) -> int:
        return int(self.time.size)

    def __repr__(self) -> str:
        return (
            f"Result(foot={self.foot!r}, terrain={self.terrain!r}, samples={len(self)}, "
            f"duration={self.time[-1] - self.time[0]:.4g} s, "
            f"max_depth={float(self.depth.max()):.4g} m)"
        )


def _resample(traj: Trajectory, dt: float) -> Trajectory:
    span = float(traj.time[-1] - traj.time[0])
    if span < MIN_GAIT_STEPS * dt * (1.0 - 1e-9):
        raise MudrftError(
            f"dt = {plain(dt)} s cuts the {span:.3g} s trajectory into fewer than "
            f"{MIN_GAIT_STEPS} steps; use dt <= {span / MIN_GAIT_STEPS:.3g} s"
        )
    what = f"simulate: the {span:.3g} s trajectory resampled at dt = {dt:g} s"
    check_samples(what, span / dt + 2, hint="use a larger dt")
    n = int(np.floor(span / dt + 1e-9)) + 1
    t = traj.time[0] + dt * np.arange(n)
    if t[-1] < traj.time[-1] - 1e-12:
        t = np.append(t, traj.time[-1])
    pos = np.stack([np.interp(t, traj.time, traj.position[:, i]) for i in range(3)], 1)
    # a sample's velocity holds over the step that ends there (D13b)
    k = np.minimum(np.searchsorted(traj.time, t, side="left"), traj.time.size - 1)
    vel = traj.velocity[k]
    return Trajectory(time=t, position=pos, velocity=vel, name=traj.name, meta=traj.meta)


def _areas(foot: Foot, depth: np.ndarray) -> np.ndarray | None:
    try:
        return np.asarray(foot.projected_areas(depth), dtype=float).reshape((*depth.shape, 3))
    except (MudrftError, NotImplementedError, AttributeError):
        return None


def simulate(
    foot: Foot, mud: Mud | Terrain, trajectory: Trajectory | LoadControl, *,
    dt: float | None = None, progress: bool | Callable[[float], None] = False,
    strict: bool = False,
) -> Result:  # fmt: skip
    """Run a foot through a terrain along a prescribed motion or under a prescribed load
    (Chen et al. 2026, eqs. 1-7 and 12-14).

    Parameters
    ----------
    foot : Foot
        Any foot of :mod:`mudrft.feet`.
    mud : Mud or Terrain
        The paper's mud (:func:`mudrft.paper_mud`), a :class:`mudrft.MudTerrain` with
        options, or any terrain of :mod:`mudrft.terrains`.
    trajectory : Trajectory or LoadControl
        Tip motion (:func:`mudrft.gait`, :func:`mudrft.plate_intrusion`, ...) or a load.
    dt : float or None, keyword-only
        Resample a trajectory at this step [s] (default: its own samples); at most the
        trajectory's duration / :data:`~mudrft.trajectories.MIN_GAIT_STEPS`. Ignored for
        load control, which has its own ``dt``.
    progress : bool or callable, keyword-only
        ``True`` logs progress through the ``mudrft`` logger; a callable is called as
        ``progress(fraction)`` with the fraction done.
    strict : bool, keyword-only
        Raise a :class:`~mudrft.MudrftError` instead of warning that the foot goes deeper
        than its own height (:class:`~mudrft.trajectories.BuriedFootWarning`).
    """
    if not isinstance(foot, Foot):
        raise MudrftError(
            f"foot must be a mudrft foot (mudrft.feet.Flat(), ...), got {type(foot).__name__}"
        )
    terrain = as_terrain(mud)
    report = make_progress(progress, f"{foot.name} in {getattr(terrain, 'name', 'terrain')}")
    if not isinstance(strict, bool):
        raise MudrftError(f"strict must be True or False, got {strict!r}")
    if isinstance(trajectory, LoadControl):
        return _simulate_load(foot, terrain, trajectory, report, strict)
    if not isinstance(trajectory, Trajectory):
        raise MudrftError(
            f"trajectory must be a Trajectory (mudrft.gait, mudrft.plate_intrusion) or a LoadControl, "
            f"got {type(trajectory).__name__}"
        )
    tr = trajectory if dt is None else _resample(trajectory, positive_number("dt", dt, unit="s"))
    how = f"{tr.name}: the tip goes"
    check_unburied(foot.name, foot.height, float(tr.depth.max()), how=how, strict=strict)
    n = len(tr)
    force, stress = np.zeros((n, 3)), np.zeros((n, 3))
    pos, vel, dts = tr.position, tr.velocity, np.diff(tr.time)
    rows = along_path(terrain, foot, pos, vel, dts) if isinstance(terrain, MudTerrain) else None
    if rows is not None:  # the mud under a foot of mudrft.feet, compiled (terrains.rows)
        force[1:], stress[1:] = rows[:, :3], rows[:, 3:6]
    else:  # a Trajectory is validated where it is made: the unchecked step may run
        state, every = terrain.initial_state(foot, tr.position[0]), max(n // 20, 1)
        step = getattr(terrain, "step_unchecked", terrain.step)
        for k in range(1, n):
            state, out = step(foot, state, pos[k], vel[k], float(dts[k - 1]))
            force[k], stress[k] = out.force, out.stress
            if report is not None and k % every == 0:
                report(k / (n - 1))
    if report is not None and rows is not None:
        report(1.0)
    if not np.all(np.isfinite(force)):
        raise MudrftError(
            "the simulation produced non-finite forces; check the terrain parameters and dt"
        )
    meta = {"trajectory": tr.name, **{k: v for k, v in tr.meta.items() if np.ndim(v) == 0}}
    return Result(
        tr.time, tr.position, tr.velocity, force, stress, tr.depth, foot.name,
        getattr(terrain, "name", ""), _areas(foot, tr.depth), meta,
    )  # fmt: skip


def _check_explicit_stability(foot: Foot, terrain: Terrain, load: LoadControl) -> None:
    mud = getattr(terrain, "mud", None)
    if mud is None or not hasattr(mud, "vertical"):
        return
    lc = float(getattr(terrain, "characteristic_length", None) or foot.characteristic_length)
    try:
        area = float(np.asarray(foot.projected_areas(foot.height))[..., 2].max())
    except Exception:
        return
    qs = bool(getattr(terrain, "quasi_static", False))
    c = vertical_viscosity(mud, quasi_static=qs) * area / lc
    m = load.foot_mass if load.leg_stiffness is not None else load.body_mass
    limit = 2.0 * m / c
    if load.dt > 0.8 * limit:
        raise MudrftError(
            f"LoadControl.dt={plain(load.dt)} s is too large for an explicit coupling: the mud damps the "
            f"{m:g} kg mass like a {c:.3g} N s/m damper, stable only for dt < {limit:.3g} s; "
            f"use dt <= {0.5 * limit:.2g} s or a heavier foot_mass"
        )
    if load.leg_stiffness is not None:
        _check_leg_stability(load, c)
    try:  # alpha (d/L)^n is infinitely stiff at d = 0: a light load chatters at the surface
        d_eq = static_sinking(foot, mud, load.weight, characteristic_length=lc)
        stiffness = (_static_support(foot, mud, lc, 1.01 * d_eq) - load.weight) / (0.01 * d_eq)
    except (MudrftError, ZeroDivisionError, FloatingPointError):
        return
    if not stiffness > 0:
        return
    elastic = 2.0 * np.sqrt(m / stiffness)
    if load.dt > 0.8 * elastic:
        warn_plausibility(
            f"LoadControl: the {plain(load.weight)} N load balances {d_eq:.3g} m deep, where the "
            f"mud is as stiff as a {stiffness:.3g} N/m spring under the {m:g} kg mass: the "
            f"explicit step is stable only for dt < {elastic:.3g} s, so at dt = "
            f"{plain(load.dt)} s the foot will chatter at the surface; use dt <= "
            f"{0.5 * elastic:.2g} s or a heavier load"
        )


def _check_leg_stability(load: LoadControl, c_mud: float) -> None:
    r"""Refuse a leg the semi-implicit Euler step cannot integrate (above 0.8 of the limit of
    :math:`\omega^2h^2+2\rho h<4`, :math:`\rho=c_{mud}/m_f+c_{leg}/\mu`, :math:`\omega^2=k/\mu`)."""
    mf, mb = load.foot_mass, load.body_mass
    mu = mf * mb / (mf + mb)
    rate = c_mud / mf + load.leg_damping / mu
    w2 = float(load.leg_stiffness) / mu  # type: ignore[arg-type]
    limit = 4.0 / (rate + np.sqrt(rate * rate + 4.0 * w2))  # root of w2 h^2 + 2 rate h = 4
    if load.dt > 0.8 * limit:
        raise MudrftError(
            f"LoadControl.dt={plain(load.dt)} s is too large for an explicit coupling: the "
            f"leg (leg_stiffness={plain(load.leg_stiffness)} N/m, leg_damping="
            f"{plain(load.leg_damping)} N s/m) between the {mb:g} kg body and the {mf:g} kg "
            f"foot, with the mud's {c_mud:.3g} N s/m damper on the foot, is stable only for "
            f"dt < {limit:.3g} s; use dt <= {0.5 * limit:.2g} s, a heavier foot_mass or a "
            "softer leg"
        )


def _simulate_load(
    foot: Foot, terrain: Terrain, load: LoadControl, report: Callable[[float], None] | None, strict: bool
) -> Result:  # fmt: skip
    _check_explicit_stability(foot, terrain, load)
    dt = load.dt
    n = int(np.ceil(load.duration / dt)) + 1
    t = dt * np.arange(n)
    m = load.body_mass
    pos, vel = np.zeros((n, 3)), np.zeros((n, 3))  # the foot tip's, along z only
    force, stress = np.zeros((n, 3)), np.zeros((n, 3))
    spring = load.leg_stiffness is not None
    zb = vb = z = v = 0.0  # body (from its rest over an unloaded leg) and foot
    state, every, f_prev = terrain.initial_state(foot, np.zeros(3)), max(n // 20, 1), 0.0
    for k in range(1, n):
        W = load.weight * (min(t[k] / load.ramp, 1.0) if load.ramp > 0 else 1.0)
        if not spring:  # semi-implicit Euler, the terrain force of the previous step
            a = (f_prev - W) / m
            v = v + a * dt
            z = z + v * dt
        else:
            k_leg = float(load.leg_stiffness)  # type: ignore[arg-type]
            f_leg = k_leg * (zb - z) + load.leg_damping * (vb - v)
            vb, v = vb + (-W - f_leg) / m * dt, v + (f_prev + f_leg) / load.foot_mass * dt
            zb, z = zb + vb * dt, z + v * dt
        if not (math.isfinite(z) and math.isfinite(v)):  # before the terrain names its input
            raise MudrftError("load-controlled simulation diverged; reduce LoadControl.dt")
        state, out = terrain.step(foot, state, np.array([0.0, 0.0, z]), np.array([0.0, 0.0, v]), dt)
        f_prev = float(out.force[2])
        force[k], stress[k] = out.force, out.stress
        pos[k, 2], vel[k, 2] = z, v
        if report is not None and k % every == 0:
            report(k / (n - 1))
    depth = np.maximum(-pos[:, 2], 0.0)
    hint = "; a lighter load or a larger foot stays within it" + (
        ". Is the weight in N (m kg weigh 9.81 m N)?" if depth.max() > BURIED_SEARCH * foot.height else ""
    )  # fmt: skip
    how = f"under {plain(load.weight)} N the tip sank"
    check_unburied(foot.name, foot.height, float(depth.max()), how=how, strict=strict, hint=hint)
    meta = {"load_control": True, "weight": load.weight, "mass": m}
    return Result(
        t, pos, vel, force, stress, depth, foot.name, getattr(terrain, "name", ""),
        _areas(foot, depth), meta,
    )  # fmt: skip


def _static_support(foot: Foot, mud: Mud, lc: float, d: float) -> float:
    """The static support ``F_z(d)`` [N] at tip depth ``d`` [m], :math:`\\alpha (d/L_c)^n`."""
    p = mud.vertical
    s = float(laws.elastic_stress(d / lc, p.alpha, p.n))
    return float(foot.resultant(d, np.array([0.0, 0.0, s]), 0.0)[2])


#: How deep :func:`static_sinking` looks for a balance, in heights of the foot.
BURIED_SEARCH = 4.0


def static_sinking(
    foot: Foot, mud: Mud, weight: float, *, characteristic_length: float | None = None
) -> float:
    r"""Depth [m] where the fully relaxed support :math:`F_z(d,\,\alpha(d/L_c)^n)` equals
    ``weight``, searched down to :data:`BURIED_SEARCH` times the foot's height.

    Parameters
    ----------
    foot, mud : Foot, Mud
        A foot and the mud (its vertical set is used).
    weight : float
        Load [N].
    characteristic_length : float or None, keyword-only
        :math:`L_c` [m]; default the foot's.

    Returns
    -------
    float
        Tip depth [m] below the mud surface (> 0).
    """
    from scipy.optimize import brentq

    if not isinstance(foot, Foot):
        raise MudrftError(f"foot must be a Foot (mudrft.feet), got {type(foot).__name__}")
    if not isinstance(mud, Mud):
        raise MudrftError(f"mud must be a Mud, got {type(mud).__name__}")
    W = positive_number("weight", weight, unit="N")
    lc = float(foot.characteristic_length)
    if characteristic_length is not None:
        lc = check_length("characteristic_length", characteristic_length)

    def support(d: float) -> float:
        return _static_support(foot, mud, lc, d) - W

    hi = foot.height * BURIED_SEARCH
    top = _static_support(foot, mud, lc, hi)
    if top < W:
        raise MudrftError(
            f"weight={plain(W)} N exceeds the static support of the {foot.name} foot "
            f"buried {BURIED_SEARCH:g} times its height ({top:.4g} N at a tip depth of "
            f"{hi:.3g} m): the balance lies deeper still, where the mud on the leg, which "
            "the model does not count (decision D26), would carry part of the load. Is the "
            "weight in newtons (a mass of m kg weighs 9.81 m N)?"
        )
    lo = hi * 1e-12  # a light load can balance far below a nanometre: solved in log(d)
    while support(lo) > 0:
        if lo < 1e-300:
            return lo
        lo *= 1e-12
    return float(
        np.exp(brentq(lambda u: support(float(np.exp(u))), np.log(lo), np.log(hi), xtol=1e-13))
    )
