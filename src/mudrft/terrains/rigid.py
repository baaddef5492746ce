"""Rigid ground: penalty contact with regularised Coulomb friction at the tip; docs/model.md
(D56) gives the equations and the defaults.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .._validation import check_nonnegative, check_positive
from .._validation import set_number as _set
from .base import TerrainOutput, kinematics, mean_stress, projected, tip_depth, tip_position

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = ["RigidGround", "RigidState"]


class RigidState(NamedTuple):
    """State of rigid ground (only whether the tip touched it) [-]."""

    in_contact: np.ndarray


@dataclass(frozen=True, eq=False)
class RigidGround:
    r"""Rigid ground as a terrain: spring-damper normal force, regularised Coulomb friction.

    Parameters
    ----------
    stiffness, damping : float
        Penalty stiffness :math:`k` [N/m] and damping :math:`c` [N s/m].
    friction, slip_speed : float
        Coulomb friction coefficient :math:`\mu` [-] (0: frictionless) and its
        regularisation speed :math:`v_s` [m/s].
    name : str
        Label in reports.

    Examples
    --------
    >>> import numpy as np
    >>> g = RigidGround()
    >>> s = g.initial_state(None, np.zeros(3))
    >>> _, out = g.step(None, s, np.array([0.0, 0.0, -0.001]), np.zeros(3), 1e-3)
    >>> out.force.round(6).tolist()
    [0.0, 0.0, 100.0]
    """

    stiffness: float = 1.0e5
    damping: float = 632.5
    friction: float = 0.6
    slip_speed: float = 0.01
    name: str = "rigid"

    def __post_init__(self) -> None:
        _set(self, "stiffness", check_positive("stiffness", self.stiffness, unit="N/m"))
        _set(self, "damping", check_nonnegative("damping", self.damping, unit="N s/m"))
        _set(self, "friction", check_nonnegative("friction", self.friction))
        _set(self, "slip_speed", check_positive("slip_speed", self.slip_speed, unit="m/s"))

    def initial_state(self, foot: Foot | None, position: ArrayLike) -> RigidState:
        """State for a foot whose tip is at ``position`` (..., 3) [m]."""
        return RigidState(in_contact=tip_depth(tip_position(position)) > 0)

    def step(
        self, foot: Foot | None, state: RigidState, position: ArrayLike, velocity: ArrayLike,
        dt: float,
    ) -> tuple[RigidState, TerrainOutput]:  # fmt: skip
        """Contact force at tip ``position`` [m] moving at ``velocity`` [m/s]; ``dt`` [s] unused."""
        check_positive("dt", dt, unit="s")
        pos, vel = kinematics(position, velocity)
        depth = tip_depth(pos)
        contact = depth > 0
        fn = np.where(
            contact, np.maximum(self.stiffness * depth - self.damping * vel[..., 2], 0.0), 0.0
        )
        vt = vel[..., :2]
        speed = np.linalg.norm(vt, axis=-1, keepdims=True)
        unit = np.where(speed > 0, vt / np.where(speed > 0, speed, 1.0), 0.0)
        slip = np.tanh(speed / self.slip_speed)
        ft = 0.0 - self.friction * fn[..., None] * slip * unit  # 0.0 - : no -0.0
        force = np.concatenate([ft, fn[..., None]], axis=-1)
        areas = np.zeros_like(force) if foot is None else projected(foot, depth)
        out = TerrainOutput(force=force, stress=mean_stress(force, areas), depth=depth)
        return RigidState(in_contact=contact), out
