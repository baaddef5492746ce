r"""The wrench of the mud on a posed foot, and its linearly implicit step (D60a, D62).

The terrain's force :math:`F^{up}` on the upright foot at the posed foot's depth is scaled
per channel by :math:`\rho_c=A_c/A_c^{up}` and acts at the channel's point (:mod:`.pose`),
:math:`w_0=\sum_c \rho_cF^{up}_c\,b_c` with :math:`b_c=(\mathbf e_c,\ \mathbf r_c\times\mathbf e_c)`;
the coupling applies

.. math:: w = (I - \Delta t\,K\,W)^{-1}\,(w_0 + \Delta t\,K\,a),

with :math:`w_0` the explicit wrench, :math:`W` the mobility, :math:`a` the twist
acceleration from all other forces and :math:`K` the symmetric negative semi-definite
damping of the wrench (D62a), from secant derivatives (D63); :func:`passive_wrench` then
bounds its work by the energy the mud has taken (D62c). Shapes: ``N`` robots, ``nb``
bodies; ``cs`` holds the cosine and sine of each foot's yaw.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..._typing import ArrayLike, FloatArray, Namespace, XpArray
from .pose import ChannelGeometry, rowdot

if TYPE_CHECKING:
    from ...feet.base import Foot
    from ...terrains import Terrain

__all__ = [
    "applied_wrench",
    "bottom_wrench",
    "channel_motion",
    "channel_rows",
    "damping_matrix",
    "foot_odometry",
    "force_and_derivative",
    "implicit_wrench",
    "passive_wrench",
    "passivity_scale",
    "posed_wrench",
    "secant_steps",
    "yaw_inertia_to_world",
]


def secant_steps(vel: XpArray, dv_min: float, xp: Namespace = np) -> XpArray:
    r"""Velocity steps [m/s] of the secant derivative toward rest (D63, D119), element-wise.

    The step is :math:`-u` for channel velocities ``vel`` [m/s]; within ``dv_min`` [m/s] of
    rest it is ``dv_min`` across it, so a resting foot sees the suction switch's own slope.
    ``xp``: numpy, ``jax.numpy`` or floats (the compiled coupling).
    """
    across = xp.where(vel > 0.0, -dv_min, dv_min)
    return xp.where(xp.abs(vel) > dv_min, -vel, across)


def channel_rows(cs: FloatArray, rel: FloatArray, xp: Namespace = np) -> FloatArray:
    r"""Rows :math:`b_c=(\mathbf e_c,\ \mathbf r_c\times\mathbf e_c)` (N, nb, 3, 6) of the channels.

    ``cs`` (N, nb, 2): cosine and sine of each foot's yaw; ``rel`` (N, nb, 3, 3): each
    channel's point relative to the center of mass [m]. :math:`b_c\cdot\xi` is that point's
    velocity along :math:`\mathbf e_c`; :math:`f\,b_c` the wrench of a force :math:`f\mathbf e_c` there.
    """
    c, s = cs[..., 0], cs[..., 1]
    z, o = xp.zeros_like(c), xp.ones_like(c)
    E = xp.stack(
        [xp.stack([c, s, z], -1), xp.stack([-s, c, z], -1), xp.stack([z, z, o], -1)], axis=-2
    )
    return xp.concatenate([E, xp.cross(rel, E)], axis=-1)


def channel_motion(
    cs: XpArray, point: XpArray, com: XpArray, tw: XpArray, surface: float, xp: Namespace = np
) -> tuple[XpArray, XpArray, XpArray]:
    """Each channel's point relative to the center of mass ``com`` [m] (world frame), its
    row :math:`b_c` and its velocity [m/s], from the points ``point`` in the yaw frame
    (:class:`~.pose.ChannelGeometry`) [m] and the twists ``tw`` [m/s, rad/s].
    """
    c, s = cs[..., 0], cs[..., 1]
    rel = xp.stack(
        [c[..., None] * point[..., 0] - s[..., None] * point[..., 1],
         s[..., None] * point[..., 0] + c[..., None] * point[..., 1],
         point[..., 2] + (surface - com[..., None, 2])], axis=-1,
    )  # fmt: skip
    b = channel_rows(cs, rel, xp=xp)
    return rel, b, rowdot(b, tw[..., None, :])


def foot_odometry(
    cs: XpArray,
    tip_xy: XpArray,
    was_in: XpArray | None = None,
    world_xy: XpArray | None = None,
    foot_xy: XpArray | None = None,
    xp: Namespace = np,
) -> XpArray:
    """The tip's horizontal position in the foot frame [m] (D65): the rotated world
    position ``tip_xy`` [m], or where the foot was in the mud (``was_in``) the last one,
    ``foot_xy``, plus the rotated move since ``world_xy`` [m]: a yawing foot sees no jump.
    """
    c, s = cs[..., 0], cs[..., 1]
    xy = tip_xy
    if was_in is not None:
        xy = xp.where(was_in[..., None], tip_xy - world_xy, tip_xy)
    fxy = xp.stack([c * xy[..., 0] + s * xy[..., 1], c * xy[..., 1] - s * xy[..., 0]], axis=-1)
    return fxy if was_in is None else xp.where(was_in[..., None], foot_xy, 0.0) + fxy


def force_and_derivative(
    terrain: Terrain,
    foot: Foot,
    state: Any,
    pos: FloatArray,
    vel: FloatArray,
    step: FloatArray,
    dt: float,
) -> tuple[Any, FloatArray, FloatArray, FloatArray]:
    r"""Step the terrain and the diagonal velocity derivative of its force in one call (D61, D63).

    Four copies of the motion (tip positions ``pos`` [m] and velocities ``vel`` [m/s] in the
    foot frame, (N, nb, 3)): as given, and each velocity component raised by ``step`` [m/s].
    Returns the new state, the force [N], :math:`\partial F_i/\partial v_i` [N s/m] and the
    channel stresses [Pa].
    """
    vk = np.repeat(vel[None], 4, axis=0)
    vk[1, ..., 0] += step[..., 0]
    vk[2, ..., 1] += step[..., 1]
    vk[3, ..., 2] += step[..., 2]
    batch = pos.shape[:-1]
    stk = _tree_map(lambda x, b=batch: _batched(x, b, 4), state)
    new, out = terrain.step(foot, stk, np.broadcast_to(pos, vk.shape), vk, dt)
    new = _tree_map(lambda x: x[0] if np.ndim(x) else x, new)
    fk = np.asarray(out.force)
    jd = (np.stack([fk[1, ..., 0], fk[2, ..., 1], fk[3, ..., 2]], axis=-1) - fk[0]) / step
    return new, fk[0], jd, np.asarray(out.stress)[0]


def implicit_wrench(
    w0: FloatArray, K: FloatArray, W: FloatArray, acc: FloatArray, dt: float, xp: Namespace = np
) -> FloatArray:
    r"""The linearly implicit wrenches of one robot's feet, solved together (D62, D62d).

    .. math:: w=(I - \Delta t\,K\,W)^{-1}(w_0 + \Delta t\,K\,a)

    ``w0`` (N, nb, 6): explicit wrenches [N, N m]; ``K`` (N, nb, 6, 6): their damping (D62a);
    ``W`` (N, nb, nb, 6, 6): the mobility, block ``(i, j)`` :math:`J_iM^{-1}J_j^T`; ``acc``
    (N, nb, 6): twist acceleration from all other forces [m/s^2, rad/s^2]; ``dt`` [s].
    Returns the wrenches to apply (N, nb, 6) [N, N m].
    """
    nb = w0.shape[-2]
    KW = xp.einsum("...iab,...ijbc->...iajc", K, W)  # K_i W_ij, rows (i, a), columns (j, c)
    shape = (*KW.shape[:-4], 6 * nb, 6 * nb)
    A = xp.eye(6 * nb) - dt * xp.reshape(KW, shape)
    rhs = w0 + dt * xp.einsum("...iab,...ib->...ia", K, acc)
    sol = xp.linalg.solve(A, xp.reshape(rhs, (*rhs.shape[:-2], 6 * nb, 1)))
    return cast(FloatArray, xp.reshape(sol, w0.shape))


def passivity_scale(
    work_lin: XpArray, work_quad: XpArray, tank: XpArray, xp: Namespace = np
) -> XpArray:
    r"""Largest :math:`s\in[0,1]` with :math:`s\,l+s^2q\le T` (the passivity bound, D62c).

    ``work_lin`` :math:`l` and ``work_quad`` :math:`q\ge0` [J]: the linear and quadratic
    parts of the wrench's work over the step; ``tank`` :math:`T\ge0` [J]: the energy the mud
    has taken and may give back. Element-wise in ``xp``.
    """
    full = work_lin + work_quad <= tank
    disc = xp.sqrt(xp.maximum(work_lin * work_lin + 4.0 * work_quad * tank, 0.0))
    # the positive root of q s^2 + l s - T = 0, in the form without cancellation
    taking = (disc - work_lin) / (2.0 * xp.where(work_quad > 0.0, work_quad, 1.0))
    den = work_lin + disc  # > 0 unless l = 0 and q T = 0, where the root is 0
    giving = 2.0 * tank / xp.where(den > 0.0, den, 1.0)
    root = xp.where(work_lin < 0.0, taking, giving)
    return xp.where(full, 1.0, xp.minimum(xp.maximum(root, 0.0), 1.0))


def passive_wrench(
    wrench: FloatArray,
    tw: FloatArray,
    W: FloatArray,
    acc: FloatArray,
    tank: FloatArray,
    dt: float,
    xp: Namespace = np,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    r"""Scale one robot's wrenches so the mud never gives it more energy than it took (D62c).

    The work of :math:`s\,w` over the step is :math:`s\,l+s^2q`, with
    :math:`l=\Delta t\,w\cdot(\xi+\tfrac{\Delta t}{2}a)` and :math:`q=\tfrac{\Delta t^2}{2}w^TWw`
    summed over the feet; :math:`s` is :func:`passivity_scale`. ``wrench``, ``tw``
    (twists [m/s, rad/s]) and ``acc`` are (..., nb, 6), ``W`` as in :func:`implicit_wrench`,
    ``tank`` (...) [J]. Returns the scaled wrenches, the tank after the step (0 when no foot
    has a wrench) and :math:`W\,s\,w` [m/s^2, rad/s^2].
    """
    Ww = xp.einsum("...ijab,...jb->...ia", W, wrench)
    lin = dt * xp.sum(wrench * (tw + 0.5 * dt * acc), axis=(-2, -1))
    quad = 0.5 * dt * dt * xp.sum(wrench * Ww, axis=(-2, -1))
    s = passivity_scale(lin, quad, tank, xp=xp)
    idle = xp.all(wrench == 0.0, axis=(-2, -1))
    left = xp.maximum(tank - (s * lin + s * s * quad), 0.0)
    scale = s[..., None, None]
    return scale * wrench, xp.where(idle, 0.0, left), scale * Ww


def applied_wrench(
    ratio: XpArray,
    f_up: XpArray,
    jd: XpArray,
    b: XpArray,
    geo: ChannelGeometry,
    cs: XpArray,
    tw: XpArray,
    com: XpArray,
    depth: XpArray,
    W: XpArray,
    acc: XpArray,
    tank: XpArray,
    dt: float,
    *,
    surface: float,
    bottom: float | None,
    stiffness: float,
    damping: float,
    xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray, XpArray]:
    r"""The wrench the coupling applies: the posed foot's (D60a) with its spin damping
    (D62a) and the rigid bottom (D67), its implicit step and passivity bound (D62-D62d).

    ``ratio``, ``f_up`` [N], ``jd`` [N s/m] (N, nb, 3): :math:`A_c/A_c^{up}`, the upright
    foot's force and its velocity derivative; ``b``: channel rows; ``geo``: the posed feet;
    ``com`` [m], ``depth`` [m], ``tank`` [J]; ``W``, ``acc``, ``dt`` as
    :func:`implicit_wrench`; ``bottom`` [m] (None: none), ``stiffness`` [N/m], ``damping``
    [N s/m]. Returns the wrench, the explicit wrench :math:`w_0`, the tank after the step
    and :math:`W w` (0 for a foot with no wrench and no damping) [m/s^2, rad/s^2].
    """
    D = ratio * xp.minimum(jd, 0.0)
    K = damping_matrix(D, b, geo.area, yaw_inertia_to_world(geo.inertia, cs, xp=xp), xp=xp)
    # the damping spread over the elements resists spin (D62a)
    spread = K - xp.einsum("...c,...ci,...cj->...ij", D, b, b)
    w0 = posed_wrench(ratio * f_up, b, xp=xp) + (spread @ tw[..., None])[..., 0]
    if bottom is not None:  # a one-sided penalty on the lowest point (D67)
        c, s, lw = cs[..., 0], cs[..., 1], geo.low
        low = xp.stack(
            [c * lw[..., 0] - s * lw[..., 1], s * lw[..., 0] + c * lw[..., 1],
             lw[..., 2] + surface - com[..., 2]], axis=-1,
        )  # fmt: skip
        wb, kb = bottom_wrench(low, tw, depth - bottom, stiffness, damping, xp=xp)
        w0, K = w0 + wb, K + kb
    wrench = implicit_wrench(w0, K, W, acc, dt, xp=xp)
    wrench, tank, wv = passive_wrench(wrench, tw, W, acc, tank, dt, xp=xp)
    idle = xp.all(w0 == 0.0, axis=-1) & xp.all(K == 0.0, axis=(-2, -1))
    return wrench, w0, tank, xp.where(idle[..., None], 0.0, wv)


def yaw_inertia_to_world(inertia: FloatArray, cs: FloatArray, xp: Namespace = np) -> FloatArray:
    r"""Second moments :math:`\mathbf J_c` (N, nb, 3, 3, 3) [m^4] from the
    foot's yaw frame (cosine and sine ``cs``) to the world frame.
    """
    c, s = cs[..., 0], cs[..., 1]
    z, o = xp.zeros_like(c), xp.ones_like(c)
    rz = xp.stack(
        [xp.stack([c, -s, z], -1), xp.stack([s, c, z], -1), xp.stack([z, z, o], -1)], axis=-2
    )
    return xp.einsum("...ij,...cjk,...lk->...cil", rz, inertia, rz)


def damping_matrix(
    D: FloatArray, b: FloatArray, area: FloatArray, inertia_w: FloatArray, xp: Namespace = np
) -> FloatArray:
    r"""Damping :math:`K=\sum_c D_c(b_cb_c^T+\mathbf J_c/A_c)` (N, nb, 6, 6) of the wrench.

    ``D`` (N, nb, 3): each channel force's velocity derivative, :math:`\le0` [N s/m]; ``b``:
    channel rows (:func:`~.implicit.channel_rows`); ``area``: :math:`A_c` [m^2];
    ``inertia_w``: :math:`\mathbf J_c` in the world frame [m^4].
    """
    K = xp.einsum("...c,...ci,...cj->...ij", D, b, b)
    per_area = xp.where(area > 0.0, D / xp.where(area > 0.0, area, 1.0), 0.0)
    spin = xp.einsum("...c,...cij->...ij", per_area, inertia_w)  # on the rotation block
    zero = xp.zeros_like(spin)
    return K + xp.concatenate(
        [xp.concatenate([zero, zero], axis=-1), xp.concatenate([zero, spin], axis=-1)], axis=-2
    )


def posed_wrench(F: FloatArray, b: FloatArray, xp: Namespace = np) -> FloatArray:
    r"""The wrench :math:`\sum_c F_c b_c` (N, nb, 6) [N, N m] of channel forces ``F`` [N]
    acting on rows ``b``.
    """
    return xp.einsum("...c,...ci->...i", F, b)


def bottom_wrench(
    low: FloatArray,
    tw: FloatArray,
    pen: FloatArray,
    stiffness: float,
    damping: float,
    xp: Namespace = np,
) -> tuple[FloatArray, FloatArray]:
    r"""Rigid bottom: :math:`F_z=\max(0,k\,p-c\,\dot z)` on the lowest point (D67).

    ``low`` (N, nb, 3): the lowest point relative to the center of mass [m]; ``tw``: body
    twists [m/s, rad/s]; ``pen`` (N, nb): penetration below the bottom [m]; ``stiffness``
    :math:`k` [N/m], ``damping`` :math:`c` [N s/m]. Returns the wrench [N, N m] and its
    damping :math:`-c\,b b^T` for the implicit step.
    """
    ez = xp.broadcast_to(xp.asarray([0.0, 0.0, 1.0]), low.shape)
    b = xp.concatenate([ez, xp.cross(low, ez)], axis=-1)
    vz = xp.einsum("...i,...i->...", b, tw)
    f = stiffness * pen - damping * vz
    on = (pen > 0) & (f > 0)
    wrench = xp.where(on, f, 0.0)[..., None] * b
    K = -xp.where(on, damping, 0.0)[..., None, None] * (b[..., :, None] * b[..., None, :])
    return wrench, K


def _tree_map(fn: Callable[..., Any], tree: object) -> Any:
    if tree is None:
        return None
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return type(tree)(*(_tree_map(fn, t) for t in tree))
    if isinstance(tree, (tuple, list)):
        return type(tree)(_tree_map(fn, t) for t in tree)
    if isinstance(tree, dict):
        return {k: _tree_map(fn, v) for k, v in tree.items()}
    return fn(tree)


def _batched(x: ArrayLike, batch: tuple[int, ...], k: int) -> np.ndarray:
    """A terrain state's leaf with ``k`` copies along a new leading axis."""
    a = np.asarray(x)
    if a.shape[: len(batch)] != batch:
        a = np.broadcast_to(a, batch + a.shape)
    return np.repeat(a[None], k, axis=0)
