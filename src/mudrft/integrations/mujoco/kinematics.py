r"""What the coupling reads from MuJoCo: body frames and velocities, and tip mobility.

The *mobility* :math:`W` of a tip is the velocity change per unit impulse applied there,
:math:`W = J M^{-1} J^T` with :math:`J` the tip's translational Jacobian and :math:`M`
the joint-space inertia. The coupling's semi-implicit step needs it
(:class:`~mudrft.integrations.mujoco.MudBatch`, decision D62): :func:`chain_mobility`
takes it from the whole model, :func:`body_mobility` from the body alone, as if the
body were free (cheaper, and an upper bound: more damping in transients).

Shapes: ``N`` robots (one ``MjData`` each), ``nb`` bodies; every array is in the world
frame.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._lazy import _mujoco

__all__ = ["body_frames", "body_mobility", "chain_mobility"]

FloatArray = NDArray[np.float64]


def body_frames(
    datas: Sequence[Any], ids: NDArray[np.int_], roots: NDArray[np.int_]
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
    model: Any,
    datas: Sequence[Any],
    ids: NDArray[np.int_],
    tip: FloatArray,
    jac: FloatArray,
    minv_jt: FloatArray,
) -> FloatArray:
    """Mobility :math:`J M^{-1} J^T` of each tip from the whole model.

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    datas : sequence of mujoco.MjData
        The ``N`` robots.
    ids : ndarray of int (nb,)
        Body ids.
    tip : ndarray (N, nb, 3)
        Tips in the world [m].
    jac, minv_jt : ndarray (3, nv)
        Work arrays (overwritten).

    Returns
    -------
    ndarray (N, nb, 3, 3)
        Mobility [1/kg].
    """
    mj = _mujoco()
    N, nb = tip.shape[:2]
    W = np.empty((N, nb, 3, 3))
    for k, d in enumerate(datas):
        for j, b in enumerate(ids):
            mj.mj_jac(model, d, jac, None, tip[k, j], int(b))
            mj.mj_solveM(model, d, minv_jt, jac)
            W[k, j] = jac @ minv_jt.T
    return W


def body_mobility(
    model: Any, datas: Sequence[Any], ids: NDArray[np.int_], tip: FloatArray, com: FloatArray
) -> FloatArray:
    r"""Mobility of each tip of a free body: :math:`I/m + [r]_\times I_c^{-1} [r]_\times^T`.

    Parameters
    ----------
    model : mujoco.MjModel
        The model (body masses and principal inertias).
    datas : sequence of mujoco.MjData
        The ``N`` robots.
    ids : ndarray of int (nb,)
        Body ids.
    tip : ndarray (N, nb, 3)
        Tips in the world [m].
    com : ndarray (N, nb, 3)
        Body centers of mass in the world [m].

    Returns
    -------
    ndarray (N, nb, 3, 3)
        Mobility [1/kg].
    """
    mass = np.array(model.body_mass)[ids]
    inert = np.array(model.body_inertia)[ids]
    N, nb = tip.shape[:2]
    Ri = np.stack([d.ximat for d in datas])[:, ids].reshape(N, nb, 3, 3)
    inv_i = np.einsum("kbij,bj,kblj->kbil", Ri, 1.0 / np.maximum(inert, 1e-12), Ri)
    r = tip - com
    rx = np.zeros((N, nb, 3, 3))
    rx[..., 0, 1], rx[..., 0, 2] = -r[..., 2], r[..., 1]
    rx[..., 1, 0], rx[..., 1, 2] = r[..., 2], -r[..., 0]
    rx[..., 2, 0], rx[..., 2, 1] = -r[..., 1], r[..., 0]
    return (np.eye(3) / mass[:, None, None]) + rx @ inv_i @ np.swapaxes(rx, -1, -2)


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """Cross product along the last axis."""
    return np.stack(
        [
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ],
        axis=-1,
    )
