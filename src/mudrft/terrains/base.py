r"""The terrain interface every terrain model implements, and the helpers they share::

    state = terrain.initial_state(foot, position)
    state, out = terrain.step(foot, state, position, velocity, dt)   # out.force [N]

``position`` [m] and ``velocity`` [m/s] (over the step that ends there) are the tip's,
``(3,)`` or ``(..., 3)``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._typing import FloatArray
from .._validation import MudrftError, check_finite

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = ["Terrain", "TerrainOutput", "check_motion", "kinematics", "tip_position"]


class TerrainOutput(NamedTuple):
    """A terrain step's ``force`` on the foot (..., 3) [N], channel ``stress`` (..., 3) [Pa]
    (zeros where the model has none) and tip ``depth`` (...) [m]."""

    force: NDArray[np.float64]
    stress: NDArray[np.float64]
    depth: NDArray[np.float64]


@runtime_checkable
class Terrain(Protocol):
    """Interface of every terrain model."""

    @property
    def name(self) -> str:
        """Short name of the model (a frozen field of every terrain: read-only here)."""
        ...

    def initial_state(self, foot: Foot, position: ArrayLike) -> Any:
        """State before the first step, for a foot whose tip is at ``position`` [m]."""
        ...

    def step(
        self, foot: Foot, state: Any, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[Any, TerrainOutput]:
        """Advance by ``dt`` [s] to a tip at ``position`` [m] moving at ``velocity`` [m/s]."""
        ...


def tip_position(position: ArrayLike) -> FloatArray:
    """Validate a tip position [m]: finite, shape (3,) or (..., 3)."""
    pos = check_finite("position", position)
    if pos.shape[-1:] != (3,):
        raise MudrftError(f"position must have shape (3,) or (..., 3) [m], got shape {pos.shape}")
    return pos


def kinematics(position: ArrayLike, velocity: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Validate tip position [m] and velocity [m/s]: finite, shape (..., 3), same shape."""
    pos, vel = tip_position(position), check_finite("velocity", velocity)
    if vel.shape != pos.shape:
        raise MudrftError(
            f"velocity must have the shape of position {pos.shape} [m/s], got shape {vel.shape}"
        )
    return pos, vel


def check_motion(
    position: ArrayLike, velocity: ArrayLike, dt: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """A terrain step's position [m], velocity [m/s] (:func:`kinematics`) and ``dt`` [s] > 0,
    validated."""
    pos, vel = kinematics(position, velocity)
    try:
        step = float(dt)
    except (TypeError, ValueError):
        raise MudrftError(f"dt must be a number of seconds > 0, got {dt!r}") from None
    if not (math.isfinite(step) and step > 0.0):
        raise MudrftError(f"dt must be finite and > 0 s, got {step!r} s")
    return pos, vel, step


def tip_depth(pos: np.ndarray) -> np.ndarray:
    """Depth of the tip below the surface z = 0 [m], >= 0."""
    return np.maximum(-pos[..., 2], 0.0)


def projected(foot: Foot, depth: FloatArray) -> FloatArray:
    """Projected areas (x, y, z) of the submerged foot [m^2], shape depth.shape + (3,)."""
    return np.asarray(foot.projected_areas(depth), dtype=float).reshape((*np.shape(depth), 3))


def vertical_output(fz: np.ndarray, sz: np.ndarray, depth: np.ndarray) -> TerrainOutput:
    """The output of a vertical-only terrain: force ``fz`` [N] and stress ``sz`` [Pa] on z."""
    zeros = np.zeros_like(fz)
    return TerrainOutput(np.stack([zeros, zeros, fz], -1), np.stack([zeros, zeros, sz], -1), depth)


def mean_stress(force: np.ndarray, areas: np.ndarray) -> np.ndarray:
    """``(-Fx/Ax, -Fy/Ay, Fz/Az)`` [Pa], the channels' sign convention; 0 where an area is 0."""
    sign = np.array([-1.0, -1.0, 1.0])
    safe = np.where(areas > 0, areas, 1.0)
    return np.where(areas > 0, sign * force / safe, 0.0)
