r"""The passive morphing foot of Chen et al. (2026), Sec. III-B: mechanism and coupling with mud.

The foot (paper Fig. 6) has three parts: a two-stage telescoping **column** with a soft
and a hard spring in series, **eight pads** carried by the lower links of **eight
two-link linkages**. Compressing the column (deflection :math:`\delta`) pushes the
upper poles down; the couplers rotate the lower links and the pads spread from curled
up (pointing almost upward) to a nearly flat disk. The paper gives no dimensions; the
defaults here are a documented reconstruction (decision D30 in
``docs/model.md``) of the same scale as the paper's fixed feet.

Frame: the foot frame has its origin at the tip (the bottom of the central base
pad), z up, pads at azimuths :math:`2\pi k/N`. Pad angle :math:`\theta` is measured from
the horizontal (0: spread flat, :math:`\pi/2`: pointing up).

Model (decisions D30-D39):

* kinematics (D30): a slider-crank per pad: the pad's lower link pivots at
  :math:`A=(r_A, h_A)`; its crank arm of length :math:`a` at angle :math:`\theta+\beta`
  carries the coupler joint :math:`C`; the coupler of length :math:`b` joins :math:`C` to
  the upper pole :math:`B=(r_B, z_{B0}-\delta)`. :math:`\theta(\delta)` is the closed-form
  circle intersection; it is nearly linear (paper Fig. S3a), within about 1.4 deg for the
  defaults;
* springs (D31): exact series law of a two-stage column, stiffness
  :math:`k_sk_h/(k_s+k_h)` until the soft stage bottoms out, then :math:`k_h`, with end
  stops at :math:`\delta=0` and the stroke (paper Fig. S3b, two stiffness regions);
* load path (D32): the trajectory prescribes the tip; the whole vertical mud force on
  the base and pads passes through the column, :math:`F_s(\delta)=F_z^{mud}(\delta)`;
* pad forces (D33): per-plate rule of eq. (6)-(7) with tilt :math:`\psi_1=\theta`,
  :math:`dF_z=\sigma_z(f_n(\theta)\cos\theta+f_t(\theta)\sin\theta)\,dA` on the submerged
  part of each pad, uniform channel stresses; horizontal forces on projected areas;
* equilibrium (D34): solved at every step by a bracketed, vectorized search, unique
  where the residual is monotone and continued from the previous deflection otherwise;
* sealing (D35): the seal factor falls as the pad rims lift (curl) from their most
  spread position of the current contact: :math:`1-\tanh(g/g_s)`;
* :math:`L_c` is the square root of the spread footprint (D36); the modes ``"expanded"``
  and ``"retracted"`` lock the column (D37).

The implementation is NumPy only (no ``xp`` namespace): the JAX backend cannot trace it.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields, replace
from typing import Any, NamedTuple

import numpy as np

from .._validation import (
    MudrftError,
    check_choice,
    check_finite,
    check_in_range,
    check_nonnegative,
    check_positive,
)
from ..constitutive.laws import f_n, f_t
from .base import Foot, SurfaceElements, unfold_forces
from .base import check_resultant_inputs as _check_inputs

__all__ = [
    "MODES",
    "MorphingFoot",
    "MorphingFootGeometry",
    "MorphingState",
    "RigidGroundResponse",
    "TwoStageSpring",
]

#: Operating modes of the supplementary experiment (Sec. III-C, Fig. S4b).
MODES = ("morphing", "expanded", "retracted")

_GRID = 33  # nodes of the coarse bracketing grid over the stroke (D34)
_MAXIT = 80  # Illinois iterations at most (converges in ~10)
_FTOL = 1e-10  # force balance tolerance [N]


@dataclass(frozen=True)
class MorphingFootGeometry:
    """Dimensions of the morphing foot's base, pads and linkage (SI, decision D30).

    All lengths in metres, angles in radians. Defaults reconstruct a foot of the scale
    of the paper's fixed feet (80 x 65 mm flat foot, R = 45 mm curved feet): about 96 mm
    across when spread.

    Attributes
    ----------
    n_pads : int
        Number of pads and linkages [-] (paper: eight).
    base_radius : float
        Radius of the central base pad (bottom of the column) [m]; the pad pivots sit on
        its rim, :math:`r_A`.
    pivot_height : float
        Height of the pad pivots above the tip, :math:`h_A` [m] (base pad thickness).
    column_radius : float
        Radius of the column above the base [m] (horizontal drag only).
    height : float
        Height of the foot, tip to ankle [m].
    pad_length : float
        Pad length from its pivot to its rim, :math:`\\ell` [m].
    pad_inner_width, pad_outer_width : float
        Widths of the trapezoidal pad at its pivot and at its rim [m].
    crank_length : float
        Distance from the pad pivot to the coupler joint on the lower link, :math:`a` [m].
    crank_offset : float
        Angle of the crank arm relative to the pad, :math:`\\beta` [rad].
    coupler_length : float
        Length of the upper link (coupler), :math:`b` [m].
    pole_radius : float
        Radius of the upper poles on the upper column, :math:`r_B` [m].
    retracted_angle : float
        Pad angle with the column unloaded (curled up), :math:`\\theta_r` [rad].
    expanded_angle : float
        Pad angle with the column fully compressed (spread), :math:`\\theta_e` [rad].
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
        if (
            not isinstance(self.n_pads, (int, np.integer))
            or isinstance(self.n_pads, bool)
            or self.n_pads < 1
        ):
            raise MudrftError(f"n_pads must be an integer >= 1, got {self.n_pads!r}")
        for k in (
            "base_radius",
            "pivot_height",
            "column_radius",
            "height",
            "pad_length",
            "pad_inner_width",
            "pad_outer_width",
            "crank_length",
            "coupler_length",
        ):
            object.__setattr__(self, k, float(check_positive(k, getattr(self, k), unit="m")))
        object.__setattr__(
            self, "pole_radius", float(check_nonnegative("pole_radius", self.pole_radius, unit="m"))
        )
        object.__setattr__(
            self,
            "crank_offset",
            float(check_in_range("crank_offset", self.crank_offset, -math.pi, math.pi, unit="rad")),
        )
        th_e = float(
            check_in_range("expanded_angle", self.expanded_angle, 0.0, 0.5 * math.pi, unit="rad")
        )
        th_r = float(
            check_in_range("retracted_angle", self.retracted_angle, 0.0, 0.5 * math.pi, unit="rad")
        )
        if not th_r > th_e:
            raise MudrftError(
                f"retracted_angle must exceed expanded_angle = {th_e!r} rad, got {th_r!r} rad"
            )
        object.__setattr__(self, "expanded_angle", th_e)
        object.__setattr__(self, "retracted_angle", th_r)
        if self.column_radius > self.base_radius:
            raise MudrftError(
                f"column_radius must be <= base_radius = {self.base_radius!r} m, "
                f"got {self.column_radius!r} m"
            )
        if self.height <= self.pivot_height:
            raise MudrftError(
                f"height must exceed pivot_height = {self.pivot_height!r} m, got {self.height!r} m"
            )


@dataclass(frozen=True)
class TwoStageSpring:
    """Two springs in series in a two-stage telescoping column (decision D31).

    Both springs compress together (series stiffness :math:`k_sk_h/(k_s+k_h)`) until the
    soft spring has compressed by ``soft_travel`` and its stage bottoms out; beyond, only
    the hard spring compresses, up to the end stop of the linkage (the stroke).

    Attributes
    ----------
    soft_stiffness : float
        :math:`k_s` [N/m].
    hard_stiffness : float
        :math:`k_h` [N/m], >= ``soft_stiffness``.
    soft_travel : float
        Compression of the soft spring when its stage bottoms out, :math:`s_s` [m].
    """

    soft_stiffness: float = 800.0
    hard_stiffness: float = 6000.0
    soft_travel: float = 0.0075

    def __post_init__(self) -> None:
        for k, u in (("soft_stiffness", "N/m"), ("hard_stiffness", "N/m"), ("soft_travel", "m")):
            object.__setattr__(self, k, float(check_positive(k, getattr(self, k), unit=u)))
        if self.hard_stiffness < self.soft_stiffness:
            raise MudrftError(
                f"hard_stiffness must be >= soft_stiffness = {self.soft_stiffness!r} N/m, "
                f"got {self.hard_stiffness!r} N/m"
            )

    @property
    def series_stiffness(self) -> float:
        """Stiffness of the first stage, :math:`k_sk_h/(k_s+k_h)` [N/m]."""
        return (
            self.soft_stiffness * self.hard_stiffness / (self.soft_stiffness + self.hard_stiffness)
        )

    @property
    def knee_deflection(self) -> float:
        """Column deflection where the soft stage bottoms out, :math:`s_s(1+k_s/k_h)` [m]."""
        return self.soft_travel * (1.0 + self.soft_stiffness / self.hard_stiffness)

    @property
    def knee_force(self) -> float:
        """Force at which the soft stage bottoms out, :math:`k_ss_s` [N]."""
        return self.soft_stiffness * self.soft_travel

    def force(self, deflection: Any) -> Any:
        """Spring force [N] at column deflection [m] (no end stops; see MorphingFoot)."""
        d = np.asarray(deflection, dtype=float)
        d1 = self.knee_deflection
        return np.where(
            d <= d1, self.series_stiffness * d, self.knee_force + self.hard_stiffness * (d - d1)
        )

    def deflection(self, force: Any) -> Any:
        """Inverse of :meth:`force`: deflection [m] under a force [N] >= 0."""
        f = np.asarray(force, dtype=float)
        f1 = self.knee_force
        return np.where(
            f <= f1,
            f / self.series_stiffness,
            self.knee_deflection + (f - f1) / self.hard_stiffness,
        )


class MorphingState(NamedTuple):
    """Internal state of a morphing foot (scalars or arrays of one batch shape).

    Attributes
    ----------
    deflection : ndarray
        Column deflection :math:`\\delta` [m].
    pad_angle : ndarray
        Pad angle :math:`\\theta(\\delta)` [rad].
    most_spread : ndarray
        Smallest pad angle reached during the current contact [rad] (seal memory, D35).
    """

    deflection: Any
    pad_angle: Any
    most_spread: Any


class RigidGroundResponse(NamedTuple):
    """Foot pressed on rigid ground (paper Fig. S3): all the load goes through the tip.

    Attributes
    ----------
    deflection : ndarray
        Column deflection [m].
    force : ndarray
        Vertical force [N] (spring law with its end stops).
    pad_angle : ndarray
        Pad angle [rad].
    stiffness : ndarray
        Tangent stiffness dF/d(deflection) [N/m]: the series stiffness below the knee,
        the hard spring's above it.
    """

    deflection: np.ndarray
    force: np.ndarray
    pad_angle: np.ndarray
    stiffness: np.ndarray


_GEOMETRY_FIELDS = {f.name for f in fields(MorphingFootGeometry)}
_SPRING_FIELDS = {f.name for f in fields(TwoStageSpring)}


class MorphingFoot(Foot):
    r"""The passive morphing foot (paper Sec. III-B, Fig. 6; supplementary Sec. III-C).

    Parameters
    ----------
    geometry : MorphingFootGeometry, optional
        Base, pad and linkage dimensions; default: the reconstruction of decision D30.
    spring : TwoStageSpring, optional
        Column springs; default: soft 800 N/m over 7.5 mm, hard 6000 N/m (D31).
    mode : {"morphing", "expanded", "retracted"}, keyword-only
        Free morphing (default), pads locked fully spread, or locked curled up.
    seal_length : float, keyword-only
        Rim lift :math:`g_s` over which curling pads break the cavity seal [m] (D35).
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
    >>> r = foot.rigid_ground([0.0, foot.stroke])
    >>> np.round(r.force, 1).tolist()
    [0.0, 26.3]
    >>> float(MorphingFoot(mode="expanded").resultant(0.02, [0.0, 0.0, 1e4], 0.0)[2]) > 50
    True
    """

    def __init__(
        self,
        geometry: MorphingFootGeometry | None = None,
        spring: TwoStageSpring | None = None,
        *,
        mode: str = "morphing",
        seal_length: float = 0.002,
        characteristic_length: float | None = None,
        **overrides: Any,
    ) -> None:
        g = geometry if geometry is not None else MorphingFootGeometry()
        s = spring if spring is not None else TwoStageSpring()
        if not isinstance(g, MorphingFootGeometry):
            raise MudrftError(f"geometry must be a MorphingFootGeometry, got {type(g).__name__}")
        if not isinstance(s, TwoStageSpring):
            raise MudrftError(f"spring must be a TwoStageSpring, got {type(s).__name__}")
        unknown = set(overrides) - _GEOMETRY_FIELDS - _SPRING_FIELDS
        if unknown:
            raise MudrftError(
                f"unknown MorphingFoot parameter(s) {sorted(unknown)}; expected fields of "
                f"MorphingFootGeometry {sorted(_GEOMETRY_FIELDS)} or "
                f"TwoStageSpring {sorted(_SPRING_FIELDS)}"
            )
        g = replace(g, **{k: v for k, v in overrides.items() if k in _GEOMETRY_FIELDS})
        s = replace(s, **{k: v for k, v in overrides.items() if k in _SPRING_FIELDS})
        self.geometry = g
        self.spring = s
        self.mode = check_choice("mode", mode, MODES)
        self.seal_length = float(check_positive("seal_length", seal_length, unit="m"))
        self.name = "morphing" if self.mode == "morphing" else f"morphing-{self.mode}"
        self._setup_linkage()
        if self.spring.knee_deflection >= self.stroke:
            raise MudrftError(
                f"the soft stage must bottom out within the stroke {self.stroke!r} m: "
                "soft_travel*(1 + "
                f"soft_stiffness/hard_stiffness) = {self.spring.knee_deflection!r} m"
            )
        self._lc = (
            None
            if characteristic_length is None
            else float(check_positive("characteristic_length", characteristic_length, unit="m"))
        )
        az = 2.0 * np.pi * np.arange(g.n_pads) / g.n_pads
        self._azimuths = az

    # -- construction ------------------------------------------------------------------------
    def _setup_linkage(self) -> None:
        g = self.geometry
        th = np.linspace(g.expanded_angle, g.retracted_angle, 721)
        phi = th + g.crank_offset
        rc = g.base_radius + g.crank_length * np.cos(phi)
        zc = g.pivot_height + g.crank_length * np.sin(phi)
        span = g.coupler_length**2 - (rc - g.pole_radius) ** 2
        if np.any(span <= 0):
            raise MudrftError(
                f"coupler_length = {g.coupler_length!r} m is too short to reach the upper pole "
                "over the "
                "pad travel; lengthen it or move pole_radius toward the pivots"
            )
        zb = zc + np.sqrt(span)
        if np.any(np.diff(zb) <= 0):
            raise MudrftError(
                "the linkage is not monotone over the pad travel (the pole must rise as the pads "
                "curl up): change crank_offset, crank_length or coupler_length"
            )
        self._zb0 = float(zb[-1])
        self._stroke = float(zb[-1] - zb[0])
        # branch of the circle intersection that reproduces the design angles
        d = np.array([0.0, self._stroke])
        for sign in (1.0, -1.0):
            self._branch = sign
            t = self._angle_raw(d)
            if abs(t[0] - g.retracted_angle) < 1e-9 and abs(t[1] - g.expanded_angle) < 1e-9:
                break
        else:  # pragma: no cover - excluded by the monotonicity check above
            raise MudrftError("could not resolve the linkage branch")

    def _angle_raw(self, deflection: Any) -> Any:
        g = self.geometry
        dr = g.pole_radius - g.base_radius
        dz = self._zb0 - deflection - g.pivot_height
        dist = np.hypot(dr, dz)
        c = (g.crank_length**2 + dist**2 - g.coupler_length**2) / (2.0 * g.crank_length * dist)
        return np.arctan2(dz, dr) + self._branch * np.arccos(np.clip(c, -1.0, 1.0)) - g.crank_offset

    # -- Foot interface ----------------------------------------------------------------------
    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{A_{spread}}` [m], square root of the spread footprint (D36)."""
        if self._lc is not None:
            return self._lc
        return math.sqrt(self.footprint_area(self.stroke))

    @property
    def height(self) -> float:
        """Height of the foot above its tip [m]."""
        return self.geometry.height

    @property
    def stroke(self) -> float:
        """Column deflection from curled up to fully spread [m] (set by the linkage)."""
        return self._stroke

    def replace(self, **changes: Any) -> MorphingFoot:
        """A copy with some parameters changed (geometry or spring fields, mode, ...)."""
        kw: dict[str, Any] = {
            "mode": self.mode,
            "seal_length": self.seal_length,
            "characteristic_length": self._lc,
        }
        for k in ("mode", "seal_length", "characteristic_length"):
            if k in changes:
                kw[k] = changes.pop(k)
        return MorphingFoot(self.geometry, self.spring, **kw, **changes)

    def as_dict(self) -> dict[str, Any]:
        """All parameters, SI, as a flat dict."""
        return {
            **asdict(self.geometry),
            **asdict(self.spring),
            "mode": self.mode,
            "seal_length": self.seal_length,
            "characteristic_length": self.characteristic_length,
        }

    def __repr__(self) -> str:
        return f"MorphingFoot(mode={self.mode!r}, stroke={self.stroke:.4g} m)"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MorphingFoot):
            return NotImplemented
        return self.as_dict() == other.as_dict()

    def __hash__(self) -> int:
        return hash(tuple(sorted(self.as_dict().items())))

    # -- mechanism ---------------------------------------------------------------------------
    def pad_angle(self, deflection: Any) -> np.ndarray:
        """Pad angle :math:`\\theta(\\delta)` from the horizontal [rad] (slider-crank, D30).

        Parameters
        ----------
        deflection : float or array
            Column deflection [m], in [0, stroke].

        Returns
        -------
        ndarray
            Pad angle [rad], decreasing from ``retracted_angle`` to ``expanded_angle``.
        """
        d = check_in_range("deflection", deflection, 0.0, self.stroke * (1 + 1e-12), unit="m")
        return self._theta(d)

    def _theta(self, d: Any) -> Any:
        g = self.geometry
        return np.clip(self._angle_raw(d), g.expanded_angle, g.retracted_angle)

    def deflection_at(self, pad_angle: Any) -> np.ndarray:
        """Inverse kinematics: column deflection [m] giving a pad angle [rad]."""
        g = self.geometry
        th = check_in_range("pad_angle", pad_angle, g.expanded_angle, g.retracted_angle, unit="rad")
        phi = th + g.crank_offset
        rc = g.base_radius + g.crank_length * np.cos(phi)
        zc = g.pivot_height + g.crank_length * np.sin(phi)
        zb = zc + np.sqrt(g.coupler_length**2 - (rc - g.pole_radius) ** 2)
        return np.clip(self._zb0 - zb, 0.0, self.stroke)

    def spring_force(self, deflection: Any) -> np.ndarray:
        """Column spring force [N] at a deflection [m] in [0, stroke] (D31)."""
        d = check_in_range("deflection", deflection, 0.0, self.stroke * (1 + 1e-12), unit="m")
        return np.asarray(self.spring.force(d))

    def rigid_ground(self, deflection: Any) -> RigidGroundResponse:
        """Force and pad angle against deflection on rigid ground (paper Fig. S3a, b).

        On rigid ground only the tip touches, so the load is the column spring force.

        Parameters
        ----------
        deflection : float or array
            Column deflection [m], in [0, stroke].

        Returns
        -------
        RigidGroundResponse
        """
        d = check_in_range("deflection", deflection, 0.0, self.stroke * (1 + 1e-12), unit="m")
        k = np.where(
            d < self.spring.knee_deflection,
            self.spring.series_stiffness,
            self.spring.hard_stiffness,
        )
        return RigidGroundResponse(
            deflection=d,
            force=np.asarray(self.spring.force(d)),
            pad_angle=self._theta(d),
            stiffness=np.asarray(k, dtype=float),
        )

    def locked_deflection(self) -> float | None:
        """Deflection the mode locks (stroke for expanded, 0 for retracted), None if free."""
        return {"morphing": None, "expanded": self.stroke, "retracted": 0.0}[self.mode]

    # -- geometry of the submerged pads --------------------------------------------------------
    def _pad_area(self, length: Any) -> Any:
        """Area of the pad from its pivot to a distance ``length`` along it [m^2]."""
        g = self.geometry
        kappa = (g.pad_outer_width - g.pad_inner_width) / g.pad_length
        return g.pad_inner_width * length + 0.5 * kappa * length**2

    def _submerged_length(self, depth: Any, theta: Any) -> Any:
        g = self.geometry
        rise = depth - g.pivot_height
        s = np.sin(theta)
        safe = np.where(s > 1e-12, s, 1.0)
        return np.where(
            s > 1e-12,
            np.clip(rise / safe, 0.0, g.pad_length),
            np.where(rise > 0, g.pad_length, 0.0),
        )

    def _vertical_area(self, depth: Any, theta: Any) -> Any:
        """Effective vertical area: base + pads weighted by f_n cos + f_t sin (D33) [m^2]."""
        g = self.geometry
        base = np.where(depth > 0, math.pi * g.base_radius**2, 0.0)
        pad = self._pad_area(self._submerged_length(depth, theta))
        weight = f_n(theta) * np.cos(theta) + f_t(theta) * np.sin(theta)
        return base + g.n_pads * pad * weight

    def _horizontal_area(self, depth: Any, theta: Any, heading: Any) -> Any:
        """Submerged area projected normal to the heading [m^2] (D33)."""
        g = self.geometry
        col = 2.0 * g.base_radius * np.clip(
            depth, 0.0, g.pivot_height
        ) + 2.0 * g.column_radius * np.clip(depth - g.pivot_height, 0.0, g.height - g.pivot_height)
        pad = self._pad_area(self._submerged_length(depth, theta)) * np.sin(theta)
        h = np.asarray(heading, dtype=float)
        proj = np.abs(np.cos(self._azimuths - h[..., None])).sum(-1)
        return col + pad * proj

    def effective_area(self, depth: Any, deflection: Any) -> np.ndarray:
        """Effective vertical area :math:`A_z` [m^2] with :math:`F_z=\\sigma_zA_z` (D33).

        Parameters
        ----------
        depth : float or array
            Tip depth [m], >= 0.
        deflection : float or array
            Column deflection [m], in [0, stroke].
        """
        d = check_nonnegative("depth", depth, unit="m")
        th = self.pad_angle(deflection)
        return np.asarray(self._vertical_area(d, th))

    def footprint_area(self, deflection: Any, depth: Any = None) -> np.ndarray:
        """Horizontal projection of the (submerged) base and pads [m^2].

        Parameters
        ----------
        deflection : float or array
            Column deflection [m].
        depth : float or array or None
            Tip depth [m]; None counts the whole foot.
        """
        th = self.pad_angle(deflection)
        d = np.inf if depth is None else check_nonnegative("depth", depth, unit="m")
        return np.asarray(self._footprint(d, th))

    def _footprint(self, d: Any, th: Any) -> Any:
        g = self.geometry
        base = np.where(d > 0, math.pi * g.base_radius**2, 0.0)
        length = np.where(
            np.isinf(d), g.pad_length, self._submerged_length(np.where(np.isinf(d), 0.0, d), th)
        )
        return base + g.n_pads * self._pad_area(length) * np.cos(th)

    def projected_areas(self, depth: Any, *, deflection: Any = None) -> np.ndarray:
        """Submerged areas projected along x, y, z [m^2], shape (..., 3) (D38).

        Parameters
        ----------
        depth : float or array
            Tip depth [m].
        deflection : float or array or None, keyword-only
            Column deflection [m]; default the locked one, or the spread foot for the free
            morphing mode (the reference for the paper's normalised stresses).
        """
        d = check_nonnegative("depth", depth, unit="m")
        if deflection is None:
            lock = self.locked_deflection()
            deflection = self.stroke if lock is None else lock
        th = self.pad_angle(deflection)
        d, th = np.broadcast_arrays(d, th)
        ax = self._horizontal_area(d, th, np.zeros_like(d))
        ay = self._horizontal_area(d, th, np.full_like(d, 0.5 * math.pi))
        az = self._footprint(d, th)
        return np.stack([ax, ay, az], axis=-1)

    # -- forces ------------------------------------------------------------------------------
    def forces_at(self, depth: Any, stress: Any, heading: Any, deflection: Any) -> np.ndarray:
        """First-quadrant force magnitudes (Fx, Fy, Fz) [N] at a given deflection.

        Parameters
        ----------
        depth : float or array
            Tip depth [m], >= 0.
        stress : array_like, shape (..., 3)
            Channel stresses (sx, sy, sz) [Pa].
        heading : float or array
            Heading in [0, pi/2] [rad].
        deflection : float or array
            Column deflection [m], in [0, stroke].
        """
        d, s, h = _check_inputs(depth, stress, heading)
        th = self.pad_angle(deflection)
        return self._forces(d, s, h, th)

    def _forces(self, d: Any, s: Any, h: Any, th: Any) -> np.ndarray:
        ah = self._horizontal_area(d, th, h)
        az = self._vertical_area(d, th)
        fx = ah * np.cos(h) * s[..., 0]
        fy = ah * np.sin(h) * s[..., 1]
        fz = az * s[..., 2]
        return np.stack(np.broadcast_arrays(fx, fy, fz), axis=-1)

    def residual(self, deflection: Any, depth: Any, sz: Any) -> np.ndarray:
        """Balance residual :math:`R=F_s(\\delta)-\\sigma_zA_z(d,\\theta(\\delta))` [N] (D32)."""
        dd = check_in_range("deflection", deflection, 0.0, self.stroke * (1 + 1e-12), unit="m")
        return np.asarray(
            self._res(dd, check_nonnegative("depth", depth, unit="m"), check_finite("sz", sz))
        )

    def _res(self, delta: Any, depth: Any, sz: Any) -> Any:
        return self.spring.force(delta) - sz * self._vertical_area(depth, self._theta(delta))

    def equilibrium(self, depth: Any, sz: Any, *, previous: Any = 0.0) -> np.ndarray:
        r"""Column deflection in balance with the mud [m] (D32, D34).

        Solves :math:`F_s(\delta)=\sigma_zA_z(d,\theta(\delta))` on :math:`[0,\text{stroke}]`
        with the end stops as complementarity: :math:`\delta=0` when the mud does not push
        (:math:`R(0)\ge0`), :math:`\delta=` stroke when it pushes harder than the fully
        compressed springs. Starting from ``previous``, the deflection moves in the
        direction of the net force to the nearest root (the stable equilibrium an
        overdamped column reaches); where :math:`R` is monotone this is the unique root.

        Parameters
        ----------
        depth : float or array
            Tip depth [m], >= 0.
        sz : float or array
            Vertical channel stress [Pa] (> 0 support, < 0 suction).
        previous : float or array, keyword-only
            Deflection at the previous instant [m].

        Returns
        -------
        ndarray
            Deflection [m].
        """
        d = check_nonnegative("depth", depth, unit="m")
        s = check_finite("sz", sz)
        p = check_in_range("previous", previous, 0.0, self.stroke * (1 + 1e-12), unit="m")
        return self._solve(d, s, p)

    def _solve(self, depth: Any, sz: Any, previous: Any) -> np.ndarray:
        d, s, p = np.broadcast_arrays(
            np.asarray(depth, float), np.asarray(sz, float), np.asarray(previous, float)
        )
        shape = d.shape
        d, s = d.ravel(), s.ravel()
        p = np.clip(p.ravel(), 0.0, self.stroke)
        out = p.copy()
        r_p = self._res(p, d, s)
        # elements balanced already, or pushed against the stop they rest on, stay put
        moving = ((r_p < 0) & (p < self.stroke)) | ((r_p > 0) & (p > 0))
        if np.any(moving):
            out[moving] = self._move(d[moving], s[moving], p[moving], r_p[moving])
        return out.reshape(shape)

    def _move(self, d: np.ndarray, s: np.ndarray, p: np.ndarray, r_p: np.ndarray) -> np.ndarray:
        """Nearest root from ``p`` in the direction of the net force (D34)."""
        n = d.size
        out = p.copy()
        nodes = np.linspace(0.0, self.stroke, _GRID)
        r_n = self._res(nodes[None, :], d[:, None], s[:, None])
        idx = np.arange(n)
        lo = np.zeros(n)
        hi = np.zeros(n)
        flo = np.zeros(n)
        fhi = np.zeros(n)
        # moving up: first node above the previous deflection where the springs win
        up = r_p < 0
        cand = (nodes[None, :] > p[:, None]) & (r_n >= 0)
        has = cand.any(axis=1)
        j = np.argmax(cand, axis=1)
        jm = np.maximum(j - 1, 0)
        sel_up = up & has
        below = nodes[jm] > p
        lo = np.where(sel_up, np.where(below, nodes[jm], p), lo)
        flo = np.where(sel_up, np.where(below, r_n[idx, jm], r_p), flo)
        hi = np.where(sel_up, nodes[j], hi)
        fhi = np.where(sel_up, r_n[idx, j], fhi)
        out = np.where(up & ~has, self.stroke, out)
        # moving down: last node below the previous deflection where the mud wins
        down = ~up
        cand = (nodes[None, :] < p[:, None]) & (r_n <= 0)
        has = cand.any(axis=1)
        j = _GRID - 1 - np.argmax(cand[:, ::-1], axis=1)
        jp = np.minimum(j + 1, _GRID - 1)
        sel_down = down & has
        above = nodes[jp] < p
        lo = np.where(sel_down, nodes[j], lo)
        flo = np.where(sel_down, r_n[idx, j], flo)
        hi = np.where(sel_down, np.where(above, nodes[jp], p), hi)
        fhi = np.where(sel_down, np.where(above, r_n[idx, jp], r_p), fhi)
        out = np.where(down & ~has, 0.0, out)
        act = sel_up | sel_down
        if np.any(act):
            out[act] = self._illinois(lo[act], hi[act], flo[act], fhi[act], d[act], s[act])
        return out

    def _illinois(
        self,
        lo: np.ndarray,
        hi: np.ndarray,
        flo: np.ndarray,
        fhi: np.ndarray,
        d: np.ndarray,
        s: np.ndarray,
    ) -> np.ndarray:
        """Bracketed root (Illinois false position) of R on [lo, hi], R(lo) <= 0 <= R(hi)."""
        x = np.where(fhi == 0, hi, lo)
        done = (fhi == 0) | (flo == 0)
        side = np.zeros(lo.size)
        for _ in range(_MAXIT):
            if np.all(done):
                break
            denom = fhi - flo
            xn = np.where(
                denom > 0, (lo * fhi - hi * flo) / np.where(denom > 0, denom, 1.0), 0.5 * (lo + hi)
            )
            xn = np.clip(xn, lo, hi)
            fx = self._res(xn, d, s)
            x = np.where(done, x, xn)
            conv = (np.abs(fx) <= _FTOL) | (hi - lo <= 1e-15)
            neg = fx < 0
            # root in [xn, hi]
            m1 = ~done & neg
            fhi = np.where(m1 & (side == -1), 0.5 * fhi, fhi)
            lo = np.where(m1, xn, lo)
            flo = np.where(m1, fx, flo)
            side = np.where(m1, -1.0, side)
            # root in [lo, xn]
            m2 = ~done & ~neg
            flo = np.where(m2 & (side == 1), 0.5 * flo, flo)
            hi = np.where(m2, xn, hi)
            fhi = np.where(m2, fx, fhi)
            side = np.where(m2, 1.0, side)
            done = done | conv
        return x

    def _deflection(self, depth: Any, sz: Any, previous: Any) -> Any:
        lock = self.locked_deflection()
        if lock is None:
            return self._solve(depth, sz, previous)
        shape = np.broadcast_shapes(np.shape(depth), np.shape(sz))
        return np.full(shape, lock)

    def resultant(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """Magnitudes (Fx, Fy, Fz) [N] at the equilibrium deflection (loading from curled up).

        The deflection is the first equilibrium met when the column is loaded from rest
        (``previous=0``, D34); :meth:`contact_force` follows the deflection in time instead.
        See :meth:`Foot.resultant` for the arguments.
        """
        d, s, h = _check_inputs(depth, stress, heading)
        delta = self._deflection(d, s[..., 2], 0.0)
        return self._forces(d, s, h, self._theta(delta))

    def initial_foot_state(self) -> MorphingState:
        """Column unloaded, or locked (D37); the seal memory at the current pad angle."""
        lock = self.locked_deflection()
        delta = 0.0 if lock is None else lock
        th = float(self._theta(delta))
        return MorphingState(
            deflection=np.asarray(delta), pad_angle=np.asarray(th), most_spread=np.asarray(th)
        )

    def seal_factor(self, foot_state: Any) -> Any:
        r"""Seal factor :math:`1-\tanh(g/g_s)` [-], :math:`g=\ell(\sin\theta-\sin\theta_m)` (D35).

        :math:`g` [m] is how far the pad rims have lifted (curled) since their most spread
        position in the current contact; locked modes keep 1.
        """
        if foot_state is None:
            return 1.0
        th = np.asarray(foot_state.pad_angle, dtype=float)
        tm = np.asarray(foot_state.most_spread, dtype=float)
        lift = np.maximum(self.geometry.pad_length * (np.sin(th) - np.sin(tm)), 0.0)
        return 1.0 - np.tanh(lift / self.seal_length)

    def contact_force(
        self, foot_state: Any, depth: Any, stress: Any, heading: Any, dt: float
    ) -> tuple[MorphingState, np.ndarray]:
        """Solve the column balance for this step and return ``(state, force)`` [N] (D32, D34).

        The deflection moves from the previous one (``foot_state.deflection``) to the
        balance with the current stresses; out of the mud (depth 0) the column relaxes to
        0 and the seal memory resets. Force in the world frame as in :meth:`Foot.force`.
        """
        if foot_state is None:
            foot_state = self.initial_foot_state()
        d = np.asarray(depth, dtype=float)
        s = np.asarray(stress, dtype=float)
        delta = self._deflection(d, s[..., 2], foot_state.deflection)
        th = self._theta(delta)
        th_e = np.asarray(th)[..., None]
        force = unfold_forces(lambda su, ph: self._forces(d[..., None], su, ph, th_e), s, heading)
        th_b = np.broadcast_to(th, d.shape) if np.ndim(th) < d.ndim else th
        most = np.where(d > 0, np.minimum(foot_state.most_spread, th_b), th_b)
        return MorphingState(
            deflection=np.asarray(delta), pad_angle=np.asarray(th_b), most_spread=np.asarray(most)
        ), force

    def center_of_pressure(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """Center of the vertical pressure in the foot frame [m], shape (..., 3).

        On the axis by symmetry, at the height of the vertical-area-weighted centroid of the
        submerged base (z = 0) and pad parts, at the loading-branch deflection.
        """
        d, s, _ = _check_inputs(depth, stress, heading)
        g = self.geometry
        th = self._theta(self._deflection(d, s[..., 2], 0.0))
        d, th = np.broadcast_arrays(d, th)
        length = self._submerged_length(d, th)
        kappa = (g.pad_outer_width - g.pad_inner_width) / g.pad_length
        area = self._pad_area(length)
        moment = g.pad_inner_width * length**2 / 2 + kappa * length**3 / 3
        sbar = np.where(area > 0, moment / np.where(area > 0, area, 1.0), 0.0)
        wp = g.n_pads * area * (f_n(th) * np.cos(th) + f_t(th) * np.sin(th))
        wb = np.where(d > 0, math.pi * g.base_radius**2, 0.0)
        zp = g.pivot_height + sbar * np.sin(th)
        tot = wp + wb
        z = np.where(tot > 0, wp * zp / np.where(tot > 0, tot, 1.0), 0.5 * np.minimum(d, g.height))
        return np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=-1)

    # -- drawing -------------------------------------------------------------------------------
    def pad_corners(self, deflection: Any = None) -> np.ndarray:
        """Corners of every pad in the foot frame [m], shape (n_pads, 4, 3).

        Order: pivot-left, pivot-right, rim-right, rim-left.

        Parameters
        ----------
        deflection : float or None
            Column deflection [m]; default the locked one (spread for the free mode).
        """
        g = self.geometry
        if deflection is None:
            lock = self.locked_deflection()
            deflection = self.stroke if lock is None else lock
        th = float(self.pad_angle(float(deflection)))
        out = np.empty((g.n_pads, 4, 3))
        for k, a in enumerate(self._azimuths):
            er = np.array([math.cos(a), math.sin(a), 0.0])
            et = np.array([-math.sin(a), math.cos(a), 0.0])
            p0 = g.base_radius * er + np.array([0.0, 0.0, g.pivot_height])
            p1 = p0 + g.pad_length * (math.cos(th) * er + np.array([0.0, 0.0, math.sin(th)]))
            out[k] = [
                p0 - 0.5 * g.pad_inner_width * et,
                p0 + 0.5 * g.pad_inner_width * et,
                p1 + 0.5 * g.pad_outer_width * et,
                p1 - 0.5 * g.pad_outer_width * et,
            ]
        return out

    def linkage_points(self, deflection: Any) -> dict[str, np.ndarray]:
        """Joint positions of one linkage in its (r, z) plane [m], for drawings.

        Returns a dict with ``A`` (pad pivot), ``C`` (coupler joint), ``B`` (upper pole)
        and ``P`` (pad rim), each ``(r, z)``.
        """
        g = self.geometry
        dl = float(
            check_in_range("deflection", deflection, 0.0, self.stroke * (1 + 1e-12), unit="m")
        )
        th = float(self._theta(dl))
        a = np.array([g.base_radius, g.pivot_height])
        c = a + g.crank_length * np.array(
            [math.cos(th + g.crank_offset), math.sin(th + g.crank_offset)]
        )
        b = np.array([g.pole_radius, self._zb0 - dl])
        p = a + g.pad_length * np.array([math.cos(th), math.sin(th)])
        return {"A": a, "C": c, "B": b, "P": p}

    def elements(self, deflection: Any = None, *, strips: int = 8) -> SurfaceElements:
        """Surface elements of the base (one downward disk) and the pads (thin plates) [m].

        Each pad is cut into ``strips`` along its length; a pad element's normal is the
        upward-outward normal of the plate. Deflection as in :meth:`pad_corners`.
        """
        g = self.geometry
        if deflection is None:
            lock = self.locked_deflection()
            deflection = self.stroke if lock is None else lock
        th = float(self.pad_angle(float(deflection)))
        edges = np.linspace(0.0, g.pad_length, strips + 1)
        areas_1 = np.diff(self._pad_area(edges))
        mids = 0.5 * (edges[1:] + edges[:-1])
        cen, nor, ar = (
            [np.array([[0.0, 0.0, 0.0]])],
            [np.array([[0.0, 0.0, -1.0]])],
            [np.array([math.pi * g.base_radius**2])],
        )
        for a in self._azimuths:
            er = np.array([math.cos(a), math.sin(a), 0.0])
            ez = np.array([0.0, 0.0, 1.0])
            p = (g.base_radius * er + g.pivot_height * ez)[None, :] + mids[:, None] * (
                math.cos(th) * er + math.sin(th) * ez
            )[None, :]
            cen.append(p)
            nor.append(np.tile(-math.sin(th) * er + math.cos(th) * ez, (strips, 1)))
            ar.append(areas_1)
        return SurfaceElements(
            centroids=np.concatenate(cen), normals=np.concatenate(nor), areas=np.concatenate(ar)
        )
