"""What the coupling reads from MuJoCo (world frame): body frames, twists, the mobility."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..._typing import FloatArray, IndexArray, Namespace

if TYPE_CHECKING:
    import mujoco

__all__ = ["body_frames", "com_twist"]


def body_frames(
    datas: Sequence[mujoco.MjData], ids: IndexArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Origins [m], orientations (body to world) [-] and centers of mass [m] of bodies
    ``ids`` of every robot: shapes (N, nb, 3), (N, nb, 3, 3), (N, nb, 3)."""
    X = np.stack([d.xpos for d in datas])[:, ids]
    R = np.stack([d.xmat for d in datas])[:, ids].reshape(len(datas), -1, 3, 3)
    C = np.stack([d.xipos for d in datas])[:, ids]
    return X, R, C


def com_twist(V: FloatArray, S: FloatArray, C: FloatArray, xp: Namespace = np) -> FloatArray:
    """Twist (velocity [m/s], angular velocity [rad/s]) at the centers of mass ``C``
    [m], from MuJoCo's ``cvel`` ``V`` taken at the root subtree centers ``S`` [m].
    """
    w = V[..., :3]
    return xp.concatenate([V[..., 3:] + xp.cross(w, C - S), w], axis=-1)
