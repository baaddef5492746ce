r"""Closed triangle meshes of the paper's three feet, generated in code.

Each returns ``(vertices (n, 3) [m], faces (m, 3))``, wound outward, tip at the origin;
curved surfaces are inscribed polyhedra.
"""

from __future__ import annotations

import math

import numpy as np

from .._validation import MudrftError, check_length, positive_int

__all__ = ["box_mesh", "rim_angle", "semicylinder_mesh", "semisphere_mesh"]


def rim_angle(radius: float, height: float) -> float:
    r"""Angle :math:`\theta_H=\cos^{-1}(1-H/R)` [rad] from the tip to the rim of a curved foot
    of radius :math:`R` and height :math:`H\le R` [m] (a taller one is refused).

    >>> round(rim_angle(0.045, 0.045), 6)  # a full half-cylinder or hemisphere: pi/2
    1.570796
    """
    if height > radius:
        raise MudrftError(f"height must be <= radius = {radius} m, got {height} m")
    return math.acos(1.0 - height / radius)


def _grid_faces(ids: np.ndarray) -> np.ndarray:
    """Triangles of a structured grid of vertex ids (nu+1, nv+1); normal along du x dv."""
    a, b = ids[:-1, :-1].ravel(), ids[1:, :-1].ravel()
    c, d = ids[1:, 1:].ravel(), ids[:-1, 1:].ravel()
    return np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)])


def _compact(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    used, inv = np.unique(faces, return_inverse=True)
    return vertices[used], inv.reshape(faces.shape)


def box_mesh(
    length: float, width: float, height: float, *, resolution: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """Closed box mesh of the flat foot, ``length`` [m] along y, ``width`` [m] along x,
    ``height`` [m] up; ``resolution``: grid divisions per edge.

    >>> v, f = box_mesh(0.08, 0.065, 0.026, resolution=2)
    >>> v.shape, f.shape
    ((26, 3), (48, 3))
    """
    length, width, height = (
        check_length(k, v) for k, v in (("length", length), ("width", width), ("height", height))
    )
    n = positive_int("resolution", resolution)
    xs = np.linspace(-0.5 * width, 0.5 * width, n + 1)
    ys = np.linspace(-0.5 * length, 0.5 * length, n + 1)
    zs = np.linspace(0.0, height, n + 1)
    L = np.arange((n + 1) ** 3).reshape(n + 1, n + 1, n + 1)  # (i, j, k) -> id
    gx, gy, gz = np.meshgrid(xs, ys, zs, indexing="ij")
    allv = np.stack([gx.ravel(), gy.ravel(), gz.ravel()], -1)
    # each face as ids[u, v] with du x dv pointing outward
    grids = [
        L[:, :, 0].T,  # bottom: du = +y, dv = +x  -> -z
        L[:, :, n],  # top: du = +x, dv = +y -> +z
        L[n, :, :],  # +x: du = +y, dv = +z -> +x
        L[0, :, :].T,  # -x: du = +z, dv = +y -> -x
        L[:, n, :].T,  # +y: du = +z, dv = +x -> +y
        L[:, 0, :],  # -y: du = +x, dv = +z -> -y
    ]
    faces = np.concatenate([_grid_faces(g) for g in grids])
    return _compact(allv, faces)


def semicylinder_mesh(
    radius: float, width: float, height: float, *, resolution: int = 16
) -> tuple[np.ndarray, np.ndarray]:
    r"""Closed mesh of the semi-cylindrical foot: axis along x (length ``width`` [m]), a circle
    of ``radius`` [m] cut flat at ``height`` [m]; ``resolution`` arc segments tip to rim.

    >>> v, f = semicylinder_mesh(0.045, 0.065, 0.026, resolution=4)
    >>> bool(v[:, 2].min() == 0.0), round(float(v[:, 2].max()), 6)
    (True, 0.026)
    """
    radius, width, height = (
        check_length(k, v) for k, v in (("radius", radius), ("width", width), ("height", height))
    )
    tm, n = rim_angle(radius, height), positive_int("resolution", resolution)
    th = np.linspace(-tm, tm, 2 * n + 1)
    ya, za = radius * np.sin(th), radius * (1.0 - np.cos(th))
    za[[0, -1]] = height  # the rim lies exactly on the top plane
    nx = max(1, round(width / (radius * tm / n)))
    xs = np.linspace(-0.5 * width, 0.5 * width, nx + 1)
    na = th.size
    # curved surface: grid (theta, x); d(theta) x dx points away from the axis
    gx, gt = np.meshgrid(xs, np.arange(na), indexing="ij")
    curved = np.stack([gx.ravel(), ya[gt.ravel()], za[gt.ravel()]], -1)
    ids = np.arange(curved.shape[0]).reshape(nx + 1, na)  # ids[i_x, j_theta]
    faces, verts = [_grid_faces(ids.T)], [curved]
    base = curved.shape[0]
    # end caps: fan from an interior point; arc order is counterclockwise in (y, z)
    for sign, i_x in ((1.0, nx), (-1.0, 0)):
        ring, nxt, c = ids[i_x], np.roll(ids[i_x], -1), np.full(na, base)
        faces.append(np.stack([c, ring, nxt], -1) if sign > 0 else np.stack([c, nxt, ring], -1))
        verts.append(np.array([[sign * 0.5 * width, 0.0, 0.5 * height]]))
        base += 1
    # top: strip between the two rims, du = +x, dv = +y
    faces.append(_grid_faces(np.stack([ids[:, 0], ids[:, -1]], -1)))
    return _compact(np.concatenate(verts), np.concatenate(faces))


def semisphere_mesh(
    radius: float, height: float, *, resolution: int = 16
) -> tuple[np.ndarray, np.ndarray]:
    r"""Closed mesh of the semi-spherical foot, a cap of ``radius`` and ``height`` [m];
    ``resolution`` rings from tip to rim, of ``4 resolution`` segments each.

    >>> v, f = semisphere_mesh(0.045, 0.026, resolution=4)
    >>> f.shape
    (128, 3)
    """
    radius, height = (check_length(k, v) for k, v in (("radius", radius), ("height", height)))
    tm, n = rim_angle(radius, height), positive_int("resolution", resolution)
    na = 4 * n
    th = np.linspace(0.0, tm, n + 1)[1:]
    ph = 2.0 * math.pi * np.arange(na) / na
    r, z = radius * np.sin(th), radius * (1.0 - np.cos(th))
    z[-1] = height
    rings = np.stack(
        [(r[:, None] * np.cos(ph)).ravel(), (r[:, None] * np.sin(ph)).ravel(), np.repeat(z, na)], -1
    )
    ids = 1 + np.arange(n * na).reshape(n, na)  # 0 is the pole
    top = 1 + n * na
    verts = np.concatenate([[[0.0, 0.0, 0.0]], rings, [[0.0, 0.0, height]]])
    k1 = np.roll(np.arange(na), -1)
    pole = np.stack([np.zeros(na, int), ids[0, k1], ids[0]], -1)
    a, b = ids[:-1], ids[1:]  # ring j and j+1
    ak, bk = a[:, k1], b[:, k1]
    quads = np.concatenate([np.stack([a, bk, b], -1), np.stack([a, ak, bk], -1)]).reshape(-1, 3)
    cap = np.stack([np.full(na, top), ids[-1], ids[-1, k1]], -1)
    return verts, np.concatenate([pole, quads, cap])
