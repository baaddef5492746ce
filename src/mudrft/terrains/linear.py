r"""Linear-stiffness mud: the "conventional linear model" of Godon et al. 2022, Liu et al. 2023.

:math:`F_z=k\,d\,A_z(d)`, vertical only, with :math:`k` [N/m^3] a stiffness per unit area and
:math:`A_z(d)` the submerged footprint at tip depth :math:`d` (decision D54).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .._typing import FloatArray
from .._validation import (
    MudrftError,
    check_choice,
    check_finite,
    check_nonnegative,
    check_positive,
    warn_implausible,
)
from .._validation import set_number as _set
from ..citations import register
from .base import TerrainOutput, kinematics, projected, tip_depth, tip_position, vertical_output

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = [
    "DEFAULT_STIFFNESS", "PLAUSIBLE_STIFFNESS", "LinearState", "LinearStiffness", "fit_stiffness"
]  # fmt: skip

#: Plausible stiffnesses per unit area [N/m^3]; below, most likely N/cm^3 read as N/m^3.
PLAUSIBLE_STIFFNESS = (1.0e3, 1.0e9)

#: Default stiffness per unit area [N/m^3]: :func:`fit_stiffness` of the mudrft W = 25 %
#: vertical plate stress over the reference plate test's intrusion (decision D54).
DEFAULT_STIFFNESS = 1.090e6


class LinearState(NamedTuple):
    """State of the linear model (only whether the tip was in the mud) [-]."""

    in_mud: np.ndarray


@dataclass(frozen=True, eq=False)
class LinearStiffness:
    r"""Linear-stiffness mud (Godon et al. 2022; Liu et al. 2023) as a terrain.

    Parameters
    ----------
    stiffness : float
        :math:`k` [N/m^3], the vertical stress per unit tip depth (D54); outside
        :data:`PLAUSIBLE_STIFFNESS` warns.
    unloading : {"elastic", "zero"}
        The force follows :math:`k d` both ways, or is 0 while the foot moves up (D54).
    name : str
        Label in reports.

    References
    ----------
    .. [1] S. Godon, A. Ristolainen and M. Kruusmaa, "An Insight on Mud Behavior Upon
       Stepping", IEEE Robotics and Automation Letters, 2022.

    Examples
    --------
    >>> LinearStiffness().stiffness
    1090000.0
    """

    stiffness: float = DEFAULT_STIFFNESS
    unloading: str = "elastic"
    name: str = "linear"

    def __post_init__(self) -> None:
        _set(self, "stiffness", check_positive("stiffness", self.stiffness, unit="N/m^3"))
        what = "LinearStiffness: stiffness is"
        hint = (
            "stiffness is the stress per depth in N/m^3 = Pa/m (1 N/cm^3 = 1 kPa/mm = 1e6 N/m^3;"
            " the paper's mud: 1.09e6)"
        )
        warn_implausible(what, self.stiffness, PLAUSIBLE_STIFFNESS, unit="N/m^3", hint=hint)
        check_choice("unloading", self.unloading, ("elastic", "zero"))
        register("godon2022ral")
        register("liu2023ral")

    def stress(self, depth: ArrayLike) -> FloatArray:
        """Vertical stress [Pa] at tip depth ``depth`` [m].

        >>> float(LinearStiffness(stiffness=1e6).stress(0.02))
        20000.0
        """
        d = check_finite("depth", depth)
        return self.stiffness * np.maximum(d, 0.0)

    def initial_state(self, foot: Foot, position: ArrayLike) -> LinearState:
        """State for a foot whose tip is at ``position`` (..., 3) [m]."""
        return LinearState(in_mud=tip_depth(tip_position(position)) > 0)

    def step(
        self, foot: Foot, state: LinearState, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[LinearState, TerrainOutput]:
        """Force at tip ``position`` [m] moving at ``velocity`` [m/s]; ``dt`` [s] unused."""
        check_positive("dt", dt, unit="s")
        pos, vel = kinematics(position, velocity)
        depth = tip_depth(pos)
        sz = self.stress(depth)
        if self.unloading == "zero":
            sz = np.where(vel[..., 2] > 0, 0.0, sz)
        fz = sz * projected(foot, depth)[..., 2]
        out = vertical_output(fz, np.where(depth > 0, sz, 0.0), depth)
        return LinearState(in_mud=depth > 0), out


def fit_stiffness(depth: ArrayLike, stress: ArrayLike) -> float:
    r"""Least-squares :math:`k` [N/m^3] of :math:`\sigma=k d` through the origin.

    Parameters
    ----------
    depth : array_like
        Tip depths below the surface [m], >= 0.
    stress : array_like
        Vertical stresses [Pa] at those depths.

    Examples
    --------
    >>> fit_stiffness([0.01, 0.02], [1e4, 2e4])
    1000000.0
    """
    d = check_nonnegative("depth", depth, unit="m").ravel()  # into the mud: >= 0
    s = check_finite("stress", stress).ravel()
    if d.shape != s.shape or not np.any(d != 0):
        raise MudrftError(
            "depth and stress must have the same length and a nonzero depth, "
            f"got {d.shape}, {s.shape}"
        )
    return float(np.dot(d, s) / np.dot(d, d))
