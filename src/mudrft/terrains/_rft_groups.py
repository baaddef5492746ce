r"""The terrain step of the granular RFTs: surface elements grouped by normal.

Granular RFT's force on a foot is a sum over groups of elements that share a normal, each
weighted by :math:`W_k(D)=\sum_{i\in k,\,h_i<D}A_i(D-h_i)`; prefix sums over the elements
sorted by height make that weight a binary search, exactly (no approximation). A step
evaluates the response of the groups with :math:`W_k>0` only, the submerged ones, and
reuses them while the direction of motion repeats (:class:`FacetRFT`).
:func:`_element_forces` is the same integrand element by element, for the public
``rft_forces`` and ``rft3d_forces``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .._validation import MudrftError
from ..feet.base import Foot, SurfaceElements
from ._common import mean_stress, projected, tip_depth, tip_position
from .base import TerrainOutput, check_motion

__all__ = ["FacetRFT", "RFTState"]  # users import them from mudrft.terrains.granular_rft


def _unit(v: np.ndarray) -> np.ndarray:
    """Rows of ``v`` (..., 3) scaled to unit length [-]."""
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def _check_elements(normals: np.ndarray, areas: np.ndarray, depths: np.ndarray) -> None:
    """Refuse element arrays whose shapes disagree: normals (m, 3), areas (m,), depths (..., m)."""
    m = normals.shape[:1]  # (m,) for a (m, 3) array
    if normals.ndim != 2 or normals.shape[1] != 3 or areas.shape != m or depths.shape[-1:] != m:
        raise MudrftError(
            "normals (m, 3), areas (m,) and depths (..., m) must agree, "
            f"got shapes {normals.shape}, {areas.shape}, {depths.shape}"
        )


def _element_forces(
    scale: float,
    depths: np.ndarray,
    areas: np.ndarray,
    unit: np.ndarray,
    *,
    per_element: bool,
) -> np.ndarray:
    r"""RFT forces of surface elements, :math:`d\mathbf F_i=k\,\max(z_i,0)\,A_i\,\boldsymbol\alpha_i`.

    Parameters
    ----------
    scale : float
        Scale :math:`k` of the medium [N/m^3] (:math:`\zeta` of 2D RFT, :math:`\xi_n` of
        3D-RFT).
    depths : ndarray, shape (..., m)
        Depth :math:`z_i` of each element's centroid below the surface [m]; elements at
        depth <= 0 are out of the medium and carry no force.
    areas : ndarray, shape (m,)
        Element areas :math:`A_i` [m^2].
    unit : ndarray, shape (..., m, 3)
        Dimensionless response :math:`\boldsymbol\alpha_i` of each element to the
        direction of motion [-] (leading weight included).
    per_element : bool, keyword-only
        Return every element's force (..., m, 3) instead of the sum (..., 3).

    Returns
    -------
    ndarray, shape (..., 3) or (..., m, 3)
        Force of the medium on the elements [N].
    """
    forces = (scale * np.maximum(depths, 0.0) * areas)[..., None] * unit
    return forces if per_element else forces.sum(axis=-2)


class _Prepared(NamedTuple):
    r"""Surface elements grouped by normal and sorted by height, for fast integration.

    The depth weight of group k, :math:`W_k(D)=\sum_{i\in k,\,h_i<D}A_i(D-h_i)` for a tip
    depth :math:`D`, comes from prefix sums in O(log m): direction-independent.
    """

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
    area = pr.cum_a[j] - pr.cum_a[pr.start]
    moment = pr.cum_ah[j] - pr.cum_ah[pr.start]
    return np.maximum(depth[..., None] * area - moment, 0.0)


class RFTState(NamedTuple):
    """State of granular RFT under a foot.

    Attributes
    ----------
    direction : ndarray (..., 3)
        Last unit direction of motion, kept while the foot is at rest (decision D52).
    elements : SurfaceElements
        The foot's surface elements (foot frame, tip at the origin).
    """

    direction: np.ndarray
    elements: SurfaceElements
    prepared: _Prepared | None = None
    #: (direction, responses (..., k, 3), which groups they hold (k,)) of the last step
    cache: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None


class FacetRFT:
    """The terrain step shared by the granular RFTs: per-facet unit responses weighted by depth.

    Subclasses provide ``rest_speed`` [m/s], ``scale`` [N/m^3] and
    ``_unit_forces(normals, direction)`` (the dimensionless response of each facet group to a
    unit direction of motion). A step evaluates it for the submerged groups only (most of
    a foot's groups are out of the medium at a gait's depths) and keeps it while the
    direction repeats (a foot at rest or pushed straight down).
    """

    rest_speed: float

    @property
    def scale(self) -> float:
        """Scale of the medium [N/m^3]."""
        raise NotImplementedError

    def _unit_forces(self, normals: np.ndarray, direction: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def initial_state(self, foot: Foot, position: ArrayLike) -> RFTState:
        """Undisturbed medium under a foot whose tip is at ``position`` (..., 3) [m]."""
        pos = tip_position(position)
        el = foot.elements()
        direction = np.broadcast_to(np.array([0.0, 0.0, -1.0]), pos.shape).copy()
        return RFTState(direction=direction, elements=el, prepared=_prepare(el))

    def step(
        self, foot: Foot, state: RFTState, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[RFTState, TerrainOutput]:
        """Force on the foot with its tip at ``position`` [m] moving at ``velocity`` [m/s].

        ``dt`` [s] is not used (RFT is rate-independent) but checked for the interface
        (:func:`~mudrft.terrains.base.check_motion`).
        """
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
        new = RFTState(
            direction=direction,
            elements=state.elements,
            prepared=pr,
            cache=(direction, unit, known),
        )
        return new, TerrainOutput(force=force, stress=stress, depth=depth)

    def _responses(
        self,
        pr: _Prepared,
        direction: np.ndarray,
        submerged: np.ndarray,
        cache: tuple[np.ndarray, np.ndarray, np.ndarray] | None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Unit responses (..., k, 3) of the groups submerged anywhere in the batch
        (``submerged`` (..., k)), zeros for the others (their weight is 0), and which groups
        hold one (k,); those of ``cache`` are reused if its direction is ``direction``."""
        need = np.any(submerged, axis=tuple(range(submerged.ndim - 1)))
        if (
            cache is not None
            and cache[0].shape == direction.shape
            and np.array_equal(cache[0], direction)
        ):
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
