r"""The semi-implicit treatment of the mud force's velocity-dependent part (D61-D63).

An explicit step of the damper-like part of the mud force, :math:`c\approx\eta_\infty
A/L_c`, is stable only for :math:`\Delta t<2m/c`
(:func:`~mudrft.integrations.mujoco.stability_limits`). The coupling instead applies the
force the mud would exert at the *end* of the step, linearised in the velocity:

.. math:: F = (I - \Delta t\,D\,W)^{-1}\,(F_0 + \Delta t\,D\,a),

with :math:`F_0` the explicit force, :math:`W` the tip's mobility
(:mod:`~mudrft.integrations.mujoco.kinematics`), :math:`a` the acceleration from all
other forces and :math:`D\le0` the diagonal velocity derivative of the mud force in the
foot frame, rotated by the foot's yaw. :func:`force_and_derivative` gets :math:`F_0` and
:math:`D` from one batched terrain call by secant differences, with the steps of
:func:`secant_steps` (D63); :func:`implicit_force` solves for :math:`F` (D62).

Shapes: ``N`` robots, ``nb`` bodies (or the bodies of one foot type); ``cs`` holds the
cosine and sine of each foot's yaw.
"""

from __future__ import annotations

from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

__all__ = ["force_and_derivative", "implicit_force", "secant_steps"]

FloatArray = NDArray[np.float64]


def secant_steps(wf_prev: FloatArray, cs: FloatArray, dt: float, dv_min: float) -> FloatArray:
    """Velocity steps of the secant derivative: what the last force did in one step (D63).

    Parameters
    ----------
    wf_prev : ndarray (N, nb, 3)
        Mobility times the last stabilised force, :math:`W F` [m/s^2] (world frame).
    cs : ndarray (N, nb, 2)
        Cosine and sine of each foot's yaw [-].
    dt : float
        Time step [s].
    dv_min : float
        Smallest step [m/s]; changes of magnitude at most ``dv_min`` are replaced by it.

    Returns
    -------
    ndarray (N, nb, 3)
        Steps in the foot frame [m/s].
    """
    c, s = cs[..., 0], cs[..., 1]
    wf = wf_prev * dt
    wf = np.stack(
        [c * wf[..., 0] + s * wf[..., 1], c * wf[..., 1] - s * wf[..., 0], wf[..., 2]], -1
    )
    return np.where(np.abs(wf) > dv_min, wf, dv_min)


def force_and_derivative(
    terrain: Any,
    foot: Any,
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


def implicit_force(
    f0_w: FloatArray,
    jd: FloatArray,
    cs: FloatArray,
    W: FloatArray,
    acc: FloatArray,
    dt: float,
) -> FloatArray:
    r"""The linearly implicit force :math:`(I - \Delta t\,D\,W)^{-1}(F_0 + \Delta t\,D\,a)` (D62).

    Parameters
    ----------
    f0_w : ndarray (N, nb, 3)
        Explicit force in the world frame [N].
    jd : ndarray (N, nb, 3)
        Diagonal velocity derivative of the force in the foot frame [N s/m]; only its
        dissipative (negative) part is used.
    cs : ndarray (N, nb, 2)
        Cosine and sine of each foot's yaw [-].
    W : ndarray (N, nb, 3, 3)
        Tip mobility [1/kg].
    acc : ndarray (N, nb, 3)
        Tip acceleration from all other forces [m/s^2].
    dt : float
        Time step [s].

    Returns
    -------
    ndarray (N, nb, 3)
        Stabilised force in the world frame [N].
    """
    c, s = cs[..., 0], cs[..., 1]
    dx, dy, dz = (np.minimum(jd[..., i], 0.0) for i in range(3))
    D = np.zeros((*f0_w.shape, 3))  # world frame: R diag(dx, dy, dz) R^T, R the yaw
    D[..., 0, 0] = c * c * dx + s * s * dy
    D[..., 1, 1] = s * s * dx + c * c * dy
    D[..., 0, 1] = D[..., 1, 0] = c * s * (dx - dy)
    D[..., 2, 2] = dz
    A = np.eye(3) - dt * (D @ W)
    rhs = f0_w + dt * (D @ acc[..., None])[..., 0]
    return cast(FloatArray, np.linalg.solve(A, rhs[..., None])[..., 0])


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
