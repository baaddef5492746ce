"""The options of ``attach`` and the model, checked once for both couplings (CPU and MJX),
and the time-step limits of a foot in mud."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from ..._validation import (
    MudrftError,
    check_number,
    nonnegative_number,
    plain,
    positive_int,
    positive_number,
    warn_plausibility,
)
from ...feet.base import Foot
from ...parameters.base import Mud
from ...terrains.mud import MudTerrain, vertical_viscosity
from ._lazy import _mujoco
from .placement import _collides, _reference_pose, auto_feet, geom_label, resolve_body
from .rigid import RIGID_CELL

if TYPE_CHECKING:
    import mujoco

    from .backend import MudContact
    from .placement import BodyFoot


#: Defaults of the hard bottom's penalty (D67): stiffness [N/m], damping [N s/m].
BOTTOM_STIFFNESS, BOTTOM_DAMPING = 1e5, 2e3


class AttachOptions(NamedTuple):
    """The checked options: body names, one foot (or None) per body, and the rest in SI."""

    bodies: list[int]  # body ids
    feet: list[Any]
    surface: float  # [m]
    bottom: float | None  # [m]
    bottom_stiffness: float  # [N/m]
    bottom_damping: float  # [N s/m]
    resolution: int
    geoms: list[Any]  # the foot's geom(s) of each body, None: derived (D124)
    auto: bool = False  # the bodies were found by feet="auto"


def check_count(name: str, value: object) -> int:
    """An integer >= 1 (not a bool, not 2.5), or an error naming ``name``."""
    if type(value) is int and value >= 1:  # the common case, cheaply (a loop's nstep)
        return value
    return positive_int(name, value)


def check_attach_options(
    model: object,
    bodies: object,
    feet: object,
    *,
    surface: object,
    bottom: object,
    bottom_stiffness: object,
    bottom_damping: object,
    resolution: object,
    foot_geoms: object = None,
    floor: object = "warn",
) -> AttachOptions:
    """Check ``attach``'s arguments (see :class:`~mudrft.integrations.mujoco.MudBatch`),
    the model (a ``mujoco.MjModel``) first."""
    if not isinstance(model, _mujoco().MjModel):
        raise MudrftError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
    check_gravity(model)
    if floor not in FLOOR_CHOICES:
        raise MudrftError(f"floor must be one of {FLOOR_CHOICES}, got {floor!r}")
    auto = isinstance(bodies, str) and bodies == "auto"
    items = auto_feet(model) if auto else [bodies] if isinstance(bodies, (str, int)) else bodies
    if not isinstance(items, Sequence) or isinstance(items, str):
        raise MudrftError(
            "bodies must be 'auto', a body's or geom's name or a body's id, or a list of them, "
            f"got {bodies!r}"
        )
    if not items:
        raise MudrftError("bodies must name at least one body, got an empty list")
    resolved = [resolve_body(model, b) for b in items]
    names = [b for b, _ in resolved]
    if len(set(names)) != len(names):
        raise MudrftError(f"bodies must be distinct bodies, got {list(items)}")
    if feet is None or hasattr(feet, "contact_force"):
        feet = [feet] * len(names)
    elif isinstance(feet, str) or not isinstance(feet, Sequence):
        raise MudrftError(
            f"feet must be a foot (mudrft.feet), one per body, or None (the geoms), got {feet!r}"
        )
    elif len(feet) != len(names):
        raise MudrftError(f"feet must be one foot or one per body ({len(names)}), got {len(feet)}")
    if bottom is None and (bottom_stiffness != BOTTOM_STIFFNESS or bottom_damping != BOTTOM_DAMPING):  # fmt: skip
        raise MudrftError(
            "bottom_stiffness and bottom_damping shape the hard bottom; give its depth with "
            "bottom= (without it they would be ignored)"
        )
    opts = AttachOptions(
        geoms=_foot_geoms(model, foot_geoms, resolved),
        bodies=names,
        feet=list(feet),
        surface=check_number("surface", surface, unit="m"),
        bottom=None if bottom is None else positive_number("bottom", bottom, unit="m"),
        bottom_stiffness=nonnegative_number("bottom_stiffness", bottom_stiffness, unit="N/m"),
        bottom_damping=nonnegative_number("bottom_damping", bottom_damping, unit="N s/m"),
        resolution=check_count("resolution", resolution),
        auto=auto,
    )
    check_floor(model, opts.surface, str(floor))  # last: "below" changes the model
    return opts


#: The options of 0.2 that were removed, and what the coupling does now.
REMOVED = {
    "implicit": "the coupling always takes the linearly implicit step of the mud's damping, "
    "bounded so that the mud never gives back more energy than it took",
    "mobility": "the coupling always uses the whole robot's mobility (the former mobility='chain')",
    "lookahead": "the coupling estimates the other forces' acceleration from the last step",
}


def check_removed(coupling: str, kw: Mapping[str, object]) -> None:
    """Refuse keyword arguments ``coupling`` does not take: a removed option (:data:`REMOVED`)
    says what the coupling does now, any other names the options it takes."""
    for name in kw:
        if name in REMOVED:
            raise MudrftError(
                f"{coupling}'s option {name}= was removed in mudrft 0.3: {REMOVED[name]}; "
                f"drop the argument"
            )
        raise MudrftError(f"{coupling} got an unexpected keyword argument {name!r}")


def check_integrator(model: mujoco.MjModel) -> None:
    """Refuse MuJoCo's RK4 integrator: holding the mud's wrench over its four stages does
    not keep a light spinning foot passive."""
    mj = _mujoco()
    it = mj.mjtIntegrator(int(model.opt.integrator))
    if it == mj.mjtIntegrator.mjINT_RK4:
        raise MudrftError(
            "the MuJoCo coupling steps with the 'Euler', 'implicitfast' or 'implicit' integrator, "
            f"got {it.name!r}; set model.opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST"
        )


def check_gravity(model: mujoco.MjModel) -> None:
    """Refuse a model whose gravity is not along -z (the mud's depth is measured along -z);
    zero gravity is accepted."""
    g = np.asarray(model.opt.gravity, dtype=float)
    norm = float(np.linalg.norm(g))
    if norm > 0.0 and (g[2] >= 0.0 or math.hypot(g[0], g[1]) > 1e-6 * norm):
        raise MudrftError(
            f"the model's gravity must point along -z (the mud's surface is horizontal, its "
            f"depth measured along -z), got {np.round(g, 6).tolist()} m/s^2; set "
            '<option gravity="0 0 -9.81"/> and turn the robot instead'
        )


#: What ``attach(floor=...)`` does with a floor at or above the mud's surface.
FLOOR_CHOICES = ("warn", "below", "keep")
#: How far under the surface ``floor="below"`` moves such a floor's top [m].
BED_DEPTH = 0.5
#: A box welded to the world is a floor when it is at least this wide in x and y [m].
FLOOR_WIDTH = 1.0


def check_floor(model: mujoco.MjModel, surface: float, floor: str) -> None:
    """Handle a floor at or above the mud's surface ``surface`` [m] (a colliding geom welded
    to the world that is an upward plane, or a box at least :data:`FLOOR_WIDTH` wide):
    ``floor="warn"`` warns, ``"below"`` lowers it to :data:`BED_DEPTH` under the surface (in
    place), ``"keep"`` leaves it."""
    if floor == "keep":
        return
    mj = _mujoco()
    d = _reference_pose(model)
    for g in range(model.ngeom):
        if not _collides(model, g) or int(model.body_weldid[model.geom_bodyid[g]]) != 0:
            continue
        if model.geom(g).name.startswith(RIGID_CELL):  # a field's rigid cell, not a floor
            continue
        t, R = int(model.geom_type[g]), np.asarray(d.geom_xmat[g]).reshape(3, 3)
        half = np.abs(R) @ np.asarray(model.geom_size[g], dtype=float)  # world half-extents
        if t == int(mj.mjtGeom.mjGEOM_PLANE) and R[2, 2] > 1.0 - 1e-9:
            top = float(d.geom_xpos[g, 2])
        elif t == int(mj.mjtGeom.mjGEOM_BOX) and min(half[0], half[1]) >= FLOOR_WIDTH / 2:
            top = float(d.geom_xpos[g, 2] + half[2])
        else:
            continue
        if top < surface - 1e-9:
            continue
        if floor == "below":  # lowered along -z, in its (static) body's frame
            b = int(model.geom_bodyid[g])
            R = np.asarray(d.xmat[b]).reshape(3, 3)
            model.geom_pos[g] -= R.T @ np.array([0.0, 0.0, top - (surface - BED_DEPTH)])
            model.geom_sameframe[g] = 0  # MuJoCo would place it at its body's frame still
            continue
        warn_plausibility(
            f"{geom_label(model, g, body=False)} is a floor at z = {top:.4g} m, at or above "
            f"the mud's surface (z = {surface:.4g} m): MuJoCo's contact with it carries the "
            f"feet the mud should carry; pass floor='below' to move it {BED_DEPTH:g} m under "
            "the surface (a rigid bed), remove it from the model, or pass floor='keep' to keep it"
        )


def _foot_geoms(
    model: mujoco.MjModel, foot_geoms: object, resolved: list[tuple[int, int | None]]
) -> list[Any]:
    """The foot's geom(s) of each body: from ``foot_geoms``, a mapping ``{body: geom, or a
    list of geoms}`` (bodies and geoms by name or id), else the geom named in ``bodies``."""
    ids = [b for b, _ in resolved]
    out: list[Any] = [g for _, g in resolved]
    if foot_geoms is None:
        return out
    if not isinstance(foot_geoms, Mapping):
        first = model.body(ids[0]).name or ids[0]
        raise MudrftError(
            "foot_geoms must be a mapping {body: geom name}, e.g. "
            f"foot_geoms={{{first!r}: 'foot_geom'}}, got {foot_geoms!r}"
        )
    mj = _mujoco()
    for body, geom in foot_geoms.items():
        bid = mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, body) if isinstance(body, str) else body
        if bid not in ids:
            names = [model.body(i).name or i for i in ids]
            raise MudrftError(
                f"foot_geoms names body {body!r}, which is not coupled; the bodies are {names}"
            )
        many = isinstance(geom, Sequence) and not isinstance(geom, str)
        for g in geom if many else [geom]:  # type: ignore[union-attr]
            if isinstance(g, bool) or not isinstance(g, (str, int, np.integer)):
                raise MudrftError(
                    f"foot_geoms[{body!r}] must be a geom's name (or id), or a list of them, "
                    f"got {geom!r}"
                )
        out[ids.index(int(bid))] = list(geom) if many else geom  # type: ignore[call-overload]
    return out


def check_data(model: mujoco.MjModel, data: object) -> None:
    """Refuse ``data`` unless it is a ``mujoco.MjData`` of ``model``."""
    if not isinstance(data, _mujoco().MjData):
        raise MudrftError(f"data must be a mujoco.MjData, got {type(data).__name__}")
    got = (data.qpos.size, data.qvel.size, data.xpos.shape[0], data.ctrl.size)
    if got != (model.nq, model.nv, model.nbody, model.nu):
        raise MudrftError(
            f"data was made for another model (nq, nv, nbody, nu = {', '.join(map(str, got))}; "
            f"this model has {model.nq}, {model.nv}, {model.nbody}, {model.nu}): use "
            "mujoco.MjData(model)"
        )


#: The time steps the passivity searches of the couplings covered [s].
SEARCHED_TIMESTEPS = (5e-4, 5e-3)
#: The largest model time step a coupling takes without a warning [s] (D123).
LARGEST_TIMESTEP = 0.01


def stability_limits(
    foot: Foot, mud: Mud | MudTerrain, *, mass: float, depth: float
) -> dict[str, float]:
    r"""Largest explicit time steps of a foot of effective mass ``mass`` in mud.

    Linearising the vertical mud force about a tip at ``depth``: the viscous damper
    :math:`c=\eta_\infty A_z/L_c` (:math:`\eta_\infty+\eta_m` for ``thixotropy="quasi-static"``,
    D15), stable for :math:`\Delta t<2m/c`; the elastic spring
    :math:`k=\alpha n\gamma^{n-1}A_z/L_c`, stable for :math:`\Delta t<2\sqrt{m/k}`; the
    suction switch's damper :math:`c_s=\sigma_Y A_z/(2\nu L_c)`, stable for :math:`\Delta t<2m/c_s`.

    Parameters
    ----------
    foot : Foot
        The foot.
    mud : Mud or MudTerrain
        The mud (vertical set).
    mass : float
        Effective mass of the foot [kg].
    depth : float
        Tip depth [m], > 0.

    Returns
    -------
    dict
        ``dt_viscous``, ``dt_elastic``, ``dt_suction`` [s] and the coefficients
        ``damping`` [N s/m], ``stiffness`` [N/m], ``suction_damping`` [N s/m].
    """
    if not isinstance(foot, Foot):
        raise MudrftError(f"foot must be a Foot (mudrft.feet), got {type(foot).__name__}")
    quasi_static = isinstance(mud, MudTerrain) and mud.quasi_static
    if isinstance(mud, MudTerrain):
        mud = mud.mud
    if not isinstance(mud, Mud):
        raise MudrftError(f"mud must be a Mud or a MudTerrain, got {type(mud).__name__}")
    m = positive_number("mass", mass, unit="kg")
    d = positive_number("depth", depth, unit="m")
    p = mud.vertical
    lc = float(foot.characteristic_length)
    az = float(np.asarray(foot.projected_areas(d))[..., 2])
    g = d / lc
    c = vertical_viscosity(mud, quasi_static=quasi_static) * az / lc
    k = float(p.alpha) * float(p.n) * g ** (float(p.n) - 1.0) * az / lc
    cs = float(p.sigma_y) * az / (2.0 * float(p.nu) * lc)
    return {
        "dt_viscous": 2 * m / c,
        "dt_elastic": 2 * math.sqrt(m / k),
        "dt_suction": 2 * m / cs,
        "damping": c,
        "stiffness": k,
        "suction_damping": cs,
    }


def check_timestep(model: mujoco.MjModel, *, checked: float | None = None) -> float:
    """Warn if the model's time step exceeds :data:`LARGEST_TIMESTEP` (D123),
    unless it is ``checked`` [s], the step checked last; returns the step [s].
    """
    dt = float(model.opt.timestep)
    if dt > LARGEST_TIMESTEP and dt != checked:
        lo, hi = SEARCHED_TIMESTEPS
        warn_plausibility(
            f"the model's timestep is {plain(dt)} s, far above those the mud coupling was "
            f"checked at ({lo * 1e3:g}-{hi * 1e3:g} ms, docs/model.md up to "
            f"{LARGEST_TIMESTEP * 1e3:g} ms for the biped's walk): a foot may settle too "
            "deep and its force alternate from step to step; use a timestep of "
            f"{hi * 1e3:g} ms or less (MuJoCo's default is 2 ms)"
        )
    return dt


def check_spring_step(model: mujoco.MjModel, bodies: Sequence[BodyFoot]) -> None:
    r"""Warn if a spring in a foot's chain is too stiff for the model's time step:
    :math:`\omega^2\Delta t^2<1+2\gamma\Delta t` must hold, :math:`\omega^2=k/m`,
    :math:`\gamma=c/m`, :math:`1/m=(M^{-1})_{jj}` at ``qpos0``.
    """
    mj = _mujoco()
    dof_joint, c = np.asarray(model.dof_jntid), np.array(model.dof_damping, dtype=float)
    free = np.asarray(model.jnt_type)[dof_joint] == int(mj.mjtJoint.mjJNT_FREE)  # no spring
    k = np.where(free, 0.0, np.asarray(model.jnt_stiffness, dtype=float)[dof_joint])
    implicit = int(model.opt.integrator) in (
        int(mj.mjtIntegrator.mjINT_IMPLICIT), int(mj.mjtIntegrator.mjINT_IMPLICITFAST)
    )  # fmt: skip
    hinge = (int(mj.mjtJoint.mjJNT_HINGE), int(mj.mjtJoint.mjJNT_SLIDE))
    for a in range(model.nu):
        j, gear = int(model.actuator_trnid[a, 0]), float(model.actuator_gear[a, 0])
        if int(model.actuator_trntype[a]) != int(mj.mjtTrn.mjTRN_JOINT) or int(model.jnt_type[j]) not in hinge:  # fmt: skip
            continue
        dof = int(model.jnt_dofadr[j])
        k[dof] += max(-float(model.actuator_biasprm[a, 1]), 0.0) * gear**2
        c[dof] += max(-float(model.actuator_biasprm[a, 2]), 0.0) * gear**2 * implicit
    if not np.any(k > 0):
        return
    chain = np.zeros(model.nv, dtype=bool)
    for b in bodies:
        i = b.body_id
        while i > 0:
            adr, num = int(model.body_dofadr[i]), int(model.body_dofnum[i])
            chain[adr : adr + num] = True
            i = int(model.body_parentid[i])
    d = mj.MjData(model)
    mj.mj_forward(model, d)
    minv = np.zeros((model.nv, model.nv))
    mj.mj_solveM(model, d, minv, np.eye(model.nv))
    dt = float(model.opt.timestep)
    w2, gamma = k * np.diag(minv), c * np.diag(minv)
    excess = np.where(chain, w2 * dt * dt - (1.0 + 2.0 * gamma * dt), -np.inf)
    j = int(np.argmax(excess))
    if excess[j] >= 0.0:
        joint = int(model.dof_jntid[j])
        name = model.joint(joint).name or f"joint {joint}"
        limit = (gamma[j] + math.sqrt(gamma[j] ** 2 + w2[j])) / w2[j]  # root of the bound
        warn_plausibility(
            f"the spring on {name!r} (stiffness {plain(k[j])}, joint stiffness and position "
            f"actuators) oscillates at {math.sqrt(w2[j]):.4g} rad/s, too fast for the time "
            f"step: the mud coupling reads the other forces one step late and is stable only "
            f"for (timestep * omega)^2 < 1 + 2 timestep * damping / mass, here "
            f"{w2[j] * dt * dt:.3g} >= {1.0 + 2.0 * gamma[j] * dt:.3g} (timestep {plain(dt)} "
            f"s); use a timestep below {limit:.2g} s, or damp the joint"
        )


def diverged_error(
    i: int, kind: int, index: int, time: float, last: MudContact | None
) -> MudrftError:
    """The error for robot ``i`` whose ``qpos``, ``qvel`` or ``qacc`` (``kind`` 0, 1, 2)
    MuJoCo found bad at degree of freedom ``index`` and reset, ``time`` [s] after reset."""
    field = ("qpos", "qvel", "qacc")[kind]
    f = None if last is None else last.force
    force = None if f is None else np.round(f[i] if f.ndim == 3 else f, 3).tolist()
    what = (
        f"the state of robot {i} is not finite: MuJoCo found NaN, inf or a huge value in "
        f"{field}[{index}] at time {time:.6g} s"
        if kind < 2
        else f"the simulation of robot {i} diverged at time {time:.6g} s: MuJoCo reported "
        f"bad accelerations (qacc[{index}])"
    )
    return MudrftError(
        f"{what} (since the coupling's reset) and reset the state "
        f"(mjWARN_BAD{field.upper()}); expected finite values, with the mud wrench {force} N "
        "(reduce the time step, check the model, or set a finite state)"
    )
