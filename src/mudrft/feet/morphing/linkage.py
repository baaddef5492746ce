r"""Dimensions and kinematics of the morphing foot's pad linkages (D30): each pad is the lower
link of a slider-crank whose upper pole the column deflection carries down; the pad angle is a
circle intersection (docs/model.md, D30). Lengths in metres, angles in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._typing import Namespace, XpArray
from ..._validation import (
    MudrftError,
    check_in_range,
    check_length,
    nonnegative_number,
    number_in_range,
    positive_int,
)

__all__ = [
    "MAX_PADS", "Linkage", "MorphingFootGeometry", "MorphingRow", "pad_angle", "raw_pad_angle"
]  # fmt: skip

_DESIGN_SAMPLES = 721  # pad angles at which the linkage is checked for reach and monotonicity

#: Most pads a morphing foot may have [-] (every force sums over the pads one by one).
MAX_PADS = 100


@dataclass(frozen=True)
class MorphingFootGeometry:
    r"""Dimensions of the morphing foot's base, pads and linkage (SI); the defaults reconstruct
    a foot about 96 mm across when spread (D30; curled, their pads overlap: D160).

    Attributes
    ----------
    n_pads : int
        Number of pads and linkages [-] (paper: eight; at most :data:`MAX_PADS`).
    base_radius, pivot_height : float
        Radius of the base pad, :math:`r_A`, and height of the pad pivots above the tip,
        :math:`h_A` [m].
    column_radius, height : float
        Radius of the column above the base (horizontal drag only) and height of the foot [m].
    pad_length, pad_inner_width, pad_outer_width : float
        Pad length :math:`\ell` from pivot to rim, and the trapezoid's widths at pivot and rim [m].
    crank_length, crank_offset : float
        Pivot to coupler joint on the pad, :math:`a` [m], at :math:`\beta` [rad] from the pad.
    coupler_length, pole_radius : float
        Coupler length :math:`b` and radius of the upper poles :math:`r_B` [m].
    retracted_angle, expanded_angle : float
        Pad angle with the column unloaded (curled), :math:`\theta_r`, and fully compressed
        (spread), :math:`\theta_e` [rad].
    """

    n_pads: int = 8
    base_radius: float = 0.014
    pivot_height: float = 0.004
    column_radius: float = 0.010
    height: float = 0.070
    pad_length: float = 0.034
    pad_inner_width: float = 0.010
    pad_outer_width: float = 0.030
    crank_length: float = 0.0085
    crank_offset: float = math.radians(-10.0)
    coupler_length: float = 0.0245
    pole_radius: float = 0.006
    retracted_angle: float = math.radians(75.0)
    expanded_angle: float = math.radians(5.0)

    def __post_init__(self) -> None:
        positive_int("n_pads", self.n_pads)
        if self.n_pads > MAX_PADS:
            raise MudrftError(
                f"n_pads must be at most {MAX_PADS} (the paper's foot has 8; every force sums "
                f"over the pads one by one), got {self.n_pads!r}"
            )
        lengths = ("base_radius", "pivot_height", "column_radius", "height", "pad_length",
                   "pad_inner_width", "pad_outer_width", "crank_length", "coupler_length")  # fmt: skip
        for k in lengths:
            object.__setattr__(self, k, check_length(k, getattr(self, k)))
        pole = nonnegative_number("pole_radius", self.pole_radius, unit="m")
        object.__setattr__(self, "pole_radius", pole)
        beta = number_in_range("crank_offset", self.crank_offset, -math.pi, math.pi, unit="rad")
        object.__setattr__(self, "crank_offset", beta)
        for k in ("expanded_angle", "retracted_angle"):
            angle = float(check_in_range(k, getattr(self, k), 0.0, 0.5 * math.pi, unit="rad"))
            object.__setattr__(self, k, angle)
        th_e, th_r = self.expanded_angle, self.retracted_angle
        if not th_r > th_e:
            raise MudrftError(
                f"retracted_angle must exceed expanded_angle = {th_e!r} rad, got {th_r!r} rad"
            )
        if self.column_radius > self.base_radius:
            raise MudrftError(
                f"column_radius must be <= base_radius = {self.base_radius!r} m, "
                f"got {self.column_radius!r} m"
            )
        if self.n_pads >= 3:  # pivot edges at most the sides of the n-gon around the rim
            fit = 2.0 * self.base_radius * math.tan(math.pi / self.n_pads)
            if self.pad_inner_width > fit:
                raise MudrftError(
                    f"n_pads = {self.n_pads} pads of pad_inner_width = {self.pad_inner_width!r} m "
                    f"overlap at their pivots: on a base_radius of {self.base_radius!r} m they fit "
                    f"only if pad_inner_width <= 2 base_radius tan(pi/n_pads) = {fit:.3g} m; use "
                    "fewer or narrower pads, or a larger base_radius"
                )
        if self.height <= self.pivot_height:
            raise MudrftError(
                f"height must exceed pivot_height = {self.pivot_height!r} m, got {self.height!r} m"
            )

    @property
    def azimuths(self) -> NDArray[np.float64]:
        """Azimuths of the pads around the foot axis, :math:`2\\pi k/N` [rad], shape (N,)."""
        return 2.0 * np.pi * np.arange(self.n_pads) / self.n_pads


def _pole_height(g: MorphingFootGeometry, theta: NDArray[np.float64]) -> NDArray[np.float64]:
    """Height of the upper pole [m] that holds the pads at angle ``theta`` [rad]."""
    phi = theta + g.crank_offset
    rc = g.base_radius + g.crank_length * np.cos(phi)
    zc = g.pivot_height + g.crank_length * np.sin(phi)
    return np.asarray(zc + np.sqrt(g.coupler_length**2 - (rc - g.pole_radius) ** 2))


def raw_pad_angle(
    g: MorphingFootGeometry | MorphingRow, pole_top: XpArray, branch: XpArray, deflection: XpArray,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """Unclipped pad angle [rad] at a deflection [m], element-wise; ``g`` by attribute,
    ``pole_top`` [m] and ``branch`` (+-1) from :class:`Linkage`."""
    dr, dz = g.pole_radius - g.base_radius, pole_top - deflection - g.pivot_height
    dist = xp.hypot(dr, dz)
    a, b = g.crank_length, g.coupler_length
    c = (a * a + dist * dist - b * b) / (2.0 * a * dist)
    return xp.arctan2(dz, dr) + branch * xp.arccos(xp.clip(c, -1.0, 1.0)) - g.crank_offset


def pad_angle(
    g: MorphingFootGeometry | MorphingRow, pole_top: XpArray, branch: XpArray, deflection: XpArray,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """Pad angle :math:`\\theta(\\delta)` [rad]: :func:`raw_pad_angle` clipped to
    [``expanded_angle``, ``retracted_angle``] (D30)."""
    th = raw_pad_angle(g, pole_top, branch, deflection, xp=xp)
    return xp.clip(th, g.expanded_angle, g.retracted_angle)


@dataclass(frozen=True)
class Linkage:
    r"""The resolved slider-crank of one pad (D30): ``geometry``, ``pole_top`` :math:`z_{B0}`
    [m], ``stroke`` from curled up to spread [m] and ``branch`` (+-1) [-].

    >>> link = Linkage.from_geometry(MorphingFootGeometry())
    >>> round(link.stroke * 1e3, 2), round(math.degrees(float(link.angle(link.stroke))), 1)
    (11.89, 5.0)
    """

    geometry: MorphingFootGeometry
    pole_top: float
    stroke: float
    branch: float

    @classmethod
    def from_geometry(cls, geometry: MorphingFootGeometry) -> Linkage:
        """Resolve the linkage of ``geometry`` [m, rad] (it must reach and be monotone)."""
        g = geometry
        th = np.linspace(g.expanded_angle, g.retracted_angle, _DESIGN_SAMPLES)
        rc = g.base_radius + g.crank_length * np.cos(th + g.crank_offset)
        if np.any(g.coupler_length**2 - (rc - g.pole_radius) ** 2 <= 0):
            raise MudrftError(
                f"coupler_length = {g.coupler_length!r} m is too short to reach the upper pole "
                "over the pad travel; lengthen it or move pole_radius toward the pivots"
            )
        zb = _pole_height(g, th)
        if np.any(np.diff(zb) <= 0):
            raise MudrftError(
                "the linkage is not monotone over the pad travel (the pole must rise as the pads "
                "curl up): change crank_offset, crank_length or coupler_length"
            )
        top, stroke = float(zb[-1]), float(zb[-1] - zb[0])
        ends = np.array([0.0, stroke])
        for sign in (1.0, -1.0):
            t = raw_pad_angle(g, top, sign, ends)
            if abs(t[0] - g.retracted_angle) < 1e-9 and abs(t[1] - g.expanded_angle) < 1e-9:
                return cls(geometry=g, pole_top=top, stroke=stroke, branch=sign)
        raise MudrftError(  # pragma: no cover - excluded by the monotonicity check above
            "could not resolve the linkage branch"
        )

    def angle(self, deflection: ArrayLike) -> NDArray[np.float64]:
        """Pad angle :math:`\\theta(\\delta)` [rad] at a deflection [m] in [0, stroke],
        clipped to the design range (unchecked)."""
        d = np.asarray(deflection, dtype=float)
        return np.asarray(pad_angle(self.geometry, self.pole_top, self.branch, d))

    def deflection_at(self, pad_angle: ArrayLike) -> NDArray[np.float64]:
        """Inverse kinematics: deflection [m] in [0, stroke] giving a pad angle [rad]
        (unchecked)."""
        zb = _pole_height(self.geometry, np.asarray(pad_angle, dtype=float))
        return np.clip(self.pole_top - zb, 0.0, self.stroke)

    def points(self, deflection: float) -> dict[str, NDArray[np.float64]]:
        """Joints ``A`` (pad pivot), ``C`` (coupler joint), ``B`` (upper pole) and ``P`` (pad
        rim), each ``(r, z)`` [m], at a deflection [m] (unchecked)."""
        g = self.geometry
        th = float(self.angle(deflection))
        a = np.array([g.base_radius, g.pivot_height])
        phi = th + g.crank_offset
        c = a + g.crank_length * np.array([math.cos(phi), math.sin(phi)])
        b = np.array([g.pole_radius, self.pole_top - deflection])
        p = a + g.pad_length * np.array([math.cos(th), math.sin(th)])
        return {"A": a, "C": c, "B": b, "P": p}


class MorphingRow(NamedTuple):
    """Every number of a :class:`~.foot.MorphingFoot`'s force, as floats [m, rad, N/m, N]:
    the geometry's, linkage's and spring's fields by name, the seal length [m], ``lock`` (the
    locked deflection [m], or -1, D37) and ``curl_delay`` [s] (D35)."""

    base_radius: float
    pivot_height: float
    column_radius: float
    height: float
    pad_length: float
    pad_inner_width: float
    pad_outer_width: float
    n_pads: float
    crank_length: float
    crank_offset: float
    coupler_length: float
    pole_radius: float
    retracted_angle: float
    expanded_angle: float
    pole_top: float
    stroke: float
    branch: float
    series_stiffness: float
    hard_stiffness: float
    knee_deflection: float
    knee_force: float
    seal_length: float
    lock: float
    curl_delay: float
