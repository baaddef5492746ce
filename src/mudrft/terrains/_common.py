"""Small helpers shared by the baseline terrains (kinematics checks, areas, stresses)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from .._typing import FloatArray
from .._validation import MudrftError, check_finite

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = ["area_z", "kinematics", "mean_stress", "tip_depth", "tip_position"]


def tip_position(position: ArrayLike) -> FloatArray:
    """Validate a tip position [m]: finite, shape (3,) or (..., 3)."""
    pos = check_finite("position", position)
    if pos.shape[-1:] != (3,):
        raise MudrftError(f"position must have shape (3,) or (..., 3), got shape {pos.shape}")
    return pos


def kinematics(position: ArrayLike, velocity: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Validate tip position [m] and velocity [m/s]: finite, shape (..., 3), same shape."""
    pos = tip_position(position)
    vel = check_finite("velocity", velocity)
    if vel.shape != pos.shape:
        raise MudrftError(
            f"velocity must have the shape of position {pos.shape}, got shape {vel.shape}"
        )
    return pos, vel


def tip_depth(pos: np.ndarray) -> np.ndarray:
    """Depth of the tip below the surface z = 0 [m], >= 0."""
    return np.maximum(-pos[..., 2], 0.0)


def projected(foot: Foot, depth: FloatArray) -> FloatArray:
    """Projected areas (x, y, z) of the submerged foot [m^2], shape depth.shape + (3,)."""
    return np.asarray(foot.projected_areas(depth), dtype=float).reshape((*np.shape(depth), 3))


def area_z(foot: Foot, depth: FloatArray) -> FloatArray:
    """Horizontal (z-projected) area of the submerged foot [m^2]."""
    return projected(foot, depth)[..., 2]


def mean_stress(force: np.ndarray, areas: np.ndarray) -> np.ndarray:
    """Force divided by projected area, in the channel sign convention [Pa].

    ``(-Fx/Ax, -Fy/Ay, Fz/Az)``: positive when the stress resists motion toward +x, +y
    or supports the foot (as the mud model's channel stresses); 0 where the area is 0.
    """
    sign = np.array([-1.0, -1.0, 1.0])
    safe = np.where(areas > 0, areas, 1.0)
    return np.where(areas > 0, sign * force / safe, 0.0)
