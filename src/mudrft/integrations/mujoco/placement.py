"""A mudrft foot placed on a body of a MuJoCo model: which foot, where its tip is.

:func:`body_foot` finds a body, derives its foot from its lowest geoms when none is given
(a tall derived foot is cut: :func:`cut_foot`), and stores in a :class:`BodyFoot` what the
coupling needs every step.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ... import feet
from ..._typing import FloatArray, IndexArray
from ..._validation import MudrftError, check_finite, plain, positive_number, warn_plausibility
from ...feet.surface import PreparedTriangles, prepare_triangles
from ._lazy import _mujoco
from .pose import POSE_RESOLUTION, foot_triangles

if TYPE_CHECKING:
    import mujoco

    from ...feet.base import Foot


@dataclasses.dataclass(frozen=True, eq=False)
class BodyFoot:
    """A foot placed on a body.

    Attributes
    ----------
    body : str
        Body name.
    body_id : int
        MuJoCo body id.
    foot : Foot
        The mudrft foot.
    tip : ndarray (3,)
        Tip (lowest point of the foot in the reference pose) in the body frame [m].
    forward : ndarray (3,)
        The foot's x axis in the body frame [-].
    kind : str
        The foot geom's kind: ``"box"``, ``"sphere"``, ``"capsule"``, ``"cylinder"``,
        ``"points"`` (a mesh, or several geoms) or ``"tip"`` (no geom).
    center : ndarray (3,)
        Geom center in the body frame [m].
    size : ndarray (3,)
        Geom size as MuJoCo defines it [m].
    upright : ndarray (m, 3, 3) or None
        Triangles of the foot in its own frame [m]; None for a foot without a surface.
    triangles : ndarray (m, 3, 3) or None
        The same triangles in the body frame [m].
    geom : int
        MuJoCo id of the foot's geom (-1: none).
    geoms : tuple of int
        Every geom of the foot (several: their convex hull is the foot).
    ball : bool
        A sphere geom's derived foot, stepped as a full ball (the same from every angle).
    uncut : float or None
        The derived foot's height before it was cut (:func:`cut_foot`) [m]; None
        when it was not.
    """

    body: str
    body_id: int
    foot: Foot
    tip: NDArray[np.float64]
    forward: NDArray[np.float64]
    kind: str
    center: NDArray[np.float64]
    size: NDArray[np.float64]
    upright: NDArray[np.float64] | None = None
    triangles: NDArray[np.float64] | None = None
    geom: int = -1
    geoms: tuple[int, ...] = ()
    ball: bool = False
    uncut: float | None = None


#: Mesh resolution of a ball foot (72 facets for the hemisphere): coarse, since the
#: coupling integrates a ball's channels exactly (:func:`.pose.ball_channels`).
BALL_RESOLUTION = 3


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
#: lower leg that is one geom is not all foot; docs/guide/mujoco.md says why 0.1 m).
CUT_HEIGHT = 0.1


def cut_foot(foot: feet.Foot, height: float | None) -> feet.Foot:
    """``foot``, a derived ``Flat`` or ``MeshFoot`` with its tip at the origin, cut ``height``
    [m] above its tip; the same object when it is not taller or ``height`` is None.

    A box stays a box; a mesh is clipped by the plane z = ``height`` and closed as the
    convex hull of its part below (the convex shape MuJoCo's own contact gives a mesh).
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


def _reference_pose(model: mujoco.MjModel) -> mujoco.MjData:
    mj = _mujoco()
    d = mj.MjData(model)
    mj.mj_kinematics(model, d)
    return d


def _body_geoms(model: mujoco.MjModel, body_id: int) -> list[int]:
    adr, num = int(model.body_geomadr[body_id]), int(model.body_geomnum[body_id])
    return list(range(adr, adr + num)) if adr >= 0 else []


def resolve_body(model: mujoco.MjModel, item: object) -> tuple[int, int | None]:
    """The body a foot is named by, and the geom when a geom is named: a body's name, a
    geom's name (its body, with that geom as the foot) or a body's id (anonymous bodies)."""
    mj = _mujoco()
    if isinstance(item, str):
        bid = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, item))
        gid = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_GEOM, item)) if bid < 0 else -1
        if bid < 0 and gid < 0:
            names = [model.body(i).name or i for i in range(1, model.nbody)]
            raise MudrftError(
                f"{item!r} is neither a body nor a geom of the model; its bodies are {names} "
                "(a body's id reaches one without a name)"
            )
        bid = bid if bid >= 0 else int(model.geom_bodyid[gid])
        if bid == 0:
            raise MudrftError(
                f"bodies cannot include the world ({item!r}): the mud acts on a body that moves"
            )
        return bid, (gid if gid >= 0 else None)
    if isinstance(item, bool) or not isinstance(item, (int, np.integer)):
        raise MudrftError(
            f"a foot is named by a body's or geom's name or a body's id, got {item!r}"
        )
    if not 0 < int(item) < model.nbody:
        raise MudrftError(f"body id must be in [1, {model.nbody - 1}], got {int(item)}")
    return int(item), None


def body_foot(
    model: mujoco.MjModel,
    body: str | int,
    foot: Foot | None = None,
    *,
    tip: ArrayLike | None = None,
    resolution: int = POSE_RESOLUTION,
    geom: str | int | Sequence[str | int] | None = None,
    cut_height: float | None = CUT_HEIGHT,
) -> BodyFoot:
    """Place a mudrft foot on a body of a MuJoCo model.

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    body : str or int
        Body name or id, or a geom's name (its body, that geom the foot).
    foot : Foot or None
        The foot; ``None`` derives it from the body's lowest colliding geom (D113): box ->
        ``Flat``, lying capsule or cylinder -> ``SemiCylinder``, sphere -> ``SemiSphere``
        (stepped as a full ball), mesh -> ``MeshFoot``, standing capsule or cylinder ->
        ``MeshFoot`` of its convex hull. Geoms as low as it (within
        :data:`TIED_HEIGHT`) make one ``MeshFoot``, the convex hull of their union.
    tip : array_like (3,) or None
        Tip in the body frame [m]; default the lowest point of the foot in the reference pose.
    resolution : int
        Mesh resolution of a curved closed-form foot's triangles.
    geom : str, int, sequence of them, or None
        The geom (name or id) that is the foot, or geoms whose union is (D124).
    cut_height : float or None
        A derived box, mesh or hull foot taller than this [m] is cut this high above its tip
        (:data:`CUT_HEIGHT`, 0.1 m, by default); None keeps it whole. ``attach``
        cuts at the default: give it ``body_foot(model, body, cut_height=h).foot`` as the
        foot to cut elsewhere.

    Returns
    -------
    BodyFoot
    """
    if cut_height is not None:
        cut_height = positive_number("cut_height", cut_height, unit="m")
    derived = foot is None
    bid, named = resolve_body(model, body)
    name = model.body(bid).name or f"body {bid}"
    ref = _reference_pose(model)
    Rb = np.array(ref.xmat[bid]).reshape(3, 3)
    xb = np.array(ref.xpos[bid])
    fwd_w = np.array([1.0, 0.0, 0.0])
    spec = geom if geom is not None else named
    if spec is None:
        geoms = lowest_geoms(model, ref, _body_geoms(model, bid))
    else:
        items = list(spec) if isinstance(spec, Sequence) and not isinstance(spec, str) else [spec]
        geoms = [_named_geom(model, name, bid, x) for x in items]  # type: ignore[arg-type]
    ball = False
    if not geoms:
        if foot is None and _body_geoms(model, bid):
            found = ", ".join(
                f"{repr(model.geom(i).name) if model.geom(i).name else f'geom {i}'} "
                f"({geom_type_name(model, i)})"
                for i in _body_geoms(model, bid)
            )
            raise MudrftError(
                f"body {name!r} has no geom mudrft can turn into a foot: {found}; use a box, "
                "sphere, capsule, cylinder or mesh, or pass the foot explicitly (feet=...)"
            )
        if foot is None:
            raise MudrftError(
                f"body {name!r} has no geom to derive a foot from; pass the foot explicitly"
            )
        kind, center, size, low_w = "tip", np.zeros(3), np.zeros(3), xb
    elif len(geoms) > 1 or (foot is None and standing(model, ref, geoms[0])):  # a meshed hull
        hull, low_w = hull_foot(np.concatenate([geom_points(model, ref, g) for g in geoms]))
        foot = hull if foot is None else foot
        kind, center, size = "points", np.zeros(3), np.zeros(3)
    else:
        g = geoms[0]
        kind = geom_type_name(model, g)
        if kind in ("capsule", "cylinder"):  # forward along a lying one's axis
            a = ref.geom_xmat[g].reshape(3, 3)[:, 2]  # its axis
            h = math.hypot(a[0], a[1])
            if h > 0.5:
                fwd_w = np.array([a[0], a[1], 0.0]) / h * (1.0 if a[0] >= 0 else -1.0)
        if foot is None:
            foot, fwd_w = _derived_foot(model, ref, g, fwd_w)
            ball = kind == "sphere"
        low_w = _support(model, ref, g)
        center = Rb.T @ (np.array(ref.geom_xpos[g]) - xb)
        size = np.array(model.geom_size[g], dtype=float)
        kind = kind.replace("mesh", "points")
    if tip is not None:
        low_w = xb + Rb @ check_finite("tip", tip)
        ball = False
    whole = foot
    if derived and not ball:
        foot = cut_foot(foot, cut_height)
    if not hasattr(foot, "contact_force") or not hasattr(foot, "characteristic_length"):
        raise MudrftError(
            f"foot for body {name!r} must be a mudrft foot (mudrft.feet), got {type(foot).__name__}"
        )
    tip_b = Rb.T @ (low_w - xb)
    fwd_b = Rb.T @ fwd_w
    up_b = Rb.T @ np.array([0.0, 0.0, 1.0])
    frame = np.stack([fwd_b, np.cross(up_b, fwd_b), up_b], axis=-1)  # foot axes (columns)
    if ball:
        resolution = min(resolution, BALL_RESOLUTION)
    upright = foot_triangles(foot, resolution=resolution)
    tri_b = None if upright is None else tip_b + upright @ frame.T
    return BodyFoot(
        body=name,
        body_id=bid,
        foot=foot,
        tip=tip_b,
        forward=fwd_b,
        kind=kind,
        center=center,
        size=size,
        upright=upright,
        triangles=tri_b,
        geom=int(geoms[0]) if geoms else -1,
        geoms=tuple(int(g) for g in geoms),
        ball=ball,
        uncut=None if foot is whole else float(whole.height),
    )


def _named_geom(model: mujoco.MjModel, body: str, bid: int, geom: str | int) -> int:
    """The id of the geom named as ``body``'s foot, or an error naming what is wrong."""
    mj = _mujoco()
    geoms = _body_geoms(model, bid)
    names = [model.geom(i).name or i for i in geoms]
    if isinstance(geom, bool) or not isinstance(geom, (str, int, np.integer)):
        raise MudrftError(
            f"the foot's geom of body {body!r} must be a geom's name or id, got {geom!r}"
        )
    g = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_GEOM, geom) if isinstance(geom, str) else geom)
    if not 0 <= g < model.ngeom:
        raise MudrftError(
            f"geom {geom!r}, named as the foot of body {body!r}, is not in the model; the "
            f"body's geoms are {names}"
        )
    if g not in geoms:
        raise MudrftError(
            f"{geom_label(model, g)}, named as the foot of body {body!r}, is not one of its "
            f"geoms: {names}"
        )
    if not _supported(model, g):
        raise MudrftError(
            f"{geom_label(model, g)}, named as the foot, has type {geom_type_name(model, g)}, "
            "which mudrft cannot turn into a foot; use a box, sphere, capsule, cylinder or mesh"
        )
    return g


def coupled_tip(b: BodyFoot) -> FloatArray:
    """The point of ``b``'s body the coupling follows [m]: the tip, or a ball's center."""
    return np.asarray(b.center if b.ball else b.tip, dtype=float)


def coupled_triangles(b: BodyFoot) -> FloatArray | None:
    """The triangles the coupling poses [m]: in the body frame, or a ball's
    upright about its center.
    """
    if b.ball and b.upright is not None:
        return np.asarray(b.upright, dtype=float) - np.array([0.0, 0.0, float(b.size[0])])
    return None if b.triangles is None else np.asarray(b.triangles, dtype=float)


def group_triangles(
    bodies: Sequence[BodyFoot], idx: IndexArray
) -> tuple[FloatArray, PreparedTriangles]:
    """Posed triangles (nb_g, m, 3, 3) and the prepared upright ones of a foot type (every
    coupled foot has a surface: :func:`.backend.not_compilable`)."""
    tri = np.stack([np.asarray(coupled_triangles(bodies[i])) for i in idx])
    return tri, prepare_triangles(bodies[idx[0]].upright)


def attached_foot(
    model: mujoco.MjModel,
    body: str | int,
    foot: Foot | None,
    *,
    resolution: int,
    geom: str | int | Sequence[str | int] | None = None,
) -> BodyFoot:
    """:func:`body_foot` for a coupling; a body welded to the world warns (D113)."""
    placed = body_foot(model, body, foot, resolution=resolution, geom=geom)
    if int(model.body_weldid[placed.body_id]) == 0:
        warn_plausibility(
            f"body {placed.body!r} is welded to the world (no joint between it and the world): "
            "the mud's force on it moves nothing; attach the mud to a body that can move"
        )
    return placed


#: How far above the lowest limb ``feet="auto"`` reaches, a fraction of the model's height.
AUTO_REACH = 0.25


def auto_feet(model: mujoco.MjModel) -> list[int]:
    """The foot bodies of a model, as ``feet="auto"`` finds them.

    Each leaf body names a limb; its foot is the nearest body up the limb with a colliding
    geom of a supported type. The feet are those whose lowest point in ``qpos0`` lies within
    :data:`AUTO_REACH` of the model's height above the lowest (a humanoid's hands hang higher).
    """
    ref = _reference_pose(model)
    parents = set(int(p) for p in model.body_parentid[1:])
    low: dict[int, float] = {}
    for leaf in (b for b in range(1, model.nbody) if b not in parents):
        b = leaf
        while b > 0:
            geoms = [
                g for g in _body_geoms(model, b) if _supported(model, g) and _collides(model, g)
            ]
            if geoms:
                if int(model.body_weldid[b]) != 0:  # a body that moves
                    low[b] = float(min(_support(model, ref, g)[2] for g in geoms))
                break
            b = int(model.body_parentid[b])
    if not low:
        raise MudrftError(
            "feet='auto' found no limb with a colliding box, sphere, capsule, cylinder or mesh "
            "geom on a body that moves; name the feet (body or geom names, or body ids)"
        )
    moving = [g for g in range(model.ngeom) if model.body_weldid[model.geom_bodyid[g]] != 0]
    top = max(float(ref.geom_xpos[g, 2] + model.geom_rbound[g]) for g in moving)
    bottom = min(low.values())
    return sorted(b for b, z in low.items() if z <= bottom + AUTO_REACH * (top - bottom))


def describe(model: mujoco.MjModel, placed: BodyFoot) -> str:
    """One line on a placed foot: its body, its geoms and the foot they became."""
    label = repr(placed.body) if model.body(placed.body_id).name else "(no name)"
    geoms = ", ".join(
        f"{geom_label(model, g, body=False)} ({geom_type_name(model, g)})" for g in placed.geoms
    )
    f = placed.foot
    if placed.ball:
        what = f"a ball of radius {plain(float(placed.size[0]))} m"
    elif len(placed.geoms) > 1:
        what = "the convex hull of their union"
    elif placed.kind == "points" and geom_type_name(model, placed.geoms[0]) != "mesh":
        what = "its convex hull, meshed (it stands)"
    else:
        what = "its foot"
    if placed.uncut is not None:
        what += f", its lowest {float(f.height):.3g} m of {placed.uncut:.3g} m (cut_height)"
    ext = ""
    if placed.upright is not None:
        span = np.ptp(np.asarray(placed.upright).reshape(-1, 3), axis=0)
        ext = ", " + " x ".join(f"{float(v):.3g}" for v in span) + " m"
    return f"body {label} (id {placed.body_id}): {geoms or 'no geom'} -> {what}, {type(f).__name__}{ext}"
