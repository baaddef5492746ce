r"""Time-step limits of a foot in mud, and the coupling's checks of a model's time step."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..._validation import MudrftError, plain, positive_number, warn_plausibility
from ...feet.base import Foot
from ...parameters.base import Mud
from ...terrains.mud import MudTerrain, vertical_viscosity
from ._lazy import _mujoco

if TYPE_CHECKING:
    import mujoco

    from .backend import MudContact
    from .placement import BodyFoot


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
