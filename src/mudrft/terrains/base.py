r"""The terrain interface every terrain model implements, and its shared input checks.

Every terrain (the mud model of Chen et al. 2026 and the baselines) implements
:class:`Terrain`, so :func:`mudrft.simulate`, the MuJoCo coupling and every comparison
accept any of them::

    state = terrain.initial_state(foot, position)
    state, out = terrain.step(foot, state, position, velocity, dt)   # out.force [N]

``position`` and ``velocity`` are those of the foot tip in the world frame, shape
``(3,)`` or ``(..., 3)`` for a batch of feet [m], [m/s]. The step is explicit: it uses
the motion over the step that ends at ``position``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import MudrftError, check_finite

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = ["Terrain", "TerrainOutput", "check_motion"]


class TerrainOutput(NamedTuple):
    """What a terrain step returns.

    Attributes
    ----------
    force : ndarray (..., 3)
        Force of the terrain on the foot, world frame [N].
    stress : ndarray (..., 3)
        Channel stresses (sx, sy, sz) [Pa] where the model has them (zeros otherwise).
    depth : ndarray (...)
        Tip depth below the surface [m].
    """

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

    # the state is each terrain's own (a NamedTuple of arrays, or None): Any here
    def initial_state(self, foot: Foot, position: ArrayLike) -> Any:
        """State before the first step, for a foot whose tip is at ``position`` [m]."""
        ...

    def step(
        self, foot: Foot, state: Any, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[Any, TerrainOutput]:
        """Advance by ``dt`` [s] to a tip at ``position`` [m] moving at ``velocity`` [m/s]."""
        ...


def check_motion(
    position: ArrayLike, velocity: ArrayLike, dt: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """Validate the inputs of a terrain step, shared by every terrain.

    Parameters
    ----------
    position : array_like, shape (3,) or (..., 3)
        Tip position [m], finite.
    velocity : array_like, same shape
        Tip velocity [m/s], finite.
    dt : float
        Step [s], finite and > 0.

    Returns
    -------
    position, velocity : ndarray
        As float arrays.
    dt : float
    """
    pos = check_finite("position", position)
    if pos.shape[-1:] != (3,):
        raise MudrftError(f"position must have shape (3,) or (..., 3) [m], got shape {pos.shape}")
    vel = check_finite("velocity", velocity)
    if vel.shape != pos.shape:
        raise MudrftError(
            f"velocity must have the shape of position {pos.shape} [m/s], got shape {vel.shape}"
        )
    try:
        step = float(dt)
    except (TypeError, ValueError):
        raise MudrftError(f"dt must be a number of seconds > 0, got {dt!r}") from None
    if not (math.isfinite(step) and step > 0.0):
        raise MudrftError(f"dt must be finite and > 0 s, got {step!r} s")
    return pos, vel, step
