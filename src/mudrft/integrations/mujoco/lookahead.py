r"""The coupling's step with the other forces' acceleration read ahead (decision D162).

Under Euler and ``implicitfast`` the implicit step (D62) and the passivity bound (D62c)
take the twist acceleration :math:`a` of all forces but the mud's from the last step's
twist difference (D62): for a free body under gravity it is exact, for a chain whose
actuators, constraints and Coriolis forces change within a step it lags by one step, and a
thrown leg can then gain energy or diverge (D62e). With ``lookahead=True`` each step reads
:math:`a` from the velocity change MuJoCo's own step gives without the feet's wrench:
after ``mj_step1`` a scratch copy of each ``MjData`` has the feet's ``xfrc_applied``
cleared and runs ``mj_step2`` (actuation, constraints and the integrator's own matrix,
:math:`M`, :math:`M+\Delta t\,B` or :math:`M-\Delta t\,\partial f/\partial\dot q`), and

.. math:: a = J\,(\dot q'_0-\dot q)/\Delta t,

with :math:`J` the Jacobian of each foot's twist at the step's start and :math:`\dot q'_0`
the copy's new velocities. Where that step solved with its own symmetric matrix
:math:`H` (``implicitfast``: :math:`M-\Delta t\,\partial f/\partial\dot q` without the
Coriolis terms; Euler with joint damping or actuators: :math:`M+\Delta t\,B`), the feet's
mobility is read through it as well, :math:`W=JH^{-1}J^\top` (the copy's factor ``qH``
stands in for ``qLD`` while the coupling solves; both are MuJoCo's compressed rows of the
same sparsity). The work the bound counts, :math:`\Delta t\,w\cdot(\xi+\xi')/2` with
:math:`\xi'=\xi+\Delta t(a+Ww)`, is then the generalized work of the wrench at the mean
of the generalized velocities before and after the step, up to the constraint forces'
response to the wrench itself. Under ``implicit`` (an unsymmetric :math:`H` with the
Coriolis derivatives, which the bound's :math:`q\ge0` needs symmetric) and RK4 (D150) the
option does nothing (:func:`reads_ahead`; D163). The cost is a copy of the data and a
second ``mj_step2`` per step, so it is an option.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from ..._typing import FloatArray, IndexArray
from ._lazy import _mujoco

if TYPE_CHECKING:
    import mujoco

    from .batch import MudBatch
    from .contact import MudContact

__all__ = ["lookahead_acceleration", "lookahead_apply", "lookahead_step", "reads_ahead"]


def reads_ahead(batch: MudBatch) -> bool:
    """Whether a coupling reads ahead this step: ``lookahead=True`` and the model's
    integrator Euler or ``implicitfast`` (RK4 reads its own way, D150; under ``implicit``
    the read acceleration and the mobility would not match, D163).

    Parameters
    ----------
    batch : MudBatch
        The coupling.

    Returns
    -------
    bool
    """
    if not batch.lookahead:
        return False
    kinds = _mujoco().mjtIntegrator
    return int(batch.model.opt.integrator) in (
        int(kinds.mjINT_EULER),
        int(kinds.mjINT_IMPLICITFAST),
    )


def _copy_data(
    mj: ModuleType,
    model: mujoco.MjModel,
    data: mujoco.MjData,
    scratch: list[mujoco.MjData],
    k: int,
) -> mujoco.MjData:
    """``data`` copied into ``scratch[k]``: in place with ``mj_copyData`` where the bindings
    have it (MuJoCo 3.3.6 does not), else as a new copy that replaces ``scratch[k]``."""
    if hasattr(mj, "mj_copyData"):
        mj.mj_copyData(scratch[k], model, data)
    else:
        scratch[k] = copy.copy(data)
    return scratch[k]


def lookahead_acceleration(
    model: mujoco.MjModel,
    datas: Sequence[mujoco.MjData],
    scratch: list[mujoco.MjData],
    ids: IndexArray,
) -> FloatArray:
    r"""Twist acceleration of each body that MuJoCo's step gives without its wrench.

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    datas : sequence of mujoco.MjData
        The ``N`` robots, after ``mj_step1``; left unchanged.
    scratch : list of mujoco.MjData
        One scratch ``MjData`` of ``model`` per robot (overwritten; replaced by a copy
        where the MuJoCo release has no ``mj_copyData``).
    ids : ndarray of int (nb,)
        Body ids.

    Returns
    -------
    ndarray (N, nb, 6)
        :math:`J(\dot q'_0-\dot q)/\Delta t` at each body's center of mass: linear
        [m/s^2], angular [rad/s^2], world frame.
    """
    mj = _mujoco()
    dt = float(model.opt.timestep)
    jac = np.zeros((6, model.nv))
    acc = np.empty((len(datas), len(ids), 6))
    for k, d in enumerate(datas):
        s = _copy_data(mj, model, d, scratch, k)
        s.xfrc_applied[ids] = 0.0
        s.qHDiagInv[:] = 0.0  # nonzero after the step: it factorized its own matrix
        mj.mj_step2(model, s)
        dv = (s.qvel - d.qvel) / dt
        for j, b in enumerate(ids):
            mj.mj_jac(model, d, jac[:3], jac[3:], d.xipos[b], int(b))
            acc[k, j] = jac @ dv
    return acc


def lookahead_apply(batch: MudBatch, datas: Sequence[mujoco.MjData]) -> MudContact:
    """Advance the mud once with the other forces' acceleration read ahead and write the
    feet's ``xfrc_applied`` (after ``mj_step1`` or ``mj_forward``, before ``mj_step2``).

    Parameters
    ----------
    batch : MudBatch
        The coupling (``lookahead=True``).
    datas : sequence of mujoco.MjData
        Its robots.

    Returns
    -------
    MudContact
        What the mud did in the step.
    """
    if len(batch._scratch) != len(datas):
        batch._scratch = [_mujoco().MjData(batch.model) for _ in datas]
    acc = lookahead_acceleration(batch.model, datas, batch._scratch, batch._ids)
    # the mobility through the step's own matrix: its factor in place of M's for the solve
    mine = [(d.qLD.copy(), d.qLDiagInv.copy()) for d in datas]
    for d, s in zip(datas, batch._scratch, strict=True):
        if np.any(s.qHDiagInv):
            d.qLD[:], d.qLDiagInv[:] = s.qH, s.qHDiagInv
    try:
        return batch._apply_given(datas, acc)
    finally:
        for d, (ld, di) in zip(datas, mine, strict=True):
            d.qLD[:], d.qLDiagInv[:] = ld, di


def lookahead_step(batch: MudBatch, datas: Sequence[mujoco.MjData]) -> MudContact:
    """One Euler or implicit step of every robot: ``mj_step1``, :func:`lookahead_apply`,
    ``mj_step2``.

    Parameters
    ----------
    batch : MudBatch
        The coupling (``lookahead=True``).
    datas : sequence of mujoco.MjData
        Its robots.

    Returns
    -------
    MudContact
        What the mud did in the step.
    """
    mj, m = _mujoco(), batch.model
    for d in datas:
        mj.mj_step1(m, d)
    out = lookahead_apply(batch, datas)
    for d in datas:
        mj.mj_step2(m, d)
    return out
