r"""The coupling's step under MuJoCo's RK4 integrator (decision D150).

The passivity bound (D62c) counts the work of the feet's wrench :math:`w` at the mean of
the twists before and after the step, :math:`\Delta t\,w\cdot\bar\xi`, with :math:`a`
the twist acceleration of all other forces. That is the work MuJoCo's Euler and
``implicitfast`` steps do. RK4 evaluates the dynamics at four stage poses and holds
``xfrc_applied`` in the world frame across them, and it differed from that work twice:

* The estimate of :math:`a`, the last step's twist difference less the mud's part (D62),
  holds, under RK4, a rotation of a spinning body's twist that no force made: RK4's new
  orientation is not Euler's. Under RK4 :math:`a` is read at the step's start instead,
  :math:`J\ddot q+\dot J\dot q` from a forward pass without the feet's wrench
  (:func:`twist_acceleration`).
* A free joint's angular velocity is in the body frame. RK4 adds its four stage
  increments, each taken in its stage's frame; a world-fixed torque on a body that turns
  far within the step then changes its energy by other than the work counted. A foot body
  moved by one free joint alone (:func:`free_bodies`) has its wrench held as the
  generalized force :math:`J^\top w` (its body-frame torque) over the stages instead
  (:func:`held_generalized_force`), which RK4 integrates exactly: for a body of constant
  joint-space inertia (isotropic inertia) the energy then changes by exactly the counted
  work, on every MuJoCo release. A foot in a chain keeps ``xfrc_applied``, whose stage
  projections on hinge and slide axes RK4 integrates consistently.

MuJoCo 4.0's RK4 composes the stage rotations on the rotation group (Runge-Kutta-Munthe-
Kaas, with the exact inverse of the exponential's derivative), where 3.17 and before
added the stage velocities: the same step turns a spinning body differently, and from
4.0 a free flat foot gained a fifth of its energy before this step was written.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..._typing import BoolArray, FloatArray, IndexArray
from ..._validation import warn_plausibility
from ._lazy import _mujoco

if TYPE_CHECKING:
    import mujoco

    from .batch import MudBatch
    from .contact import MudContact

__all__ = [
    "free_bodies",
    "held_generalized_force",
    "rk4_step",
    "twist_acceleration",
    "warn_rk4_apply",
]


def twist_acceleration(
    model: mujoco.MjModel, datas: Sequence[mujoco.MjData], ids: IndexArray
) -> FloatArray:
    r"""Acceleration of each body's twist from MuJoCo's last forward pass, world frame.

    :math:`a=J\ddot q+\dot J\dot q` with :math:`J` the Jacobian of the twist (velocity of
    the body's center of mass, angular velocity), ``qacc`` and ``qvel`` of each ``MjData``
    (after ``mj_forward``).

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    datas : sequence of mujoco.MjData
        The ``N`` robots, after ``mj_forward``.
    ids : ndarray of int (nb,)
        Body ids.

    Returns
    -------
    ndarray (N, nb, 6)
        Linear acceleration of each center of mass [m/s^2], angular acceleration [rad/s^2].
    """
    mj = _mujoco()
    nv = model.nv
    jac, jdot = np.zeros((6, nv)), np.zeros((6, nv))
    acc = np.empty((len(datas), len(ids), 6))
    for k, d in enumerate(datas):
        for j, b in enumerate(ids):
            com = d.xipos[b]
            mj.mj_jac(model, d, jac[:3], jac[3:], com, int(b))
            mj.mj_jacDot(model, d, jdot[:3], jdot[3:], com, int(b))
            acc[k, j] = jac @ d.qacc + jdot @ d.qvel
    return acc


def free_bodies(model: mujoco.MjModel, ids: IndexArray) -> BoolArray:
    """Which bodies move by one free joint alone (their own, or a welded ancestor's).

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    ids : ndarray of int (nb,)
        Body ids.

    Returns
    -------
    ndarray of bool (nb,)
    """
    free = int(_mujoco().mjtJoint.mjJNT_FREE)
    out = np.zeros(len(ids), dtype=bool)
    for j, b in enumerate(ids):
        b = int(b)
        while b > 0 and model.body_dofnum[b] == 0:  # welded to its parent
            b = int(model.body_parentid[b])
        if b > 0 and model.body_jntnum[b] == 1:
            out[j] = int(model.jnt_type[model.body_jntadr[b]]) == free
    return out


def held_generalized_force(
    model: mujoco.MjModel, data: mujoco.MjData, ids: IndexArray, wrench: FloatArray
) -> FloatArray:
    r"""The generalized force :math:`\sum_i J_i^\top w_i` of the bodies' wrenches.

    What MuJoCo makes of ``xfrc_applied`` at the current pose (a force at each body's
    center of mass and a torque, ``mj_applyFT``), as a vector RK4 holds over its stages.

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    data : mujoco.MjData
        One robot, after ``mj_forward``.
    ids : ndarray of int (nb,)
        Body ids.
    wrench : ndarray (nb, 6)
        Force at each center of mass [N], torque [N m], world frame.

    Returns
    -------
    ndarray (nv,)
        Generalized force [N or N m per degree of freedom].
    """
    mj = _mujoco()
    qfrc = np.zeros(model.nv)
    for j, b in enumerate(ids):
        w = np.ascontiguousarray(wrench[j], dtype=float)
        mj.mj_applyFT(model, data, w[:3], w[3:], data.xipos[b], int(b), qfrc)
    return qfrc


def rk4_step(batch: MudBatch, datas: Sequence[mujoco.MjData]) -> MudContact:
    """One RK4 step of every robot of a :class:`~.batch.MudBatch` (see the module docstring).

    The feet's ``xfrc_applied`` is cleared for the forward pass (``qacc`` is then what all
    other forces do), the mud is advanced with that acceleration, and the wrench of each
    free foot body is held in ``qfrc_applied`` over ``mj_step`` (the others' stays in
    ``xfrc_applied``); afterwards ``qfrc_applied`` is the user's again and the feet's
    ``xfrc_applied`` shows the wrench, as after an Euler step.

    Parameters
    ----------
    batch : MudBatch
        The coupling.
    datas : sequence of mujoco.MjData
        Its robots.

    Returns
    -------
    MudContact
        What the mud did in the step.
    """
    mj = _mujoco()
    m, ids = batch.model, batch._ids
    for d in datas:
        d.xfrc_applied[ids] = 0.0
        mj.mj_forward(m, d)
    out = batch._apply_given(datas, twist_acceleration(m, datas, ids))
    free = ids[free_bodies(m, ids)]
    for d in datas:
        wrench = np.array(d.xfrc_applied[ids])
        user = np.array(d.qfrc_applied)
        if len(free):
            d.qfrc_applied[:] = user + held_generalized_force(m, d, free, d.xfrc_applied[free])
            d.xfrc_applied[free] = 0.0
        try:
            mj.mj_step(m, d)
        finally:
            d.qfrc_applied[:] = user
            d.xfrc_applied[ids] = wrench
    return out


def warn_rk4_apply() -> bool:
    """Warn (once per coupling) that ``apply`` followed by ``mj_step`` is outside D150.

    Returns
    -------
    bool
        True (the caller records that it warned).
    """
    warn_plausibility(
        "the model integrates with RK4 and the mud coupling is applied with apply() before "
        "mj_step: MuJoCo then holds the mud's wrench in the world frame over RK4's stages "
        "and a light, fast-spinning foot can gain energy from the mud (docs/model.md D150); "
        "step the coupling with step(), which holds it the way RK4 integrates it, or use "
        "integrator='implicitfast' or 'Euler'"
    )
    return True
