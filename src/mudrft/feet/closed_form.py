r"""The paper's three feet in closed form: flat, semi-cylindrical, semi-spherical (Sec. III-A).

Each closed form is the paper's own integral of eqs. (6)-(7) over the foot (supplementary
Sec. II), corrected where the printed final expression differs from that integral
(errata E20-E23 in ``docs/model.md``). With :math:`z` the tip depth capped at the
foot height :math:`H` (decision D26: deeper, the foot is buried), :math:`\varphi` the
first-quadrant heading, :math:`\varphi_c=\pi/2-\varphi`,
:math:`\theta_c=\cos^{-1}(1-z/R)`, :math:`s=\sin\theta_c`, :math:`c=\cos\theta_c`:

* flat (eq. 12), length :math:`L` along y, width :math:`W` along x (decision D20):
  :math:`F_x=z[Lf_n(\varphi)\sigma_x+Wf_t(\varphi_c)\sigma_y]`,
  :math:`F_y=z[Lf_t(\varphi)\sigma_x+Wf_n(\varphi_c)\sigma_y]`, :math:`F_z=LW\sigma_z`;
* semi-cylinder (eq. 13), axis along x: :math:`F_x=R^2(\theta_c-sc)f_n(\varphi)\sigma_x
  +WR(1-c)f_t(\varphi_c)\sigma_y`, :math:`F_y` likewise with :math:`f_t(\varphi)`,
  :math:`f_n(\varphi_c)`, and (E20) :math:`F_z=2WR\sigma_z[s-\tfrac{s^3}{3}+\tfrac23-c
  +\tfrac{c^3}{3}]`;
* semi-sphere (eq. 14), a spherical cap: (E21) :math:`F_z=\tfrac{S_e}{4}(2+2c^2
  +\tfrac{2c^3}{s}-\tfrac{5c}{s}+\tfrac{3\theta_c}{s^2})\sigma_z` with
  :math:`S_e=\pi R^2s^2`, and (E22, E23) :math:`F_x=\tfrac83R^2(\theta_c-sc)\cos\varphi\,
  \sigma_x`, :math:`F_y=\tfrac83R^2(\theta_c-sc)\sin\varphi\,\sigma_y`.

The ``printed_*`` functions reproduce the printed finals for the erratum tests and docs.
All functions are vectorized (depth, stress and heading broadcast) and take ``xp``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from .._validation import (
    MudrftError,
    check_nonnegative,
    check_positive,
)
from ..constitutive.laws import f_n, f_t
from .base import Foot, SurfaceElements, unfold_forces
from .base import check_resultant_inputs as _check_inputs
from .mesh import MeshFoot
from .meshgen import box_mesh, semicylinder_mesh, semisphere_mesh

__all__ = [
    "Flat",
    "SemiCylinder",
    "SemiSphere",
    "flat_forces",
    "printed_semicylinder_fz",
    "printed_semisphere_fxy",
    "printed_semisphere_fz",
    "semicylinder_forces",
    "semisphere_forces",
]

#: Resolution of the mesh a closed-form foot uses for its surface elements and its center
#: of pressure (segments from the tip to the rim; see :mod:`mudrft.feet.meshgen`).
DEFAULT_RESOLUTION = 48


def _split(stress: Any, xp: Any) -> tuple[Any, Any, Any]:
    s = xp.asarray(stress)
    return s[..., 0], s[..., 1], s[..., 2]


def _theta(z: Any, radius: float, xp: Any) -> Any:
    return xp.arccos(xp.clip(1.0 - z / radius, -1.0, 1.0))


def flat_forces(
    depth: Any,
    stress: Any,
    heading: Any,
    *,
    length: float,
    width: float,
    height: float,
    xp: Any = np,
) -> Any:
    r"""Flat foot, eq. (12): first-quadrant force magnitudes (Fx, Fy, Fz) [N].

    Parameters
    ----------
    depth : array_like
        Tip depth [m] (capped at ``height``; 0 gives no force).
    stress : array_like, shape (..., 3)
        Channel stresses (sx, sy, sz) [Pa], positive when resisting.
    heading : array_like
        Heading :math:`\varphi` in [0, pi/2] [rad].
    length, width, height : float
        :math:`L` (along y), :math:`W` (along x) and height [m].
    xp : module, optional
        Array namespace.

    Returns
    -------
    array, shape (..., 3)
        Force magnitudes [N].

    Examples
    --------
    >>> f = flat_forces(0.01, [1e3, 0.0, 1e3], 0.0, length=0.08, width=0.065, height=0.026)
    >>> f.round(4).tolist()
    [0.8, 0.0, 5.2]
    """
    d = xp.asarray(depth)
    sx, sy, sz = _split(stress, xp)
    z = xp.minimum(d, height)
    phi = xp.asarray(heading)
    phic = 0.5 * math.pi - phi
    fx = z * (length * f_n(phi, xp=xp) * sx + width * f_t(phic, xp=xp) * sy)
    fy = z * (length * f_t(phi, xp=xp) * sx + width * f_n(phic, xp=xp) * sy)
    fz = xp.where(d > 0, length * width, 0.0) * sz
    return xp.stack(xp.broadcast_arrays(fx, fy, fz), axis=-1)


def semicylinder_forces(
    depth: Any,
    stress: Any,
    heading: Any,
    *,
    radius: float,
    width: float,
    height: float,
    xp: Any = np,
) -> Any:
    r"""Semi-cylindrical foot, eq. (13) with the corrected :math:`F_z` (E20) [N].

    Parameters
    ----------
    depth : array_like
        Tip depth [m] (capped at ``height``).
    stress : array_like, shape (..., 3)
        Channel stresses (sx, sy, sz) [Pa].
    heading : array_like
        Heading :math:`\varphi` in [0, pi/2] [rad] from the cylinder axis (x).
    radius, width, height : float
        :math:`R`, :math:`W` (axis length, along x) and height (<= R) [m].
    xp : module, optional
        Array namespace.

    Returns
    -------
    array, shape (..., 3)
        Force magnitudes [N].

    Examples
    --------
    >>> kw = dict(radius=0.045, width=0.065, height=0.045)
    >>> f = semicylinder_forces(0.045, [0.0, 0.0, 1.0], 0.0, **kw)
    >>> round(float(f[2]) / (2 * 0.045 * 0.065), 6)  # half-cylinder: 2WR[1 - 1/3 + 2/3]
    1.333333
    """
    d = xp.asarray(depth)
    sx, sy, sz = _split(stress, xp)
    z = xp.minimum(d, height)
    th = _theta(z, radius, xp)
    s, c = xp.sin(th), xp.cos(th)
    phi = xp.asarray(heading)
    phic = 0.5 * math.pi - phi
    seg = radius**2 * (th - s * c)  # end-cap segment area (x projection)
    side = width * radius * (1.0 - c)  # = W z (y projection)
    fx = seg * f_n(phi, xp=xp) * sx + side * f_t(phic, xp=xp) * sy
    fy = seg * f_t(phi, xp=xp) * sx + side * f_n(phic, xp=xp) * sy
    # 2/3 - c + c^3/3 = (1 - c)^2 (2 + c)/3 with 1 - c = z/R: no cancellation near z = 0
    u = z / radius
    fz = 2.0 * width * radius * (s - s**3 / 3.0 + u * u * (2.0 + c) / 3.0) * sz
    return xp.stack(xp.broadcast_arrays(fx, fy, fz), axis=-1)


def semisphere_forces(
    depth: Any, stress: Any, heading: Any, *, radius: float, height: float, xp: Any = np
) -> Any:
    r"""Semi-spherical foot (spherical cap), eq. (14) corrected (E21-E23) [N].

    Parameters
    ----------
    depth : array_like
        Tip depth [m] (capped at ``height``).
    stress : array_like, shape (..., 3)
        Channel stresses (sx, sy, sz) [Pa].
    heading : array_like
        Heading :math:`\varphi` in [0, pi/2] [rad].
    radius, height : float
        :math:`R` and cap height (<= R) [m].
    xp : module, optional
        Array namespace.

    Returns
    -------
    array, shape (..., 3)
        Force magnitudes [N].

    Examples
    --------
    >>> f = semisphere_forces(0.045, [1.0, 1.0, 1.0], 0.0, radius=0.045, height=0.045)
    >>> round(float(f[0]) / 0.045**2, 6), round(float(f[2]) / (np.pi * 0.045**2), 6)
    (4.18879, 1.678097)
    """
    d = xp.asarray(depth)
    sx, sy, sz = _split(stress, xp)
    z = xp.minimum(d, height)
    th = _theta(z, radius, xp)
    s, c = xp.sin(th), xp.cos(th)
    phi = xp.asarray(heading)
    side = 8.0 / 3.0 * radius**2 * (th - s * c)
    fx = side * xp.cos(phi) * sx
    fy = side * xp.sin(phi) * sy
    u = z / radius  # = 1 - c, exact
    # int_0^tc (cos^3 sin + sin^4); 1 - c^4 = (1 - c)(1 + c)(1 + c^2)
    ring = u * (1 + c) * (1 + c * c) / 4.0 + 3.0 * th / 8.0 - xp.sin(2 * th) / 4.0
    ring = ring + xp.sin(4 * th) / 32.0
    fz = 2.0 * math.pi * radius**2 * ring * sz
    return xp.stack(xp.broadcast_arrays(fx, fy, fz), axis=-1)


def printed_semicylinder_fz(depth: Any, sz: Any, *, radius: float, width: float) -> Any:
    r"""Printed eq. (13c): :math:`F_z=\tfrac13S_e(2+c^2)\sigma_z` [N] (see erratum E20)."""
    th = _theta(np.asarray(depth, dtype=float), radius, np)
    se = 2 * radius * width * np.sin(th)
    return se / 3.0 * (2.0 + np.cos(th) ** 2) * sz


def printed_semisphere_fz(depth: Any, sz: Any, *, radius: float) -> Any:
    r"""Printed eq. (14b) final, with "2 + c^2" [N] (see erratum E21); needs depth > 0."""
    th = _theta(np.asarray(depth, dtype=float), radius, np)
    s, c = np.sin(th), np.cos(th)
    se = math.pi * radius**2 * s**2
    return se / 4.0 * (2 + c**2 + 2 * c**3 / s - 5 * c / s + 3 * th / s**2) * sz


def printed_semisphere_fxy(depth: Any, sx: Any, sy: Any, heading: Any, *, radius: float) -> Any:
    r"""Printed eq. (14a): :math:`\tfrac{4S_e}{3\pi s}(\tfrac{2\theta_c}{s}-1)` (E22, E23) [N].

    Returns ``(Fx, Fy)`` stacked on the last axis; equal to :math:`\tfrac13R^2(8\theta_c
    -4\sin\theta_c)(\cos\varphi\,\sigma_x,\sin\varphi\,\sigma_y)`.
    """
    th = _theta(np.asarray(depth, dtype=float), radius, np)
    s = np.sin(th)
    se = math.pi * radius**2 * s**2
    k = 4 * se / (3 * math.pi * s) * (2 * th / s - 1)
    return np.stack([k * np.cos(heading) * sx, k * np.sin(heading) * sy], axis=-1)




class _ClosedFormFoot(Foot):
    """Shared behaviour of the closed-form feet (mesh, elements, pose, center of pressure)."""

    #: whether the matching mesh rule lets trailing facets resist (decision D23)
    trailing: ClassVar[bool] = False

    def _mesh_arrays(self, resolution: int) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def _forces(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """The closed form without validation (first-quadrant heading)."""
        raise NotImplementedError

    def resultant(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """Closed-form magnitudes (Fx, Fy, Fz) [N]; see :meth:`Foot.resultant`."""
        return self._forces(*_check_inputs(depth, stress, heading))

    def force_unchecked(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """:meth:`Foot.force` without validation: closed forms mapped to the world (D9) [N]."""
        d = np.asarray(depth, dtype=float)
        return unfold_forces(lambda su, ph: self._forces(d[..., None], su, ph), stress, heading)

    def to_mesh(self, *, resolution: int = DEFAULT_RESOLUTION) -> MeshFoot:
        """A closed triangle mesh of this foot, as a :class:`MeshFoot` with the same rule.

        Parameters
        ----------
        resolution : int, optional
            Mesh density (segments from the tip to the rim for curved feet, grid divisions
            per edge for the flat foot), >= 1.
        """
        v, f = self._mesh_arrays(resolution)
        return MeshFoot(v, f, trailing=self.trailing, name=self.name)

    @cached_property
    def _mesh(self) -> MeshFoot:
        return self.to_mesh(resolution=DEFAULT_RESOLUTION)

    def elements(self) -> SurfaceElements:
        """Surface elements of the default mesh (``resolution=48``) in the foot frame."""
        return self._mesh.elements()

    def posed(self, rotation: Any, *, resolution: int = DEFAULT_RESOLUTION) -> MeshFoot:
        """The foot rotated by ``rotation`` (3x3 matrix or scipy Rotation), as a mesh foot.

        The closed forms hold for the axis-aligned foot only, so a posed foot is integrated
        on its mesh (see :meth:`MeshFoot.posed`).
        """
        return self.to_mesh(resolution=resolution).posed(rotation)

    def center_of_pressure(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """Center of pressure in the foot frame [m], shape (..., 3), from the default mesh.

        See :func:`mudrft.feet.surface.integrate_wrench` (decision D24).
        """
        return self._mesh.center_of_pressure(depth, stress, heading)


@dataclass(frozen=True, eq=True)
class Flat(_ClosedFormFoot):
    """Rectangular flat foot (paper: 80 x 65 mm, 26 mm tall), eq. (12).

    The length :math:`L` runs along y and the width :math:`W` along x (decision D20: the
    face whose normal is x has area :math:`Lz` in eq. 12).

    Parameters
    ----------
    length : float, optional
        :math:`L` [m], along y.
    width : float, optional
        :math:`W` [m], along x.
    height : float, optional
        Height of the plate [m]; deeper than this the foot is buried (decision D26).

    Examples
    --------
    >>> foot = Flat()
    >>> foot.resultant(0.01, [1e3, 1e3, 1e3], 0.0).round(3).tolist()
    [1.45, 0.0, 5.2]
    """

    length: float = 0.08
    width: float = 0.065
    height: float = field(default=0.026, kw_only=True)  # type: ignore[assignment]
    name: ClassVar[str] = "flat"  # type: ignore[misc]
    trailing: ClassVar[bool] = False

    def __post_init__(self) -> None:
        for k in ("length", "width", "height"):
            object.__setattr__(self, k, float(check_positive(k, getattr(self, k), unit="m")))

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{LW}` [m] (decision D27)."""
        return math.sqrt(self.length * self.width)

    def _forces(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """Eq. (12): force magnitudes (Fx, Fy, Fz) [N]."""
        return flat_forces(
            depth, stress, heading, length=self.length, width=self.width, height=self.height
        )

    def projected_areas(self, depth: Any) -> np.ndarray:
        """Submerged areas projected along x, y, z [m^2]: (L z, W z, L W), shape (..., 3)."""
        d = check_nonnegative("depth", depth, unit="m")
        z = np.minimum(d, self.height)
        az = np.where(d > 0, self.length * self.width, 0.0)
        return np.stack([self.length * z, self.width * z, az], axis=-1)

    def _mesh_arrays(self, resolution: int) -> tuple[np.ndarray, np.ndarray]:
        return box_mesh(self.length, self.width, self.height, resolution=resolution)


@dataclass(frozen=True, eq=True)
class SemiCylinder(_ClosedFormFoot):
    """Semi-cylindrical foot (paper: R = 45 mm, W = 65 mm, 26 mm tall), eq. (13).

    The cylinder axis runs along x (length :math:`W`); the cross-section is a circular
    segment of radius :math:`R` and height ``height`` <= R, cut flat on top (decision D20).

    Parameters
    ----------
    radius : float, optional
        :math:`R` [m].
    width : float, optional
        :math:`W` [m], along the axis (x).
    height : float, optional
        Height of the foot [m], <= ``radius``.

    Examples
    --------
    >>> SemiCylinder().resultant(0.02, [0.0, 1e3, 0.0], np.pi / 2).round(4).tolist()
    [0.0, 1.3, 0.0]
    """

    radius: float = 0.045
    width: float = 0.065
    height: float = field(default=0.026, kw_only=True)  # type: ignore[assignment]
    name: ClassVar[str] = "semi-cylinder"  # type: ignore[misc]
    trailing: ClassVar[bool] = False

    def __post_init__(self) -> None:
        for k in ("radius", "width", "height"):
            object.__setattr__(self, k, float(check_positive(k, getattr(self, k), unit="m")))
        if self.height > self.radius:
            raise MudrftError(
                f"height must be <= radius = {self.radius!r} m for a semi-cylinder, "
                f"got {self.height!r} m"
            )

    @property
    def _theta_max(self) -> float:
        return math.acos(1.0 - self.height / self.radius)

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{2R\\sin\\theta_H\\,W}` [m], the top cross-section (D27)."""
        return math.sqrt(2 * self.radius * math.sin(self._theta_max) * self.width)

    def _forces(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """Eq. (13), F_z corrected (E20): magnitudes (Fx, Fy, Fz) [N]."""
        return semicylinder_forces(
            depth, stress, heading, radius=self.radius, width=self.width, height=self.height
        )

    def projected_areas(self, depth: Any) -> np.ndarray:
        """Submerged areas projected along x, y, z [m^2]: (segment, W z, 2 R W sin(theta_c))."""
        d = check_nonnegative("depth", depth, unit="m")
        z = np.minimum(d, self.height)
        th = _theta(z, self.radius, np)
        seg = self.radius**2 * (th - np.sin(th) * np.cos(th))
        return np.stack([seg, self.width * z, 2 * self.radius * self.width * np.sin(th)], axis=-1)

    def _mesh_arrays(self, resolution: int) -> tuple[np.ndarray, np.ndarray]:
        return semicylinder_mesh(self.radius, self.width, self.height, resolution=resolution)


@dataclass(frozen=True, eq=True)
class SemiSphere(_ClosedFormFoot):
    """Semi-spherical foot, a spherical cap (paper: R = 45 mm, 26 mm tall), eq. (14).

    Its closed form counts the facets that trail the motion (the supplementary's full-range
    factors), so its mesh uses ``trailing=True`` (decision D23).

    Parameters
    ----------
    radius : float, optional
        :math:`R` [m].
    height : float, optional
        Cap height [m], <= ``radius``.

    Examples
    --------
    >>> SemiSphere().resultant(0.0, [1e3, 1e3, 1e3], 0.3).tolist()
    [0.0, 0.0, 0.0]
    """

    radius: float = 0.045
    height: float = field(default=0.026, kw_only=True)  # type: ignore[assignment]
    name: ClassVar[str] = "semi-sphere"  # type: ignore[misc]
    trailing: ClassVar[bool] = True

    def __post_init__(self) -> None:
        for k in ("radius", "height"):
            object.__setattr__(self, k, float(check_positive(k, getattr(self, k), unit="m")))
        if self.height > self.radius:
            raise MudrftError(
                f"height must be <= radius = {self.radius!r} m for a semi-sphere, "
                f"got {self.height!r} m"
            )

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{\\pi}R\\sin\\theta_H`, the top cross-section (D27) [m]."""
        th = math.acos(1.0 - self.height / self.radius)
        return math.sqrt(math.pi) * self.radius * math.sin(th)

    def _forces(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """Eq. (14) corrected (E21-E23): magnitudes (Fx, Fy, Fz) [N]."""
        return semisphere_forces(depth, stress, heading, radius=self.radius, height=self.height)

    def projected_areas(self, depth: Any) -> np.ndarray:
        """Submerged areas projected along x, y, z [m^2]: (segment, segment, pi R^2 sin^2)."""
        d = check_nonnegative("depth", depth, unit="m")
        z = np.minimum(d, self.height)
        th = _theta(z, self.radius, np)
        seg = self.radius**2 * (th - np.sin(th) * np.cos(th))
        return np.stack([seg, seg, math.pi * (self.radius * np.sin(th)) ** 2], axis=-1)

    def _mesh_arrays(self, resolution: int) -> tuple[np.ndarray, np.ndarray]:
        return semisphere_mesh(self.radius, self.height, resolution=resolution)
