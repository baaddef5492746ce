"""Feet from MuJoCo geoms: the lowest point of a geom, and the mudrft foot it stands for
(the rules: :func:`.placement.body_foot`); a tall derived foot is cut (:func:`cut_foot`).
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ... import feet
from ._lazy import _mujoco

if TYPE_CHECKING:
    import mujoco


def geom_label(model: mujoco.MjModel, g: int, *, body: bool = True) -> str:
    """``geom 'name' of body 'body'`` (``geom 3 of body 'body'`` for an unnamed geom);
    ``geom 'name'`` with ``body=False``."""
    name = model.geom(g).name
    which = f"geom {name!r}" if name else f"geom {g}"
    return f"{which} of body {model.body(int(model.geom_bodyid[g])).name!r}" if body else which


def geom_type_name(model: mujoco.MjModel, g: int) -> str:
    """The type of geom ``g`` as MJCF spells it (``"ellipsoid"``)."""
    return str(_mujoco().mjtGeom(int(model.geom_type[g])).name[len("mjGEOM_") :].lower())


def _collides(model: mujoco.MjModel, g: int) -> bool:
    """Whether geom ``g`` takes part in collisions."""
    return bool(int(model.geom_contype[g]) or int(model.geom_conaffinity[g]))


def _supported(model: mujoco.MjModel, g: int) -> bool:
    """Whether geom ``g`` is a box, sphere, capsule, cylinder or mesh."""
    return geom_type_name(model, g) in ("box", "sphere", "capsule", "cylinder", "mesh")


#: Colliding geoms whose lowest points lie within this height of the foot geom's reach
#: equally low [m]: they are one foot, the convex hull of their union.
TIED_HEIGHT = 1e-3


def lowest_geoms(model: mujoco.MjModel, ref: mujoco.MjData, geoms: list[int]) -> list[int]:
    """The supported geom reaching lowest in the reference pose (among the colliding ones
    when there are any, D113), then the other colliding ones as low (:data:`TIED_HEIGHT`)."""
    supported = [g for g in geoms if _supported(model, g)]
    colliding = [g for g in supported if _collides(model, g)]
    if not supported:
        return []
    low = {g: float(_support(model, ref, g)[2]) for g in colliding or supported}
    g = min(low, key=low.__getitem__)
    return [g, *(o for o in colliding if o != g and low[o] <= low[g] + TIED_HEIGHT)]


def _support(model: mujoco.MjModel, d: mujoco.MjData, g: int) -> NDArray[np.float64]:
    """Lowest point (world) of geom ``g`` in pose ``d`` (ties resolved to the center)."""
    c = np.array(d.geom_xpos[g])
    R = np.array(d.geom_xmat[g]).reshape(3, 3)
    s = np.array(model.geom_size[g])
    kind = geom_type_name(model, g)
    if kind == "box":
        u = R[2]  # z component of each geom axis
        return c - R @ (np.where(np.abs(u) > 1e-9, np.sign(u), 0.0) * s)
    if kind == "sphere":
        return c - np.array([0.0, 0.0, s[0]])
    if kind in ("capsule", "cylinder"):
        a = R[:, 2]
        end = c - (s[1] * np.sign(a[2]) if abs(a[2]) > 1e-9 else 0.0) * a
        if kind == "capsule":
            return end - np.array([0.0, 0.0, s[0]])
        perp = np.array([0.0, 0.0, 1.0]) - a[2] * a
        nrm = np.linalg.norm(perp)
        return end - (s[0] * perp / nrm if nrm > 1e-9 else 0.0)
    v = _mesh(model, g)[0]  # a mesh (the types were checked where g was chosen)
    return _lowest_center(c + v @ R.T, max(float(model.geom_rbound[g]), 1e-9))


#: The corners of the cube [-1, 1]^3 [-].
_CORNERS = np.array(list(itertools.product((-1.0, 1.0), repeat=3)))

#: A sphere in a hull: its six extreme points along the axes and eight between them [-].
#: The hull of a union of spheres keeps their exact extents with few facets.
SPHERE_POINTS = np.concatenate([np.eye(3), -np.eye(3), _CORNERS / math.sqrt(3.0)])


def geom_points(model: mujoco.MjModel, d: mujoco.MjData, g: int) -> NDArray[np.float64]:
    """Points (world) [m] whose convex hull is geom ``g`` in pose ``d``."""
    import trimesh

    c, R = np.array(d.geom_xpos[g]), np.array(d.geom_xmat[g]).reshape(3, 3)
    s, kind = np.array(model.geom_size[g], dtype=float), geom_type_name(model, g)
    if kind == "box":
        local = _CORNERS * s
    elif kind == "sphere":
        local = s[0] * SPHERE_POINTS
    elif kind == "capsule":
        local = trimesh.creation.capsule(height=2 * s[1], radius=s[0], count=[4, 16]).vertices
    elif kind == "cylinder":
        local = trimesh.creation.cylinder(radius=s[0], height=2 * s[1], sections=16).vertices
    else:
        local = _mesh(model, g)[0]
    return np.asarray(c + np.asarray(local, dtype=float) @ R.T, dtype=float)


def hull_foot(points: NDArray[np.float64]) -> tuple[feet.MeshFoot, NDArray[np.float64]]:
    """The convex hull of world ``points`` [m] as a ``MeshFoot`` (world axes, tip at the
    origin), and its tip in the world [m]."""
    import trimesh

    hull = trimesh.convex.convex_hull(points)
    v = np.asarray(hull.vertices, dtype=float)
    tip = _lowest_center(v, max(float(np.ptp(v)), 1e-9))
    return feet.MeshFoot(v - tip, np.asarray(hull.faces)), tip


#: A derived foot taller than this keeps only its part this high above its tip [m] (a
#: lower leg that is one geom is not all foot). A legged robot's foot settles 20-30 mm deep
#: in the paper's mud; one sunk past 0.1 m is stuck, whatever is above.
CUT_HEIGHT = 0.1


def cut_foot(foot: feet.Foot, height: float | None) -> feet.Foot:
    """``foot``, a derived ``Flat`` or ``MeshFoot`` with its tip at the origin, cut ``height``
    [m] above its tip; the same object when it is not taller or ``height`` is None.

    A box stays a box, ``height`` tall. A mesh is clipped by the plane z = ``height``
    (trimesh) and closed as the convex hull of its part below: the convex shape MuJoCo's own
    contact gives a mesh geom, exact for a hull foot of several geoms.
    """
    if height is None or foot.height <= height:
        return foot
    if isinstance(foot, feet.Flat):
        return dataclasses.replace(foot, height=height)
    if isinstance(foot, feet.MeshFoot):
        import trimesh

        v, f = trimesh.intersections.slice_faces_plane(
            foot.vertices,
            foot.faces,
            plane_normal=[0.0, 0.0, -1.0],
            plane_origin=[0.0, 0.0, height],
        )[:2]
        hull = trimesh.convex.convex_hull(v[np.unique(f)])
        return feet.MeshFoot(hull.vertices, hull.faces, trailing=foot.trailing, name=foot.name)
    return foot


def _lowest_center(points: NDArray[np.float64], size: float) -> NDArray[np.float64]:
    """The center of the box around the lowest of ``points`` (within ``1e-6 size``) [m]."""
    zmin = points[:, 2].min()
    low = points[points[:, 2] <= zmin + 1e-6 * size, :2]
    return np.array([*(0.5 * (low.min(axis=0) + low.max(axis=0))), zmin])


def _mesh(model: mujoco.MjModel, g: int) -> tuple[NDArray[np.float64], NDArray[np.int_]]:
    """The vertices (geom frame) [m] and faces of mesh geom ``g``."""
    m = int(model.geom_dataid[g])
    v, f = int(model.mesh_vertadr[m]), int(model.mesh_faceadr[m])
    vertices = model.mesh_vert[v : v + int(model.mesh_vertnum[m])]
    faces = model.mesh_face[f : f + int(model.mesh_facenum[m])]
    return np.array(vertices, dtype=float), np.array(faces, dtype=int)


def standing(model: mujoco.MjModel, ref: mujoco.MjData, g: int) -> bool:
    """Whether geom ``g`` is a capsule or cylinder whose axis rises more than 30 degrees
    from the horizontal in pose ``ref``: its foot is then its meshed convex hull, not a
    ``SemiCylinder``."""
    rod = geom_type_name(model, g) in ("capsule", "cylinder")
    return rod and abs(float(ref.geom_xmat[g][8])) > 0.5  # the axis's z component


def _derived_foot(
    model: mujoco.MjModel, ref: mujoco.MjData, g: int, fwd_w: NDArray[np.float64]
) -> tuple[feet.Foot, NDArray[np.float64]]:
    """mudrft foot for geom ``g`` and the foot's forward axis in the world (reference pose);
    ``fwd_w`` is the body's forward axis (a lying capsule's or cylinder's: along its axis)."""
    kind = geom_type_name(model, g)
    R = np.array(ref.geom_xmat[g]).reshape(3, 3)
    s = np.array(model.geom_size[g], dtype=float)
    if kind == "box":
        up = int(np.argmax(np.abs(R[2])))
        hor = [i for i in range(3) if i != up]
        ix = max(hor, key=lambda i: abs(float(R[:, i] @ fwd_w)))
        iy = hor[0] if hor[1] == ix else hor[1]
        ax = R[:, ix] * (1.0 if R[:, ix] @ fwd_w >= 0 else -1.0)
        # Flat: width W along x, length L along y (decision D20 of the feet)
        return feet.Flat(length=2 * s[iy], width=2 * s[ix], height=2 * s[up]), ax
    if kind == "sphere":
        return feet.SemiSphere(radius=s[0], height=s[0]), fwd_w
    if kind in ("capsule", "cylinder"):  # lying (standing ones are meshed: :func:`standing`)
        # SemiCylinder: axis along x; capsule caps are neglected (documented)
        return feet.SemiCylinder(radius=s[0], width=2 * s[1], height=s[0]), fwd_w
    v, f = _mesh(model, g)  # a mesh (the types were checked where g was chosen)
    low = _support(model, ref, g) - np.array(ref.geom_xpos[g])
    frame = np.stack([fwd_w, np.cross([0.0, 0.0, 1.0], fwd_w), [0.0, 0.0, 1.0]])
    return feet.MeshFoot((v @ R.T - low) @ frame.T, f), fwd_w
