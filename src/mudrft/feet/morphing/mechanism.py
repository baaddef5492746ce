r"""The morphing foot's mechanism on its own: parameters, kinematics, springs, balance, drawing.

:class:`MorphingMechanism` validates the dimensions, springs and mode of the foot and gives
the checked, public views of its mechanism: pad angle and inverse kinematics (D30), spring
force on rigid ground (D31, paper Fig. S3), effective and footprint areas (D33, D36), the
column balance with a given vertical stress (D32, D34) and the pads for drawings. The
physics is delegated to :mod:`.linkage`, :mod:`.springs`, :mod:`.pads` and
:mod:`.equilibrium`; :class:`~mudrft.feet.morphing.MorphingFoot` adds the mud-facing
:class:`~mudrft.feet.base.Foot` interface.
"""

from __future__ import annotations

from dataclasses import fields, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._validation import (
    MudrftError,
    check_choice,
    check_finite,
    check_in_range,
    check_nonnegative,
)
from ..base import SurfaceElements
from . import pads
from .equilibrium import balanced_deflection, residual
from .linkage import Linkage, MorphingFootGeometry
from .springs import RigidGroundResponse, TwoStageSpring

__all__ = ["MODES", "MorphingMechanism"]

#: Operating modes of the supplementary experiment (Sec. III-C, Fig. S4b).
MODES = ("morphing", "expanded", "retracted")

_GEOMETRY_FIELDS = {f.name for f in fields(MorphingFootGeometry)}
_SPRING_FIELDS = {f.name for f in fields(TwoStageSpring)}
_STROKE_SLACK = 1 + 1e-12  # deflections up to the stroke times this are accepted [-]


class MorphingMechanism:
    r"""Column, springs and pad linkages of the morphing foot, without the mud model.

    Parameters
    ----------
    geometry : MorphingFootGeometry, optional
        Base, pad and linkage dimensions [m, rad]; default: the reconstruction of D30.
    spring : TwoStageSpring, optional
        Column springs; default: soft 800 N/m over 7.5 mm, hard 6000 N/m (D31).
    mode : {"morphing", "expanded", "retracted"}, keyword-only
        Free morphing (default), pads locked fully spread, or locked curled up (D37).
    **overrides
        Any field of :class:`MorphingFootGeometry` or :class:`TwoStageSpring` by name,
        e.g. ``pad_length=0.04`` [m] or ``hard_stiffness=12000.0`` [N/m].

    Raises
    ------
    MudrftError
        For an unknown override, a bad mode, a linkage that cannot be built, or a soft
        stage that does not bottom out within the stroke.

    Examples
    --------
    >>> m = MorphingMechanism()
    >>> round(float(m.spring_force(m.stroke)), 1), round(float(m.deflection_at(0.5)) * 1e3, 2)
    (26.3, 8.06)
    """

    def __init__(
        self,
        geometry: MorphingFootGeometry | None = None,
        spring: TwoStageSpring | None = None,
        *,
        mode: str = "morphing",
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
                f"unknown {type(self).__name__} parameter(s) {sorted(unknown)}; expected fields "
                f"of MorphingFootGeometry {sorted(_GEOMETRY_FIELDS)} or "
                f"TwoStageSpring {sorted(_SPRING_FIELDS)}"
            )
        g = replace(g, **{k: v for k, v in overrides.items() if k in _GEOMETRY_FIELDS})
        s = replace(s, **{k: v for k, v in overrides.items() if k in _SPRING_FIELDS})
        self.geometry = g
        self.spring = s
        self.mode = check_choice("mode", mode, MODES)
        self._linkage = Linkage.from_geometry(g)
        if s.knee_deflection >= self.stroke:
            raise MudrftError(
                f"the soft stage must bottom out within the stroke {self.stroke!r} m: "
                f"soft_travel*(1 + soft_stiffness/hard_stiffness) = {s.knee_deflection!r} m"
            )

    # -- kinematics and springs --------------------------------------------------------------
    @property
    def linkage(self) -> Linkage:
        """The resolved pad linkage (D30)."""
        return self._linkage

    @property
    def stroke(self) -> float:
        """Column deflection from curled up to fully spread [m] (set by the linkage)."""
        return self._linkage.stroke

    def _check_deflection(self, deflection: ArrayLike) -> NDArray[np.float64]:
        return check_in_range("deflection", deflection, 0.0, self.stroke * _STROKE_SLACK, unit="m")

    def pad_angle(self, deflection: ArrayLike) -> NDArray[np.float64]:
        """Pad angle :math:`\\theta(\\delta)` from the horizontal [rad] (slider-crank, D30).

        Parameters
        ----------
        deflection : float or array_like
            Column deflection [m], in [0, stroke].

        Returns
        -------
        ndarray
            Pad angle [rad], decreasing from ``retracted_angle`` to ``expanded_angle``.
        """
        return self._linkage.angle(self._check_deflection(deflection))

    def deflection_at(self, pad_angle: ArrayLike) -> NDArray[np.float64]:
        """Inverse kinematics: column deflection [m] giving a pad angle [rad].

        Parameters
        ----------
        pad_angle : float or array_like
            Pad angle [rad], in [expanded_angle, retracted_angle].
        """
        g = self.geometry
        th = check_in_range("pad_angle", pad_angle, g.expanded_angle, g.retracted_angle, unit="rad")
        return self._linkage.deflection_at(th)

    def spring_force(self, deflection: ArrayLike) -> NDArray[np.float64]:
        """Column spring force [N] at a deflection [m] in [0, stroke] (D31)."""
        return np.asarray(self.spring.force(self._check_deflection(deflection)))

    def rigid_ground(self, deflection: ArrayLike) -> RigidGroundResponse:
        """Force and pad angle against deflection on rigid ground (paper Fig. S3a, b).

        On rigid ground only the tip touches, so the load is the column spring force.

        Parameters
        ----------
        deflection : float or array_like
            Column deflection [m], in [0, stroke].
        """
        d = self._check_deflection(deflection)
        return RigidGroundResponse(
            deflection=d,
            force=np.asarray(self.spring.force(d)),
            pad_angle=self._linkage.angle(d),
            stiffness=self.spring.stiffness(d),
        )

    def locked_deflection(self) -> float | None:
        """Deflection the mode locks (stroke for expanded, 0 for retracted), None if free."""
        return {"morphing": None, "expanded": self.stroke, "retracted": 0.0}[self.mode]

    def _shown_deflection(self, deflection: float | None) -> float:
        """Deflection to draw [m]: the given one, else the locked one, else the stroke."""
        if deflection is not None:
            return float(deflection)
        lock = self.locked_deflection()
        return self.stroke if lock is None else lock

    # -- areas (the two private views serve the tests of the pad geometry) ---------------------
    def _submerged_length(self, depth: ArrayLike, theta: ArrayLike) -> NDArray[np.float64]:
        return pads.submerged_length(self.geometry, depth, theta)

    def _vertical_area(self, depth: ArrayLike, theta: ArrayLike) -> NDArray[np.float64]:
        return pads.vertical_area(self.geometry, depth, theta)

    def effective_area(self, depth: ArrayLike, deflection: ArrayLike) -> NDArray[np.float64]:
        """Effective vertical area :math:`A_z` [m^2] with :math:`F_z=\\sigma_zA_z` (D33).

        Parameters
        ----------
        depth, deflection : float or array_like
            Tip depth [m], >= 0; column deflection [m], in [0, stroke].
        """
        d = check_nonnegative("depth", depth, unit="m")
        return pads.vertical_area(self.geometry, d, self.pad_angle(deflection))

    def footprint_area(
        self, deflection: ArrayLike, depth: ArrayLike | None = None
    ) -> NDArray[np.float64]:
        """Horizontal projection of the (submerged) base and pads [m^2].

        Parameters
        ----------
        deflection : float or array_like
            Column deflection [m].
        depth : float or array_like or None
            Tip depth [m]; None counts the whole foot.
        """
        th = self.pad_angle(deflection)
        d = np.inf if depth is None else check_nonnegative("depth", depth, unit="m")
        return pads.footprint_area(self.geometry, d, th)

    # -- balance with a given stress ----------------------------------------------------------
    def residual(
        self, deflection: ArrayLike, depth: ArrayLike, sz: ArrayLike
    ) -> NDArray[np.float64]:
        """Balance residual :math:`R=F_s(\\delta)-\\sigma_zA_z(d,\\theta(\\delta))` [N] (D32).

        Parameters
        ----------
        deflection, depth, sz : float or array_like
            Column deflection [m], in [0, stroke]; tip depth [m], >= 0; vertical channel
            stress [Pa].
        """
        dd = self._check_deflection(deflection)
        d = check_nonnegative("depth", depth, unit="m")
        return residual(dd, d, check_finite("sz", sz), linkage=self._linkage, spring=self.spring)

    def equilibrium(
        self, depth: ArrayLike, sz: ArrayLike, *, previous: ArrayLike = 0.0
    ) -> NDArray[np.float64]:
        r"""Column deflection in balance with the mud [m] (D32, D34).

        Solves :math:`F_s(\delta)=\sigma_zA_z(d,\theta(\delta))` on :math:`[0,\text{stroke}]`
        with the end stops as complementarity. Starting from ``previous``, the deflection
        moves in the direction of the net force to the nearest root (the stable equilibrium
        an overdamped column reaches: hysteresis across a snap-through); where :math:`R` is
        monotone this is the unique root. Brackets from a 33-node scan are refined to
        :math:`|R|\le10^{-10}` N: by bisection on floats for up to 16 moving elements, by
        :func:`scipy.optimize.elementwise.find_root` for more (see
        :mod:`mudrft.feet.morphing.equilibrium`).

        Parameters
        ----------
        depth, sz : float or array_like
            Tip depth [m], >= 0; vertical channel stress [Pa] (> 0 support, < 0 suction).
        previous : float or array_like, keyword-only
            Deflection at the previous instant [m].

        Returns
        -------
        ndarray
            Deflection [m].
        """
        d = check_nonnegative("depth", depth, unit="m")
        s = check_finite("sz", sz)
        p = check_in_range("previous", previous, 0.0, self.stroke * _STROKE_SLACK, unit="m")
        return balanced_deflection(d, s, previous=p, linkage=self._linkage, spring=self.spring)

    def _deflection(
        self, depth: ArrayLike, sz: ArrayLike, previous: ArrayLike
    ) -> NDArray[np.float64]:
        lock = self.locked_deflection()
        if lock is None:
            return balanced_deflection(
                depth, sz, previous=previous, linkage=self._linkage, spring=self.spring
            )
        return np.full(np.broadcast_shapes(np.shape(depth), np.shape(sz)), lock)

    # -- drawing -----------------------------------------------------------------------------
    def pad_corners(self, deflection: float | None = None) -> NDArray[np.float64]:
        """Corners of every pad in the foot frame [m], shape (n_pads, 4, 3).

        Order: pivot-left, pivot-right, rim-right, rim-left.

        Parameters
        ----------
        deflection : float or None
            Column deflection [m]; default the locked one (spread for the free mode).
        """
        th = float(self.pad_angle(self._shown_deflection(deflection)))
        return pads.pad_corners(self.geometry, th)

    def linkage_points(self, deflection: float) -> dict[str, NDArray[np.float64]]:
        """Joint positions of one linkage in its (r, z) plane [m], for drawings.

        Returns a dict with ``A`` (pad pivot), ``C`` (coupler joint), ``B`` (upper pole)
        and ``P`` (pad rim), each ``(r, z)``.

        Parameters
        ----------
        deflection : float
            Column deflection [m], in [0, stroke].
        """
        return self._linkage.points(float(self._check_deflection(deflection)))

    def elements(self, deflection: float | None = None, *, strips: int = 8) -> SurfaceElements:
        """Surface elements of the base, the column and both faces of every pad [m] (D159).

        What a terrain that integrates elements (granular RFT) sees: the base disk facing
        down, the base rim and the column facing out, and each pad as a thin plate with a
        lower face (leading into the ground) and an upper face (leading out of it), at the
        pad angle of ``deflection``: the foot does not morph on such a terrain.

        Parameters
        ----------
        deflection : float or None
            Column deflection [m]; default as in :meth:`pad_corners` (the locked one, or
            fully spread for the free foot).
        strips : int, keyword-only
            Elements along each pad face and up each wall [-].
        """
        th = float(self.pad_angle(self._shown_deflection(deflection)))
        return pads.surface_elements(self.geometry, th, strips=strips)
