r"""Mud under MuJoCo bodies: read the foot motion, step the mud once, write the wrench.

:func:`attach` puts mud under named bodies of any MJCF model. Each body gets a mudrft
foot, derived from its geoms or given explicitly. Every physics step the coupling

1. reads the pose and velocity of the foot *tip* (the point of the foot that is lowest in
   the model's reference pose, fixed in the body) and the depth of the lowest point of
   the foot geom in its current pose;
2. rotates the motion into the foot frame (the foot's yaw; the foot is treated as upright,
   see the tilt approximation below) and advances the mud state **once**;
3. makes the force safe for an explicit step (the semi-implicit treatment of the
   velocity-dependent part, below) and writes force and moment about the body's
   center of mass into ``data.xfrc_applied``.

It uses ``mj_step1`` / ``mj_step2``, so the forces come from the state at the start of
the step and held over it, and MuJoCo's own integrator does the rest::

    import mujoco, mudrft
    from mudrft.integrations.mujoco import attach
    coupling = attach(model, ["left_foot", "right_foot"], mudrft.paper_mud(0.25))
    coupling.reset(data)
    for _ in range(1000):
        coupling.step(data)            # mj_step1, mud, mj_step2

Stability (docs/model.md, decisions D61-D64). The mud force has a part that
acts like a damper, :math:`c\approx\eta_\infty A/L_c` (1-2 kN s/m for the paper's feet),
and the suction switch :math:`H_\nu` makes the force jump by :math:`\sigma_s A` within a
velocity band :math:`\nu L_c` of a millimetre per second. An explicit step of a damper is
stable only for :math:`\Delta t<2m/c` (about 0.5 ms for a 0.3 kg foot). The coupling
therefore applies the force the mud would exert at the *end* of the step, linearised in
the velocity: with :math:`W` the tip's mobility (:math:`J M^{-1} J^T`, from MuJoCo),
:math:`D\le0` the diagonal velocity derivative of the mud force (secant differences,
one batched mud call) and :math:`a` the acceleration from all other forces (from the
previous step),

.. math:: F = (I - \Delta t\,D\,W)^{-1}\,(F_0 + \Delta t\,D\,a),

the linearly implicit Euler step of the dissipative part. It equals the explicit
:math:`F_0` at rest and for kinematic bodies (:math:`W=0`), never reverses the velocity
within one step, and so never injects energy through the damper.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from .._validation import MudrftError, check_finite, check_nonnegative, check_positive
from ..citations import register
from ..terrains import as_terrain

__all__ = [
    "MudBatch",
    "MudContact",
    "MudCoupling",
    "attach",
    "attach_batch",
    "body_foot",
    "stability_limits",
]


def _mujoco() -> Any:
    """Import MuJoCo lazily with a helpful message."""
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the MuJoCo coupling needs mujoco: pip install 'mudrft[mujoco]'") from exc
    return mujoco


# ---------------------------------------------------------------------------------------
# Foot geometry from geoms
# ---------------------------------------------------------------------------------------
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
    """

    body: str
    body_id: int
    foot: Any
    tip: np.ndarray
    forward: np.ndarray
    kind: str
    center: np.ndarray
    axes: np.ndarray
    size: np.ndarray
    points: np.ndarray


def _feet_module() -> Any:
    try:
        from .. import feet
    except ImportError as exc:  # pragma: no cover - while the feet are being written
        raise MudrftError("deriving a foot from geoms needs mudrft.feet; pass the foot explicitly") from exc
    return feet


def _reference_pose(model: Any) -> Any:
    mj = _mujoco()
    d = mj.MjData(model)
    mj.mj_kinematics(model, d)
    return d


def _body_geoms(model: Any, body_id: int) -> list[int]:
    adr, num = int(model.body_geomadr[body_id]), int(model.body_geomnum[body_id])
    return list(range(adr, adr + num)) if adr >= 0 else []


def _lowest_geom(model: Any, ref: Any, geoms: list[int]) -> int:
    """The geom reaching lowest in the reference pose (mesh/box/sphere/capsule/cylinder)."""
    mj = _mujoco()
    best, zbest = -1, math.inf
    for g in geoms:
        t = int(model.geom_type[g])
        if t not in _SUPPORTED_GEOMS(mj):
            continue
        z = float(ref.geom_xpos[g, 2]) - float(model.geom_rbound[g])
        if t != int(mj.mjtGeom.mjGEOM_MESH):
            z = _support(model, ref, g)[2]
        if z < zbest:
            best, zbest = g, z
    return best


def _SUPPORTED_GEOMS(mj: Any) -> tuple[int, ...]:
    G = mj.mjtGeom
    return tuple(int(t) for t in (G.mjGEOM_BOX, G.mjGEOM_SPHERE, G.mjGEOM_CAPSULE, G.mjGEOM_CYLINDER,
                                  G.mjGEOM_MESH))


def _support(model: Any, d: Any, g: int) -> np.ndarray:
    """Lowest point (world) of geom ``g`` in pose ``d`` (ties resolved to the center)."""
    mj = _mujoco()
    c = np.array(d.geom_xpos[g])
    R = np.array(d.geom_xmat[g]).reshape(3, 3)
    s = np.array(model.geom_size[g])
    t = int(model.geom_type[g])
    u = R[2]  # z component of each geom axis
    if t == int(mj.mjtGeom.mjGEOM_BOX):
        sg = -np.where(np.abs(u) > 1e-9, np.sign(u), 0.0)
        return c + R @ (sg * s)
    if t == int(mj.mjtGeom.mjGEOM_SPHERE):
        return c - np.array([0.0, 0.0, s[0]])
    if t in (int(mj.mjtGeom.mjGEOM_CAPSULE), int(mj.mjtGeom.mjGEOM_CYLINDER)):
        a = R[:, 2]
        end = c - (s[1] * np.sign(a[2]) if abs(a[2]) > 1e-9 else 0.0) * a
        if t == int(mj.mjtGeom.mjGEOM_CAPSULE):
            return end - np.array([0.0, 0.0, s[0]])
        perp = np.array([0.0, 0.0, 1.0]) - a[2] * a
        nrm = np.linalg.norm(perp)
        return end - (s[0] * perp / nrm if nrm > 1e-9 else 0.0)
    if t == int(mj.mjtGeom.mjGEOM_MESH):
        v = _mesh_vertices(model, g)
        w = c + v @ R.T
        zmin = w[:, 2].min()
        low = w[w[:, 2] <= zmin + 1e-6 * max(float(model.geom_rbound[g]), 1e-9)]
        return np.array([0.5 * (low[:, 0].min() + low[:, 0].max()), 0.5 * (low[:, 1].min() + low[:, 1].max()), zmin])
    raise MudrftError(
        f"geom {g} has type {mj.mjtGeom(t).name}, which mudrft cannot turn into a foot; "
        "use a box, sphere, capsule, cylinder or mesh, or pass the foot explicitly"
    )


def _mesh_vertices(model: Any, g: int) -> np.ndarray:
    m = int(model.geom_dataid[g])
    adr, num = int(model.mesh_vertadr[m]), int(model.mesh_vertnum[m])
    return np.array(model.mesh_vert[adr:adr + num], dtype=float)


def _mesh_faces(model: Any, g: int) -> np.ndarray:
    m = int(model.geom_dataid[g])
    adr, num = int(model.mesh_faceadr[m]), int(model.mesh_facenum[m])
    return np.array(model.mesh_face[adr:adr + num], dtype=int)


def _derived_foot(model: Any, ref: Any, g: int, fwd_w: np.ndarray) -> tuple[Any, np.ndarray]:
    """mudrft foot for geom ``g`` and the foot's forward axis in the world (reference pose)."""
    mj = _mujoco()
    feet = _feet_module()
    t = int(model.geom_type[g])
    R = np.array(ref.geom_xmat[g]).reshape(3, 3)
    s = np.array(model.geom_size[g], dtype=float)
    if t == int(mj.mjtGeom.mjGEOM_BOX):
        up = int(np.argmax(np.abs(R[2])))
        hor = [i for i in range(3) if i != up]
        ix = max(hor, key=lambda i: abs(float(R[:, i] @ fwd_w)))
        iy = hor[0] if hor[1] == ix else hor[1]
        ax = R[:, ix] * (1.0 if R[:, ix] @ fwd_w >= 0 else -1.0)
        # Flat: width W along x, length L along y (decision D20 of the feet)
        foot = feet.Flat(length=2 * s[iy], width=2 * s[ix], height=2 * s[up])
        return foot, ax
    if t == int(mj.mjtGeom.mjGEOM_SPHERE):
        return feet.SemiSphere(radius=s[0], height=s[0]), fwd_w
    if t in (int(mj.mjtGeom.mjGEOM_CAPSULE), int(mj.mjtGeom.mjGEOM_CYLINDER)):
        a = R[:, 2]
        if abs(a[2]) > 0.5:
            raise MudrftError(
                f"geom {g} is a {mj.mjtGeom(t).name[7:].lower()} whose axis is not horizontal; "
                "mudrft derives a SemiCylinder from horizontal cylinders and capsules only, "
                "pass the foot explicitly (feet=...)"
            )
        a = np.array([a[0], a[1], 0.0]) / math.hypot(a[0], a[1])
        a = a if a @ fwd_w >= 0 else -a
        # SemiCylinder: axis along x; capsule caps are neglected (documented)
        return feet.SemiCylinder(radius=s[0], width=2 * s[1], height=s[0]), a
    if t == int(mj.mjtGeom.mjGEOM_MESH):
        v = _mesh_vertices(model, g) @ R.T
        low = _support(model, ref, g) - np.array(ref.geom_xpos[g])
        ex = fwd_w
        ey = np.cross([0.0, 0.0, 1.0], ex)
        frame = np.stack([ex, ey, [0.0, 0.0, 1.0]])  # rows: foot axes in the world
        return feet.MeshFoot((v - low) @ frame.T, _mesh_faces(model, g)), fwd_w
    raise MudrftError(
        f"geom {g} has type {mj.mjtGeom(t).name}, which mudrft cannot turn into a foot; "
        "use a box, sphere, capsule, cylinder or mesh, or pass the foot explicitly"
    )


def body_foot(model: Any, body: str | int, foot: Any = None, *, tip: Any = None) -> BodyFoot:
    """Place a mudrft foot on a body of a MuJoCo model.

    Parameters
    ----------
    model : mujoco.MjModel
        The model.
    body : str or int
        Body name or id.
    foot : Foot or None
        The foot; ``None`` derives it from the body's lowest geom: box -> ``Flat``,
        horizontal cylinder or capsule -> ``SemiCylinder`` (capsule caps neglected),
        sphere -> ``SemiSphere``, mesh -> ``MeshFoot``.
    tip : array_like (3,) or None, keyword-only
        Tip in the body frame [m]; default the lowest point of that geom in the
        reference pose (the body origin when the body has no geom).

    Returns
    -------
    BodyFoot
    """
    mj = _mujoco()
    if isinstance(body, str):
        bid = int(mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, body))
        if bid < 0:
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
    g = _lowest_geom(model, ref, _body_geoms(model, bid))
    if g < 0:
        if foot is None:
            raise MudrftError(f"body {name!r} has no geom to derive a foot from; pass the foot explicitly")
        kind, center, axes, size, pts = "tip", np.zeros(3), np.eye(3), np.zeros(3), np.zeros((0, 3))
        low_w = xb if tip is None else xb + Rb @ check_finite("tip", tip)
    else:
        if foot is None:
            foot, fwd_w = _derived_foot(model, ref, g, fwd_w)
        elif int(model.geom_type[g]) in (int(mj.mjtGeom.mjGEOM_CAPSULE), int(mj.mjtGeom.mjGEOM_CYLINDER)):
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
        kinds = {int(mj.mjtGeom.mjGEOM_BOX): "box", int(mj.mjtGeom.mjGEOM_SPHERE): "sphere",
                 int(mj.mjtGeom.mjGEOM_CAPSULE): "capsule", int(mj.mjtGeom.mjGEOM_CYLINDER): "cylinder",
                 int(mj.mjtGeom.mjGEOM_MESH): "points"}
        kind = kinds[t]
        pts = center + _mesh_vertices(model, g) @ axes.T if kind == "points" else np.zeros((0, 3))
        if tip is not None:
            low_w = xb + Rb @ check_finite("tip", tip)
    if not hasattr(foot, "contact_force") or not hasattr(foot, "characteristic_length"):
        raise MudrftError(f"foot for body {name!r} must be a mudrft foot (mudrft.feet), got {type(foot).__name__}")
    tip_b = Rb.T @ (low_w - xb)
    return BodyFoot(body=name, body_id=bid, foot=foot, tip=tip_b, forward=Rb.T @ fwd_w, kind=kind,
                    center=center, axes=axes, size=size, points=pts)


# ---------------------------------------------------------------------------------------
# Stability analysis
# ---------------------------------------------------------------------------------------
def stability_limits(foot: Any, mud: Any, *, mass: float, depth: float) -> dict[str, float]:
    r"""Largest explicit time steps of a foot of effective mass ``mass`` in mud.

    Linearising the vertical mud force about a tip at ``depth``:

    * viscous part, a damper :math:`c=\eta_\infty A_z/L_c`: explicit Euler is stable for
      :math:`\Delta t<2m/c` (``dt_viscous``);
    * elastic part, a spring :math:`k=\alpha n\gamma^{n-1}A_z/L_c` (infinite at
      :math:`\gamma\to0` for :math:`n<1`): symplectic Euler is stable for
      :math:`\Delta t<2\sqrt{m/k}` (``dt_elastic``);
    * suction switch, a damper :math:`c_s=\sigma_Y A_z/(2\nu L_c)` at full suction
      (``dt_suction`` = :math:`2m/c_s`).

    Parameters
    ----------
    foot : Foot
        The foot (its ``projected_areas`` and ``characteristic_length``).
    mud : Mud
        The mud (vertical set).
    mass : float
        Effective mass of the foot [kg].
    depth : float
        Tip depth [m], > 0.

    Returns
    -------
    dict
        ``dt_viscous``, ``dt_elastic``, ``dt_suction`` [s] and the coefficients
        ``damping`` [N s/m], ``stiffness`` [N/m], ``suction_damping`` [N s/m].
    """
    m = float(check_positive("mass", mass, unit="kg"))
    d = float(check_positive("depth", depth, unit="m"))
    p = mud.vertical
    lc = float(foot.characteristic_length)
    az = float(np.asarray(foot.projected_areas(d))[..., 2])
    g = d / lc
    c = float(p.eta_inf) * az / lc
    k = float(p.alpha) * float(p.n) * g ** (float(p.n) - 1.0) * az / lc
    cs = float(p.sigma_y) * az / (2.0 * float(p.nu) * lc)
    return {"dt_viscous": 2 * m / c, "dt_elastic": 2 * math.sqrt(m / k), "dt_suction": 2 * m / cs,
            "damping": c, "stiffness": k, "suction_damping": cs}


# ---------------------------------------------------------------------------------------
# The coupling
# ---------------------------------------------------------------------------------------
class MudContact(NamedTuple):
    """What the mud did in the last step, per robot and body (world frame).

    Shapes are ``(nbody, ...)`` for :class:`MudCoupling` and ``(nrobot, nbody, ...)`` for
    :class:`MudBatch`.

    Attributes
    ----------
    force : ndarray (..., 3)
        Force written to ``xfrc_applied`` (stabilised) [N].
    explicit_force : ndarray (..., 3)
        Force of the mud model at the start of the step (what :class:`mudrft.MudTerrain`
        returns for the same motion) plus the rigid bottom [N].
    torque : ndarray (..., 3)
        Moment about the body's center of mass written to ``xfrc_applied`` [N m].
    point : ndarray (..., 3)
        Point of application (center of pressure) [m].
    tip : ndarray (..., 3)
        Tip position; its z is that of the lowest point of the foot [m].
    velocity : ndarray (..., 3)
        Tip velocity [m/s].
    depth : ndarray (...)
        Depth of the lowest point below the mud surface [m].
    stress : ndarray (..., 3)
        Channel stresses in the foot frame [Pa].
    """

    force: np.ndarray
    explicit_force: np.ndarray
    torque: np.ndarray
    point: np.ndarray
    tip: np.ndarray
    velocity: np.ndarray
    depth: np.ndarray
    stress: np.ndarray


def _tree_map(fn: Any, tree: Any) -> Any:
    if tree is None:
        return None
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return type(tree)(*(_tree_map(fn, t) for t in tree))
    if isinstance(tree, (tuple, list)):
        return type(tree)(_tree_map(fn, t) for t in tree)
    if isinstance(tree, dict):
        return {k: _tree_map(fn, v) for k, v in tree.items()}
    return fn(tree)


def _batched(x: Any, batch: tuple[int, ...], k: int) -> np.ndarray:
    """Leaf of a terrain state with ``k`` copies along a new leading axis, batch-shaped."""
    a = np.asarray(x)
    if a.shape[: len(batch)] != batch:
        a = np.broadcast_to(a, batch + a.shape)
    return np.repeat(a[None], k, axis=0)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


class MudBatch:
    """Mud under named bodies of ``n`` MjData of one model, vectorized across robots.

    Every step reads the kinematics of all robots, calls the terrain once per foot type
    for all robots and bodies together, and writes ``xfrc_applied`` of each MjData.

    Parameters
    ----------
    model : mujoco.MjModel
        The model shared by all robots.
    bodies : sequence of str
        Names of the bodies that touch the mud.
    mud : Mud or Terrain
        The mud (:func:`mudrft.paper_mud`), a configured :class:`mudrft.MudTerrain`, or
        any terrain.
    n : int, keyword-only
        Number of robots.
    feet : Foot, sequence of Foot or None, keyword-only
        Foot of every body (one for all, or one per body); ``None`` derives each from the
        body's geoms (see :func:`body_foot`).
    surface : float, keyword-only
        Height of the mud surface in the world [m].
    bottom : float or None, keyword-only
        Depth of a rigid bottom below the surface [m] (a one-sided penalty on the lowest
        point of the foot), or ``None`` for bottomless mud.
    bottom_stiffness : float, keyword-only
        Stiffness of that bottom [N/m] (explicit).
    bottom_damping : float, keyword-only
        Damping of that bottom [N s/m] (treated implicitly like the mud's).
    implicit : bool, keyword-only
        Apply the semi-implicit treatment of the velocity-dependent part (default).
        ``False`` writes the explicit force, exactly what :class:`mudrft.MudTerrain` gives.
    mobility : {"chain", "body"}, keyword-only
        Tip mobility :math:`W` from the whole model (:math:`JM^{-1}J^T`, default) or from
        the body alone (cheaper, an upper bound: more damping in transients).
    center_of_pressure : {"axis", "foot", "tip"}, keyword-only
        Where the force acts: on the foot axis half-way up the submerged height (default,
        cheap), at the foot's own center of pressure (``foot.center_of_pressure``; exact
        for mesh-integrated feet but slower), or at the tip.
    """

    def __init__(
        self,
        model: Any,
        bodies: Sequence[str],
        mud: Any,
        *,
        n: int = 1,
        feet: Any = None,
        surface: float = 0.0,
        bottom: float | None = None,
        bottom_stiffness: float = 1e5,
        bottom_damping: float = 2e3,
        implicit: bool = True,
        mobility: str = "chain",
        center_of_pressure: str = "axis",
    ) -> None:
        mj = _mujoco()
        if not isinstance(model, mj.MjModel):
            raise MudrftError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        if isinstance(bodies, str):
            bodies = [bodies]
        bodies = list(bodies)
        if not bodies:
            raise MudrftError("bodies must name at least one body, got an empty list")
        if len(set(bodies)) != len(bodies):
            raise MudrftError(f"bodies must be distinct, got {bodies}")
        if not isinstance(n, (int, np.integer)) or n < 1:
            raise MudrftError(f"n must be an integer >= 1, got {n!r}")
        if mobility not in ("chain", "body"):
            raise MudrftError(f"mobility must be 'chain' or 'body', got {mobility!r}")
        if feet is None or hasattr(feet, "contact_force"):
            feet_list = [feet] * len(bodies)
        else:
            feet_list = list(feet)
            if len(feet_list) != len(bodies):
                raise MudrftError(f"feet must be one foot or one per body ({len(bodies)}), got {len(feet_list)}")
        self.model = model
        self.terrain = as_terrain(mud)
        register("todorov2012mujoco")
        self.n = int(n)
        self.surface = float(check_finite("surface", surface))
        self.bottom = None if bottom is None else float(check_positive("bottom", bottom, unit="m"))
        self.bottom_stiffness = float(check_nonnegative("bottom_stiffness", bottom_stiffness, unit="N/m"))
        self.bottom_damping = float(check_nonnegative("bottom_damping", bottom_damping, unit="N s/m"))
        self.implicit = bool(implicit)
        self.mobility = mobility
        if center_of_pressure not in ("axis", "foot", "tip"):
            raise MudrftError(f"center_of_pressure must be 'axis', 'foot' or 'tip', got {center_of_pressure!r}")
        self.use_cop = center_of_pressure if center_of_pressure != "tip" else ""
        # one foot object per identical geometry, so equal feet share one terrain call
        cache: dict[Any, Any] = {}
        placed = []
        for b, f in zip(bodies, feet_list, strict=True):
            bf = body_foot(model, b, f)
            key = repr(bf.foot) if f is None else id(f)
            foot = cache.setdefault(key, bf.foot) if f is None and _hashable_repr(bf.foot) else bf.foot
            placed.append(BodyFoot(**{**bf.__dict__, "foot": foot}))
        self.bodies: tuple[BodyFoot, ...] = tuple(placed)
        self._ids = np.array([b.body_id for b in self.bodies])
        self._roots = np.array(model.body_rootid)[self._ids]
        self._tip = np.stack([b.tip for b in self.bodies])
        self._fwd = np.stack([b.forward for b in self.bodies])
        groups: dict[int, list[int]] = {}
        for i, placed_body in enumerate(self.bodies):
            groups.setdefault(id(placed_body.foot), []).append(i)
        self._groups = [(self.bodies[idx[0]].foot, np.array(idx)) for idx in groups.values()]
        nb = len(self.bodies)
        self._states: list[Any] = [None] * len(self._groups)
        self._foot_xy = np.zeros((self.n, nb, 2))
        self._world_xy = np.zeros((self.n, nb, 2))
        self._v_prev = np.zeros((self.n, nb, 3))
        self._wf_prev = np.zeros((self.n, nb, 3))
        self._has_prev = False
        self._jac = np.zeros((3, model.nv))
        self._minv_jt = np.zeros((3, model.nv))
        self._dv_min = 1e-4  # smallest secant step in velocity [m/s] (D63)
        self.last: MudContact | None = None
        self.time_steps = 0

    # -- reading MuJoCo ---------------------------------------------------------------
    def _read(self, datas: Sequence[Any]) -> dict[str, np.ndarray]:
        mj = _mujoco()
        m = self.model
        ids, roots = self._ids, self._roots
        if len(datas) == 1:
            d = datas[0]
            X, R, C = d.xpos[ids][None], d.xmat[ids].reshape(1, -1, 3, 3), d.xipos[ids][None]
            V, S = d.cvel[ids][None], d.subtree_com[roots][None]
        else:
            X = np.stack([d.xpos for d in datas])[:, ids]
            R = np.stack([d.xmat for d in datas])[:, ids].reshape(len(datas), -1, 3, 3)
            C = np.stack([d.xipos for d in datas])[:, ids]
            V = np.stack([d.cvel for d in datas])[:, ids]
            S = np.stack([d.subtree_com for d in datas])[:, roots]
        tip = X + (R @ self._tip[..., None])[..., 0]
        low = self._lowest(X, R, tip)
        w, vlin = V[..., :3], V[..., 3:]
        v_tip = vlin + _cross(w, tip - S)
        r = low - S  # z velocity of the material point that is lowest (envelope theorem)
        vz_low = vlin[..., 2] + w[..., 0] * r[..., 1] - w[..., 1] * r[..., 0]
        W = None
        if self.implicit:
            if self.mobility == "chain":
                N, nb = tip.shape[:2]
                W = np.empty((N, nb, 3, 3))
                jac, mjt = self._jac, self._minv_jt
                for k, d in enumerate(datas):
                    for j, b in enumerate(ids):
                        mj.mj_jac(m, d, jac, None, tip[k, j], int(b))
                        mj.mj_solveM(m, d, mjt, jac)
                        W[k, j] = jac @ mjt.T
            else:
                W = self._body_mobility(datas, tip, C)
        return {"R": R, "com": C, "tip": tip, "low": low, "v_tip": v_tip, "vz_low": vz_low, "W": W}

    def _body_mobility(self, datas: Sequence[Any], tip: np.ndarray, com: np.ndarray) -> np.ndarray:
        m = self.model
        ids = self._ids
        mass = np.array(m.body_mass)[ids]
        inert = np.array(m.body_inertia)[ids]
        N, nb = tip.shape[:2]
        Ri = np.stack([d.ximat for d in datas])[:, ids].reshape(N, nb, 3, 3)
        inv_i = np.einsum("kbij,bj,kblj->kbil", Ri, 1.0 / np.maximum(inert, 1e-12), Ri)
        r = tip - com
        rx = np.zeros((N, nb, 3, 3))
        rx[..., 0, 1], rx[..., 0, 2] = -r[..., 2], r[..., 1]
        rx[..., 1, 0], rx[..., 1, 2] = r[..., 2], -r[..., 0]
        rx[..., 2, 0], rx[..., 2, 1] = -r[..., 1], r[..., 0]
        return (np.eye(3) / mass[:, None, None]) + rx @ inv_i @ np.swapaxes(rx, -1, -2)

    def _lowest(self, X: np.ndarray, R: np.ndarray, tip: np.ndarray) -> np.ndarray:
        """Lowest point of each foot geom in its current pose (world) [m]."""
        low = tip.copy()
        for j, b in enumerate(self.bodies):
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

    # -- public API -------------------------------------------------------------------
    def reset(self, datas: Sequence[Any]) -> None:
        """Start with undisturbed mud under the feet in their current pose (calls mj_forward)."""
        mj = _mujoco()
        datas = self._check(datas)
        for d in datas:
            mj.mj_forward(self.model, d)
        k = self._read(datas)
        pos, _vel, _cs = self._foot_frame(k, fresh=True)
        for gi, (foot, idx) in enumerate(self._groups):
            self._states[gi] = self.terrain.initial_state(foot, pos[:, idx])
        self._world_xy = k["tip"][..., :2]
        self._has_prev = False
        self._wf_prev[:] = 0.0
        self.last = None
        for d in datas:
            d.xfrc_applied[self._ids] = 0.0

    def _check(self, datas: Any) -> list[Any]:
        mj = _mujoco()
        if isinstance(datas, mj.MjData):
            datas = [datas]
        datas = list(datas)
        if len(datas) != self.n:
            raise MudrftError(f"expected {self.n} MjData, got {len(datas)}")
        return datas

    def _foot_frame(self, k: dict[str, np.ndarray], *, fresh: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Tip position and velocity in the foot frame, and (cos, sin) of the foot's yaw."""
        fw = (k["R"] @ self._fwd[..., None])[..., 0]
        h = np.maximum(np.hypot(fw[..., 0], fw[..., 1]), 1e-12)
        cs = np.stack([fw[..., 0] / h, fw[..., 1] / h], axis=-1)  # the foot's heading (yaw)
        c, s = cs[..., 0], cs[..., 1]
        tip, v = k["tip"], k["v_tip"]
        if fresh:
            xy = tip[..., :2]
            fxy = np.stack([c * xy[..., 0] + s * xy[..., 1], c * xy[..., 1] - s * xy[..., 0]], axis=-1)
        else:
            # odometry in the foot frame: a yawing foot sees no jump in its position (D65);
            # out of the mud the position restarts from the rotated world position
            was_in = self._in_mud()[..., None]
            xy = np.where(was_in, tip[..., :2] - self._world_xy, tip[..., :2])
            base = np.where(was_in, self._foot_xy, 0.0)
            fxy = base + np.stack([c * xy[..., 0] + s * xy[..., 1], c * xy[..., 1] - s * xy[..., 0]], axis=-1)
        self._foot_xy = fxy
        pos = np.concatenate([fxy, k["low"][..., 2:] - self.surface], axis=-1)
        vel = np.stack([c * v[..., 0] + s * v[..., 1], c * v[..., 1] - s * v[..., 0], k["vz_low"]], axis=-1)
        return pos, vel, cs

    def _in_mud(self) -> np.ndarray:
        out = np.zeros((self.n, len(self.bodies)), dtype=bool)
        for (_, idx), st in zip(self._groups, self._states, strict=True):
            im = getattr(st, "in_mud", None)
            out[:, idx] = np.broadcast_to(im, (self.n, len(idx))) if im is not None else True
        return out

    def apply(self, datas: Sequence[Any]) -> MudContact:
        """Advance the mud once and write ``xfrc_applied`` for the current state.

        Call after ``mj_step1`` (or ``mj_forward``) and before ``mj_step2``; :meth:`step`
        does all three.
        """
        return self._apply(self._check(datas))

    def _apply(self, datas: list[Any]) -> MudContact:
        if self._states[0] is None:
            raise MudrftError("call reset(data) before stepping the mud coupling")
        dt = float(self.model.opt.timestep)
        k = self._read(datas)
        pos, vel, cs = self._foot_frame(k, fresh=False)
        self._world_xy = k["tip"][..., :2]
        c, s = cs[..., 0], cs[..., 1]
        N, nb = pos.shape[:2]
        f0 = np.empty((N, nb, 3))
        jd = np.zeros((N, nb, 3))
        stress = np.empty((N, nb, 3))
        cop = np.zeros((N, nb, 3))
        depth = np.maximum(-pos[..., 2], 0.0)
        if self.implicit:
            # secant steps: the velocity change the last force made in one step (D63)
            wf = self._wf_prev * dt
            wf = np.stack([c * wf[..., 0] + s * wf[..., 1], c * wf[..., 1] - s * wf[..., 0], wf[..., 2]], -1)
            step = np.where(np.abs(wf) > self._dv_min, wf, self._dv_min)
        for gi, (foot, idx) in enumerate(self._groups):
            st = self._states[gi]
            p, v = (pos, vel) if len(idx) == nb else (pos[:, idx], vel[:, idx])
            if self.implicit:
                # one batched terrain call: the motion, and the motion with each velocity
                # component nudged, for the secant derivative of the force (D61, D63)
                vk = np.repeat(v[None], 4, axis=0)
                sk = step if len(idx) == nb else step[:, idx]
                vk[1, ..., 0] += sk[..., 0]
                vk[2, ..., 1] += sk[..., 1]
                vk[3, ..., 2] += sk[..., 2]
                batch = p.shape[:-1]
                stk = _tree_map(lambda x, b=batch: _batched(x, b, 4), st)
                new, out = self.terrain.step(foot, stk, np.broadcast_to(p, vk.shape), vk, dt)
                new = _tree_map(lambda x: x[0] if np.ndim(x) else x, new)
                fk = np.asarray(out.force)
                f0[:, idx] = fk[0]
                jd[:, idx] = (np.stack([fk[1, ..., 0], fk[2, ..., 1], fk[3, ..., 2]], axis=-1) - fk[0]) / sk
                sg = np.asarray(out.stress)[0]
            else:
                new, out = self.terrain.step(foot, st, p, v, dt)
                f0[:, idx] = np.asarray(out.force)
                sg = np.asarray(out.stress)
            self._states[gi] = new
            stress[:, idx] = sg
            if self.use_cop:
                d = depth[:, idx]
                if self.use_cop == "foot":
                    heading = np.broadcast_to(getattr(new, "heading", 0.0), d.shape)
                    cp = np.asarray(foot.center_of_pressure(d, sg, heading), dtype=float)
                    cop[:, idx] = np.where((d > 0)[..., None], cp, 0.0)
                else:  # on the axis, half-way up the submerged height
                    cop[:, idx, 2] = 0.5 * np.minimum(d, float(foot.height))
        if self.bottom is not None:
            pen = depth - self.bottom
            on = pen > 0
            fb = np.where(on, np.maximum(self.bottom_stiffness * pen - self.bottom_damping * vel[..., 2], 0.0), 0.0)
            f0[..., 2] += fb
            jd[..., 2] -= np.where(on & (fb > 0), self.bottom_damping, 0.0)
        f0_w = np.stack([c * f0[..., 0] - s * f0[..., 1], s * f0[..., 0] + c * f0[..., 1], f0[..., 2]], axis=-1)
        if self.implicit:
            # linearly implicit step of the dissipative part (D62): F = (I - dt D W)^-1 (F0 + dt D a)
            dx, dy, dz = (np.minimum(jd[..., i], 0.0) for i in range(3))
            D = np.zeros((N, nb, 3, 3))  # world frame: R diag(dx, dy, dz) R^T, R the yaw
            D[..., 0, 0] = c * c * dx + s * s * dy
            D[..., 1, 1] = s * s * dx + c * c * dy
            D[..., 0, 1] = D[..., 1, 0] = c * s * (dx - dy)
            D[..., 2, 2] = dz
            if self._has_prev:
                acc = (k["v_tip"] - self._v_prev) / dt - self._wf_prev
            else:
                acc = np.broadcast_to(np.asarray(self.model.opt.gravity, dtype=float), f0_w.shape)
            W = k["W"]
            A = np.eye(3) - dt * (D @ W)
            rhs = f0_w + dt * (D @ acc[..., None])[..., 0]
            force = np.linalg.solve(A, rhs[..., None])[..., 0]
            self._wf_prev = (W @ force[..., None])[..., 0]
        else:
            force = f0_w
        self._v_prev = k["v_tip"]
        self._has_prev = True
        tip = np.concatenate([k["tip"][..., :2], k["low"][..., 2:]], axis=-1)
        point = tip.copy()
        point[..., 0] += c * cop[..., 0] - s * cop[..., 1]
        point[..., 1] += s * cop[..., 0] + c * cop[..., 1]
        point[..., 2] += cop[..., 2]
        torque = _cross(point - k["com"], force)
        wrench = np.concatenate([force, torque], axis=-1)
        if not np.all(np.isfinite(wrench)):
            raise MudrftError("the mud coupling produced a non-finite force; the simulation diverged "
                              "(check the model, the time step and the mud parameters)")
        for i, d in enumerate(datas):
            d.xfrc_applied[self._ids] = wrench[i]
        self.time_steps += 1
        self.last = MudContact(force=force, explicit_force=f0_w, torque=torque, point=point,
                               tip=tip, velocity=k["v_tip"], depth=depth, stress=stress)
        return self.last

    def step(self, datas: Sequence[Any], nstep: int = 1) -> MudContact:
        """``nstep`` physics steps of every robot, the mud advanced once per step."""
        return self._step(self._check(datas), nstep)

    def _step(self, datas: list[Any], nstep: int) -> MudContact:
        mj = _mujoco()
        m = self.model
        rk4 = int(m.opt.integrator) == int(mj.mjtIntegrator.mjINT_RK4)
        out = self.last
        for _ in range(int(nstep)):
            if rk4:  # mj_step1/mj_step2 do not support RK4: full forward, then mj_step
                for d in datas:
                    mj.mj_forward(m, d)
                out = self._apply(datas)
                for d in datas:
                    mj.mj_step(m, d)
            else:
                for d in datas:
                    mj.mj_step1(m, d)
                out = self._apply(datas)
                for d in datas:
                    mj.mj_step2(m, d)
        assert out is not None
        return out


def _hashable_repr(foot: Any) -> bool:
    # dataclass feet with eq=True print their parameters; equal reprs = equal geometry
    return type(foot).__repr__ is not object.__repr__ and "(" in repr(foot) and "=" in repr(foot)


class MudCoupling(MudBatch):
    """Mud under named bodies of one MuJoCo model and one MjData (see :class:`MudBatch`).

    Outputs in :attr:`last` have shape ``(nbody, ...)``.
    """

    def __init__(self, model: Any, bodies: Sequence[str], mud: Any, **kw: Any) -> None:
        if "n" in kw:
            raise MudrftError("MudCoupling couples one MjData; use MudBatch(n=...) for many")
        super().__init__(model, bodies, mud, n=1, **kw)

    def reset(self, data: Any) -> None:  # type: ignore[override]
        """Start with undisturbed mud under the feet in their current pose."""
        super().reset([data])

    def apply(self, data: Any) -> MudContact:  # type: ignore[override]
        """Advance the mud once and write ``data.xfrc_applied`` (after ``mj_step1``)."""
        self.last = MudContact(*(a[0] for a in self._apply(self._check(data))))
        return self.last

    def step(self, data: Any, nstep: int = 1) -> MudContact:  # type: ignore[override]
        """``nstep`` physics steps, the mud advanced once per step."""
        self.last = MudContact(*(a[0] for a in self._step(self._check(data), nstep)))
        return self.last


def attach(model: Any, bodies: Sequence[str] | str, mud: Any, **kw: Any) -> MudCoupling:
    """Attach mud to named bodies of a MuJoCo model; see :class:`MudBatch` for options.

    Examples
    --------
    >>> import mujoco, mudrft
    >>> from mudrft.integrations.mujoco import attach
    >>> xml = '''<mujoco><worldbody><body name="foot" pos="0 0 0.01">
    ...   <freejoint/><geom type="box" size="0.0325 0.04 0.013" mass="1"/></body></worldbody></mujoco>'''
    >>> model = mujoco.MjModel.from_xml_string(xml)
    >>> data = mujoco.MjData(model)
    >>> coupling = attach(model, "foot", mudrft.paper_mud(0.25))
    >>> coupling.reset(data)
    >>> out = coupling.step(data, 500)
    >>> bool(out.depth[0] > 0 and out.force[0, 2] > 0)
    True
    """
    return MudCoupling(model, [bodies] if isinstance(bodies, str) else bodies, mud, **kw)


def attach_batch(model: Any, bodies: Sequence[str] | str, mud: Any, *, n: int, **kw: Any) -> MudBatch:
    """Attach mud to named bodies of ``n`` robots of one model; see :class:`MudBatch`."""
    return MudBatch(model, [bodies] if isinstance(bodies, str) else bodies, mud, n=n, **kw)
