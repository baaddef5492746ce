r"""Separate parts of a closed mesh that overlap: a sole and its cleats exported unmerged.

Facets where parts overlap or touch count as if mud touched them, so the forces come out
too large: :class:`~mudrft.feet.MeshFoot` warns (decision D136).

A point is inside or on a closed part when its generalized winding number,
:math:`w(p)=\frac1{4\pi}\sum_t\Omega_t(p)`, is above 1/4 (1 inside, 1/2 on a face, 0
outside). Each facet's solid angle is that of Van Oosterom and Strackee (1983),
:math:`\tan\frac{\Omega}{2}=\frac{\mathbf a\cdot(\mathbf b\times\mathbf c)}
{abc+(\mathbf a\cdot\mathbf b)c+(\mathbf b\cdot\mathbf c)a+(\mathbf c\cdot\mathbf a)b}`
with :math:`\mathbf a,\mathbf b,\mathbf c` the facet's corners from :math:`p` ("The solid
angle of a plane triangle", IEEE Trans. Biomed. Eng. BME-30(2), 125-126, 1983).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._typing import FloatArray, IntArray

__all__ = ["PartOverlap", "overlapping_parts", "winding_numbers"]

#: Most points a part is tested with against another, and how many at a time.
MAX_POINTS = 64
BATCH_POINTS = 8
#: Most parts checked pairwise (more is a scan or a lattice, left unchecked).
MAX_PARTS = 64
#: Point-facet pairs evaluated at once (memory: about 200 bytes each).
CHUNK_PAIRS = 200_000


class PartOverlap(NamedTuple):
    """Two parts of a mesh, one with a vertex inside or on the other: the number of
    ``parts``, the ``inner`` and ``outer`` parts (numbered from 1 by first facet) and that
    vertex, ``point`` (3,) [m]."""

    parts: int
    inner: int
    outer: int
    point: FloatArray


def winding_numbers(points: FloatArray, triangles: FloatArray) -> FloatArray:
    """Generalized winding number [-] of each of ``points`` (p, 3) [m] with respect to a
    closed surface of ``triangles`` (t, 3, 3) [m], wound outward: 1 inside, 0 outside, 1/2 on
    a face (up to round-off), -1 inside a surface wound inward; a facet whose plane holds the
    point counts 0."""
    out = np.empty(len(points))
    step = max(1, CHUNK_PAIRS // max(len(triangles), 1))
    for s in range(0, len(points), step):
        d = triangles[None, :, :, :] - points[s : s + step, None, None, :]
        a, b, c = d[..., 0, :], d[..., 1, :], d[..., 2, :]
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        num = np.einsum("...i,...i->...", a, np.cross(b, c))
        den = (
            la * lb * lc
            + np.einsum("...i,...i->...", a, b) * lc
            + np.einsum("...i,...i->...", b, c) * la
            + np.einsum("...i,...i->...", c, a) * lb
        )
        # a point in a facet's plane sees it at 0 (arctan2 could give +-pi: a rounded zero)
        flat = np.abs(num) <= 1e-12 * la * lb * lc
        angle = np.where(flat, 0.0, np.arctan2(num, den))
        out[s : s + step] = angle.sum(axis=1) / (2.0 * np.pi)
    return out


def overlapping_parts(
    vertices: FloatArray, faces: IntArray, *, weld: IntArray | None = None
) -> PartOverlap | None:
    """The first pair of separate parts of a closed mesh that overlap or touch, if any.

    ``vertices`` (n, 3) [m], vertices at the same coordinates being one; ``faces`` (m, 3),
    each closed part wound outward; ``weld`` (n,), each vertex's index among the distinct
    coordinates, if known. None for a mesh of one part, of parts apart, or of more than
    :data:`MAX_PARTS` parts (not checked).
    """
    from scipy.sparse import coo_matrix  # heavy (0.5 s): imported for a closed mesh only
    from scipy.sparse.csgraph import connected_components

    if weld is None:
        weld = np.unique(vertices, axis=0, return_inverse=True)[1].reshape(-1)
    f = weld[faces]
    n = int(f.max()) + 1
    rows = np.concatenate([f[:, 0], f[:, 1], f[:, 2]])
    cols = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    graph = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n))
    count, label = connected_components(graph, directed=False)
    if count < 2 or count > MAX_PARTS:
        return None
    part_of_face = label[f[:, 0]]
    # the parts in the order of their first facet, as a user reading the file numbers them
    first = np.sort(np.unique(part_of_face, return_index=True)[1])
    tris = [vertices[faces[part_of_face == part_of_face[i]]] for i in first]
    boxes = [(t.reshape(-1, 3).min(axis=0), t.reshape(-1, 3).max(axis=0)) for t in tris]
    for inner, inner_tris in enumerate(tris):
        pts = np.unique(inner_tris.reshape(-1, 3), axis=0)
        for outer, (low, high) in enumerate(boxes):
            if outer == inner:
                continue
            cand = pts[np.all((pts >= low) & (pts <= high), axis=1)]
            if cand.size == 0:
                continue
            if len(cand) > MAX_POINTS:
                cand = cand[np.linspace(0, len(cand) - 1, MAX_POINTS).astype(int)]
            for s in range(0, len(cand), BATCH_POINTS):
                w = winding_numbers(cand[s : s + BATCH_POINTS], tris[outer])
                hit = np.flatnonzero(np.abs(w) > 0.25)
                if hit.size:
                    point = cand[s + int(hit[0])]
                    return PartOverlap(count, inner + 1, outer + 1, point)
    return None
