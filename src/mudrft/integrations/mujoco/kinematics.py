r"""What the coupling reads from MuJoCo: body frames, twists, and the 6x6 mobility.

The *mobility* :math:`W` of a foot body is the change of its twist (velocity of its
center of mass and angular velocity) per unit impulse of a wrench (force at the center
of mass, torque), :math:`W = J M^{-1} J^T` with :math:`J` the body's 6 x nv Jacobian at
its center of mass and :math:`M` the joint-space inertia. The coupling's semi-implicit step needs it
(:class:`~mudrft.integrations.mujoco.MudBatch`, decision D62): :func:`chain_mobility`
takes it from the whole model.

Shapes: ``N`` robots (one ``MjData`` each), ``nb`` bodies; every array is in the world
frame.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..._typing import FloatArray, IndexArray, Namespace
from ._lazy import _mujoco

if TYPE_CHECKING:
    import mujoco

__all__ = ["body_frames", "chain_mobility", "com_twist"]


def body_frames(
    datas: Sequence[mujoco.MjData], ids: IndexArray, roots: IndexArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Frames and velocities of bodies ``ids`` of every robot.

    Parameters
    ----------
    datas : sequence of mujoco.MjData
        The ``N`` robots, after ``mj_forward`` or ``mj_step1``.
    ids : ndarray of int (nb,)
        Body ids.
    roots : ndarray of int (nb,)
        Root body id of each body (``model.body_rootid``).

    Returns
    -------
    X : ndarray (N, nb, 3)
        Body origins [m].
    R : ndarray (N, nb, 3, 3)
        Body orientations (body to world) [-].
    C : ndarray (N, nb, 3)
        Body centers of mass [m].
    V : ndarray (N, nb, 6)
        Angular [rad/s] and linear [m/s] velocity of each body (MuJoCo's ``cvel``: the
        linear part is that of the point at the root's subtree center of mass).
    S : ndarray (N, nb, 3)
        Center of mass of each body's root subtree [m], where ``V`` is taken.
    """
    if len(datas) == 1:
        d = datas[0]
        X, R, C = d.xpos[ids][None], d.xmat[ids].reshape(1, -1, 3, 3), d.xipos[ids][None]
        V, S = d.cvel[ids][None], d.subtree_com[roots][None]
    else:
        X = np.stack([d.xpos for d in datas])[:, ids]
        R = np.stack([d.xmat for d in datas])[:, ids].reshape(len(datas), -1, 3, 3)
        C = np.stack([d.xipos for d in datas])[:, ids]
        V = np.stack([d.cvel for d in datas])[:, ids]
        S = np.stack([d.subtree_com for d in datas])[:, roots]
    return X, R, C, V, S


def chain_mobility(
    model: mujoco.MjModel,
    datas: Sequence[mujoco.MjData],
    ids: IndexArray,
    com: FloatArray,
    jac: FloatArray,
    minv_jt: FloatArray,
) -> FloatArray:
    """Mobility :math:`J_iM^{-1}J_j^T` of the bodies' centers of mass, from the whole model.

    :math:`J_i=(J_p; J_r)` is the Jacobian of body ``i``'s twist (velocity of its center of
    mass, angular velocity) in the world frame; block ``(i, j)`` maps a wrench on body ``j``
    (force at its center of mass, torque) to the change of body ``i``'s twist per unit
    impulse (D62); the cross blocks couple the feet of one robot (D62d).

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    datas : sequence of mujoco.MjData
        The ``N`` robots.
    ids : ndarray of int (nb,)
        Body ids.
    com : ndarray (N, nb, 3)
        Centers of mass in the world [m].
    jac, minv_jt : ndarray (nb, 6, nv)
        Work arrays (overwritten).

    Returns
    -------
    ndarray (N, nb, nb, 6, 6)
        Mobility: [1/kg] (force to velocity), [1/(kg m)] (coupling) and [1/(kg m^2)]
        (torque to angular velocity).
    """
    mj = _mujoco()
    N, nb = com.shape[:2]
    W = np.empty((N, nb, nb, 6, 6))
    for k, d in enumerate(datas):
        for j, b in enumerate(ids):
            mj.mj_jac(model, d, jac[j, :3], jac[j, 3:], com[k, j], int(b))
            mj.mj_solveM(model, d, minv_jt[j], jac[j])
        W[k] = np.einsum("iav,jbv->ijab", jac, minv_jt)
    return W


def com_twist(V: FloatArray, S: FloatArray, C: FloatArray, xp: Namespace = np) -> FloatArray:
    """Twist of each body at its center of mass: (linear velocity [m/s], angular [rad/s]).

    Parameters
    ----------
    V : ndarray (..., 6)
        MuJoCo's ``cvel`` (angular, then linear velocity at ``S``).
    S : ndarray (..., 3)
        Root subtree centers of mass [m].
    C : ndarray (..., 3)
        Body centers of mass [m].
    xp : module, keyword-only
        Array namespace (numpy, or ``jax.numpy`` for the MJX coupling).

    Returns
    -------
    ndarray (..., 6)
    """
    w = V[..., :3]
    return xp.concatenate([V[..., 3:] + _cross(w, C - S, xp), w], axis=-1)


def _cross(a: FloatArray, b: FloatArray, xp: Namespace = np) -> FloatArray:
    """Cross product along the last axis."""
    return xp.stack(
        [
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ],
        axis=-1,
    )
