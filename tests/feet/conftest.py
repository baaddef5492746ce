"""Fixtures for the feet tests: an asymmetric closed mesh and the paper's feet."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull


def oriented_hull(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and outward-wound faces of the convex hull of ``points``."""
    hull = ConvexHull(points)
    f = hull.simplices.copy()
    tri = points[f]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    inward = np.einsum("ij,ij->i", n, hull.equations[:, :3]) < 0
    f[inward] = f[inward][:, ::-1]
    return points, f


@pytest.fixture(scope="module")
def lumpy_mesh() -> tuple[np.ndarray, np.ndarray]:
    """A closed convex polyhedron with no symmetry (random points on a squashed ellipsoid)."""
    rng = np.random.default_rng(7)
    p = rng.normal(size=(60, 3))
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    p *= [0.04, 0.025, 0.03]
    p[:, 0] += 0.3 * p[:, 2]  # shear: no mirror plane
    return oriented_hull(p)
