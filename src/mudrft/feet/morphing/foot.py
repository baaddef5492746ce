r"""The passive morphing foot: the Foot interface over its mechanism (:mod:`.linkage`,
:mod:`.springs`, :mod:`.pads`, :mod:`.equilibrium`), with checked views of it."""

from __future__ import annotations

import math
from dataclasses import asdict, fields, replace
from typing import Any, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._typing import FloatOrArray, RotationLike
from ..._validation import (
    MudrftError,
    check_choice,
    check_finite,
    check_in_range,
    check_length,
    check_nonnegative,
    positive_number,
)
from ..base import Foot, SurfaceElements, check_resultant_inputs, magnitudes
from . import pads
from .equilibrium import (
    MorphingState,
    balanced_deflection,
    column_residual,
    held_deflection,
    seal_factor,
    track_most_spread,
)
from .linkage import Linkage, MorphingFootGeometry
from .springs import RigidGroundResponse, TwoStageSpring

__all__ = ["MODES", "MorphingFoot"]

#: Operating modes of the supplementary experiment (Sec. III-C, Fig. S4b).
MODES = ("morphing", "expanded", "retracted")

_GEOMETRY_FIELDS = {f.name for f in fields(MorphingFootGeometry)}
_SPRING_FIELDS = {f.name for f in fields(TwoStageSpring)}
_STROKE_SLACK = 1 + 1e-12  # deflections up to the stroke times this are accepted [-]


class MorphingFoot(Foot):
    r"""The passive morphing foot (paper Sec. III-B, Fig. 6; supplementary Sec. III-C).

    Parameters
    ----------
    geometry : MorphingFootGeometry, optional
        Base, pad and linkage dimensions [m, rad]; default: the reconstruction of D30.
    spring : TwoStageSpring, optional
        Column springs; default: soft 800 N/m over 7.5 mm, hard 6000 N/m (D31).
    mode : {"morphing", "expanded", "retracted"}, keyword-only
        Free morphing (default), pads locked fully spread, or locked curled up (D37).
    seal_length : float, keyword-only
        Rim lift :math:`g_s` over which curling pads break the cavity seal [m] (D35).
    curl_delay : float, keyword-only
        Time after the retraction begins during which the pads stay spread [s] (D35).
    characteristic_length : float or None, keyword-only
        :math:`L_c` [m]; default the square root of the spread footprint (D36).
    **overrides
        Any field of :class:`MorphingFootGeometry` or :class:`TwoStageSpring` by name,
        e.g. ``pad_length=0.04`` [m] or ``hard_stiffness=12000.0`` [N/m].

    Examples
    --------
    >>> foot = MorphingFoot()
    >>> round(foot.stroke * 1e3, 2), round(math.degrees(float(foot.pad_angle(foot.stroke))), 1)
    (11.89, 5.0)
    >>> round(float(foot.spring_force(foot.stroke)), 1), round(float(foot.deflection_at(0.5)) * 1e3, 2)
    (26.3, 8.06)
    >>> r = foot.rigid_ground([0.0, foot.stroke])
    >>> np.round(r.force, 1).tolist()
    [0.0, 26.3]
    >>> float(MorphingFoot(mode="expanded").resultant(0.02, [0.0, 0.0, 1e4], 0.0)[2]) > 50
    True
    """

    def __init__(
        self, geometry: MorphingFootGeometry | None = None, spring: TwoStageSpring | None = None, *,
        mode: str = "morphing", seal_length: float = 0.002, curl_delay: float = 0.0,
        characteristic_length: float | None = None, **overrides: Any,
    ) -> None:  # fmt: skip
        g = geometry if geometry is not None else MorphingFootGeometry()
        s = spring if spring is not None else TwoStageSpring()
        if not isinstance(g, MorphingFootGeometry):
            raise MudrftError(f"geometry must be a MorphingFootGeometry, got {type(g).__name__}")
        if not isinstance(s, TwoStageSpring):
            raise MudrftError(f"spring must be a TwoStageSpring, got {type(s).__name__}")
        unknown = set(overrides) - _GEOMETRY_FIELDS - _SPRING_FIELDS
        if unknown:
            raise MudrftError(
                f"unknown {type(self).__name__} parameter(s) {sorted(unknown)}; expected fields "
                f"of MorphingFootGeometry {sorted(_GEOMETRY_FIELDS)} or "
                f"TwoStageSpring {sorted(_SPRING_FIELDS)}"
            )
        self.geometry = replace(g, **{k: v for k, v in overrides.items() if k in _GEOMETRY_FIELDS})
        self.spring = replace(s, **{k: v for k, v in overrides.items() if k in _SPRING_FIELDS})
        self.mode = check_choice("mode", mode, MODES)
        self.linkage = Linkage.from_geometry(self.geometry)  # resolved (D30)
        if self.spring.knee_deflection >= self.stroke:
            raise MudrftError(
                f"the soft stage must bottom out within the stroke {self.stroke!r} m: "
                f"soft_travel*(1 + soft_stiffness/hard_stiffness) = "
                f"{self.spring.knee_deflection!r} m"
            )
        self.seal_length = positive_number("seal_length", seal_length, unit="m")
        self.curl_delay = float(check_nonnegative("curl_delay", curl_delay, unit="s"))
        self.name = "morphing" if self.mode == "morphing" else f"morphing-{self.mode}"
        lc = characteristic_length
        self._lc = None if lc is None else check_length("characteristic_length", lc)
        self._lc_spread = math.sqrt(float(self.footprint_area(self.stroke)))  # D36

    @property
    def stroke(self) -> float:
        """Column deflection from curled up to fully spread [m] (set by the linkage)."""
        return self.linkage.stroke

    def _check_deflection(self, deflection: ArrayLike) -> NDArray[np.float64]:
        return check_in_range("deflection", deflection, 0.0, self.stroke * _STROKE_SLACK, unit="m")

    def pad_angle(self, deflection: ArrayLike) -> NDArray[np.float64]:
        """Pad angle :math:`\\theta(\\delta)` from the horizontal [rad] at a column deflection
        [m] in [0, stroke]: from ``retracted_angle`` down to ``expanded_angle`` (D30)."""
        return self.linkage.angle(self._check_deflection(deflection))

    def deflection_at(self, pad_angle: ArrayLike) -> NDArray[np.float64]:
        """Inverse kinematics: column deflection [m] giving a pad angle [rad] in
        [expanded_angle, retracted_angle]."""
        g = self.geometry
        th = check_in_range("pad_angle", pad_angle, g.expanded_angle, g.retracted_angle, unit="rad")
        return self.linkage.deflection_at(th)

    def spring_force(self, deflection: ArrayLike) -> NDArray[np.float64]:
        """Column spring force [N] at a deflection [m] in [0, stroke] (D31)."""
        return np.asarray(self.spring.force(self._check_deflection(deflection)))

    def rigid_ground(self, deflection: ArrayLike) -> RigidGroundResponse:
        """Force, pad angle and stiffness against deflection [m] on rigid ground, where only
        the tip touches and the load is the column spring's (paper Fig. S3a, b)."""
        d = self._check_deflection(deflection)
        force, angle = np.asarray(self.spring.force(d)), self.linkage.angle(d)
        return RigidGroundResponse(d, force, angle, self.spring.stiffness(d))

    def locked_deflection(self) -> float | None:
        """Deflection the mode locks (stroke for expanded, 0 for retracted), None if free [m]."""
        return {"morphing": None, "expanded": self.stroke, "retracted": 0.0}[self.mode]

    def _shown_angle(self, deflection: ArrayLike | None) -> NDArray[np.float64]:
        """Pad angle [rad] to draw: at the given deflection [m], else the locked one, else
        the stroke."""
        if deflection is None:
            lock = self.locked_deflection()
            deflection = self.stroke if lock is None else lock
        return self.pad_angle(deflection)

    def effective_area(self, depth: ArrayLike, deflection: ArrayLike) -> NDArray[np.float64]:
        """Effective vertical area :math:`A_z` [m^2], :math:`F_z=\\sigma_zA_z` (D33), at tip
        depth [m] >= 0 and column deflection [m] in [0, stroke]."""
        d = check_nonnegative("depth", depth, unit="m")
        return pads.vertical_area(self.geometry, d, self.pad_angle(deflection))

    def footprint_area(
        self, deflection: ArrayLike, depth: ArrayLike | None = None
    ) -> NDArray[np.float64]:
        """Horizontal projection of the (submerged) base and pads [m^2] at a deflection [m],
        to tip ``depth`` [m] (None: the whole foot)."""
        th = self.pad_angle(deflection)
        d = np.inf if depth is None else check_nonnegative("depth", depth, unit="m")
        return pads.footprint_area(self.geometry, d, th)

    def residual(
        self, deflection: ArrayLike, depth: ArrayLike, sz: ArrayLike
    ) -> NDArray[np.float64]:
        """Balance residual :math:`R=F_s(\\delta)-\\sigma_zA_z(d,\\theta(\\delta))` [N] (D32) at
        a deflection [m] in [0, stroke], tip depth [m] >= 0 and vertical stress [Pa]."""
        dd = self._check_deflection(deflection)
        d, s = check_nonnegative("depth", depth, unit="m"), check_finite("sz", sz)
        link = self.linkage
        return np.asarray(
            column_residual(self.geometry, link.pole_top, link.branch, self.spring, dd, d, s)
        )

    def equilibrium(
        self, depth: ArrayLike, sz: ArrayLike, *, previous: ArrayLike = 0.0
    ) -> NDArray[np.float64]:
        r"""Column deflection [m] in balance with the mud (D32, D34) at tip ``depth`` [m] >= 0
        and vertical stress ``sz`` [Pa], reached from the ``previous`` deflection [m]."""
        d, s = check_nonnegative("depth", depth, unit="m"), check_finite("sz", sz)
        p = check_in_range("previous", previous, 0.0, self.stroke * _STROKE_SLACK, unit="m")
        return balanced_deflection(d, s, previous=p, linkage=self.linkage, spring=self.spring)

    def _deflection(
        self, depth: ArrayLike, sz: ArrayLike, previous: ArrayLike
    ) -> NDArray[np.float64]:
        lock = self.locked_deflection()
        if lock is None:
            return balanced_deflection(
                depth, sz, previous=previous, linkage=self.linkage, spring=self.spring
            )
        return np.full(np.broadcast_shapes(np.shape(depth), np.shape(sz)), lock)

    def pad_corners(self, deflection: float | None = None) -> NDArray[np.float64]:
        """Pad corners (pivot-left, pivot-right, rim-right, rim-left) in the foot frame [m],
        (n_pads, 4, 3), at a deflection [m] (default the locked one, or spread)."""
        th = float(self._shown_angle(deflection))
        return pads.pad_corners(self.geometry, th)

    def linkage_points(self, deflection: float) -> dict[str, NDArray[np.float64]]:
        """The joints of one linkage (:meth:`Linkage.points`) at a deflection [m], for drawings."""
        return self.linkage.points(float(self._check_deflection(deflection)))

    def elements(self, deflection: float | None = None, *, strips: int = 8) -> SurfaceElements:
        """Surface elements of the base, the column and both faces of every pad [m] (D159), at
        ``deflection`` [m] (default as :meth:`pad_corners`; the foot does not morph on an
        element terrain); ``strips``: elements along each pad face and up each wall [-]."""
        th = float(self._shown_angle(deflection))
        return pads.surface_elements(self.geometry, th, strips=strips)

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{A_{spread}}` [m], square root of the spread footprint (D36)."""
        return self._lc_spread if self._lc is None else self._lc

    @property
    def height(self) -> float:
        """Height of the foot above its tip [m]."""
        return self.geometry.height

    def replace(self, **changes: Any) -> MorphingFoot:
        """A copy with some parameters changed (geometry or spring fields, mode, ...)."""
        kw: dict[str, Any] = {"mode": self.mode, "seal_length": self.seal_length}
        kw.update(curl_delay=self.curl_delay, characteristic_length=self._lc)
        return MorphingFoot(self.geometry, self.spring, **(kw | changes))

    def as_dict(self) -> dict[str, float | int | str]:
        """All parameters, SI, as a flat dict."""
        return {
            **asdict(self.geometry),
            **asdict(self.spring),
            "mode": self.mode,
            "seal_length": self.seal_length,
            "curl_delay": self.curl_delay,
            "characteristic_length": self.characteristic_length,
        }

    def __repr__(self) -> str:
        delay = f", curl_delay={self.curl_delay:g} s" if self.curl_delay else ""
        return f"MorphingFoot(mode={self.mode!r}, stroke={self.stroke:.4g} m{delay})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MorphingFoot):
            return NotImplemented
        return self.as_dict() == other.as_dict()

    def __hash__(self) -> int:
        return hash(tuple(sorted(self.as_dict().items())))

    def projected_areas(
        self, depth: ArrayLike, *, deflection: ArrayLike | None = None
    ) -> NDArray[np.float64]:
        """Submerged areas projected along x, y, z [m^2], shape (..., 3) (D38), at tip depth
        [m] and deflection [m] (default the locked one, or the spread foot when free)."""
        g = self.geometry
        d = check_nonnegative("depth", depth, unit="m")
        d, th = np.broadcast_arrays(d, self._shown_angle(deflection))
        ax = pads.horizontal_area(g, d, th, np.zeros_like(d))
        ay = pads.horizontal_area(g, d, th, np.full_like(d, 0.5 * math.pi))
        return np.stack([ax, ay, pads.footprint_area(g, d, th)], axis=-1)

    def forces_at(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike, deflection: ArrayLike
    ) -> NDArray[np.float64]:
        """First-quadrant magnitudes (Fx, Fy, Fz) [N] at a given deflection [m]; the other
        arguments as :meth:`resultant`."""
        d, s, h = check_resultant_inputs(depth, stress, heading, height=self.height)
        return magnitudes(pads.coefficients(self.geometry, d, self.pad_angle(deflection), h), s)

    def resultant(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> NDArray[np.float64]:
        """Magnitudes (Fx, Fy, Fz) [N] at the first equilibrium met loading from rest (D34);
        arguments as :meth:`Foot.resultant`."""
        d, s, h = check_resultant_inputs(depth, stress, heading, height=self.height)
        delta = self._deflection(d, s[..., 2], 0.0)
        return magnitudes(pads.coefficients(self.geometry, d, self.linkage.angle(delta), h), s)

    def posed(self, rotation: RotationLike) -> NoReturn:
        """Not available (the pads move with the load): raises :class:`~mudrft.MudrftError`."""
        raise MudrftError(
            "MorphingFoot.posed(rotation): the morphing foot has no rotated "
            "mesh, since its pads open and curl with the load; the flat, "
            "semi-cylindrical, semi-spherical and mesh feet have one. Under a robot in "
            "MuJoCo, mudrft.integrations.mujoco.attach poses the morphing foot at every "
            "step (docs/model.md D60a)"
        )

    def initial_foot_state(self) -> MorphingState:
        """Column unloaded, or locked (D37); the seal memory at the current pad angle."""
        delta = self.locked_deflection() or 0.0
        th = float(self.linkage.angle(delta))
        return MorphingState(np.asarray(delta), np.asarray(th), np.asarray(th))

    def seal_factor(self, foot_state: MorphingState | None) -> FloatOrArray:
        """Seal factor [-] of :func:`~.equilibrium.seal_factor` at the state's pad angles
        (D35); 1.0 for ``None``."""
        if foot_state is None:
            return 1.0
        g_s, length = self.seal_length, self.geometry.pad_length
        return seal_factor(foot_state.pad_angle, foot_state.most_spread, length, g_s)

    def contact_force(
        self, foot_state: MorphingState | None, depth: ArrayLike, stress: ArrayLike,
        heading: ArrayLike, dt: float, *, retraction: ArrayLike = 0.0,
    ) -> tuple[MorphingState, NDArray[np.float64]]:  # fmt: skip
        """Solve the column balance for this step; return ``(state, force)`` [N] (D32, D34).

        Depth [m], stresses (..., 3) [Pa] and world heading [rad] are checked by the caller;
        ``dt`` [s] is unused (quasi-static); ``retraction``: time since it began [s] (or 0).
        """
        if foot_state is None:
            foot_state = self.initial_foot_state()
        d, s = np.asarray(depth, dtype=float), np.asarray(stress, dtype=float)
        delta = self._deflection(d, s[..., 2], foot_state.deflection)
        if self.curl_delay > 0.0 and self.mode == "morphing":
            delta = held_deflection(delta, foot_state.deflection, retraction, self.curl_delay)
        th = self.linkage.angle(delta)
        h = np.asarray(heading, dtype=float)
        f = pads.morphing_force(self.geometry, d, th, s[..., 0], s[..., 1], s[..., 2], h)
        force = np.stack(np.broadcast_arrays(*f), axis=-1)
        th_b = np.broadcast_to(th, d.shape) if np.ndim(th) < d.ndim else th
        most = track_most_spread(d, th_b, foot_state.most_spread)
        return MorphingState(np.asarray(delta), np.asarray(th_b), most), force

    def center_of_pressure(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> NDArray[np.float64]:
        """Center of the vertical pressure in the foot frame [m], shape (..., 3): on the axis,
        at the height of the area-weighted centroid of the submerged base and pad parts."""
        d, s, _ = check_resultant_inputs(depth, stress, heading, height=self.height)
        th = self.linkage.angle(self._deflection(d, s[..., 2], 0.0))
        z = pads.center_height(self.geometry, d, th)
        return np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=-1)
