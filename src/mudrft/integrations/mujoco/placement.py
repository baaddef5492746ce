"""A mudrft foot placed on a body of a MuJoCo model: which foot, where its tip is.

:func:`body_foot` finds a body, derives its foot from the lowest geom when none is
given (:mod:`mudrft.integrations.mujoco.geoms`), and stores in a :class:`BodyFoot` what
the coupling needs every step: the tip and the forward axis in the body frame, and the
geom data from which :func:`lowest_points` finds the lowest point of the foot in its
current pose.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._typing import FloatArray, IndexArray
from ..._validation import MudrftError, check_finite, warn_plausibility
from ...feet.surface import PreparedTriangles, prepare_triangles
from ._lazy import _mujoco
from .geoms import (
    _SUPPORTED_GEOMS,
    TIED_HEIGHT,
    _derived_foot,
    _lowest_geom,
    _mesh_vertices,
    _support,
    _tied_geoms,
    geom_label,
    geom_type_name,
)
from .pose import POSE_RESOLUTION, foot_triangles

if TYPE_CHECKING:
    import mujoco

    from ...feet.base import Foot

__all__ = ["BodyFoot", "attached_foot", "body_foot", "group_triangles", "lowest_points"]


@dataclass(frozen=True, eq=False)
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
        The foot's x axis in the body frame [-] (horizontal in the reference pose).
    kind : str
        How the lowest point is found in the current pose: ``"box"``, ``"sphere"``,
        ``"capsule"``, ``"cylinder"``, ``"points"`` (mesh vertices) or ``"tip"``.
    center : ndarray (3,)
        Geom center in the body frame [m].
    axes : ndarray (3, 3)
        Geom axes (columns) in the body frame [-].
    size : ndarray (3,)
        Geom size as MuJoCo defines it [m].
    points : ndarray (k, 3)
        Mesh vertices in the body frame [m] (``kind == "points"``).
    upright : ndarray (m, 3, 3) or None
        Triangles of the foot in its own frame (:func:`~.pose.foot_triangles`) [m]; None
        for a foot without a surface.
    triangles : ndarray (m, 3, 3) or None
        The same triangles in the body frame [m].
    geom : int
        MuJoCo id of the geom the foot stands for (-1: none, the tip is a point).
    """

    body: str
    body_id: int
    foot: Foot
    tip: NDArray[np.float64]
    forward: NDArray[np.float64]
    kind: str
    center: NDArray[np.float64]
    axes: NDArray[np.float64]
    size: NDArray[np.float64]
    points: NDArray[np.float64]
    upright: NDArray[np.float64] | None = None
    triangles: NDArray[np.float64] | None = None
    geom: int = -1


def _reference_pose(model: mujoco.MjModel) -> mujoco.MjData:
    mj = _mujoco()
    d = mj.MjData(model)
    mj.mj_kinematics(model, d)
    return d


def _body_geoms(model: mujoco.MjModel, body_id: int) -> list[int]:
    adr, num = int(model.body_geomadr[body_id]), int(model.body_geomnum[body_id])
    return list(range(adr, adr + num)) if adr >= 0 else []


def body_foot(
    model: mujoco.MjModel,
    body: str | int,
    foot: Foot | None = None,
    *,
    tip: ArrayLike | None = None,
    resolution: int = POSE_RESOLUTION,
    geom: str | int | None = None,
) -> BodyFoot:
    """Place a mudrft foot on a body of a MuJoCo model.

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    body : str or int
        Body name or id.
    foot : Foot or None
        The foot; ``None`` derives it from the body's lowest geom (of those that collide,
        when it has any; D113): box -> ``Flat``,
        horizontal cylinder or capsule -> ``SemiCylinder`` (capsule caps neglected),
        sphere -> ``SemiSphere``, mesh -> ``MeshFoot``.
    tip : array_like (3,) or None, keyword-only
        Tip in the body frame [m]; default the lowest point of that geom in the
        reference pose (the body origin when the body has no geom).
    resolution : int, keyword-only
        Mesh resolution of a curved closed-form foot's triangles (:func:`~.pose.foot_triangles`).
    geom : str, int or None, keyword-only
        The body's geom that is the foot (name or id), when the lowest colliding one is not
        (D124); it must belong to the body and be a box, sphere, capsule, cylinder or mesh.

    Returns
    -------
    BodyFoot
    """
    mj = _mujoco()
    if isinstance(body, str):
        bid = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, body))
        if bid < 0:
            gid = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_GEOM, body))
            if gid >= 0:  # the natural mix-up: the foot geom's name for its body's
                owner = model.body(int(model.geom_bodyid[gid])).name
                raise MudrftError(
                    f"{body!r} is a geom, not a body: the mud acts on the bodies named, and "
                    f"its body is {owner!r} (to make this geom the foot, name the body and "
                    f"the geom with foot_geoms={{{owner!r}: {body!r}}}; the foot is otherwise "
                    "derived from the body's lowest colliding geom, or given with feet=)"
                )
            names = [model.body(i).name for i in range(model.nbody)]
            raise MudrftError(f"body {body!r} is not in the model; bodies are {names}")
    else:
        bid = int(body)
        if not 0 < bid < model.nbody:
            raise MudrftError(f"body id must be in [1, {model.nbody - 1}], got {bid}")
    name = model.body(bid).name
    ref = _reference_pose(model)
    Rb = np.array(ref.xmat[bid]).reshape(3, 3)
    xb = np.array(ref.xpos[bid])
    fwd_w = np.array([1.0, 0.0, 0.0])
    g = (
        _lowest_geom(model, ref, _body_geoms(model, bid))
        if geom is None
        else _named_geom(model, name, bid, geom)
    )
    if g < 0:
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
        kind, center, axes, size, pts = "tip", np.zeros(3), np.eye(3), np.zeros(3), np.zeros((0, 3))
        low_w = xb if tip is None else xb + Rb @ check_finite("tip", tip)
    else:
        if foot is None:
            foot, fwd_w = _derived_foot(model, ref, g, fwd_w)
        elif int(model.geom_type[g]) in (
            int(mj.mjtGeom.mjGEOM_CAPSULE),
            int(mj.mjtGeom.mjGEOM_CYLINDER),
        ):
            a = np.array(ref.geom_xmat[g]).reshape(3, 3)[:, 2]
            if math.hypot(a[0], a[1]) > 0.5:
                fwd_w = np.array([a[0], a[1], 0.0]) / math.hypot(a[0], a[1])
                fwd_w = fwd_w if fwd_w[0] >= 0 else -fwd_w
        low_w = _support(model, ref, g)
        t = int(model.geom_type[g])
        Rg = np.array(ref.geom_xmat[g]).reshape(3, 3)
        center = Rb.T @ (np.array(ref.geom_xpos[g]) - xb)
        axes = Rb.T @ Rg
        size = np.array(model.geom_size[g], dtype=float)
        kinds = {
            int(mj.mjtGeom.mjGEOM_BOX): "box",
            int(mj.mjtGeom.mjGEOM_SPHERE): "sphere",
            int(mj.mjtGeom.mjGEOM_CAPSULE): "capsule",
            int(mj.mjtGeom.mjGEOM_CYLINDER): "cylinder",
            int(mj.mjtGeom.mjGEOM_MESH): "points",
        }
        kind = kinds[t]
        pts = center + _mesh_vertices(model, g) @ axes.T if kind == "points" else np.zeros((0, 3))
        if tip is not None:
            low_w = xb + Rb @ check_finite("tip", tip)
    if not hasattr(foot, "contact_force") or not hasattr(foot, "characteristic_length"):
        raise MudrftError(
            f"foot for body {name!r} must be a mudrft foot (mudrft.feet), got {type(foot).__name__}"
        )
    tip_b = Rb.T @ (low_w - xb)
    fwd_b = Rb.T @ fwd_w
    up_b = Rb.T @ np.array([0.0, 0.0, 1.0])
    frame = np.stack([fwd_b, np.cross(up_b, fwd_b), up_b], axis=-1)  # foot axes (columns)
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
        axes=axes,
        size=size,
        points=pts,
        upright=upright,
        triangles=tri_b,
        geom=int(g),
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
    if int(model.geom_type[g]) not in _SUPPORTED_GEOMS(mj):
        raise MudrftError(
            f"{geom_label(model, g)}, named as the foot, has type {geom_type_name(model, g)}, "
            "which mudrft cannot turn into a foot; use a box, sphere, capsule, cylinder or mesh"
        )
    return g


def lowest_points(
    bodies: Sequence[BodyFoot],
    X: NDArray[np.float64],
    R: NDArray[np.float64],
    tip: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Lowest point of each foot geom in its current pose, for many robots at once.

    The batched form of :func:`~mudrft.integrations.mujoco.geoms._support`, from the
    geom data that :func:`body_foot` stored in each :class:`BodyFoot`.

    Parameters
    ----------
    bodies : sequence of BodyFoot
        The ``nb`` placed feet.
    X : ndarray (N, nb, 3)
        Body origins in the world [m].
    R : ndarray (N, nb, 3, 3)
        Body orientations (body to world) [-].
    tip : ndarray (N, nb, 3)
        Tips in the world [m]; the answer for bodies of kind ``"tip"``.

    Returns
    -------
    ndarray (N, nb, 3)
        Lowest points in the world [m].
    """
    low = tip.copy()
    for j, b in enumerate(bodies):
        if b.kind == "tip":
            continue
        Rj = R[:, j]
        c = X[:, j] + Rj @ b.center
        G = Rj @ b.axes  # geom axes in the world, (N, 3, 3)
        s = b.size
        if b.kind == "box":
            u = G[:, 2, :]
            sg = -np.where(np.abs(u) > 1e-9, np.sign(u), 0.0)
            low[:, j] = c + (G @ (sg * s)[..., None])[..., 0]
        elif b.kind == "sphere":
            low[:, j] = c - [0.0, 0.0, s[0]]
        elif b.kind in ("capsule", "cylinder"):
            a = G[:, :, 2]
            az = a[:, 2:3]
            end = c - np.where(np.abs(az) > 1e-9, np.sign(az), 0.0) * s[1] * a
            if b.kind == "capsule":
                low[:, j] = end - [0.0, 0.0, s[0]]
            else:
                perp = np.array([0.0, 0.0, 1.0]) - az * a
                nrm = np.linalg.norm(perp, axis=-1, keepdims=True)
                low[:, j] = end - s[0] * perp / np.maximum(nrm, 1e-12) * (nrm > 1e-9)
        else:
            pts = X[:, j, None, :] + b.points @ np.swapaxes(Rj, -1, -2)
            i = np.argmin(pts[..., 2], axis=1)
            low[:, j] = pts[np.arange(len(i)), i]
    return low


def group_triangles(
    bodies: Sequence[BodyFoot], idx: IndexArray
) -> tuple[FloatArray | None, PreparedTriangles | None]:
    """Body-frame triangles (nb_g, m, 3, 3) and the prepared foot-frame ones of a foot type."""
    tri = [bodies[i].triangles for i in idx]
    if any(t is None for t in tri):
        return None, None
    return np.stack([np.asarray(t) for t in tri]), prepare_triangles(bodies[idx[0]].upright)


def attached_foot(
    model: mujoco.MjModel,
    body: str | int,
    foot: Foot | None,
    *,
    resolution: int,
    geom: str | int | None = None,
) -> BodyFoot:
    """:func:`body_foot` for a coupling: a body welded to the world warns (D113), and so
    does a foot derived from one of several colliding geoms that reach equally low (D124).

    The mud's force on a body with no joint between it and the world moves nothing, so a
    coupling that attaches to one is most likely a mistake (the foot's body named instead
    of the leg's, a joint missing from the model). The mud acts on one geom of a body; when
    others reach as low (within :data:`~.geoms.TIED_HEIGHT`), which one was the user's to
    say, with ``foot_geoms``. Arguments as :func:`body_foot`.
    """
    placed = body_foot(model, body, foot, resolution=resolution, geom=geom)
    if geom is None and placed.geom >= 0:
        tied = _tied_geoms(
            model, _reference_pose(model), _body_geoms(model, placed.body_id), placed.geom
        )
        if tied:
            label = model.geom(placed.geom).name or placed.geom
            others = ", ".join(geom_label(model, g, body=False) for g in tied)
            warn_plausibility(
                f"body {placed.body!r} has colliding geoms that reach as low as its foot, "
                f"{geom_label(model, placed.geom, body=False)} (within {TIED_HEIGHT * 1e3:g} "
                f"mm): {others}; the mud acts on one geom of a body, so name the foot's with "
                f"foot_geoms={{{placed.body!r}: {label!r}}} (or another of them)"
            )
    if int(model.body_weldid[placed.body_id]) == 0:
        warn_plausibility(
            f"body {placed.body!r} is welded to the world (no joint between it and the world): "
            "the mud's force on it moves nothing; attach the mud to a body that can move"
        )
    return placed
