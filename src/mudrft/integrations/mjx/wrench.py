r"""The array form of the mud's wrench on a posed foot and its linearly implicit step
(D60a, D62), which MJX runs.

The upright foot's force :math:`F^{up}` at the posed foot's depth is scaled per channel by
:math:`\rho_c=A_c/A_c^{up}` and acts at the channel's point (:mod:`.pose`):
:math:`w_0=\sum_c \rho_cF^{up}_c\,b_c`, :math:`b_c=(\mathbf e_c,\ \mathbf r_c\times\mathbf e_c)`.
Shapes: ``N`` robots, ``nb`` bodies; ``cs``: the cosine and sine of each foot's yaw.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from ..._typing import FloatArray, Namespace, XpArray
from ..mujoco.pose import passivity_scale
from .pose import ChannelGeometry, rowdot

__all__ = [
    "applied_wrench", "channel_motion", "com_twist", "foot_odometry", "implicit_wrench",
    "passive_wrench",
]  # fmt: skip


def com_twist(V: FloatArray, S: FloatArray, C: FloatArray, xp: Namespace = np) -> FloatArray:
    """Twist (velocity [m/s], angular velocity [rad/s]) at the centers of mass ``C``
    [m], from MuJoCo's ``cvel`` ``V`` taken at the root subtree centers ``S`` [m].
    """
    w = V[..., :3]
    return xp.concatenate([V[..., 3:] + xp.cross(w, C - S), w], axis=-1)


def channel_motion(
    cs: XpArray, point: XpArray, com: XpArray, tw: XpArray, surface: float, xp: Namespace = np
) -> tuple[XpArray, XpArray, XpArray]:
    """Each channel's point relative to the center of mass ``com`` [m] (world frame), its
    row :math:`b_c` and velocity [m/s], from ``point`` [m] (yaw frame) and twists ``tw``.
    """
    c, s = cs[..., 0], cs[..., 1]
    rel = xp.stack(
        [c[..., None] * point[..., 0] - s[..., None] * point[..., 1],
         s[..., None] * point[..., 0] + c[..., None] * point[..., 1],
         point[..., 2] + (surface - com[..., None, 2])], axis=-1,
    )  # fmt: skip
    z, o = xp.zeros_like(c), xp.ones_like(c)
    E = xp.stack(
        [xp.stack([c, s, z], -1), xp.stack([-s, c, z], -1), xp.stack([z, z, o], -1)], axis=-2
    )
    b = xp.concatenate([E, xp.cross(rel, E)], axis=-1)
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

    The work of :math:`s\,w` is :math:`s\,l+s^2q`, with :math:`q=\tfrac{\Delta t^2}{2}w^TWw`,
    :math:`l=\Delta t\,w\cdot(\xi+\tfrac{\Delta t}{2}a)`; :math:`s`: :func:`passivity_scale`.
    ``wrench``, ``tw`` [m/s, rad/s] and ``acc`` (..., nb, 6); ``W`` as :func:`implicit_wrench`;
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
    frame: XpArray | None = None,
    world_tw: XpArray | None = None,
    xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray, XpArray]:
    r"""The wrench the coupling applies: the posed foot's (D60a) with its spin damping
    (D62a) and the rigid bottom (D67), its implicit step and passivity bound (D62-D62d).
    On uneven ground (D175) the feet are posed in their surface frames ``frame`` (..., nb,
    3, 3), rows the frame's axes, ``tw`` and ``com`` in them: the explicit wrench and its
    damping are turned back to the world, where the robot's step takes ``world_tw``.

    The damping is :math:`K=\sum_c D_c(b_cb_c^T+\mathbf J_c/A_c)`, :math:`D_c\le0` the
    channel force's velocity derivative; the rigid bottom pushes the lowest point with
    :math:`F_z=\max(0,k\,p-c\,\dot z)` and adds :math:`-c\,b b^T` to :math:`K`.

    ``ratio``, ``f_up`` [N], ``jd`` [N s/m] (N, nb, 3): :math:`A_c/A_c^{up}`, the upright
    foot's force and its velocity derivative; ``b``: channel rows; ``geo``: the posed feet;
    ``com`` [m], ``depth`` [m], ``tank`` [J]; ``W``, ``acc``, ``dt`` as
    :func:`implicit_wrench`; ``bottom`` [m] (None: none), ``stiffness`` [N/m], ``damping``
    [N s/m]. Returns the wrench, the explicit wrench :math:`w_0`, the tank after the step
    and :math:`W w` (0 for a foot with no wrench and no damping) [m/s^2, rad/s^2].
    """
    c, s = cs[..., 0], cs[..., 1]
    z, o = xp.zeros_like(c), xp.ones_like(c)
    rz = xp.stack(
        [xp.stack([c, -s, z], -1), xp.stack([s, c, z], -1), xp.stack([z, z, o], -1)], axis=-2
    )
    inertia_w = xp.einsum("...ij,...cjk,...lk->...cil", rz, geo.inertia, rz)
    D = ratio * xp.minimum(jd, 0.0)
    bb = xp.einsum("...c,...ci,...cj->...ij", D, b, b)
    area = geo.area
    per_area = xp.where(area > 0.0, D / xp.where(area > 0.0, area, 1.0), 0.0)
    spin = xp.einsum("...c,...cij->...ij", per_area, inertia_w)  # on the rotation block
    zero = xp.zeros_like(spin)
    K = bb + xp.concatenate(
        [xp.concatenate([zero, zero], axis=-1), xp.concatenate([zero, spin], axis=-1)], axis=-2
    )
    # the damping spread over the elements resists spin (D62a)
    spread = K - bb
    w0 = xp.einsum("...c,...ci->...i", ratio * f_up, b) + (spread @ tw[..., None])[..., 0]
    if bottom is not None:  # a one-sided penalty on the lowest point (D67)
        lw = geo.low
        low = xp.stack(
            [c * lw[..., 0] - s * lw[..., 1], s * lw[..., 0] + c * lw[..., 1],
             lw[..., 2] + surface - com[..., 2]], axis=-1,
        )  # fmt: skip
        ez = xp.broadcast_to(xp.asarray([0.0, 0.0, 1.0]), low.shape)
        bl = xp.concatenate([ez, xp.cross(low, ez)], axis=-1)
        pen = depth - bottom
        f = stiffness * pen - damping * xp.einsum("...i,...i->...", bl, tw)
        on = (pen > 0) & (f > 0)
        w0 = w0 + xp.where(on, f, 0.0)[..., None] * bl
        K = K - xp.where(on, damping, 0.0)[..., None, None] * (bl[..., :, None] * bl[..., None, :])
    if frame is not None:  # back to the world: w0 <- B^T w0, K <- B^T K B, B = diag(Q, Q)
        z3 = xp.zeros_like(frame)
        B = xp.concatenate(
            [xp.concatenate([frame, z3], axis=-1), xp.concatenate([z3, frame], axis=-1)], axis=-2
        )
        w0 = xp.einsum("...ji,...j->...i", B, w0)
        K = xp.einsum("...ji,...jk,...kl->...il", B, K, B)
        tw = world_tw
    wrench = implicit_wrench(w0, K, W, acc, dt, xp=xp)
    wrench, tank, wv = passive_wrench(wrench, tw, W, acc, tank, dt, xp=xp)
    idle = xp.all(w0 == 0.0, axis=-1) & xp.all(K == 0.0, axis=(-2, -1))
    return wrench, w0, tank, xp.where(idle[..., None], 0.0, wv)
