"""What the mud did in the last step: :class:`MudContact`, the coupling's output."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray


class MudContact(NamedTuple):
    """What the mud did in the last step, per robot and body (world frame).

    Shapes are ``(nbody, ...)`` for :class:`~mudrft.integrations.mujoco.MudCoupling` and
    ``(nrobot, nbody, ...)`` for :class:`MudBatch`.

    Attributes
    ----------
    force : ndarray (..., 3)
        Force written to ``xfrc_applied`` (stabilised, D62; bounded, D62c) [N].
    explicit_force : ndarray (..., 3)
        Force of the mud model at the start of the step (what :class:`mudrft.MudTerrain`
        returns for the same motion) plus the rigid bottom [N].
    torque : ndarray (..., 3)
        Moment about the body's center of mass written to ``xfrc_applied`` [N m].
    point : ndarray (..., 3)
        Point of application (center of pressure) [m].
    tip : ndarray (..., 3)
        Tip position; its z is that of the lowest point of the foot [m].
    velocity : ndarray (..., 3)
        Tip velocity [m/s].
    depth : ndarray (...)
        Depth of the lowest point below the mud surface [m].
    stress : ndarray (..., 3)
        Channel stresses in the foot frame [Pa].
    """

    force: NDArray[np.float64]
    explicit_force: NDArray[np.float64]
    torque: NDArray[np.float64]
    point: NDArray[np.float64]
    tip: NDArray[np.float64]
    velocity: NDArray[np.float64]
    depth: NDArray[np.float64]
    stress: NDArray[np.float64]
