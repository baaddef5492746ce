r"""The MJX coupling's step under RK4 (decision D165): the CPU coupling's rule of D150.

MJX's ``rungekutta4`` (MJX 3.17) forms the new position as
:math:`q_0\oplus h\sum_jb_j\dot q_j` and holds ``xfrc_applied`` and ``qfrc_applied`` fixed
over its four stages, as MuJoCo's RK4 did up to 3.17. The coupling's step without this
module held the feet's wrench in ``xfrc_applied`` (world frame) and took the other forces'
twist acceleration :math:`a` from the last step's twist difference (D62); a light free
foot spinning fast then gained energy from the mud (D165). Under RK4 the step now does
what :func:`mudrft.integrations.mujoco.rk4.rk4_step` does on the CPU:

* :math:`a=J\ddot q+\dot J\dot q` at each foot's center of mass, read from a forward
  pass without the feet's wrench (:func:`twist_acceleration`: the time derivative of the
  twist along the motion, by :func:`jax.jvp` of MJX's own kinematics);
* the wrench of a foot body moved by one free joint alone
  (:func:`mudrft.integrations.mujoco.rk4.free_bodies`) is held over the stages as the
  generalized force :math:`J^\top w` (``mjx.apply_ft`` at the center of mass, as MJX
  treats ``xfrc_applied``); the feet in a chain keep ``xfrc_applied``. Afterwards
  ``qfrc_applied`` is the caller's again and ``xfrc_applied`` shows the wrench.

The physics (the mud step, the implicit step, the bound) is the one definition,
:func:`~mudrft.integrations.mjx.physics.mud_wrench`; this module only says what RK4 holds.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..mujoco.kinematics import com_twist
from ..mujoco.rk4 import free_bodies
from ._lazy import _jax, _mjx, _xp

if TYPE_CHECKING:
    import mujoco
    from jax import Array
    from mujoco import mjx

    from ..._typing import XpArray

__all__ = ["RK4Plan", "held_step", "twist_acceleration"]


class RK4Plan:
    """What the RK4 step needs of the model, read once at attach (numpy, static).

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    ids : ndarray of int (nb,)
        The foot bodies.
    """

    def __init__(self, model: mujoco.MjModel, ids: np.ndarray) -> None:
        self.ids = np.asarray(ids)
        self.free = self.ids[free_bodies(model, self.ids)]  # held as J^T w (D150)
        self.roots = np.array(model.body_rootid)[self.ids]
        self.joints = [
            (int(model.jnt_type[j]), int(model.jnt_qposadr[j]), int(model.jnt_dofadr[j]))
            for j in range(model.njnt)
        ]


def _quat_rate(q: Array, w: Array) -> Array:
    r""":math:`\dot q=\tfrac12\,q\otimes(0,\boldsymbol\omega)`, ``w`` in the body frame [1/s]."""
    xp = _xp()
    s, v = q[0], q[1:]
    return 0.5 * xp.concatenate([-(v @ w)[None], s * w + xp.cross(v, w)])


def _position_rate(plan: RK4Plan, qpos: Array, qvel: Array) -> Array:
    """The rate of ``qpos`` for the velocities ``qvel`` (quaternions by their body-frame
    angular velocity, MuJoCo's convention for free and ball joints)."""
    mj_free, mj_ball = 0, 1  # mjtJoint: free, ball, slide, hinge
    rate = _xp().zeros_like(qpos)
    for kind, qa, da in plan.joints:
        if kind == mj_free:
            rate = rate.at[qa : qa + 3].set(qvel[da : da + 3])
            rate = rate.at[qa + 3 : qa + 7].set(_quat_rate(qpos[qa + 3 : qa + 7], qvel[da + 3 : da + 6]))  # fmt: skip
        elif kind == mj_ball:
            rate = rate.at[qa : qa + 4].set(_quat_rate(qpos[qa : qa + 4], qvel[da : da + 3]))
        else:
            rate = rate.at[qa].set(qvel[da])
    return rate


def twist_acceleration(plan: RK4Plan, mx: mjx.Model, d: mjx.Data) -> Array:
    r"""Acceleration of each foot body's twist, :math:`J\ddot q+\dot J\dot q`, world frame.

    The time derivative of the twist (velocity of the center of mass, angular velocity,
    :func:`~mudrft.integrations.mujoco.kinematics.com_twist`) along the motion with
    ``d.qvel`` and ``d.qacc``: what :func:`mudrft.integrations.mujoco.rk4.twist_acceleration`
    reads with ``mj_jac`` and ``mj_jacDot`` on the CPU.

    Parameters
    ----------
    plan : RK4Plan
        The feet and the joints.
    mx : mjx.Model
        The model.
    d : mjx.Data
        One robot after a forward pass (``qacc``).

    Returns
    -------
    array (nb, 6)
        Linear acceleration of each center of mass [m/s^2], angular acceleration [rad/s^2].
    """
    mjx_, jax = _mjx(), _jax()
    ids = plan.ids

    def twist(qpos: Array, qvel: Array) -> XpArray:
        k = mjx_.com_vel(mx, mjx_.com_pos(mx, mjx_.kinematics(mx, d.replace(qpos=qpos, qvel=qvel))))  # fmt: skip
        return com_twist(k.cvel[ids], k.subtree_com[plan.roots], k.xipos[ids], xp=_xp())

    rate = _position_rate(plan, d.qpos, d.qvel)
    acc: Array = jax.jvp(twist, (d.qpos, d.qvel), (rate, d.qacc))[1]
    return acc


def held_step(plan: RK4Plan, mx: mjx.Model, d: mjx.Data, xfrc: Array) -> mjx.Data:
    """``mjx.step`` under RK4 with the feet's wrench held the way RK4 integrates it (D150).

    Parameters
    ----------
    plan : RK4Plan
        The feet; :attr:`RK4Plan.free` are held as :math:`J^\\top w` in ``qfrc_applied``.
    mx : mjx.Model
        The model (RK4).
    d : mjx.Data
        One robot after a forward pass at the step's start.
    xfrc : array (nbody, 6)
        ``xfrc_applied`` with the mud's wrench on the feet [N, N m].

    Returns
    -------
    mjx.Data
        After the step; ``qfrc_applied`` is ``d``'s, ``xfrc_applied`` is ``xfrc``.
    """
    mjx_ = _mjx()
    user = d.qfrc_applied
    qfrc, held = user, xfrc
    for b in plan.free:
        b = int(b)
        qfrc = qfrc + mjx_.apply_ft(mx, d, xfrc[b, :3], xfrc[b, 3:], d.xipos[b], b)
        held = held.at[b].set(0.0)
    out: Any = mjx_.step(mx, d.replace(qfrc_applied=qfrc, xfrc_applied=held))
    return out.replace(qfrc_applied=user, xfrc_applied=xfrc)
