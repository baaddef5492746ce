"""Run the constitutive model along a plate test (paper experiments E1-E4)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ._validation import MudrftError, check_characteristic_length, check_finite, number_in_range
from ._xp import pyfloat
from .constitutive import laws
from .constitutive.dynamics import evaluation
from .constitutive.kernel import ChannelConstants, channel_constants, channel_step
from .constitutive.state import ChannelState
from .parameters.base import Mud, MudParameters
from .plotting import AxesArg, plot_plate
from .terrains.rows import constants_at
from .trajectories import Trajectory

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["DEFAULT_PLATE_LENGTH", "PlateResult", "plate_history", "plate_response"]

#: Characteristic length of the paper's plates [m], not given by the paper (decision D1).
DEFAULT_PLATE_LENGTH = 0.05


@dataclass(frozen=True, eq=False)
class PlateResult:
    """A plate test, each field (n,): ``time`` [s], ``displacement`` [m], the ``stress``
    (eq. 1), its ``normal`` and ``tangential`` parts (eq. 7), its terms ``elastic``,
    ``thixotropic``, ``suction`` [Pa], and the structure ``xi`` [-]."""

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
    trajectory: Trajectory, params: MudParameters | Mud, *,
    characteristic_length: float = DEFAULT_PLATE_LENGTH, acceleration: bool | None = None,
    thixotropy: str = "ode", clock: str = "contact", xi0: float = 0.0,
) -> PlateResult:  # fmt: skip
    """Stress on a plate driven along ``trajectory`` (from :func:`mudrft.plate_intrusion`).

    Parameters
    ----------
    trajectory : Trajectory
        A plate test; its ``meta["displacement"]`` (or the tip depth) is the intrusion [m].
    params : MudParameters or Mud
        A parameter set, or a Mud (the set of the test's direction is used).
    characteristic_length : float, keyword-only
        Plate characteristic length :math:`L_c` [m].
    acceleration : bool or None, keyword-only
        Keep the acceleration term of f_xi (decision D6); None keeps it in the ODE.
    thixotropy, clock : str, keyword-only
        As :class:`mudrft.MudTerrain` (decision D15).
    xi0 : float, keyword-only
        Initial structure parameter [-].

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
    if p.shape != ():
        raise MudrftError(f"params must be a single parameter set, got a batch of shape {p.shape}")
    t = trajectory.time
    q = trajectory.meta.get("displacement")
    if q is None:
        q = trajectory.depth if direction == "vertical" else trajectory.position[:, 0]
    q = check_finite("trajectory.meta['displacement']", q)
    if q.shape != t.shape:
        raise MudrftError(
            f"trajectory.meta['displacement'] must have shape {t.shape} to match the time, "
            f"got {q.shape}"
        )
    qs, restart, kappa = evaluation(thixotropy, clock, acceleration)
    number_in_range("xi0", xi0, 0.0, 1.0)
    gamma = (q / L)[:, None]
    out = plate_history(
        channel_constants(p), gamma, np.diff(gamma, axis=0) / np.diff(t)[:, None],
        np.diff(t)[:, None], kappa=kappa, quasi_static=qs, restart=restart, xi0=xi0,
        contact=direction == "vertical",
    )  # fmt: skip
    total, el, th, su, xi = out[:, 0, 0].T
    angle = float(trajectory.meta.get("angle", 0.0))
    return PlateResult(
        time=t, displacement=q, stress=total, normal=laws.f_n(angle) * total,
        tangential=laws.f_t(angle) * total, elastic=el, thixotropic=th, suction=su, xi=xi,
    )  # fmt: skip


def _plate_run(
    c: NDArray[np.float64], gamma: NDArray[np.float64], rate: NDArray[np.float64],
    dt: NDArray[np.float64], kappa: float, quasi_static: bool, restart: bool, xi0: float,
    contact: bool, out: NDArray[np.float64],
) -> None:  # fmt: skip
    """:func:`plate_history` on floats, compiled: constant rows ``c`` (B T, 12), ``gamma``
    (n, T), ``rate`` and ``dt`` (n - 1, T), outputs into ``out`` (n, B, T, 5)."""
    n, T = gamma.shape
    for b in range(out.shape[1]):
        for t in range(T):
            ch = constants_at(c, b * T + t, 0)
            inside = gamma[0, t] > 0.0 or not contact  # in_contact
            g = gamma[0, t] if inside else 0.0
            st = ChannelState(g, g, xi0, 0.0, 0.0, 0.0, 0.0)
            out[0, b, t, 4] = xi0
            for k in range(1, n):
                now = gamma[k, t] > 0.0 or not contact
                if not inside:  # entering undisturbed mud (enter)
                    st = ChannelState(0.0, 0.0, xi0, 0.0, 0.0, 0.0, 0.0)
                r = rate[k - 1, t] if inside or now else 0.0  # contact_rate
                g = gamma[k, t] if now else 0.0
                st, stress = channel_step(
                    ch, st, g, r, dt[k - 1, t], 1.0, kappa, quasi_static, restart, pyfloat
                )
                o = out[k, b, t]
                if now:
                    o[0], o[1], o[2], o[3] = stress
                o[4] = st.xi
                inside = now


def plate_history(
    consts: ChannelConstants, gamma: NDArray[np.float64], rate: NDArray[np.float64],
    dt: NDArray[np.float64], *, kappa: float, quasi_static: bool, restart: bool, xi0: float,
    contact: bool, batch: int = 1,
) -> NDArray[np.float64]:  # fmt: skip
    """A plate channel along a history (unchecked; also the calibration's model).

    ``gamma`` (n, T) [-] at the samples of T histories, ``rate`` [1/s] and ``dt`` [s]
    (n - 1, T) over the steps, ``consts`` broadcasting to (batch, T), flags from
    :func:`mudrft.constitutive.dynamics.evaluation`, undisturbed structure ``xi0`` [-]; with
    ``contact`` the plate feels the mud only while ``gamma > 0``. Returns (n, batch, T, 5):
    the total, elastic, thixotropic and suction stresses [Pa] (0 out of the mud) and the
    structure [-] at each sample, compiled from the one channel step.
    """
    from ._jit import jit

    n, T = gamma.shape
    rows = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (batch, T)) for v in consts], -1)
    c = np.ascontiguousarray(rows.reshape(batch * T, -1))
    out = np.zeros((n, batch, T, 5))
    steps = [np.ascontiguousarray(np.broadcast_to(a, (n - 1, T)), dtype=float) for a in (rate, dt)]
    g = np.ascontiguousarray(gamma, dtype=float)
    jit(_plate_run)(c, g, *steps, float(kappa), bool(quasi_static), bool(restart), float(xi0), bool(contact), out)  # fmt: skip
    return out
