r"""Surface elements grouped by normal, for granular RFT's depth weights in O(log m).

Granular RFT's force on a foot is a sum over groups of elements that share a normal, each
weighted by :math:`W_k(D)=\sum_{i\in k,\,h_i<D}A_i(D-h_i)`; prefix sums over the elements
sorted by height make that weight a binary search, exactly (no approximation).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..feet.base import SurfaceElements

__all__: list[str] = []  # private to granular_rft


def _unit(v: np.ndarray) -> np.ndarray:
    """Rows of ``v`` (..., 3) scaled to unit length [-]."""
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


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
