r"""The linearly implicit treatment of the mud's dissipative part, in six dimensions (D62).

An explicit step of the damper-like part of the mud force, :math:`c\approx\eta_\infty
A/L_c`, is stable only for :math:`\Delta t<2m/c`
(:func:`~mudrft.integrations.mujoco.stability_limits`); the same damper acting at a lever
arm on a light foot that can rotate is stiffer still (:math:`c\,r^2/I`). The coupling
applies the wrench the mud would exert at the *end* of the step, linearised in the body
twist :math:`\xi=(\mathbf v,\boldsymbol\omega)` (velocity of the center of mass, angular
velocity):

.. math:: w = (I - \Delta t\,K\,W)^{-1}\,(w_0 + \Delta t\,K\,a),

with :math:`w_0` the explicit wrench, :math:`W` the 6x6 mobility of the body
(:mod:`~mudrft.integrations.mujoco.kinematics`), :math:`a` the twist acceleration from
all other forces and :math:`K` the symmetric, negative semi-definite damping of the
wrench (D62a): each channel's velocity derivative :math:`D_c\le0` acting at the channel's
point, :math:`D_c\,b_cb_c^T` (:func:`channel_rows`), plus the same damping spread over the
submerged elements, :math:`(D_c/A_c)\mathbf J_c` on the rotation. :func:`force_and_derivative`
gets :math:`D_c` from one batched terrain call by secant differences, with the steps of
:func:`secant_steps` (D63); :func:`implicit_wrench` solves for :math:`w`;
:func:`passive_wrench` then scales it so that its work over the step never exceeds the
energy the mud has taken from the foot (D62c).

Shapes: ``N`` robots, ``nb`` bodies (or the bodies of one foot type); ``cs`` holds the
cosine and sine of each foot's yaw.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..._typing import ArrayLike, FloatArray, Namespace, XpArray

if TYPE_CHECKING:
    from ...feet.base import Foot
    from ...terrains import Terrain

__all__ = [
    "channel_rows",
    "force_and_derivative",
    "implicit_wrench",
    "passive_wrench",
    "passivity_scale",
    "secant_steps",
]


def secant_steps(vel: XpArray, dv_min: float, xp: Namespace = np) -> XpArray:
    r"""Velocity steps of the secant derivative: from each channel's velocity to rest (D63, D119).

    Element-wise: the step is :math:`-u`, so that the secant spans the mud's force between
    the channel velocity :math:`u` and rest, where the suction switch :math:`H_\nu` of
    eq. (1) turns within :math:`\nu L_c` (about 0.5 mm/s); a velocity within ``dv_min`` of
    rest steps by ``dv_min`` across it (away from its sign; up from exactly 0), so that a
    foot that rests or creeps sees the switch's own slope. A secant that ends beyond rest
    on the far side of the switch (the rule of D63 before D119: the velocity change the
    last wrench made) has a slope far below the switch's, and a resting foot jumped across
    the switch every step (a period-two oscillation).

    Parameters
    ----------
    vel : array_like
        Channel velocities [m/s].
    dv_min : float
        Smallest step [m/s] (> 0).
    xp : module, keyword-only
        Element-wise namespace (numpy, ``jax.numpy`` for the MJX coupling, or floats for
        the compiled coupling).

    Returns
    -------
    array_like
        Steps of the channel velocities [m/s], never 0.
    """
    across = xp.where(vel > 0.0, -dv_min, dv_min)
    return xp.where(xp.abs(vel) > dv_min, -vel, across)


def channel_rows(cs: FloatArray, rel: FloatArray, xp: Namespace = np) -> FloatArray:
    r"""Rows :math:`b_c=(\mathbf e_c,\ \mathbf r_c\times\mathbf e_c)` of the three channels.

    :math:`b_c\cdot\xi` is the velocity along the channel's axis :math:`\mathbf e_c` (the
    foot's yaw frame in the world) of the point :math:`\mathbf r_c` (relative to the center
    of mass) for the body twist :math:`\xi=(\mathbf v,\boldsymbol\omega)`, and
    :math:`f\,b_c` is the wrench (force, moment about the center of mass) of a force
    :math:`f\mathbf e_c` applied there.

    Parameters
    ----------
    cs : ndarray (N, nb, 2)
        Cosine and sine of each foot's yaw [-].
    rel : ndarray (N, nb, 3, 3)
        Point of each channel relative to the center of mass, world frame (row c) [m].
    xp : module, keyword-only
        Array namespace.

    Returns
    -------
    ndarray (N, nb, 3, 6)
    """
    c, s = cs[..., 0], cs[..., 1]
    z, o = xp.zeros_like(c), xp.ones_like(c)
    E = xp.stack(
        [xp.stack([c, s, z], -1), xp.stack([-s, c, z], -1), xp.stack([z, z, o], -1)], axis=-2
    )
    return xp.concatenate([E, xp.cross(rel, E)], axis=-1)


def force_and_derivative(
    terrain: Terrain,
    foot: Foot,
    state: Any,
    pos: FloatArray,
    vel: FloatArray,
    step: FloatArray,
    dt: float,
) -> tuple[Any, FloatArray, FloatArray, FloatArray]:
    """Step the terrain, and the diagonal velocity derivative of its force, in one call.

    The terrain steps four copies of the motion in one batched call: as given, and with
    each velocity component in turn increased by ``step`` (D61, D63).

    Parameters
    ----------
    terrain : Terrain
        The terrain (its ``step``).
    foot : Foot
        The foot.
    state : terrain state
        State for the ``(N, nb)`` tips.
    pos : ndarray (N, nb, 3)
        Tip positions in the foot frame [m].
    vel : ndarray (N, nb, 3)
        Tip velocities in the foot frame [m/s].
    step : ndarray (N, nb, 3)
        Secant steps [m/s] (:func:`secant_steps`).
    dt : float
        Time step [s].

    Returns
    -------
    new_state : terrain state
        State after the step of the unperturbed motion.
    force : ndarray (N, nb, 3)
        Force in the foot frame [N].
    derivative : ndarray (N, nb, 3)
        :math:`\\partial F_i/\\partial v_i` [N s/m].
    stress : ndarray (N, nb, 3)
        Channel stresses [Pa].
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

    :math:`w=(I - \Delta t\,K\,W)^{-1}(w_0 + \Delta t\,K\,a)` with :math:`w` the
    wrenches of all ``nb`` foot bodies stacked (``6 nb`` entries), :math:`K` their damping,
    block-diagonal, and :math:`W` the robot's mobility with its cross blocks
    :math:`W_{ij}=J_iM^{-1}J_j^T` (how body ``j``'s wrench moves body ``i``): every foot's
    damping sees the twist all the feet's wrenches give it at the end of the step.

    Parameters
    ----------
    w0 : ndarray (N, nb, 6)
        Explicit wrench (force at the center of mass [N], torque [N m]), world frame.
    K : ndarray (N, nb, 6, 6)
        Symmetric, negative semi-definite damping of each wrench in its body's twist (D62a).
    W : ndarray (N, nb, nb, 6, 6)
        Mobility: block ``(i, j)`` maps body ``j``'s wrench to the change of body ``i``'s
        twist per unit time and impulse (block-diagonal for bodies that cannot move each
        other).
    acc : ndarray (N, nb, 6)
        Twist acceleration from all forces but the mud's [m/s^2, rad/s^2].
    dt : float
        Time step [s].
    xp : module, keyword-only
        Array namespace (numpy, or ``jax.numpy`` for the MJX coupling).

    Returns
    -------
    ndarray (N, nb, 6)
        Wrenches to apply [N, N m].
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

    Element-wise; :math:`q\ge0` and :math:`T\ge0`, so :math:`s=0` always satisfies it.

    Parameters
    ----------
    work_lin : array_like
        :math:`l`, the work the wrench would do on the body over the step, linear part [J].
    work_quad : array_like
        :math:`q\ge0`, its quadratic part [J].
    tank : array_like
        :math:`T\ge0`, the energy the mud has taken from the body and may give back [J].
    xp : module, keyword-only
        Element-wise namespace (numpy, ``jax.numpy``, or floats for the compiled coupling).

    Returns
    -------
    array_like
        The scale :math:`s` of the wrench [-].
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
    r"""Scale one robot's wrenches so that the mud never gives it more energy than it took (D62c).

    The work of wrenches :math:`s\,w` held over the step on bodies of twists :math:`\xi`,
    mobility :math:`W` (cross blocks included, D62d) and acceleration :math:`a` from all
    other forces, at the middle twist :math:`\xi+\tfrac{\Delta t}{2}(a+sWw)` of the step,
    is :math:`s\,l+s^2q` with :math:`l=\Delta t\,w\cdot(\xi+\tfrac{\Delta t}{2}a)` and
    :math:`q=\tfrac{\Delta t^2}{2}w^TWw\ge0`, summed over the robot's feet. The tank
    :math:`T\ge0` holds the energy the mud has taken from the robot since its feet last had
    no wrench; the wrenches are scaled by the largest :math:`s\le1`
    (:func:`passivity_scale`) whose work stays within it, and the tank gives up that work.
    A robot with no wrench on any foot (out of the mud) empties the tank.

    Parameters
    ----------
    wrench : ndarray (..., nb, 6)
        Wrenches of the implicit step (:func:`implicit_wrench`) [N, N m].
    tw : ndarray (..., nb, 6)
        Body twists at the start of the step [m/s, rad/s].
    W : ndarray (..., nb, nb, 6, 6)
        Mobility of the body twists (see :func:`implicit_wrench`).
    acc : ndarray (..., nb, 6)
        Twist accelerations from all other forces [m/s^2, rad/s^2].
    tank : ndarray (...)
        Energy the mud has taken from the robot and may give back [J].
    dt : float
        Time step [s].
    xp : module, keyword-only
        Array namespace (numpy, or ``jax.numpy`` for the MJX coupling).

    Returns
    -------
    wrench : ndarray (..., nb, 6)
        The scaled wrenches [N, N m].
    tank : ndarray (...)
        The tank after the step [J].
    wv : ndarray (..., nb, 6)
        :math:`W\,s\,w`, the change of each twist per unit time the applied wrenches make
        [m/s^2, rad/s^2] (the next step's estimate of :math:`a` subtracts it).
    """
    Ww = xp.einsum("...ijab,...jb->...ia", W, wrench)
    lin = dt * xp.sum(wrench * (tw + 0.5 * dt * acc), axis=(-2, -1))
    quad = 0.5 * dt * dt * xp.sum(wrench * Ww, axis=(-2, -1))
    s = passivity_scale(lin, quad, tank, xp=xp)
    idle = xp.all(wrench == 0.0, axis=(-2, -1))
    left = xp.maximum(tank - (s * lin + s * s * quad), 0.0)
    scale = s[..., None, None]
    return scale * wrench, xp.where(idle, 0.0, left), scale * Ww


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
    """Leaf of a terrain state with ``k`` copies along a new leading axis, batch-shaped."""
    a = np.asarray(x)
    if a.shape[: len(batch)] != batch:
        a = np.broadcast_to(a, batch + a.shape)
    return np.repeat(a[None], k, axis=0)
