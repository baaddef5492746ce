r"""3D resistive force theory of Agarwal, Goldman & Kamrin (PNAS 2023) as a terrain.

A submerged leading element carries :math:`d\mathbf F=\boldsymbol\alpha\,|z|\,dA`: the generic
response (:func:`rft3d_alpha`) times the material constant :math:`\xi_n` (:func:`agarwal_xi`),
its tangential part capped by the intruder-surface friction :math:`\mu_{surf}` [-];
docs/model.md, section 8, gives the equations (decisions D90-D95).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import (
    MudrftError,
    check_finite,
    check_in_range,
    check_positive,
    number_in_range,
    positive_number,
    warn_implausible,
    warn_plausibility,
)
from .._validation import set_number as _set
from ..citations import register
from .granular_rft import (
    LEADING_WIDTH,
    FacetRFT,
    _element_forces,
    check_facets,
    leading_weight,
    unit_vectors,
)

__all__ = [
    "AGARWAL2023", "GRAVITY", "PLAUSIBLE_RHO_C", "WALL_WIDTH", "GranularRFT3D",
    "PolynomialCoefficients", "agarwal_generic_alpha", "agarwal_xi", "rft3d_alpha", "rft3d_forces"
]  # fmt: skip

#: Standard gravity used by the material constant [m/s^2] (the value the sources use).
GRAVITY = 9.81

#: Width in :math:`n_z` of the blend across vertical walls [-] (decision D93).
WALL_WIDTH = 1e-3

#: Plausible bulk densities of a granular medium [kg/m^3]; below, most likely g/cm^3.
PLAUSIBLE_RHO_C = (100.0, 1.0e4)


@dataclass(frozen=True)
class PolynomialCoefficients:
    r"""Coefficients :math:`c_i^k` of 3D-RFT's cubic fits :math:`f_i=\sum_k c_i^k T_k` [-].

    The 20 terms :math:`T_k` are, in order, :math:`1, x_1, x_2, x_3, x_1^2, x_2^2, x_3^2,
    x_1x_2, x_2x_3, x_3x_1, x_1^3, x_2^3, x_3^3, x_1x_2^2, x_2x_1^2, x_2x_3^2, x_3x_2^2,
    x_3x_1^2, x_1x_3^2, x_1x_2x_3` with :math:`x_1=\sin\gamma`, :math:`x_2=\cos\beta`,
    :math:`x_3=\cos\psi\cos\gamma\sin\beta+\sin\gamma\cos\beta`.
    """

    c1: tuple[float, ...]
    c2: tuple[float, ...]
    c3: tuple[float, ...]

    def __post_init__(self) -> None:
        for name in ("c1", "c2", "c3"):
            c = check_finite(name, getattr(self, name))
            if c.shape != (20,):
                raise MudrftError(f"{name} must hold 20 coefficients, got shape {c.shape}")

    def table(self) -> NDArray[np.float64]:
        """The coefficients as a (20, 3) array, columns :math:`c_1, c_2, c_3` [-]."""
        return np.array([self.c1, self.c2, self.c3], dtype=float).T

    def f(self, x1: ArrayLike, x2: ArrayLike, x3: ArrayLike) -> NDArray[np.float64]:
        """``(f1, f2, f3)`` stacked on a last axis of 3, for arrays of ``x1, x2, x3`` [-]."""
        x1, x2, x3 = (np.asarray(x, dtype=float) for x in (x1, x2, x3))
        terms = np.stack(
            np.broadcast_arrays(
                np.ones_like(x1), x1, x2, x3, x1**2, x2**2, x3**2, x1 * x2, x2 * x3, x3 * x1,
                x1**3, x2**3, x3**3, x1 * x2**2, x2 * x1**2, x2 * x3**2, x3 * x2**2,
                x3 * x1**2, x1 * x3**2, x1 * x2 * x3,
            ),
            axis=-1,
        )  # fmt: skip
        return terms @ self.table()


#: Agarwal, Goldman & Kamrin (2023), supplementary coefficients (decision D91).
AGARWAL2023 = PolynomialCoefficients(
    c1=(
        0.00212, -0.02320, -0.20890, -0.43083, -0.00259, 0.48872, -0.00415, 0.07204,
        -0.02750, -0.08772, 0.01992, -0.45961, 0.40799, -0.10107, -0.06576, 0.05664,
        -0.09269, 0.01892, 0.01033, 0.15120,
    ),
    c2=(
        -0.06796, -0.10941, 0.04725, -0.06914, -0.05835, -0.65880, -0.11985, -0.25739,
        -0.26834, 0.02692, -0.00736, 0.63758, 0.08997, 0.21069, 0.04748, 0.20406,
        0.18519, 0.04934, 0.13527, -0.33207,
    ),
    c3=(
        -0.02634, -0.03436, 0.45256, 0.00835, 0.02553, -1.31290, -0.05532, 0.06790,
        -0.16404, 0.02287, 0.02927, 0.95406, -0.00131, -0.11028, 0.01487, -0.02730,
        0.10911, -0.04097, 0.07881, -0.27519,
    ),
)  # fmt: skip

_Z = np.array([0.0, 0.0, 1.0])


def agarwal_xi(
    rho_c: ArrayLike, mu_int: ArrayLike, *, gravity: float = GRAVITY
) -> NDArray[np.float64]:
    r"""Material constant of 3D-RFT, :math:`\xi_n=\rho_c g(894\mu^3-386\mu^2+89\mu)` [N/m^3].

    Parameters
    ----------
    rho_c, mu_int : array_like
        Bulk density [kg/m^3] and internal friction coefficient [-] of the medium.
    gravity : float, keyword-only
        Gravitational acceleration [m/s^2].

    Examples
    --------
    >>> round(float(agarwal_xi(1310.0, 0.21)), 1)      # 1310 * 9.81 * 9.946734
    127826.5
    """
    rho = check_positive("rho_c", rho_c, unit="kg/m^3")
    mu = check_positive("mu_int", mu_int)
    g = positive_number("gravity", gravity, unit="m/s^2")
    return np.asarray(rho * g * (894.0 * mu**3 - 386.0 * mu**2 + 89.0 * mu), dtype=float)


def agarwal_generic_alpha(
    beta: ArrayLike, gamma: ArrayLike, psi: ArrayLike, *,
    coefficients: PolynomialCoefficients = AGARWAL2023,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:  # fmt: skip
    r"""The paper's generic response in its local frame,
    :math:`(\alpha_r, \alpha_\theta, \alpha_z)` [-] (docs/model.md, section 8): :math:`\hat r`
    the horizontal direction of motion, :math:`\hat\theta=\hat z\times\hat r`, :math:`\hat z`
    up; positive components push the element along them.

    Parameters
    ----------
    beta : array_like
        Tilt of the element [rad], :math:`[-\pi/2, \pi/2]`; its downward normal is
        :math:`(\sin\beta\cos\psi, \sin\beta\sin\psi, -\cos\beta)` (0: horizontal).
    gamma : array_like
        Angle of the motion below the horizontal [rad], :math:`[-\pi/2, \pi/2]`.
    psi : array_like
        Angle of the element's horizontal normal from :math:`\hat r` [rad], :math:`[-\pi/2, \pi/2]`.
    coefficients : PolynomialCoefficients, keyword-only
        The fit (default :data:`AGARWAL2023`).

    Examples
    --------
    >>> # a horizontal plate pushed straight down: -sum_k (c1 + c2 + c3), not 1 (D92)
    >>> [round(float(a), 5) + 0.0 for a in agarwal_generic_alpha(0.0, np.pi / 2, 0.0)]
    [0.0, 0.0, 0.87574]
    """
    b = check_finite("beta", beta)
    g = check_finite("gamma", gamma)
    p = check_finite("psi", psi)
    sb, cb, sg, cg, sp, cp = np.sin(b), np.cos(b), np.sin(g), np.cos(g), np.sin(p), np.cos(p)
    f = coefficients.f(sg, cb, cp * cg * sb + sg * cb)
    f1, f2, f3 = f[..., 0], f[..., 1], f[..., 2]
    return f1 * sb * cp + f2 * cg, f1 * sb * sp, -f1 * cb - f2 * sg - f3


def _generic_for(
    n_down: NDArray[np.float64], v: NDArray[np.float64], coefficients: PolynomialCoefficients
) -> NDArray[np.float64]:
    """f1 n_d + f2 v - f3 z for downward normals ``n_down`` and directions ``v`` (..., 3)."""
    f = coefficients.f(-v[..., 2], -n_down[..., 2], (n_down * v).sum(-1))
    return f[..., :1] * n_down + f[..., 1:2] * v - f[..., 2:] * _Z


def _generic(
    normals: NDArray[np.float64], direction: NDArray[np.float64],
    coefficients: PolynomialCoefficients, wall_width: float,
) -> NDArray[np.float64]:  # fmt: skip
    """Generic response (..., k, 3) [-] of unit ``normals`` (k, 3) moving along the unit
    ``direction`` (D90); the downward normal is blended across walls, ``|n_z| < wall_width`` (D93)."""
    nz = normals[:, 2]
    if wall_width > 0.0:
        w = np.clip(0.5 - nz / (2.0 * wall_width), 0.0, 1.0)  # weight of n_d = n
    else:
        w = (nz < 0.0).astype(float)
    v = np.broadcast_to(direction[..., None, :], direction.shape[:-1] + normals.shape)
    n_down = np.broadcast_to(np.where((w >= 0.5)[:, None], normals, -normals), v.shape)
    alpha = _generic_for(n_down, v, coefficients)
    band = (w > 0.0) & (w < 1.0)  # walls within wall_width of vertical: blend both readings
    if np.any(band):
        vb, wb = v[..., band, :], w[band][:, None]
        nb = np.broadcast_to(normals[band], vb.shape)
        below, above = _generic_for(nb, vb, coefficients), _generic_for(-nb, vb, coefficients)
        alpha[..., band, :] = wb * below + (1.0 - wb) * above
    return alpha


def _cap(
    alpha: NDArray[np.float64], normals: NDArray[np.float64], mu_surf: float
) -> NDArray[np.float64]:
    """Friction cap (D94): tangential part scaled to at most ``mu_surf`` times the normal part."""
    n = np.broadcast_to(normals, alpha.shape)
    a_n = (alpha * n).sum(-1, keepdims=True) * n
    a_t = alpha - a_n
    limit = mu_surf * np.linalg.norm(a_n, axis=-1, keepdims=True)
    t = np.linalg.norm(a_t, axis=-1, keepdims=True)
    scale = np.where(t > limit, limit / np.where(t > limit, t, 1.0), 1.0)
    return a_n + scale * a_t


def rft3d_alpha(
    normals: ArrayLike, direction: ArrayLike, *, mu_surf: float | None = None,
    coefficients: PolynomialCoefficients = AGARWAL2023, wall_width: float = WALL_WIDTH,
) -> NDArray[np.float64]:  # fmt: skip
    r"""Generic 3D-RFT response of elements (..., m, 3), optionally friction-capped: the force per
    unit :math:`\xi_n`, depth and area, world frame [-]; :func:`agarwal_generic_alpha` in the
    world frame, :math:`f_1\hat n_d+f_2\hat v-f_3\hat z` (D90), leading or not.

    Parameters
    ----------
    normals, direction, coefficients, wall_width
        As :func:`rft3d_forces`.
    mu_surf : float or None, keyword-only
        Intruder-surface friction coefficient [-] of the cap; ``None``: no cap.

    Examples
    --------
    >>> rft3d_alpha([[0, 0, -1]], [0, 0, -1]).round(5) + 0.0     # flat plate pushed down
    array([[0.     , 0.     , 0.87574]])
    """
    n = unit_vectors("normals", normals)
    if n.ndim != 2:
        raise MudrftError(f"normals must have shape (m, 3), got shape {n.shape}")
    v = unit_vectors("direction", direction)
    check_in_range("wall_width", wall_width, 0.0, 1.0)
    alpha = _generic(n, v, coefficients, wall_width)
    if mu_surf is None:
        return alpha
    return _cap(alpha, n, number_in_range("mu_surf", mu_surf, 0.0, 1e3))


def _unit_forces(
    normals: NDArray[np.float64], direction: NDArray[np.float64],
    coefficients: PolynomialCoefficients, mu_surf: float, leading_width: float, wall_width: float,
) -> NDArray[np.float64]:  # fmt: skip
    """Capped response (..., k, 3) of unit ``normals`` weighted by how much each leads."""
    alpha = _cap(_generic(normals, direction, coefficients, wall_width), normals, mu_surf)
    lead = leading_weight((normals * direction[..., None, :]).sum(-1), leading_width)
    return lead[..., None] * alpha


def rft3d_forces(
    normals: ArrayLike, depths: ArrayLike, areas: ArrayLike, direction: ArrayLike, *, xi_n: float,
    mu_surf: float, coefficients: PolynomialCoefficients = AGARWAL2023, per_element: bool = False,
    leading_width: float = LEADING_WIDTH, wall_width: float = WALL_WIDTH,
) -> NDArray[np.float64]:  # fmt: skip
    r"""3D-RFT force [N] :math:`d\mathbf F = w\,\boldsymbol\alpha\,|z|\,dA` on elements moving
    in one direction, :math:`w` their leading weight.

    Parameters
    ----------
    normals, depths, areas, direction : array_like
        As :func:`~mudrft.terrains.granular_rft.rft_forces`.
    xi_n : float, keyword-only
        Material constant [N/m^3] (:func:`agarwal_xi`).
    mu_surf : float, keyword-only
        Intruder-surface friction coefficient of the cap [-].
    coefficients : PolynomialCoefficients, keyword-only
        The fit (default :data:`AGARWAL2023`).
    per_element : bool, keyword-only
        Return every element's force (..., m, 3) instead of the sum (..., 3).
    leading_width, wall_width : float, keyword-only
        Ramp widths [-] of :func:`~mudrft.terrains.granular_rft.leading_weight` (D53) and of
        the wall blend (D93).

    Examples
    --------
    >>> f = rft3d_forces([[0, 0, -1]], [0.02], [1e-3], [0, 0, -1], xi_n=1e5, mu_surf=0.4)
    >>> [round(float(c), 6) + 0.0 for c in f]
    [0.0, 0.0, 1.75148]
    """
    n, d, a, v = check_facets(normals, depths, areas, direction)
    xi = positive_number("xi_n", xi_n, unit="N/m^3")
    mu = number_in_range("mu_surf", mu_surf, 0.0, 1e3)
    check_in_range("leading_width", leading_width, 0.0, 1.0)
    check_in_range("wall_width", wall_width, 0.0, 1.0)
    unit = _unit_forces(n, v, coefficients, mu, leading_width, wall_width)
    return _element_forces(xi, d, a, unit, per_element=per_element)


@dataclass(frozen=True, eq=False)
class GranularRFT3D(FacetRFT):
    r"""3D-RFT (Agarwal, Goldman & Kamrin 2023) as a terrain: :func:`rft3d_forces` on the foot.

    Parameters
    ----------
    rho_c : float
        Bulk density of the medium [kg/m^3] (D95); below 100 warns (g/cm^3 given as kg/m^3).
    mu_int : float
        Internal friction coefficient [-], the tangent of the friction angle (D95).
    mu_surf : float
        Intruder-surface friction coefficient of the cap [-] (D95); (2, 90] warns as an
        angle in degrees; 1e3 turns the cap off.
    gravity : float
        Gravitational acceleration [m/s^2].
    coefficients : PolynomialCoefficients
        The cubic fits (default :data:`AGARWAL2023`, D91).
    rest_speed, leading_width, wall_width : float
        As :class:`~mudrft.terrains.GranularRFT` [m/s], [-]; the wall blend's width [-] (D93).
    name : str
        Label in reports.

    References
    ----------
    .. [1] S. Agarwal, D. I. Goldman and K. Kamrin, "Mechanistic framework for
       reduced-order models in soft materials: Application to three-dimensional granular
       intrusion", PNAS 120:e2214017120, 2023, doi:10.1073/pnas.2214017120.

    Examples
    --------
    >>> t = GranularRFT3D()
    >>> round(t.xi_n), round(t.plate_constant)    # [N/m^3]; plate: 0.87574 xi_n
    (127826, 111943)
    """

    rho_c: float = 1310.0
    mu_int: float = 0.21
    mu_surf: float = 0.4
    gravity: float = GRAVITY
    coefficients: PolynomialCoefficients = AGARWAL2023
    rest_speed: float = 1e-6
    leading_width: float = LEADING_WIDTH
    wall_width: float = WALL_WIDTH
    name: str = "granular-rft3d"

    def __post_init__(self) -> None:
        _set(self, "rho_c", check_positive("rho_c", self.rho_c, unit="kg/m^3"))
        try:
            _set(self, "mu_int", check_in_range("mu_int", self.mu_int, 1e-6, 2.0))
        except MudrftError as exc:  # an angle in degrees is the usual mistake
            raise MudrftError(
                f"{exc}: mu_int is the internal friction coefficient, tan(angle) (30 degrees: 0.58)"
            ) from None
        _set(self, "mu_surf", check_in_range("mu_surf", self.mu_surf, 0.0, 1e3))
        _set(self, "gravity", check_positive("gravity", self.gravity, unit="m/s^2"))
        _set(self, "wall_width", check_in_range("wall_width", self.wall_width, 0.0, 1.0))
        self._check_options(PolynomialCoefficients)
        if not isinstance(self.name, str) or not self.name:
            raise MudrftError(f"name must be a non-empty string, got {self.name!r}")
        what = "GranularRFT3D: rho_c is"
        hint = "rho_c is the bulk density in kg/m^3 (1.31 g/cm^3 = 1310 kg/m^3)"
        warn_implausible(what, self.rho_c, PLAUSIBLE_RHO_C, unit="kg/m^3", hint=hint)
        if 2.0 < self.mu_surf <= 90.0:
            warn_plausibility(
                f"GranularRFT3D: mu_surf = {self.mu_surf:g} looks like a friction angle in "
                "degrees; mu_surf is a friction coefficient, tan(angle) (22 degrees: 0.40)"
            )
        register("agarwal2023rft3d")

    @cached_property  # read at every step
    def xi_n(self) -> float:
        """Material constant :math:`\\xi_n` [N/m^3] (:func:`agarwal_xi`)."""
        return float(agarwal_xi(self.rho_c, self.mu_int, gravity=self.gravity))

    @property
    def scale(self) -> float:
        """Scale of the medium: the material constant :math:`\\xi_n` [N/m^3]."""
        return self.xi_n

    @property
    def plate_constant(self) -> float:
        """Vertical stress per depth of a horizontal plate pushed down [N/m^3] (D92)."""
        down = np.array([0.0, 0.0, -1.0])
        a = _generic(down[None, :], down, self.coefficients, self.wall_width)
        return float(a[0, 2]) * self.xi_n

    def _unit_forces(
        self, normals: NDArray[np.float64], direction: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        c, mu, lw, ww = self.coefficients, float(self.mu_surf), self.leading_width, self.wall_width
        return _unit_forces(normals, direction, c, mu, lw, ww)
