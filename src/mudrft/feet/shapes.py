r"""The paper's three feet: closed forms (:mod:`.closed_form`) and meshes (:mod:`.meshgen`),
which give the center of pressure and the posed (tilted) foot."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from functools import cached_property
from typing import ClassVar

import numpy as np

from .._typing import ArrayLike, FloatArray, Namespace, RotationLike, XpArray
from .._validation import MudrftError, check_dimensions, check_nonnegative
from .base import Foot, SurfaceElements, check_resultant_inputs, magnitudes
from .closed_form import DEFAULT_RESOLUTION, _theta, closed_form_coefficients, closed_form_force
from .mesh import MeshFoot
from .meshgen import box_mesh, rim_angle, semicylinder_mesh, semisphere_mesh

__all__ = ["Flat", "SemiCylinder", "SemiSphere"]

#: Height of the paper's feet, the default ``height`` of every closed-form foot [m].
PAPER_HEIGHT = 0.026


class _ClosedFormFoot(Foot):
    """Shared behaviour of the closed-form feet (mesh, elements, pose, center of pressure)."""

    trailing: ClassVar[bool] = False
    elementwise: ClassVar[bool] = True
    _KIND: ClassVar[int]  # of closed_form_coefficients

    def __post_init__(self) -> None:
        """Check the dimensions [m] and keep them as floats."""
        dims = {f.name: getattr(self, f.name) for f in fields(self)}  # type: ignore[arg-type]
        for k, v in check_dimensions(type(self).__name__, **dims).items():
            object.__setattr__(self, k, v)
        r, h = getattr(self, "radius", math.inf), self.height  # the curved feet have a radius
        if h > r:
            shape = self.name[5:]  # "cylinder", "sphere"
            hint = (
                f" (the default height, the paper's {PAPER_HEIGHT * 1e3:g} mm, is taller than this "
                f"foot: give height <= radius, e.g. height={r!r} for a full half-{shape}; in a "
                "sweep, fix or sweep height in [foot])"
                if h == PAPER_HEIGHT
                else ""
            )
            raise MudrftError(
                f"height must be <= radius = {r} m for a semi-{shape}, got {h} m{hint}"
            )

    def _segment(self, depth: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Submerged height ``z`` [m], rim angle [rad] and circular segment area [m^2]."""
        z = np.minimum(check_nonnegative("depth", depth, unit="m"), self.height)
        th = _theta(z, self.radius)  # type: ignore[attr-defined]
        return z, th, self.radius**2 * (th - np.sin(th) * np.cos(th))  # type: ignore[attr-defined]

    @cached_property
    def kernel_geometry(self) -> tuple[int, float, float, float]:
        """``(kind, g0, g1, g2)`` of :func:`closed_form_coefficients` for compiled paths: the
        kind (0 flat, 1 semi-cylinder, 2 semi-sphere) and the dimensions in the order of the
        fields, then 0 [m]."""
        g = (*self._sizes, 0.0)  # the semi-sphere has two sizes
        return self._KIND, g[0], g[1], g[2]

    @property
    def _sizes(self) -> tuple[float, ...]:
        return tuple(getattr(self, f.name) for f in fields(self))  # type: ignore[arg-type]

    def coefficients(self, depth: XpArray, phi: XpArray, xp: Namespace = np) -> tuple[XpArray, ...]:
        """Coefficients ``(a_x, b_x, b_y, a_y, a_z)`` [m^2] of the closed form at tip depth
        [m] and first-quadrant heading [rad]."""
        return closed_form_coefficients(*self.kernel_geometry, depth, phi, xp=xp)

    def resultant(self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike) -> FloatArray:
        """Closed-form magnitudes (Fx, Fy, Fz) [N]; see :meth:`Foot.resultant`."""
        d, s, h = check_resultant_inputs(depth, stress, heading, height=self.height)
        return magnitudes(self.coefficients(d, h), s)

    def force_components(
        self, depth: XpArray, sx: XpArray, sy: XpArray, sz: XpArray, heading: XpArray,
        xp: Namespace = np,
    ) -> tuple[XpArray, XpArray, XpArray]:  # fmt: skip
        """World force ``(F_x, F_y, F_z)`` [N], element-wise (the heading rule, D9)."""
        return closed_form_force(*self.kernel_geometry, depth, sx, sy, sz, heading, xp=xp)

    def force_unchecked(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> FloatArray:
        """:meth:`Foot.force` without validation: closed forms mapped to the world (D9) [N]."""
        return self.force_array(*(np.asarray(a, dtype=float) for a in (depth, stress, heading)))

    def to_mesh(self, *, resolution: int = DEFAULT_RESOLUTION) -> MeshFoot:
        """This foot as a closed :class:`MeshFoot`; ``resolution``: segments from tip to rim,
        or divisions per edge (flat) [-]."""
        mesher = (box_mesh, semicylinder_mesh, semisphere_mesh)[self._KIND]
        v, f = mesher(*self._sizes, resolution=resolution)
        return MeshFoot(v, f, trailing=self.trailing, name=self.name)

    @cached_property
    def _mesh(self) -> MeshFoot:
        return self.to_mesh(resolution=DEFAULT_RESOLUTION)

    def elements(self) -> SurfaceElements:
        """Surface elements of the default mesh (``resolution=48``) in the foot frame."""
        return self._mesh.elements()

    def posed(self, rotation: RotationLike, *, resolution: int = DEFAULT_RESOLUTION) -> MeshFoot:
        """The foot rotated by ``rotation`` (3x3 matrix or scipy Rotation), as a mesh foot
        (the closed forms hold for the axis-aligned foot only)."""
        return self.to_mesh(resolution=resolution).posed(rotation)

    def center_of_pressure(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> FloatArray:
        """Center of pressure in the foot frame [m], shape (..., 3), from the default mesh
        (:func:`mudrft.feet.surface.integrate_wrench`)."""
        return self._mesh.center_of_pressure(depth, stress, heading)


@dataclass(frozen=True, eq=True)
class Flat(_ClosedFormFoot):
    """Rectangular flat foot (paper: 80 x 65 mm, 26 mm tall), eq. (12); the face whose
    normal is x has area :math:`Lz` (D20).

    Parameters
    ----------
    length, width : float, optional
        :math:`L` along y and :math:`W` along x [m].
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
    height: float = field(default=PAPER_HEIGHT, kw_only=True)  # type: ignore[assignment]
    name: ClassVar[str] = "flat"  # type: ignore[misc]
    _KIND: ClassVar[int] = 0

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{LW}` [m] (decision D27)."""
        return math.sqrt(self.length * self.width)

    def projected_areas(self, depth: ArrayLike) -> FloatArray:
        """Submerged areas projected along x, y, z [m^2]: (L z, W z, L W), shape (..., 3)."""
        d = check_nonnegative("depth", depth, unit="m")
        z = np.minimum(d, self.height)
        az = np.where(d > 0, self.length * self.width, 0.0)
        return np.stack([self.length * z, self.width * z, az], axis=-1)


@dataclass(frozen=True, eq=True)
class SemiCylinder(_ClosedFormFoot):
    """Semi-cylindrical foot (paper: R = 45 mm, W = 65 mm, 26 mm tall), eq. (13): axis along x,
    a circular segment cut flat on top (D20).

    Parameters
    ----------
    radius, width : float, optional
        :math:`R` and the length along the axis (x) :math:`W` [m].
    height : float, optional
        Height of the foot [m], <= ``radius``.

    Examples
    --------
    >>> SemiCylinder().resultant(0.02, [0.0, 1e3, 0.0], np.pi / 2).round(4).tolist()
    [0.0, 1.3, 0.0]
    """

    radius: float = 0.045
    width: float = 0.065
    height: float = field(default=PAPER_HEIGHT, kw_only=True)  # type: ignore[assignment]
    name: ClassVar[str] = "semi-cylinder"  # type: ignore[misc]
    _KIND: ClassVar[int] = 1

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{2R\\sin\\theta_H\\,W}` [m], the top cross-section (D27)."""
        th = rim_angle(self.radius, self.height)
        return math.sqrt(2 * self.radius * math.sin(th) * self.width)

    def projected_areas(self, depth: ArrayLike) -> FloatArray:
        """Submerged areas projected along x, y, z [m^2]: (segment, W z, 2 R W sin(theta_c))."""
        z, th, seg = self._segment(depth)
        return np.stack([seg, self.width * z, 2 * self.radius * self.width * np.sin(th)], axis=-1)


@dataclass(frozen=True, eq=True)
class SemiSphere(_ClosedFormFoot):
    """Semi-spherical foot, a spherical cap (paper: R = 45 mm, 26 mm tall), eq. (14); its
    closed form counts the facets that trail the motion, so its mesh does (D23).

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
    height: float = field(default=PAPER_HEIGHT, kw_only=True)  # type: ignore[assignment]
    name: ClassVar[str] = "semi-sphere"  # type: ignore[misc]
    _KIND: ClassVar[int] = 2
    trailing: ClassVar[bool] = True

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{\\pi}R\\sin\\theta_H`, the top cross-section (D27) [m]."""
        th = rim_angle(self.radius, self.height)
        return math.sqrt(math.pi) * self.radius * math.sin(th)

    def projected_areas(self, depth: ArrayLike) -> FloatArray:
        """Submerged areas projected along x, y, z [m^2]: (segment, segment, pi R^2 sin^2)."""
        _, th, seg = self._segment(depth)
        return np.stack([seg, seg, math.pi * (self.radius * np.sin(th)) ** 2], axis=-1)
