r"""What the granular RFTs share: facet checks, the element integrand, the terrain step.

The step groups a foot's elements by normal: group :math:`k` weighs
:math:`W_k(D)=\sum_{i\in k,\,h_i<D}A_i(D-h_i)` at tip depth :math:`D` (prefix sums).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .._validation import (
    MudrftError,
    check_finite,
    check_in_range,
    check_nonnegative,
    check_positive,
    set_number,
)
from ..feet.base import Foot, SurfaceElements
from .base import TerrainOutput, check_motion, mean_stress, projected, tip_depth, tip_position

__all__ = ["FacetRFT", "RFTState", "check_facets", "unit_vectors"]


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
    """Surface elements grouped by normal and sorted by height (module docstring)."""

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
        set_number(self, "rest_speed", check_positive("rest_speed", self.rest_speed, unit="m/s"))
        width = check_in_range("leading_width", self.leading_width, 0.0, 1.0)
        set_number(self, "leading_width", width)
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
