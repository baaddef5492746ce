r"""One coupling step of the mud under the feet of one MJX robot, as a pure JAX function.

:func:`mud_wrench` is what :class:`~mudrft.integrations.mujoco.MudBatch` does between
``mj_step1`` and ``mj_step2``, for an MJX ``Data`` after ``fwd_position`` and
``fwd_velocity``, so that :func:`jax.jit`, :func:`jax.vmap`, :func:`jax.lax.scan` and
:func:`jax.grad` apply. The posed feet, the mud step, the wrench, its implicit step and
the passivity bound are the CPU coupling's own functions called with ``xp=jax.numpy``;
the mobility comes from ``mjx.jac`` and ``mjx.full_m``. Shapes: ``nb`` bodies of one robot.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from ...feet.surface import PreparedTriangles
from ...terrains.field import field_blend, surface_blend
from ...terrains.mud import MudChannels, MudTerrain, initial_channels, mud_step
from ..mujoco.pose import matvec, on_planes, secant_steps
from ._lazy import _jax, _mjx, _xp
from .pose import ChannelGeometry, posed_channels
from .wrench import applied_wrench, channel_motion, com_twist, foot_odometry

if TYPE_CHECKING:
    import jax
    from mujoco import mjx

    from ..._typing import XpArray
    from ...constitutive.kernel import ChannelConstants

__all__ = ["MAX_SPEED", "MjxContact", "MjxMudState", "Static", "initial_state", "mud_wrench"]

#: A foot body's center of mass moving faster than this is unstable [m/s]: no robot walks
#: or falls into mud at 100 m/s, a diverged simulation does (a body thrown in at 1e6 m/s
#: turned the whole state into NaN).
MAX_SPEED = 100.0


class MjxMudState(NamedTuple):
    """The coupling's memory for one robot (a JAX pytree; leading robot axis when batched).

    Attributes
    ----------
    mud : MudChannels
        The mud under each foot, arrays of shape (nb,).
    foot_xy : array (nb, 2)
        Tip odometry in the foot frame [m] (D65).
    world_tip : array (nb, 3)
        Tip position in the world at the last step [m].
    tw_prev : array (nb, 6)
        Body twist at the last step [m/s, rad/s].
    wv_prev : array (nb, 6)
        Mobility times the last wrench, :math:`Ww` [m/s^2, rad/s^2].
    has_prev : array ()
        1.0 after the first step, else 0.0.
    tank : array ()
        Energy the mud has taken from the robot and may give back (D62c, D62d) [J].
    """

    mud: MudChannels
    foot_xy: Any
    world_tip: Any
    tw_prev: Any
    wv_prev: Any
    has_prev: Any
    tank: Any


class MjxContact(NamedTuple):
    """What the coupling applied at one step, per body (world frame).

    Attributes
    ----------
    force : array (nb, 3)
        Force applied at the body's center of mass (the implicit wrench, bounded by D62c) [N].
    torque : array (nb, 3)
        Moment about the center of mass [N m].
    explicit_force : array (nb, 3)
        The explicit mud force before the implicit step [N].
    depth : array (nb,)
        Depth of the foot's lowest point [m].
    stress : array (nb, 3)
        Channel stresses [Pa].
    tip : array (nb, 3)
        Lowest point of each foot [m].
    velocity : array (nb, 3)
        Channel velocities where each channel acts [m/s].
    finite : array ()
        True when every component of the wrench is finite.
    unstable : array ()
        True when the robot's ``qpos`` or ``qvel`` is not finite, a foot body's center
        of mass moves faster than :data:`MAX_SPEED`, or the wrench is not finite; the
        step then holds the mud state and applies no wrench (``force``, ``torque`` and
        ``explicit_force`` are zero), so that the NaN does not enter the mud. ``jit``
        cannot raise: check this flag (the environments end the episode on it).
    """

    force: Any
    torque: Any
    explicit_force: Any
    depth: Any
    stress: Any
    tip: Any
    velocity: Any
    finite: Any
    unstable: Any


@dataclass(frozen=True, eq=False)
class Group:
    """Bodies with one foot: indices, characteristic length, force rule, triangles (numpy)."""

    idx: np.ndarray
    lc: float
    force_fn: Any
    triangles: np.ndarray  # (nb_g, m, 3, 3) in the body frames (a ball's: about its center) [m]
    upright: PreparedTriangles  # the foot in its own frame
    ball: bool = False  # a sphere geom's foot, the same from every angle


@dataclass(frozen=True, eq=False)
class Static:
    """Everything the step needs that is not traced: the placement of the feet, options."""

    ids: np.ndarray
    roots: np.ndarray
    tip: np.ndarray  # (nb, 3) body frame, a ball's center [m]
    forward: np.ndarray  # (nb, 3) body frame [-]
    ball: np.ndarray  # (nb,) bool
    groups: tuple[Group, ...]
    surface: float
    bottom: float | None
    bottom_stiffness: float
    bottom_damping: float
    terrain: MudTerrain  # its options (all but the mud's constants)
    dv_min: float = 1e-4
    uneven: bool = False  # a field with heights: each foot turned onto its surface (D175)


def _frames(cfg: Static, d: mjx.Data) -> dict[str, XpArray]:
    """Body frames, tips, yaw and twist of the foot bodies (``MudBatch._read``)."""
    xp = _xp()
    ids, roots = cfg.ids, cfg.roots
    X, R, C = d.xpos[ids], d.xmat[ids].reshape(-1, 3, 3), d.xipos[ids]
    V, S = d.cvel[ids], d.subtree_com[roots]
    tip = X + matvec(R, xp.asarray(cfg.tip))
    X = xp.where(xp.asarray(cfg.ball)[:, None], tip, X)  # a ball's center
    fw = matvec(R, xp.asarray(cfg.forward))
    h = xp.maximum(xp.hypot(fw[..., 0], fw[..., 1]), 1e-12)
    cs = xp.stack([fw[..., 0] / h, fw[..., 1] / h], axis=-1)
    return {"X": X, "R": R, "C": C, "tip": tip, "cs": cs, "tw": com_twist(V, S, C, xp=xp)}


def _on_planes(
    cfg: Static, k: dict[str, XpArray], field: tuple[XpArray, ...]
) -> tuple[dict[str, XpArray], XpArray, XpArray, XpArray]:
    """:func:`_frames` of each foot on the tangent plane of ``field``'s surface under its tip
    (:func:`~mudrft.integrations.mujoco.pose.on_planes`); and the frames (nb, 3, 3), P and
    P' [m]."""
    xp = _xp()
    grid, cells, _, heights = field
    tip, tw = k["tip"], k["tw"]
    ny, nx = cells.shape
    slope = surface_blend(tip[..., 0], tip[..., 1], grid, ny, nx, heights, xp=xp)
    X, R, C, tip_l, Q, P, Pd = on_planes(k["X"], k["R"], k["C"], tip, *slope, cfg.surface, xp=xp)
    fw = matvec(R, xp.asarray(cfg.forward))
    h = xp.maximum(xp.hypot(fw[..., 0], fw[..., 1]), 1e-12)
    local = {
        "X": X, "R": R, "C": C, "tip": tip_l,
        "cs": xp.stack([fw[..., 0] / h, fw[..., 1] / h], axis=-1),
        "tw": xp.concatenate([matvec(Q, tw[..., :3]), matvec(Q, tw[..., 3:])], axis=-1),
    }  # fmt: skip
    return local, Q, P, Pd


def _mobility(cfg: Static, mx: mjx.Model, d: mjx.Data, C: XpArray) -> XpArray:
    """Mobility (nb, nb, 6, 6) of the foot bodies' center-of-mass twists (D62d)."""
    xp = _xp()
    mjx = _mjx()
    rows = []
    for j, b in enumerate(cfg.ids):
        jp, jr = mjx.jac(mx, d, C[j], int(b))  # (nv, 3) each
        rows.append(xp.concatenate([jp.T, jr.T], axis=0))
    J = xp.stack(rows)  # (nb, 6, nv)
    M = mjx.full_m(mx, d)
    jax = _jax()
    fac = jax.scipy.linalg.cho_factor(M)
    minv_jt = jax.scipy.linalg.cho_solve(fac, xp.concatenate(rows, axis=0).T)  # (nv, 6 nb)
    minv_jt = xp.moveaxis(minv_jt.reshape(M.shape[0], -1, 6), 1, 0)  # (nb, nv, 6)
    return xp.einsum("iav,jvb->ijab", J, minv_jt)  # (nb, nb, 6, 6), cross blocks (D62d)


def _posed(cfg: Static, k: dict[str, XpArray]) -> tuple[ChannelGeometry, XpArray]:
    """Channel geometry of each posed foot and its ratio to the upright foot (D60a)."""
    groups = [(g.triangles, g.upright, g.idx, g.ball) for g in cfg.groups]
    X, R, C, cs = (k[n][None] for n in ("X", "R", "C", "cs"))
    geo, ratio = posed_channels(groups, X, R, C, cs, cfg.surface, xp=_xp())
    return ChannelGeometry(*(a[0] for a in geo)), ratio[0]


def _take(tree: Any, idx: Any) -> Any:
    """Every leaf of a pytree (mud state, constants) indexed by ``idx``."""
    return _jax().tree_util.tree_map(lambda a: a[idx], tree)


def _force_and_derivative(
    cfg: Static,
    g: Group,
    consts: tuple[ChannelConstants, ChannelConstants],
    st: MudChannels,
    pos: jax.Array,
    vel: jax.Array,
    step: jax.Array,
    dt: float | jax.Array,
) -> tuple[MudChannels, jax.Array, jax.Array, jax.Array]:
    """The mud step of four copies of the motion (D61, D63): as it is, and with each
    channel's velocity nudged by ``step`` [m/s] (the secant derivative toward rest)."""
    xp = _xp()
    nudge = xp.asarray(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]))
    vk = vel[None] + nudge[:, None, :] * step[None]
    n = vk.shape[0]
    st4 = _jax().tree_util.tree_map(lambda a: xp.broadcast_to(a, (n, *a.shape)), st)
    p4, t = xp.broadcast_to(pos, vk.shape), cfg.terrain
    new, sx, sy, sz, depth = mud_step(
        consts, st4, p4[..., 0], p4[..., 1], p4[..., 2], vk[..., 0], vk[..., 1], vk[..., 2], dt,
        g.lc, t.kappa, t.xi0, t.reset_on_exit, t.heading_speed, 1.0, t.quasi_static, t.restart,
        xp=xp,
    )  # fmt: skip
    stress = xp.stack([sx, sy, sz], axis=-1)
    fk = g.force_fn(depth, stress, new.heading) * new.in_mud[..., None]
    new = _take(new, 0)
    jd = (xp.stack([fk[1, ..., 0], fk[2, ..., 1], fk[3, ..., 2]], axis=-1) - fk[0]) / step
    return new, fk[0], jd, stress[0]


def mud_wrench(
    cfg: Static,
    consts: tuple[ChannelConstants, ChannelConstants],
    mx: mjx.Model,
    d: mjx.Data,
    st: MjxMudState,
    field: tuple[XpArray, XpArray, XpArray, XpArray] | None = None,
) -> tuple[jax.Array, MjxMudState, MjxContact]:
    """``(xfrc_applied, state, contact)``: the mud's wrench on every foot body [N, N m]
    for robot ``d`` (after ``fwd_position`` and ``fwd_velocity``) from state ``st``, with the
    feet's placement ``cfg`` and the (horizontal, vertical) channel constants ``consts``,
    or, where ``field`` (``MjxCoupling.field_arrays``: grid, cells, rows, heights) is given,
    the field's under each tip (:func:`~mudrft.terrains.field.field_blend`: constants, and
    the mud's share of the force), on its uneven surface where ``cfg.uneven`` (D175).
    """
    xp = _xp()
    dt = mx.opt.timestep
    k = _frames(cfg, d)
    world_tip, world_tw, world_com, Q = k["tip"], k["tw"], k["C"], None
    odo_tip, odo_last = world_tip[..., :2], st.world_tip[..., :2]
    if cfg.uneven and field is not None:  # each foot on the tangent plane under its tip
        k, Q, P, Pd = _on_planes(cfg, k, field)
        odo_tip, odo_last = matvec(Q, world_tip)[..., :2], matvec(Q, st.world_tip)[..., :2]
    geo, ratio = _posed(cfg, k)
    cs, tw, com, tip = k["cs"], k["tw"], k["C"], k["tip"]
    share = None
    if field is not None:  # per foot: the mud under its tip
        share, c = field_blend(world_tip[..., 0], world_tip[..., 1], *field[:3], xp=xp)
        h, v = consts
        consts = (type(h)(*(c[..., i] for i in range(12))), type(v)(*(c[..., 12 + i] for i in range(12))))  # fmt: skip
    _rel, b, vel = channel_motion(cs, geo.point, com, tw, cfg.surface, xp=xp)
    fxy = foot_odometry(cs, odo_tip, st.mud.in_mud > 0.5, odo_last, st.foot_xy, xp=xp)
    pos = xp.concatenate([fxy, geo.low[..., 2:]], axis=-1)
    depth = xp.maximum(-pos[..., 2], 0.0)
    step = secant_steps(vel, cfg.dv_min, xp=xp)
    mud, f_up, jd, stress = st.mud, xp.zeros_like(pos), xp.zeros_like(pos), xp.zeros_like(pos)
    for g in cfg.groups:
        idx = g.idx
        cg = consts if field is None else _take(consts, idx)
        new, fg, jg, sg = _force_and_derivative(
            cfg, g, cg, _take(st.mud, idx), pos[idx], vel[idx],
            step[idx], dt,
        )  # fmt: skip
        mud = _jax().tree_util.tree_map(lambda a, v, i=idx: a.at[i].set(v), mud, new)
        f_up, jd, stress = f_up.at[idx].set(fg), jd.at[idx].set(jg), stress.at[idx].set(sg)
    if share is not None:  # rigid ground carries the rest (MuJoCo's contact)
        f_up, jd = f_up * share[..., None], jd * share[..., None]
    W = _mobility(cfg, mx, d, world_com)
    g0 = xp.concatenate([mx.opt.gravity, xp.zeros(3)]) + xp.zeros_like(tw)
    # the other forces' twist acceleration, from the last step's twists (D62)
    acc = xp.where(st.has_prev > 0.5, (world_tw - st.tw_prev) / dt - st.wv_prev, g0)
    wrench, w0, tank, wv = applied_wrench(
        ratio, f_up, jd, b, geo, cs, tw, com, depth, W, acc, st.tank, dt,
        surface=cfg.surface, bottom=cfg.bottom, stiffness=cfg.bottom_stiffness,
        damping=cfg.bottom_damping, frame=Q, world_tw=world_tw, xp=xp,
    )  # fmt: skip
    finite = xp.all(xp.isfinite(wrench))
    fast = xp.any(xp.sum(world_tw[..., :3] ** 2, axis=-1) > MAX_SPEED**2)
    unstable = ~(finite & xp.all(xp.isfinite(d.qpos)) & xp.all(xp.isfinite(d.qvel))) | fast
    wrench, w0 = xp.where(unstable, 0.0, wrench), xp.where(unstable, 0.0, w0)
    xfrc = d.xfrc_applied.at[cfg.ids].set(wrench)
    new_state = MjxMudState(mud, fxy, world_tip, world_tw, wv, xp.ones_like(st.has_prev), tank)
    new_state = _jax().tree_util.tree_map(
        lambda new, old: xp.where(unstable, old, new), new_state, st
    )  # an unstable robot's mud is held
    low = xp.concatenate([tip[..., :2], geo.low[..., 2:] + cfg.surface], -1)
    if Q is not None:  # back to the world
        low = P + xp.einsum("...ji,...j->...i", Q, low - Pd)
    out = MjxContact(
        force=wrench[..., :3], torque=wrench[..., 3:], explicit_force=w0[..., :3], depth=depth,
        stress=stress, tip=low, velocity=vel, finite=finite, unstable=unstable,
    )  # fmt: skip
    return xfrc, new_state, out


def initial_state(
    cfg: Static, d: mjx.Data, field: tuple[XpArray, ...] | None = None
) -> MjxMudState:
    """Undisturbed mud under the feet of ``d`` (after ``mjx.kinematics`` and
    ``mjx.com_pos``) in their current pose, on ``field`` (its arrays) where it is uneven.
    """
    xp = _xp()
    k = _frames(cfg, d)
    tip = k["tip"]
    xy = tip[..., :2]
    if cfg.uneven and field is not None:
        k, Q, _, _ = _on_planes(cfg, k, field)
        xy = matvec(Q, tip)[..., :2]
    low = _posed(cfg, k)[0].low
    fxy = foot_odometry(k["cs"], xy, xp=xp)
    depth = xp.maximum(-low[..., 2], 0.0)
    lc = np.zeros(len(cfg.ids))
    for g in cfg.groups:
        lc[g.idx] = g.lc
    mud = initial_channels(fxy[..., 0], fxy[..., 1], depth, xp.asarray(lc), cfg.terrain.xi0, xp=xp)
    zero6, zero = xp.zeros((len(cfg.ids), 6), dtype=tip.dtype), xp.zeros((), dtype=tip.dtype)
    return MjxMudState(mud, fxy, tip, zero6, zero6, zero, zero)
