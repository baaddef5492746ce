r"""Maxwell-type mud (after Chen et al., AIM 2024): a 1D vertical reconstruction (D55).

The vertical stress at :math:`\gamma=d/L_c` is a nonlinear spring, a Maxwell element and
suction through a second-order filter, times the footprint :math:`A_z(d)`; docs/model.md (D55)
gives the equations, and says what is reconstructed and what fitted (:func:`fit_maxwell`).
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .._progress import Progress, make_progress
from .._typing import Namespace, XpArray
from .._validation import (
    MudrftError,
    check_characteristic_length,
    check_finite,
    check_in_range,
    check_nonnegative,
    check_positive,
    positive_number,
)
from .._validation import set_number as _set
from .._xp import pyfloat
from ..citations import register
from ..trajectories import Trajectory
from .base import TerrainOutput, kinematics, projected, tip_depth, tip_position, vertical_output

if TYPE_CHECKING:
    from ..feet.base import Foot

__all__ = ["MaxwellFit", "MaxwellMud", "MaxwellState", "fit_maxwell"]


class MaxwellState(NamedTuple):
    """Maxwell stress ``sigma_m`` [Pa], ``suction`` [Pa], ``suction_rate`` [Pa/s], deepest
    ``gamma_max`` [-] since entry, ``in_mud`` (bool)."""

    sigma_m: np.ndarray
    suction: np.ndarray
    suction_rate: np.ndarray
    gamma_max: np.ndarray
    in_mud: np.ndarray


def _zoh(
    dt: float, omega: float, damping: float
) -> tuple[float, float, float, float, float, float]:
    r"""Exact zero-order hold of the suction filter over ``dt`` [s]: ``(p00, p01, p10, p11,
    g0, g1)`` of :math:`\Phi=e^{A\,dt}` and :math:`\Gamma=A^{-1}(\Phi-I)B`."""
    a = damping * omega
    q = cmath.sqrt(omega * omega * (damping * damping - 1.0))
    qt = q * dt
    ch = cmath.cosh(qt).real
    sh = (cmath.sinh(qt) / q).real if abs(qt) > 1e-8 else dt * (1.0 + (qt * qt).real / 6.0)
    e = math.exp(-a * dt)
    p00, p01 = e * (ch + a * sh), e * sh
    p10, p11 = -e * omega * omega * sh, e * (ch - a * sh)
    g0, g1 = -2.0 * a * p01 - (p11 - 1.0), omega * omega * p01
    return p00, p01, p10, p11, g0, g1


@dataclass(frozen=True, eq=False)
class MaxwellMud:
    r"""Maxwell-type mud, a documented reconstruction of Chen et al. (AIM 2024); 1D vertical.

    Parameters
    ----------
    alpha, n : float
        Stiffness [Pa] and exponent in (0, 1] [-] of the nonlinear spring.
    modulus, relaxation : float
        Spring :math:`G` [Pa] and relaxation time :math:`\lambda_M=\eta_M/G` [s] of the
        Maxwell element.
    sigma_y : float
        Yield suction :math:`\sigma_Y` fed to the filter [Pa].
    omega, damping : float
        Natural frequency :math:`\omega_s` [rad/s] and damping ratio :math:`\zeta_s` [-]
        (default :math:`1/\sqrt2`, not fitted) of the suction filter.
    release : float
        Retraction :math:`r_b` over which the suction input lets go [-] (in :math:`L_c`).
    characteristic_length : float or None
        :math:`L_c` [m]; ``None`` uses the foot's.
    name : str
        Label in reports.

    References
    ----------
    .. [1] X. Chen, J. Yi and J. Shan, "A Reduced-Order Resistive Force Model for Robotic
       Foot-Mud Interactions", IEEE/ASME AIM 2024, arXiv:2403.02617.

    Examples
    --------
    >>> m = MaxwellMud()
    >>> m.alpha, m.n
    (24000.0, 0.53)
    """

    # alpha, n: Table S1; the rest fit_maxwell() (re-derived by tests/terrains/test_maxwell.py)
    alpha: float = 24e3
    n: float = 0.53
    modulus: float = 9.283e4
    relaxation: float = 0.2017
    sigma_y: float = 2.247e4
    omega: float = 62.50
    damping: float = 1.0 / np.sqrt(2.0)
    release: float = 1.471
    characteristic_length: float | None = None
    name: str = "maxwell"

    def __post_init__(self) -> None:
        for f in ("alpha", "modulus", "relaxation", "omega", "damping", "release"):
            _set(self, f, check_positive(f, getattr(self, f)))
        _set(self, "sigma_y", check_nonnegative("sigma_y", self.sigma_y, unit="Pa"))
        _set(self, "n", check_in_range("n", self.n, 1e-6, 1.0))
        if self.characteristic_length is not None:
            lc = check_characteristic_length("MaxwellMud", self.characteristic_length)
            object.__setattr__(self, "characteristic_length", lc)
        register("chen2024aim")

    @property
    def viscosity(self) -> float:
        """Dashpot viscosity :math:`\\eta_M=G\\lambda_M` [Pa s]."""
        return self.modulus * self.relaxation

    def replace(self, **kw: Any) -> MaxwellMud:
        """A copy with some fields changed."""
        return replace(self, **kw)

    def _lc(self, foot: Foot) -> float:
        return float(self.characteristic_length or foot.characteristic_length)

    def initial_state(self, foot: Foot, position: ArrayLike) -> MaxwellState:
        """Undisturbed mud under a foot whose tip is at ``position`` (..., 3) [m]."""
        depth = tip_depth(tip_position(position))
        z = np.zeros(depth.shape)
        return MaxwellState(z, z.copy(), z.copy(), depth / self._lc(foot), depth > 0)

    def advance(
        self, state: MaxwellState, gamma: ArrayLike, gamma_dot: ArrayLike, dt: float
    ) -> tuple[MaxwellState, np.ndarray]:
        """Advance over ``dt`` [s] to the dimensionless depth ``gamma`` [-] at the rate
        ``gamma_dot`` [1/s] (down > 0); return (state, stress [Pa]), reset out of the mud."""
        check_positive("dt", dt, unit="s")
        g, gd = np.asarray(gamma, dtype=float), np.asarray(gamma_dot, dtype=float)
        in_mud = g > 0
        hold = (np.exp(-dt / self.relaxation), *_zoh(float(dt), self.omega, self.damping))
        sigma_m, s, sd, gmax, inside = _update(self, *state[:4], g, gd, hold, np)
        stress = np.where(in_mud, inside, 0.0)
        zero = np.zeros(np.shape(stress))
        sigma_m, s, sd, gmax = (np.where(in_mud, v, zero) for v in (sigma_m, s, sd, gmax))
        return MaxwellState(sigma_m, s, sd, gmax, in_mud), stress  # reset out of the mud

    def step(
        self, foot: Foot, state: MaxwellState, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[MaxwellState, TerrainOutput]:
        """Advance by ``dt`` [s] to a tip at ``position`` [m] moving at ``velocity`` [m/s]."""
        pos, vel = kinematics(position, velocity)
        lc, depth = self._lc(foot), tip_depth(pos)
        in_mud = depth > 0
        gd = np.where(in_mud | state.in_mud, -vel[..., 2], 0.0) / lc
        new, sz = self.advance(state, depth / lc, gd, dt)
        return new, vertical_output(sz * projected(foot, depth)[..., 2], sz, depth)

    def response(
        self, trajectory: Trajectory, *, characteristic_length: float = 0.05
    ) -> np.ndarray:
        r"""Vertical stress :math:`\sigma_e+\sigma_M+\sigma_s` [Pa] on a plate at the samples of a
        vertical trajectory, 0 out of the mud (no foot needed).

        Parameters
        ----------
        trajectory : Trajectory
            Tip motion; its depth [m] and vertical velocity [m/s] are used.
        characteristic_length : float, keyword-only
            Plate :math:`L_c` [m].

        Examples
        --------
        >>> import mudrft
        >>> s = MaxwellMud().response(mudrft.plate_intrusion())
        >>> bool(s.max() > 0 > s.min())
        True
        """
        return _stress_history(self, trajectory.time, *_gammas(trajectory, characteristic_length))


def _gammas(trajectory: Trajectory, characteristic_length: float) -> tuple[np.ndarray, ...]:
    if not isinstance(trajectory, Trajectory):
        raise MudrftError(f"trajectory must be a Trajectory, got {type(trajectory).__name__}")
    lc = positive_number("characteristic_length", characteristic_length, unit="m")
    return trajectory.depth / lc, -trajectory.velocity[:, 2] / lc


def _update(
    m: MaxwellMud, sm: XpArray, s: XpArray, sd: XpArray, gmax: XpArray, g: XpArray,
    gd: XpArray, hold: tuple[XpArray, ...], xp: Namespace,
) -> tuple[XpArray, ...]:  # fmt: skip
    """One step at constant rate, element-wise: the new ``(sigma_m, suction, suction_rate,
    gamma_max)`` and the stress in the mud [Pa]; ``hold`` is ``(exp(-dt/lambda_M), *_zoh)``."""
    decay, p00, p01, p10, p11, g0, g1 = hold
    sm = sm * decay + m.modulus * m.relaxation * gd * (1.0 - decay)
    gmax = xp.maximum(gmax, g)
    u = xp.where(gd < 0, -m.sigma_y * xp.exp(-(gmax - g) / m.release), 0.0)
    s, sd = p00 * s + p01 * sd + g0 * u, p10 * s + p11 * sd + g1 * u
    return sm, s, sd, gmax, m.alpha * xp.maximum(g, 0.0) ** m.n + sm + s


def _stress_history(
    model: MaxwellMud, time: np.ndarray, gamma: np.ndarray, gamma_dot: np.ndarray
) -> np.ndarray:
    """:meth:`MaxwellMud.advance` along a history, on Python floats (fast)."""
    lam, om, zt = model.relaxation, model.omega, model.damping
    t, gam, gdot = (np.asarray(a, dtype=float).tolist() for a in (time, gamma, gamma_dot))
    out = np.zeros(len(t))
    sm = s = sd = gmax = 0.0
    was_in = gam[0] > 0
    cache: dict[float, tuple[float, ...]] = {}
    for i in range(len(t)):
        dt = t[i] - t[i - 1] if i > 0 else t[1] - t[0]
        key = round(dt, 12)
        hold = cache.get(key)
        if hold is None:
            hold = cache[key] = (math.exp(-dt / lam), *_zoh(dt, om, zt))
        g = gam[i]
        gd = gdot[i] if (g > 0 or was_in) else 0.0
        sm, s, sd, gmax, stress = _update(model, sm, s, sd, gmax, g, gd, hold, pyfloat)
        was_in = g > 0
        if was_in:
            out[i] = stress
        else:
            sm = s = sd = gmax = 0.0
    return out


@dataclass(frozen=True)
class MaxwellFit:
    """:func:`fit_maxwell`'s ``model``, stress ``rmse`` [Pa] and the optimiser's ``success``,
    ``message`` and ``nfev``."""

    model: MaxwellMud
    rmse: float
    success: bool
    message: str
    nfev: int


_FIT_FIELDS = ("modulus", "relaxation", "sigma_y", "omega", "release")


def fit_maxwell(
    trajectory: Trajectory, stress: ArrayLike, *, characteristic_length: float = 0.05,
    initial: MaxwellMud | None = None, progress: bool = False,
) -> MaxwellFit:  # fmt: skip
    r"""Fit :math:`G, \lambda_M, \sigma_Y, \omega_s, r_b` (least squares on their logs, over the
    samples in the mud) to a vertical stress history; :math:`\alpha, n, \zeta_s` are kept.

    Parameters
    ----------
    trajectory : Trajectory
        Vertical plate motion.
    stress : array_like, shape (n,)
        Vertical stress [Pa] at the trajectory's samples.
    characteristic_length : float, keyword-only
        Plate :math:`L_c` [m].
    initial : MaxwellMud or None, keyword-only
        Starting point (default: :class:`MaxwellMud` defaults).
    progress : bool, keyword-only
        Report every 20th evaluation through the ``mudrft.progress`` logger.
    """
    from scipy.optimize import least_squares

    g, gd = _gammas(trajectory, characteristic_length)
    s = check_finite("stress", stress)
    if s.shape != trajectory.time.shape:
        raise MudrftError(
            f"stress must have shape {trajectory.time.shape} to match the trajectory, got {s.shape}"
        )
    m0 = initial or MaxwellMud()
    inside = g > 0  # out of the mud both models give 0 as terrains
    if not np.any(inside):
        raise MudrftError("the trajectory never enters the mud (depth > 0); nothing to fit")
    x0 = np.log([getattr(m0, f) for f in _FIT_FIELDS])
    count = [0]
    report = make_progress(bool(progress), "fit_maxwell")

    def resid(x: np.ndarray) -> np.ndarray:
        count[0] += 1
        if isinstance(report, Progress) and count[0] % 20 == 0:
            report.note(f"fit_maxwell: evaluation {count[0]}")
        m = m0.replace(**dict(zip(_FIT_FIELDS, np.exp(x), strict=True)))
        return (_stress_history(m, trajectory.time, g, gd) - s)[inside]

    sol = least_squares(resid, x0, method="trf", x_scale=1.0, diff_step=1e-4)
    model = m0.replace(**dict(zip(_FIT_FIELDS, np.exp(sol.x), strict=True)))
    rmse = float(np.sqrt(np.mean(sol.fun**2)))
    return MaxwellFit(model, rmse, bool(sol.success), str(sol.message), int(sol.nfev))
