"""Run the constitutive model along a plate test (paper experiments E1-E4)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ._validation import MudrftError, check_characteristic_length
from .constitutive import laws
from .constitutive.dynamics import run
from .parameters.base import Mud, MudParameters
from .plotting import AxesArg, plot_plate
from .trajectories import Trajectory

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["DEFAULT_PLATE_LENGTH", "PlateResult", "plate_response"]

#: Characteristic length of the paper's plates [m]. The paper does not give the plate
#: size; 50 mm fits its 28 x 23 cm container (decision D1 in docs/model.md).
DEFAULT_PLATE_LENGTH = 0.05


@dataclass(frozen=True, eq=False)
class PlateResult:
    """Stress on a plate along a plate test.

    Attributes
    ----------
    time : ndarray (n,)
        Times [s].
    displacement : ndarray (n,)
        Intrusion displacement of the plate [m].
    stress : ndarray (n,)
        Total stress sigma_tot along the motion [Pa] (eq. 1).
    normal, tangential : ndarray (n,)
        Normal and tangential stress on the tilted plate, f_n(angle)*sigma and
        f_t(angle)*sigma [Pa] (eq. 7).
    elastic, thixotropic, suction : ndarray (n,)
        The three terms of eq. (1) [Pa].
    xi : ndarray (n,)
        Structure parameter [-].
    """

    time: np.ndarray
    displacement: np.ndarray
    stress: np.ndarray
    normal: np.ndarray
    tangential: np.ndarray
    elastic: np.ndarray
    thixotropic: np.ndarray
    suction: np.ndarray
    xi: np.ndarray

    def __repr__(self) -> str:
        return (
            f"PlateResult(samples={self.time.size}, "
            f"duration={self.time[-1] - self.time[0]:.4g} s, "
            f"max_displacement={float(self.displacement.max()):.4g} m, "
            f"min_stress={float(self.stress.min()):.4g} Pa, "
            f"max_stress={float(self.stress.max()):.4g} Pa)"
        )

    def plot(self, ax: AxesArg = None) -> Figure:
        """Stress against time and displacement (needs matplotlib)."""
        return plot_plate(self, ax=ax)


def plate_response(
    trajectory: Trajectory,
    params: MudParameters | Mud,
    *,
    characteristic_length: float = DEFAULT_PLATE_LENGTH,
    acceleration: bool | None = None,
    thixotropy: str = "ode",
    clock: str = "contact",
    xi0: float = 0.0,
) -> PlateResult:
    """Stress on a plate driven along ``trajectory`` (from :func:`mudrft.plate_intrusion`).

    Parameters
    ----------
    trajectory : Trajectory
        A plate test; its ``meta["displacement"]`` (or the tip depth) is the intrusion [m].
    params : MudParameters or Mud
        A parameter set, or a Mud from which the set matching the test direction is taken.
    characteristic_length : float, keyword-only
        Plate characteristic length L_c [m].
    acceleration : bool or None, keyword-only
        Keep the acceleration term of f_xi (decision D6); None keeps it in the ODE.
    thixotropy : {"ode", "quasi-static"}, keyword-only
        Step eqs. (3) and (5), or evaluate the paper's closed forms (9)-(11) (decision D15).
    clock : {"contact", "retraction"}, keyword-only
        Quasi-static only: the clock of eq. (9) (decision D15).
    xi0 : float, keyword-only
        Initial structure parameter [-].

    Notes
    -----
    A vertical plate whose displacement is back to 0 has left the mud; its stress is 0.

    References
    ----------
    .. [1] X. Chen, L. Wang, X. Huang, J. Shan, Y. Shen and J. Yi, "A Foot Resistive Force
       Model for Legged Locomotion on Muddy Terrains", 2026 (preprint with supplementary
       materials), Sec. IV-A and supplementary Fig. S2 (plate tests).

    Examples
    --------
    >>> import mudrft
    >>> res = mudrft.plate_response(mudrft.plate_intrusion(), mudrft.paper_mud(0.25))
    >>> bool(res.stress.max() > 0 > res.stress.min())
    True
    """
    if not isinstance(trajectory, Trajectory):
        raise MudrftError(
            f"trajectory must be a Trajectory (see mudrft.plate_intrusion), got {type(trajectory).__name__}"
        )
    L = check_characteristic_length("plate_response", characteristic_length)
    direction = trajectory.meta.get("direction", "vertical")
    if isinstance(params, Mud):
        p = params.vertical if direction == "vertical" else params.horizontal
    elif isinstance(params, MudParameters):
        p = params
    else:
        raise MudrftError(f"params must be a MudParameters or a Mud, got {type(params).__name__}")
    q = trajectory.meta.get("displacement")
    if q is None:
        q = trajectory.depth if direction == "vertical" else trajectory.position[:, 0]
    h = run(
        p,
        trajectory.time,
        np.asarray(q) / L,
        acceleration=acceleration,
        thixotropy=thixotropy,
        clock=clock,
        xi0=xi0,
    )
    # a vertical plate back at the surface has left the mud: no stress (as MudTerrain does for feet)
    inside = np.asarray(q) > 0 if direction == "vertical" else np.ones(np.shape(q), dtype=bool)
    total, el, th, su = (
        np.where(inside, a, 0.0) for a in (h.total, h.elastic, h.thixotropic, h.suction)
    )
    angle = float(trajectory.meta.get("angle", 0.0))
    return PlateResult(
        time=trajectory.time,
        displacement=np.asarray(q, dtype=float),
        stress=total,
        normal=laws.f_n(angle) * total,
        tangential=laws.f_t(angle) * total,
        elastic=el,
        thixotropic=th,
        suction=su,
        xi=h.xi,
    )
