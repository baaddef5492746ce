r"""How large a time step an explicit coupling of a foot with mud can take.

The mud force on a foot linearised about a depth is a damper (the viscous part), a
spring (the elastic part) and a second damper where the suction switch turns on;
:func:`stability_limits` gives the explicit time-step limit of each. They explain why
:class:`~mudrft.integrations.mujoco.MudBatch` treats the velocity-dependent part
semi-implicitly (docs/model.md, decisions D61-D64).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..._validation import (
    MudrftError,
    plain,
    positive_number,
    warn_plausibility,
)
from ...feet.base import Foot
from ...parameters.base import Mud
from ...terrains.mud import MudTerrain, vertical_viscosity

if TYPE_CHECKING:
    import mujoco

    from .contact import MudContact
    from .placement import BodyFoot

__all__ = [
    "LARGEST_TIMESTEP",
    "SEARCHED_TIMESTEPS",
    "check_spring_step",
    "check_timestep",
    "diverged_error",
    "stability_limits",
]

#: The time steps the passivity searches of the couplings covered [s].
SEARCHED_TIMESTEPS = (5e-4, 5e-3)
#: The largest model time step a coupling takes without a warning [s] (decision D123): twice
#: the searched range, the biped's largest step (``walk.MAX_DT``); at 20 ms a free 1.5 kg box
#: foot settled 2.8 times too deep with a force alternating step by step.
LARGEST_TIMESTEP = 0.01


def stability_limits(
    foot: Foot, mud: Mud | MudTerrain, *, mass: float, depth: float
) -> dict[str, float]:
    r"""Largest explicit time steps of a foot of effective mass ``mass`` in mud.

    Linearising the vertical mud force about a tip at ``depth``:

    * viscous part, a damper :math:`c=\eta_\infty A_z/L_c` (:math:`\eta_\infty+\eta_m`
      for a terrain with ``thixotropy="quasi-static"``: eq. (9) from rest, decision D15):
      explicit Euler is stable for :math:`\Delta t<2m/c` (``dt_viscous``);
    * elastic part, a spring :math:`k=\alpha n\gamma^{n-1}A_z/L_c` (infinite at
      :math:`\gamma\to0` for :math:`n<1`): symplectic Euler is stable for
      :math:`\Delta t<2\sqrt{m/k}` (``dt_elastic``);
    * suction switch, a damper :math:`c_s=\sigma_Y A_z/(2\nu L_c)` at full suction
      (``dt_suction`` = :math:`2m/c_s`).

    Parameters
    ----------
    foot : Foot
        The foot (its ``projected_areas`` and ``characteristic_length``).
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
    """Warn if the model's time step is far above those the coupling was checked at.

    The passivity searches ran at 0.5-5 ms (:data:`SEARCHED_TIMESTEPS`)
    and the biped walks at up to 10 ms; above :data:`LARGEST_TIMESTEP` a foot that settles
    correctly at 1-10 ms sinks too deep and its force alternates from step to step (decision
    D123): :class:`~mudrft._validation.PlausibilityWarning`, naming the time step, the range
    checked and the advice.

    Parameters
    ----------
    model : mujoco.MjModel
        The model (its ``opt.timestep`` [s]).
    checked : float or None, keyword-only
        The time step checked last [s]; the same step again does not warn again.

    Returns
    -------
    float
        The time step checked [s] (a coupling checks again only when it changes).
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
    r"""Warn if a spring in a foot's chain is too stiff for the model's time step.

    The implicit step (D62) needs the acceleration the other forces give the foot; it
    reads it from the last step, one step late. Where the mud's damping dominates (a foot
    in mud), a spring of stiffness :math:`k` with a damper :math:`c` that MuJoCo integrates
    implicitly, on a mass :math:`m`, then multiplies the foot's velocity each step by

    .. math:: \lambda = rac{\gamma\Delta t-\omega^2\Delta t^2}{1+\gamma\Delta t},
       \quad \omega^2=k/m,\ \gamma=c/m,

    stable for :math:`\omega^2\Delta t^2<1+2\gamma\Delta t` (undamped: :math:`\omega\Delta
    t<1`, half of MuJoCo's own limit without the mud). A 0.3 kg box on a 5000 N/m spring
    (:math:`\omega=129` rad/s) stays bounded at 7.5 ms and diverges from 8 ms on; with a
    damper of :math:`\zeta=0.3` it holds at 10 ms and diverges at 15 ms, as the bound says.

    The springs are the joint stiffnesses and position actuators (``kp``, joint
    transmission) on the degrees of freedom of each foot's chain; the dampers the joint
    damping, and the actuators' ``kv`` under the implicit integrators; each with the
    inverse inertia :math:`(M^{-1})_{jj}` at ``qpos0`` for :math:`1/m`. Above the bound:
    :class:`~mudrft._validation.PlausibilityWarning`.

    Parameters
    ----------
    model : mujoco.MjModel
        The model (its ``opt.timestep`` [s], joint stiffness [N/m, N m/rad] and damping
        [N s/m, N m s/rad], actuators).
    bodies : sequence of BodyFoot
        The coupled bodies.
    """
    from ._lazy import _mujoco

    mj = _mujoco()
    k, c = np.zeros(model.nv), np.array(model.dof_damping, dtype=float)
    for j in range(model.njnt):
        n = {int(mj.mjtJoint.mjJNT_FREE): 0, int(mj.mjtJoint.mjJNT_BALL): 3}.get(int(model.jnt_type[j]), 1)  # fmt: skip
        adr = int(model.jnt_dofadr[j])
        k[adr : adr + n] += float(model.jnt_stiffness[j])
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


#: The state MuJoCo checks in each step, in the order of the coupling's counters.
_CHECKED = ("qpos", "qvel", "qacc")


def diverged_error(
    i: int, kind: int, index: int, time: float, last: MudContact | None
) -> MudrftError:
    """The error for robot ``i`` in whose step MuJoCo found a non-finite or huge
    ``qpos``, ``qvel`` or ``qacc`` (``kind`` 0, 1, 2; at degree of freedom ``index``) and
    reset the state, ``time`` [s] after the coupling's reset, with the mud's last wrench."""
    field = _CHECKED[kind]
    force = None
    if last is not None:
        f = last.force
        force = np.round(f[i] if f.ndim == 3 else f, 3).tolist()
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
