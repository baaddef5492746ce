r"""Granular resistive force theory (RFT): Li, Zhang & Goldman (Science 2013), in 3D.

Each submerged *leading* surface element of the foot carries Li et al.'s Fourier fit
(:func:`li2013_alpha`) times the medium's scale :math:`\zeta` [N/m^3] and its depth, in the
3D frame and with the weights of Treers, Cao & Stuart (RA-L 2021, :func:`treers_weights`);
trailing elements carry nothing. docs/model.md, section 8, gives the equations (D50-D53).
:class:`FacetRFT` is the terrain step of both granular RFTs (this one and 3D-RFT).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .._validation import (
    MudrftError,
    check_choice,
    check_finite,
    check_in_range,
    check_nonnegative,
    check_positive,
    warn_implausible,
    warn_plausibility,
)
from .._validation import set_number as _set
from ..citations import register
from ..feet.base import Foot, SurfaceElements
from ..units import parse_unit
from .base import TerrainOutput, check_motion, mean_stress, projected, tip_depth, tip_position
from .li2013 import (
    DEFAULT_ZETA,
    GRANULAR_MEDIA,
    LI2013_GENERIC,
    PLAUSIBLE_ZETA,
    FourierCoefficients,
    li2013_alpha,
)

__all__ = [
    "DEFAULT_ZETA", "GRANULAR_MEDIA", "LEADING_WIDTH", "LI2013_GENERIC", "PLAUSIBLE_ZETA",
    "FourierCoefficients", "GranularRFT", "RFTState", "horizontal_share", "leading_weight",
    "li2013_alpha", "rft_forces", "treers_weights"
]  # fmt: skip


# Treers et al. (2021) sigmoid fits of the 3D weights (D51): f1 (tanh), f23 (atanh)
_TREERS_F1 = (3.62263982880971, 1.60910808139526)
_TREERS_F23 = (1.61146827229181, 0.973746396532650)
_HORIZONTAL_TOL = 1e-3  # Treers et al.'s tolerance on |n_z| (horizontal_share)


def treers_weights(v1: ArrayLike, v23: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    r"""Treers et al.'s (2021) sigmoid weights :math:`f_1` (tanh) and :math:`f_{23}` (atanh)
    [-] of the unit velocity's components along the plate's horizontal edge (:math:`v_1`) and
    in its normal plane (:math:`v_{23}`), normalised to 0 at 0 and 1 at 1 (D51).

    Examples
    --------
    >>> f1, f23 = treers_weights([0.0, 1.0], [0.0, 1.0])
    >>> f1.round(12).tolist(), f23.round(12).tolist()
    ([0.0, 1.0], [0.0, 1.0])
    """
    u1 = np.clip(np.abs(check_finite("v1", v1)), 0.0, 1.0)
    u23 = np.clip(np.abs(check_finite("v23", v23)), 0.0, 1.0)
    a, b = _TREERS_F1
    c, d = _TREERS_F23
    f1 = (np.tanh(a * u1 - b) + np.tanh(b)) / (np.tanh(a - b) + np.tanh(b))
    f23 = (np.arctanh(c * u23 - d) + np.arctanh(d)) / (np.arctanh(c - d) + np.arctanh(d))
    return f1, f23


def _unit_horizontal(vec: np.ndarray, fallback: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal direction of ``vec`` (..., 3) and whether it was defined."""
    h = vec.copy()
    h[..., 2] = 0.0
    norm = np.linalg.norm(h, axis=-1, keepdims=True)
    ok = norm[..., 0] > 1e-9
    return np.where(ok[..., None], h / np.where(norm > 0, norm, 1.0), fallback), ok


#: Default width of the leading-facet ramp in :math:`\hat n\cdot\hat v` [-] (decision D53).
LEADING_WIDTH = 1e-3


def leading_weight(n_dot_v: ArrayLike, width: float = LEADING_WIDTH) -> np.ndarray:
    r"""Weight [-] of a facet by how much it leads the motion (D53),
    :math:`w=\min(\max(\hat n\cdot\hat v/\delta,0),1)`, continuous in the pose; ``width=0``
    gives RFT's sharp rule.

    Examples
    --------
    >>> leading_weight([-0.1, 0.0, 5e-4, 0.2]).tolist()
    [0.0, 0.0, 0.5, 1.0]
    >>> leading_weight([1e-12, 0.0], width=0.0).tolist()
    [1.0, 0.0]
    """
    d = np.asarray(n_dot_v, dtype=float)
    if width <= 0.0:
        return (d > 0.0).astype(float)
    return np.clip(d / width, 0.0, 1.0)


def horizontal_share(nz: ArrayLike, tol: float = _HORIZONTAL_TOL) -> np.ndarray:
    r"""How much a facet counts as horizontal in the 3D extension (D51) [-]: 1 from Treers et
    al.'s :math:`|n_z|\ge1-\delta`, :math:`\delta=10^{-3}`, down linearly to 0 at
    :math:`1-2\delta`; the force mixes the two frames' forces alike.

    Examples
    --------
    >>> [round(float(horizontal_share(z)), 9) for z in (1.0, 0.999, 0.9985, 0.998, 0.5)]
    [1.0, 1.0, 0.5, 0.0, 0.0]
    """
    a = np.abs(nz)
    ramp = np.clip((a - (1.0 - 2.0 * tol)) / tol, 0.0, 1.0)
    return np.where(a >= 1.0 - tol, 1.0, ramp)  # exactly Treers et al.'s rule from 1 - tol


def _frame_forces(
    nb: np.ndarray, vd: np.ndarray, e2: np.ndarray, axial: np.ndarray,
    coefficients: FourierCoefficients, extension: str,
) -> np.ndarray:  # fmt: skip
    """Force per unit depth, area and zeta of facets ``nb`` moving along ``vd`` in the frame of
    the horizontal direction ``e2`` (D51), before the leading weight [-]."""
    z_hat = np.array([0.0, 0.0, 1.0])
    e1 = np.stack([e2[..., 1], -e2[..., 0], np.zeros(e2.shape[:-1])], axis=-1)  # e2 x z
    v1c = (vd * e1).sum(-1)
    v23 = vd - v1c[..., None] * e1
    s = (v23 * e2).sum(-1)
    e2m = np.where((s < 0)[..., None], -e2, e2)  # mirror so the velocity points along +e2
    n_along = np.where(axial, 0.0, (nb * e2m).sum(-1))
    beta, gamma = np.arctan2(nb[..., 2], n_along) + np.pi / 2, -np.arctan2(v23[..., 2], np.abs(s))
    ax, az = coefficients.alpha(beta, gamma)
    if extension == "planar":
        return -ax[..., None] * e2m + az[..., None] * z_hat  # type: ignore[no-any-return]
    ay = coefficients.alpha(0.0, 0.0)[0]
    f1, f23 = treers_weights(v1c, np.linalg.norm(v23, axis=-1))
    return (  # type: ignore[no-any-return]
        -(f1 * ay * np.sign(v1c))[..., None] * e1
        - (f23 * ax)[..., None] * e2m
        + (f23 * az)[..., None] * z_hat
    )


def _unit_forces(
    normals: np.ndarray, direction: np.ndarray, coefficients: FourierCoefficients, extension: str,
    leading_width: float = LEADING_WIDTH,
) -> np.ndarray:  # fmt: skip
    """Leading-weighted force per unit depth, area and zeta (..., k, 3) [-] of unit
    ``normals`` (k, 3) moving along the unit ``direction`` (..., 3)."""
    vb = np.broadcast_to(direction[..., None, :], direction.shape[:-1] + normals.shape)
    nb = np.broadcast_to(normals, vb.shape)
    x_hat = np.array([1.0, 0.0, 0.0])
    vh_dir, vh_ok = _unit_horizontal(vb, x_hat)
    nh_dir, nh_ok = _unit_horizontal(nb, x_hat)
    axial = ~(vh_ok | nh_ok)  # purely vertical: the force must not depend on the yaw (D53)
    vd = np.where(axial[..., None], vb * np.array([0.0, 0.0, 1.0]), vb)
    # the frame of the motion (planar; treers2021: on nearly horizontal facets) or the normal
    share = np.where(vh_ok, 1.0 if extension == "planar" else horizontal_share(nb[..., 2]), 0.0)
    e2 = np.where((share >= 1.0)[..., None], vh_dir, nh_dir)
    f = _frame_forces(nb, vd, e2, axial, coefficients, extension)
    band = (share > 0.0) & (share < 1.0)  # both frames, mixed (few facets)
    if np.any(band):
        fh = _frame_forces(nb[band], vd[band], vh_dir[band], axial[band], coefficients, extension)
        h = share[band][:, None]
        f[band] = (1.0 - h) * f[band] + h * fh
    w = leading_weight((nb * vb).sum(-1), leading_width)
    return w[..., None] * f


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def unit_vectors(name: str, value: ArrayLike) -> np.ndarray:
    """``value`` (..., 3), finite and nonzero, scaled to unit length [-]."""
    v = check_finite(name, value)
    if v.shape[-1:] != (3,):
        raise MudrftError(f"{name} must have shape (..., 3), got shape {v.shape}")
    norm = np.linalg.norm(v, axis=-1, keepdims=True)
    if not np.all(norm > 0):
        i = int(np.argmin(norm.ravel()))
        raise MudrftError(f"{name} must be nonzero vectors, got {name}[{i}] = 0")
    return v / norm  # type: ignore[no-any-return]


def check_facets(
    normals: ArrayLike, depths: ArrayLike, areas: ArrayLike, direction: ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Unit normals (m, 3), depths (..., m) [m], areas (m,) [m^2], unit direction (..., 3)."""
    n = unit_vectors("normals", normals)
    a = check_nonnegative("areas", areas, unit="m^2")
    d = check_finite("depths", depths)
    v = unit_vectors("direction", direction)
    if n.ndim != 2 or a.shape != n.shape[:1] or d.shape[-1:] != n.shape[:1]:
        raise MudrftError(
            "normals (m, 3), areas (m,) and depths (..., m) must agree, "
            f"got shapes {n.shape}, {a.shape}, {d.shape}"
        )
    return n, d, a, v


def _element_forces(
    scale: float, depths: np.ndarray, areas: np.ndarray, unit: np.ndarray, *, per_element: bool,
) -> np.ndarray:  # fmt: skip
    r"""Forces [N] :math:`k\,\max(z_i,0)\,A_i\,\boldsymbol\alpha_i` of elements at depths (..., m)
    [m], areas (m,) [m^2], responses ``unit`` (..., m, 3) [-], scale ``k`` [N/m^3]; summed
    unless ``per_element``."""
    forces = (scale * np.maximum(depths, 0.0) * areas)[..., None] * unit
    return forces if per_element else forces.sum(axis=-2)


class _Prepared(NamedTuple):
    r"""Surface elements grouped by normal and sorted by height: group :math:`k` weighs
    :math:`W_k(D)=\sum_{i\in k,\,h_i<D}A_i(D-h_i)` at tip depth :math:`D` (prefix sums)."""

    normals: np.ndarray  # (k, 3) distinct unit normals
    keys: np.ndarray  # (m,) group + normalised height, sorted
    cum_a: np.ndarray  # (m + 1,) prefix sums of areas [m^2]
    cum_ah: np.ndarray  # (m + 1,) prefix sums of area x height [m^3]
    start: np.ndarray  # (k,) first sorted index of each group
    h0: float  # lowest centroid height [m]
    span: float  # normalisation of heights [m]


def _prepare(el: SurfaceElements) -> _Prepared:
    n = _unit(np.asarray(el.normals, dtype=float))
    h = np.asarray(el.centroids, dtype=float)[:, 2]
    a = np.asarray(el.areas, dtype=float)
    uniq, inverse = np.unique(np.round(n, 9), axis=0, return_inverse=True)
    inverse = np.asarray(inverse).ravel()
    h0 = float(h.min())
    span = float(h.max() - h0) + 1.0
    keys = inverse + (h - h0) / span
    order = np.argsort(keys, kind="stable")
    keys, a_s, h_s = keys[order], a[order], h[order]
    cum_a = np.concatenate([[0.0], np.cumsum(a_s)])
    cum_ah = np.concatenate([[0.0], np.cumsum(a_s * h_s)])
    start = np.searchsorted(keys, np.arange(uniq.shape[0], dtype=float), side="left")
    return _Prepared(_unit(uniq), keys, cum_a, cum_ah, start, h0, span)


def _group_weights(pr: _Prepared, depth: np.ndarray) -> np.ndarray:
    """Depth weights W_k (..., k) [m^3] for signed tip depths ``depth`` (...) [m]."""
    k = pr.normals.shape[0]
    frac = np.clip((depth[..., None] - pr.h0) / pr.span, 0.0, 1.0 - 1e-12)
    query = np.arange(k) + frac  # (..., k)
    j = np.searchsorted(pr.keys, query.ravel(), side="left").reshape(query.shape)
    area, moment = pr.cum_a[j] - pr.cum_a[pr.start], pr.cum_ah[j] - pr.cum_ah[pr.start]
    return np.maximum(depth[..., None] * area - moment, 0.0)


class RFTState(NamedTuple):
    """The last unit ``direction`` of motion (..., 3), kept at rest (D52), and the foot's
    surface ``elements``."""

    direction: np.ndarray
    elements: SurfaceElements
    prepared: _Prepared | None = None
    #: (direction, responses (..., k, 3), which groups they hold (k,)) of the last step
    cache: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None


class FacetRFT:
    """The terrain step of the granular RFTs; subclasses provide ``rest_speed`` [m/s],
    ``scale`` [N/m^3] and ``_unit_forces(normals, direction)`` (..., k, 3) [-]."""

    rest_speed: float
    leading_width: float
    coefficients: object

    def _check_options(self, coefficients: type) -> None:
        _set(self, "rest_speed", check_positive("rest_speed", self.rest_speed, unit="m/s"))
        width = check_in_range("leading_width", self.leading_width, 0.0, 1.0)
        _set(self, "leading_width", width)
        if not isinstance(self.coefficients, coefficients):
            raise MudrftError(
                f"coefficients must be a {coefficients.__name__}, "
                f"got {type(self.coefficients).__name__}"
            )

    @property
    def scale(self) -> float:
        """Scale of the medium [N/m^3]."""
        raise NotImplementedError

    def _unit_forces(self, normals: np.ndarray, direction: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def initial_state(self, foot: Foot, position: ArrayLike) -> RFTState:
        """Undisturbed medium under a foot whose tip is at ``position`` (..., 3) [m]."""
        pos, el = tip_position(position), foot.elements()
        direction = np.broadcast_to(np.array([0.0, 0.0, -1.0]), pos.shape).copy()
        return RFTState(direction=direction, elements=el, prepared=_prepare(el))

    def step(
        self, foot: Foot, state: RFTState, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[RFTState, TerrainOutput]:
        """Force on the foot with its tip at ``position`` [m] moving at ``velocity`` [m/s];
        ``dt`` [s] is checked but not used (RFT is rate-independent)."""
        pos, vel, _ = check_motion(position, velocity, dt)
        speed = np.linalg.norm(vel, axis=-1, keepdims=True)
        moving = speed > self.rest_speed
        direction = np.where(moving, vel / np.where(moving, speed, 1.0), state.direction)
        pr = state.prepared if state.prepared is not None else _prepare(state.elements)
        w = _group_weights(pr, -pos[..., 2])  # (..., k) [m^3]
        unit, known = self._responses(pr, direction, w > 0.0, state.cache)
        force = self.scale * np.einsum("...k,...kc->...c", w, unit)
        depth = tip_depth(pos)
        stress = mean_stress(force, projected(foot, depth))
        new = RFTState(direction, state.elements, pr, cache=(direction, unit, known))
        return new, TerrainOutput(force=force, stress=stress, depth=depth)

    def _responses(
        self, pr: _Prepared, direction: np.ndarray, submerged: np.ndarray,
        cache: tuple[np.ndarray, np.ndarray, np.ndarray] | None,
    ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """Responses (..., k, 3) of the groups ``submerged`` anywhere in the batch and which
        groups hold one (k,), reusing ``cache`` of the same ``direction``."""
        need = np.any(submerged, axis=tuple(range(submerged.ndim - 1)))
        if cache is not None and np.array_equal(cache[0], direction):  # False for another shape
            unit, known = cache[1], cache[2]
        else:
            unit = np.zeros((*direction.shape[:-1], need.size, 3))
            known = np.zeros(need.size, dtype=bool)
        todo = need & ~known
        if np.any(todo):
            unit = unit.copy()  # the previous state keeps its own
            unit[..., todo, :] = self._unit_forces(pr.normals[todo], direction)
            known = known | todo
        return unit, known


def rft_forces(
    normals: ArrayLike, depths: ArrayLike, areas: ArrayLike, direction: ArrayLike, *,
    zeta: float = DEFAULT_ZETA, coefficients: FourierCoefficients = LI2013_GENERIC,
    extension: str = "treers2021", per_element: bool = False, leading_width: float = LEADING_WIDTH,
) -> np.ndarray:  # fmt: skip
    r"""Granular RFT force [N] of the medium on surface elements moving in one direction, world
    frame: shape (..., 3), or (..., m, 3) with ``per_element``.

    Parameters
    ----------
    normals : array_like, shape (m, 3)
        Outward normals of the elements [-].
    depths : array_like, shape (..., m)
        Depth of each element's centroid below the surface [m] (<= 0: out of the medium).
    areas : array_like, shape (m,)
        Element areas [m^2].
    direction : array_like, shape (..., 3)
        Direction of motion [-].
    zeta : float, keyword-only
        Scale of the medium [N/m^3].
    coefficients : FourierCoefficients, keyword-only
        2D fit of :math:`\alpha_{x,z}`.
    extension : {"treers2021", "planar"}, keyword-only
        3D extension: Treers et al. (2021), or 2D RFT in the velocity's vertical plane (D51).
    per_element : bool, keyword-only
        Return the force of every element (..., m, 3) instead of the sum.
    leading_width : float, keyword-only
        Width of the leading-facet ramp [-] (:func:`leading_weight`, D53).

    Examples
    --------
    >>> f = rft_forces([[0, 0, -1]], [0.02], [1e-4], [0, 0, -1], zeta=0.254e6)
    >>> [round(float(v), 6) + 0.0 for v in f]
    [0.0, 0.0, 0.508]
    """
    check_choice("extension", extension, ("treers2021", "planar"))
    n, d, a, v = check_facets(normals, depths, areas, direction)
    f = _unit_forces(n, v, coefficients, extension, leading_width)
    return _element_forces(zeta, d, a, f, per_element=per_element)


@dataclass(frozen=True, eq=False)
class GranularRFT(FacetRFT):
    r"""Granular RFT (Li et al. 2013) as a terrain: :func:`rft_forces` on the foot.

    Parameters
    ----------
    zeta : float
        Scale of the medium [N/m^3], the vertical stress per depth of a horizontal plate;
        default loosely packed poppy seeds, 0.254 N/cm^3 (D50); below 1e3 N/m^3 warns.
    coefficients : FourierCoefficients
        2D fit normalised to :math:`\alpha_z(0,\pi/2)=1` (default Li et al.'s generic one);
        a medium's own fit in N/cm^3 goes through :meth:`from_coefficients`.
    extension : {"treers2021", "planar"}
        3D extension (decision D51).
    rest_speed, leading_width : float
        Below ``rest_speed`` [m/s] the last direction is kept (D52); width of the
        leading-facet ramp [-] (:func:`leading_weight`, D53), 0 the sharp rule.
    name : str
        Label in reports.

    References
    ----------
    .. [1] C. Li, T. Zhang and D. I. Goldman, "A Terradynamics of Legged Locomotion on
       Granular Media", Science 339(6126):1408-1412, 2013, doi:10.1126/science.1229163.
    .. [2] L. K. Treers, C. Cao and H. S. Stuart, "Granular Resistive Force Theory
       Implementation for Three-Dimensional Trajectories", IEEE Robotics and Automation
       Letters 6(2):1887-1894, 2021, doi:10.1109/LRA.2021.3057052.
    .. [3] X. Chen, L. Wang, X. Huang, J. Shan, Y. Shen and J. Yi, "A Foot Resistive Force
       Model for Legged Locomotion on Muddy Terrains", 2026 (preprint with supplementary
       materials), supplementary Fig. S6 (the comparison with sand).

    Examples
    --------
    >>> rft = GranularRFT()
    >>> rft.zeta
    254000.0
    >>> GranularRFT(zeta=0.464e6).zeta     # closely packed poppy seeds, 0.464 N/cm^3
    464000.0
    """

    zeta: float = DEFAULT_ZETA
    coefficients: FourierCoefficients = LI2013_GENERIC
    extension: str = "treers2021"
    rest_speed: float = 1e-6
    leading_width: float = LEADING_WIDTH
    name: str = "granular-rft"

    def __post_init__(self) -> None:
        _set(self, "zeta", check_positive("zeta", self.zeta, unit="N/m^3"))
        self._check_options(FourierCoefficients)
        check_choice("extension", self.extension, ("treers2021", "planar"))
        hint = "zeta is in N/m^3; RFT papers print N/cm^3 (0.254 N/cm^3 = 2.54e5 N/m^3)"
        warn_implausible("GranularRFT: zeta is", self.zeta, PLAUSIBLE_ZETA, unit="N/m^3", hint=hint)
        plate = self.coefficients.plate
        if not abs(plate - 1.0) <= 0.01:
            warn_plausibility(
                "GranularRFT: coefficients are not normalised (alpha_z(0, pi/2) = "
                f"{plate:.4g}, expected 1) and the force is zeta = {self.zeta:.4g} N/m^3 "
                "times them; for a medium's own Fourier fit in N/cm^3 use "
                "GranularRFT.from_coefficients(coefficients, unit='N/cm^3')"
            )
        register("li2013terradynamics")
        if self.extension == "treers2021":
            register("treers2021granular")

    @classmethod
    def medium(cls, name: str, **kw: Any) -> GranularRFT:
        """RFT for a named medium of :data:`GRANULAR_MEDIA` (``"poppy-lp"``, ``"poppy-cp"``)."""
        check_choice("name", name, tuple(GRANULAR_MEDIA))
        return cls(zeta=GRANULAR_MEDIA[name], **kw)

    @classmethod
    def from_coefficients(
        cls, coefficients: FourierCoefficients, *, unit: str = "N/cm^3", **kw: Any
    ) -> GranularRFT:
        r"""RFT for a medium's own Fourier fit (as Li et al. 2013 tabulate it), kept exactly as
        :math:`\zeta\,\alpha^{norm}` with :math:`\zeta=\alpha_z(0,\pi/2)`.

        Parameters
        ----------
        coefficients : FourierCoefficients
            The medium's fit, in ``unit``; its :math:`\alpha_z(0,\pi/2)` must be > 0.
        unit : {"N/cm^3", "N/m^3", "kN/m^3"}, keyword-only
            Unit of the coefficients (default N/cm^3, as printed).
        **kw
            Other options of :class:`GranularRFT` (``extension``, ``name``, ...).

        Examples
        --------
        >>> lp = FourierCoefficients(A00=0.051, A10=0.047, B01=0.083, B11=0.053, Bm11=0.020,
        ...                          C01=0.057, C11=-0.026, Cm11=0.0, D10=0.025)
        >>> rft = GranularRFT.from_coefficients(lp, unit="N/cm^3")
        >>> round(rft.zeta)                       # [N/m^3]
        254000
        >>> ax, az = rft.alpha(np.pi / 2, 0.0)    # a vertical wall dragged face-on [N/m^3]
        >>> round(float(ax)), round(float(az))
        (83000, 4000)
        """
        if not isinstance(coefficients, FourierCoefficients):
            raise MudrftError(
                f"coefficients must be a FourierCoefficients, got {type(coefficients).__name__}"
            )
        for field in ("zeta", "coefficients"):
            if field in kw:
                raise MudrftError(
                    f"from_coefficients takes its scale from the coefficients, got {field}="
                )
        factor = parse_unit("stress per depth", unit)
        values = {k: check_finite(k, v) for k, v in vars(coefficients).items()}
        plate = coefficients.plate
        if not plate > 0.0:
            raise MudrftError(
                "coefficients must support a horizontal plate pushed down, alpha_z(0, pi/2) "
                f"= A00 + A10 + B01 + B11 + Bm11 > 0, got {plate:.4g} {unit}"
            )
        normalised = FourierCoefficients(**{k: float(v) / plate for k, v in values.items()})
        return cls(zeta=plate * factor, coefficients=normalised, **kw)

    def alpha(self, beta: ArrayLike, gamma: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        r"""This medium's stress per unit depth :math:`(\alpha_x,\alpha_z)=\zeta\,\alpha^{fit}`
        [N/m^3] at attack angle ``beta`` and intrusion angle ``gamma`` [rad]
        (:func:`li2013_alpha` for the conventions)."""
        ax, az = li2013_alpha(beta, gamma, coefficients=self.coefficients)
        return self.zeta * ax, self.zeta * az

    @property
    def scale(self) -> float:
        r"""Scale of the medium :math:`\zeta` [N/m^3]."""
        return float(self.zeta)

    def _unit_forces(self, normals: np.ndarray, direction: np.ndarray) -> np.ndarray:
        return _unit_forces(
            normals, direction, self.coefficients, self.extension, self.leading_width
        )
