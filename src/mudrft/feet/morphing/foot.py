r"""The passive morphing foot in the mud model: the Foot interface over its mechanism.

:class:`MorphingFoot` is the :class:`~.mechanism.MorphingMechanism` (parameters, kinematics,
springs, balance, drawing) plus what the mud terrain needs of a foot: forces at the balanced
deflection (D32-D34), the internal state stepped in time with its seal memory and factor
(D35), the characteristic length (D36), areas for normalised stresses (D38) and the center
of pressure. The package docstring (:mod:`mudrft.feet.morphing`) summarises the model.
"""

from __future__ import annotations

import math
from dataclasses import asdict
from typing import Any, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._typing import FloatOrArray, RotationLike
from ..._validation import MudrftError, check_length, check_nonnegative, positive_number
from ..base import Foot
from ..base import check_resultant_inputs as _check_inputs
from . import pads
from .equilibrium import MorphingState, held_deflection, seal_factor, track_most_spread
from .linkage import MorphingFootGeometry
from .mechanism import MorphingMechanism
from .springs import TwoStageSpring

__all__ = ["MorphingFoot"]


class MorphingFoot(MorphingMechanism, Foot):
    r"""The passive morphing foot (paper Sec. III-B, Fig. 6; supplementary Sec. III-C).

    Parameters
    ----------
    geometry : MorphingFootGeometry, optional
        Base, pad and linkage dimensions [m, rad]; default: the reconstruction of D30.
    spring : TwoStageSpring, optional
        Column springs; default: soft 800 N/m over 7.5 mm, hard 6000 N/m (D31).
    mode : {"morphing", "expanded", "retracted"}, keyword-only
        Free morphing (default), pads locked fully spread, or locked curled up.
    seal_length : float, keyword-only
        Rim lift :math:`g_s` over which curling pads break the cavity seal [m] (D35).
    curl_delay : float, keyword-only
        Time after the retraction begins during which the pads stay spread [s] (D35). The
        paper says the suction comes before the curl but gives no timing; 0, the default,
        lets them curl the moment the retraction begins.
    characteristic_length : float or None, keyword-only
        :math:`L_c` [m]; default the square root of the spread footprint (D36).
    **overrides
        Any field of :class:`MorphingFootGeometry` or :class:`TwoStageSpring` by name,
        e.g. ``pad_length=0.04`` [m] or ``hard_stiffness=12000.0`` [N/m].

    Raises
    ------
    MudrftError
        For an unknown override, a bad mode or length, a linkage that cannot be built, or
        a soft stage that does not bottom out within the stroke.

    References
    ----------
    .. [1] X. Chen, L. Wang, X. Huang, J. Shan, Y. Shen and J. Yi, "A Foot Resistive Force
       Model for Legged Locomotion on Muddy Terrains", 2026 (preprint with supplementary
       materials), Sec. III-B and supplementary Figs. S3-S4; mudrft decisions D30-D39
       (docs/model.md).

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
        curl_delay: float = 0.0,
        characteristic_length: float | None = None,
        **overrides: Any,
    ) -> None:
        super().__init__(geometry, spring, mode=mode, **overrides)
        self.seal_length = positive_number("seal_length", seal_length, unit="m")
        self.curl_delay = float(check_nonnegative("curl_delay", curl_delay, unit="s"))
        self.name = "morphing" if self.mode == "morphing" else f"morphing-{self.mode}"
        self._lc = (
            None
            if characteristic_length is None
            else check_length("characteristic_length", characteristic_length)
        )
        self._lc_spread: float | None = None

    # -- parameters --------------------------------------------------------------------------

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{A_{spread}}` [m], square root of the spread footprint (D36)."""
        if self._lc is not None:
            return self._lc
        if self._lc_spread is None:  # the terrain asks every step; the geometry is fixed
            self._lc_spread = math.sqrt(float(self.footprint_area(self.stroke)))
        return self._lc_spread

    @property
    def height(self) -> float:
        """Height of the foot above its tip [m]."""
        return self.geometry.height

    def replace(self, **changes: Any) -> MorphingFoot:
        """A copy with some parameters changed (geometry or spring fields, mode, ...)."""
        kw: dict[str, Any] = {
            "mode": self.mode,
            "seal_length": self.seal_length,
            "curl_delay": self.curl_delay,
            "characteristic_length": self._lc,
        }
        for k in tuple(kw):
            if k in changes:
                kw[k] = changes.pop(k)
        return MorphingFoot(self.geometry, self.spring, **kw, **changes)

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

    # -- the Foot interface ------------------------------------------------------------------
    def projected_areas(
        self, depth: ArrayLike, *, deflection: ArrayLike | None = None
    ) -> NDArray[np.float64]:
        """Submerged areas projected along x, y, z [m^2], shape (..., 3) (D38).

        Parameters
        ----------
        depth : float or array_like
            Tip depth [m].
        deflection : float or array_like or None, keyword-only
            Column deflection [m]; default the locked one, or the spread foot for the free
            morphing mode (the reference for the paper's normalised stresses).
        """
        g = self.geometry
        d = check_nonnegative("depth", depth, unit="m")
        if deflection is None:
            deflection = self._shown_deflection(None)
        d, th = np.broadcast_arrays(d, self.pad_angle(deflection))
        ax = pads.horizontal_area(g, d, th, np.zeros_like(d))
        ay = pads.horizontal_area(g, d, th, np.full_like(d, 0.5 * math.pi))
        return np.stack([ax, ay, pads.footprint_area(g, d, th)], axis=-1)

    def forces_at(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike, deflection: ArrayLike
    ) -> NDArray[np.float64]:
        """First-quadrant force magnitudes (Fx, Fy, Fz) [N] at a given deflection.

        Parameters
        ----------
        depth, stress, heading
            As in :meth:`resultant`: depth [m], stresses (..., 3) [Pa], heading [rad].
        deflection : float or array_like
            Column deflection [m], in [0, stroke].
        """
        d, s, h = _check_inputs(depth, stress, heading, height=self.height)
        return pads.magnitudes(self.geometry, d, s, h, self.pad_angle(deflection))

    def resultant(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> NDArray[np.float64]:
        """Magnitudes (Fx, Fy, Fz) [N] at the equilibrium deflection (loading from curled up).

        The deflection is the first equilibrium met when the column is loaded from rest
        (``previous=0``, D34); :meth:`contact_force` follows the deflection in time instead.
        See :meth:`Foot.resultant` for the arguments.
        """
        d, s, h = _check_inputs(depth, stress, heading, height=self.height)
        delta = self._deflection(d, s[..., 2], 0.0)
        return pads.magnitudes(self.geometry, d, s, h, self._linkage.angle(delta))

    def posed(self, rotation: RotationLike) -> NoReturn:
        """Not available for the morphing foot: raises :class:`~mudrft.MudrftError`.

        A rigid foot's ``posed`` is its rotated mesh; the morphing foot's pads open and curl
        with the load, so no one rigid mesh stands for it. Under a robot in
        MuJoCo the coupling poses it at every step (decision D60a).
        """
        raise MudrftError(
            "MorphingFoot.posed(rotation): the morphing foot has no rotated "
            "mesh, since its pads open and curl with the load; the flat, "
            "semi-cylindrical, semi-spherical and mesh feet have one. Under a robot in "
            "MuJoCo, mudrft.integrations.mujoco.attach poses the morphing foot at every "
            "step (docs/model.md D60a)"
        )

    def initial_foot_state(self) -> MorphingState:
        """Column unloaded, or locked (D37); the seal memory at the current pad angle."""
        lock = self.locked_deflection()
        delta = 0.0 if lock is None else lock
        th = float(self._linkage.angle(delta))
        return MorphingState(
            deflection=np.asarray(delta), pad_angle=np.asarray(th), most_spread=np.asarray(th)
        )

    def seal_factor(self, foot_state: MorphingState | None) -> FloatOrArray:
        r"""Seal factor :math:`1-\tanh(g/g_s)` [-], :math:`g=\ell(\sin\theta-\sin\theta_m)` (D35).

        :math:`g` [m] is how far the pad rims have lifted (curled) since their most spread
        position in the current contact; locked modes keep 1.

        Parameters
        ----------
        foot_state : MorphingState or None
            State from :meth:`contact_force`; None gives 1.0.
        """
        if foot_state is None:
            return 1.0
        return seal_factor(
            foot_state.pad_angle,
            foot_state.most_spread,
            pad_length=self.geometry.pad_length,
            seal_length=self.seal_length,
        )

    def contact_force(
        self,
        foot_state: MorphingState | None,
        depth: ArrayLike,
        stress: ArrayLike,
        heading: ArrayLike,
        dt: float,
        *,
        retraction: ArrayLike = 0.0,
    ) -> tuple[MorphingState, NDArray[np.float64]]:
        """Solve the column balance for this step and return ``(state, force)`` [N] (D32, D34).

        The deflection moves from the previous one (``foot_state.deflection``) to the
        balance with the current stresses, held for the first :attr:`curl_delay` seconds of
        a retraction (:func:`~.equilibrium.held_deflection`); out of the mud (depth 0) the
        column relaxes to 0 and the seal memory resets. Force in the world frame as in
        :meth:`Foot.force`.

        Parameters
        ----------
        foot_state : MorphingState or None
            State after the previous step; None starts from :meth:`initial_foot_state`.
        depth, stress, heading
            Tip depth [m] >= 0, signed stresses (..., 3) [Pa], world heading [rad]
            (checked by the caller, as in :meth:`Foot.force_unchecked`).
        dt : float
            Step [s]; unused, the balance is quasi-static.
        retraction : float or array_like, keyword-only
            Time since the retraction began, :math:`t-t_w` [s] (the mud's vertical suction
            clock; 0 while not retracting).
        """
        if foot_state is None:
            foot_state = self.initial_foot_state()
        d = np.asarray(depth, dtype=float)
        s = np.asarray(stress, dtype=float)
        delta = self._deflection(d, s[..., 2], foot_state.deflection)
        if self.curl_delay > 0.0 and self.mode == "morphing":
            delta = held_deflection(delta, foot_state.deflection, retraction, self.curl_delay)
        th = self._linkage.angle(delta)
        h = np.asarray(heading, dtype=float)
        f = pads.morphing_force(self.geometry, d, th, s[..., 0], s[..., 1], s[..., 2], h)
        force = np.stack(np.broadcast_arrays(*f), axis=-1)
        th_b = np.broadcast_to(th, d.shape) if np.ndim(th) < d.ndim else th
        most = track_most_spread(d, th_b, foot_state.most_spread)
        return MorphingState(
            deflection=np.asarray(delta), pad_angle=np.asarray(th_b), most_spread=most
        ), force

    def center_of_pressure(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> NDArray[np.float64]:
        """Center of the vertical pressure in the foot frame [m], shape (..., 3).

        On the axis by symmetry, at the height of the vertical-area-weighted centroid of the
        submerged base (z = 0) and pad parts, at the loading-branch deflection.
        """
        d, s, _ = _check_inputs(depth, stress, heading, height=self.height)
        th = self._linkage.angle(self._deflection(d, s[..., 2], 0.0))
        z = pads.center_height(self.geometry, d, th)
        return np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=-1)
