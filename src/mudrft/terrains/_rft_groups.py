r"""Surface elements grouped by normal, for granular RFT's depth weights in O(log m).

Granular RFT's force on a foot is a sum over groups of elements that share a normal, each
weighted by :math:`W_k(D)=\sum_{i\in k,\,h_i<D}A_i(D-h_i)`; prefix sums over the elements
sorted by height make that weight a binary search, exactly (no approximation).
:func:`_element_forces` is the same integrand element by element, for the public
``rft_forces`` and ``rft3d_forces``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._validation import MudrftError
from ..feet.base import SurfaceElements

__all__: list[str] = []  # private to the granular RFTs (granular_rft, granular_rft3d)


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
