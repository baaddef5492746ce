"""What the coupling reads from MuJoCo (world frame): body frames, twists, the mobility."""

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
    """Frames and velocities of bodies ``ids`` (roots ``roots``) of every robot.

    Returns
    -------
    X, R, C : ndarray (N, nb, 3), (N, nb, 3, 3), (N, nb, 3)
        Body origins [m], orientations (body to world) [-], centers of mass [m].
    V : ndarray (N, nb, 6)
        MuJoCo's ``cvel``: angular [rad/s], then linear velocity [m/s] at ``S``.
    S : ndarray (N, nb, 3)
        Center of mass of each body's root subtree [m].
    """
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
    """Mobility :math:`J_iM^{-1}J_j^T` (N, nb, nb, 6, 6) of the bodies at their
    centers of mass ``com`` [m], from the whole model (D62, D62d): [1/kg], [1/(kg m)],
    [1/(kg m^2)]. ``jac`` and ``minv_jt`` (nb, 6, nv) are work arrays.
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
    """Twist (velocity [m/s], angular velocity [rad/s]) at the centers of mass ``C``
    [m], from MuJoCo's ``cvel`` ``V`` taken at the root subtree centers ``S`` [m].
    """
    w = V[..., :3]
    return xp.concatenate([V[..., 3:] + xp.cross(w, C - S), w], axis=-1)
