r"""The morphing foot's two-stage spring column (decision D31, paper Fig. S3b): a soft spring
:math:`k_s` and a hard one :math:`k_h` in series, the soft stage bottoming out at the *knee*
after a compression :math:`s_s` of the soft spring (the force law: :func:`spring_force`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._typing import Namespace, XpArray
from ..._validation import MudrftError, positive_number

if TYPE_CHECKING:
    from .linkage import MorphingRow

__all__ = ["RigidGroundResponse", "TwoStageSpring", "spring_force"]


def spring_force(
    s: TwoStageSpring | MorphingRow, deflection: XpArray, xp: Namespace = np
) -> XpArray:
    r"""Column spring force [N] at a deflection :math:`\delta` [m] (D31), element-wise:
    :math:`F_s=\frac{k_sk_h}{k_s+k_h}\delta` up to the knee :math:`\delta_1=s_s(1+k_s/k_h)`,
    :math:`k_ss_s+k_h(\delta-\delta_1)` beyond; ``s`` holds ``knee_deflection`` [m],
    ``knee_force`` [N], ``series_stiffness`` and ``hard_stiffness`` [N/m] by attribute."""
    d1 = s.knee_deflection
    return xp.where(
        deflection <= d1,
        s.series_stiffness * deflection,
        s.knee_force + s.hard_stiffness * (deflection - d1),
    )


@dataclass(frozen=True)
class TwoStageSpring:
    """Two springs in series in a two-stage telescoping column (D31).

    Attributes: ``soft_stiffness`` :math:`k_s` [N/m]; ``hard_stiffness`` :math:`k_h` [N/m],
    >= ``soft_stiffness``; ``soft_travel`` :math:`s_s`, the soft spring's compression when its
    stage bottoms out [m]. All positive, else a :class:`MudrftError`.

    >>> s = TwoStageSpring()
    >>> round(s.series_stiffness, 1), round(s.knee_deflection * 1e3, 2), s.knee_force
    (705.9, 8.5, 6.0)
    >>> s.force([0.0, s.knee_deflection]).round(6).tolist()
    [0.0, 6.0]
    """

    soft_stiffness: float = 800.0
    hard_stiffness: float = 6000.0
    soft_travel: float = 0.0075

    def __post_init__(self) -> None:
        for k, u in (("soft_stiffness", "N/m"), ("hard_stiffness", "N/m"), ("soft_travel", "m")):
            object.__setattr__(self, k, positive_number(k, getattr(self, k), unit=u))
        if self.hard_stiffness < self.soft_stiffness:
            raise MudrftError(
                f"hard_stiffness must be >= soft_stiffness = {self.soft_stiffness!r} N/m, "
                f"got {self.hard_stiffness!r} N/m"
            )

    @property
    def series_stiffness(self) -> float:
        """Stiffness of the first stage, :math:`k_sk_h/(k_s+k_h)` [N/m]."""
        ks, kh = self.soft_stiffness, self.hard_stiffness
        return ks * kh / (ks + kh)

    @property
    def knee_deflection(self) -> float:
        """Column deflection where the soft stage bottoms out, :math:`s_s(1+k_s/k_h)` [m]."""
        return self.soft_travel * (1.0 + self.soft_stiffness / self.hard_stiffness)

    @property
    def knee_force(self) -> float:
        """Force at which the soft stage bottoms out, :math:`k_ss_s` [N]."""
        return self.soft_stiffness * self.soft_travel

    def force(self, deflection: ArrayLike) -> NDArray[np.float64]:
        """Spring force [N] at a column deflection [m] >= 0 (no end stops: see the linkage)."""
        return np.asarray(spring_force(self, np.asarray(deflection, dtype=float)))

    def deflection(self, force: ArrayLike) -> NDArray[np.float64]:
        """Inverse of :meth:`force`: deflection [m] under a force [N] >= 0."""
        f = np.asarray(force, dtype=float)
        f1 = self.knee_force
        return np.where(
            f <= f1,
            f / self.series_stiffness,
            self.knee_deflection + (f - f1) / self.hard_stiffness,
        )

    def stiffness(self, deflection: ArrayLike) -> NDArray[np.float64]:
        """Tangent stiffness :math:`dF_s/d\\delta` [N/m] at a deflection [m]: the series
        stiffness below the knee, the hard spring's from the knee on."""
        d = np.asarray(deflection, dtype=float)
        return np.where(d < self.knee_deflection, self.series_stiffness, self.hard_stiffness)


class RigidGroundResponse(NamedTuple):
    """Foot pressed on rigid ground (paper Fig. S3), all the load through the tip:
    ``deflection`` [m], ``force`` [N], ``pad_angle`` [rad] and tangent ``stiffness`` [N/m]."""

    deflection: NDArray[np.float64]
    force: NDArray[np.float64]
    pad_angle: NDArray[np.float64]
    stiffness: NDArray[np.float64]
