r"""The wrench of the mud on a posed foot, and its damping in the body twist (D60a, D62a).

The terrain gives the force :math:`F^{up}` of the mud on the *upright* foot whose tip is
at the depth of the posed foot's lowest point (the foot's own model: closed form, mesh or
morphing), with the velocity of each channel read at that channel's point
:math:`\mathbf p_c` (:mod:`.pose`). On the posed foot, component :math:`c` of that force is
scaled by the ratio :math:`\rho_c=A_c/A_c^{up}` of the channel's submerged weight in the
current pose to that of the upright foot at the same depth, and acts at
:math:`\mathbf p_c`:

.. math:: w_0=\sum_c \rho_cF^{up}_c\,b_c,\qquad
          b_c=(\mathbf e_c,\ \mathbf r_c\times\mathbf e_c),

:math:`\mathbf r_c=\mathbf p_c-\mathbf x_{com}`. Upright, :math:`\rho_c=1` and the force is
exactly the model's; tilted, a flat foot carries only the part of its sole that is
submerged, at the centroid of that part. Because each channel's velocity is read where its
force acts, the velocity-dependent part of :math:`w_0` is a damper in the body twist,
:math:`D_c\,b_cb_c^T` with :math:`D_c=\rho_c\,\partial F^{up}_c/\partial u_c\le0`:
symmetric, so it can only dissipate. Spread over the submerged elements (each element's
own velocity damped at the same rate per unit weight, :math:`D_c/A_c`) the damper adds a
moment :math:`(D_c/A_c)\mathbf J_c\boldsymbol\omega` that resists spin about any axis;
the coupling includes it in :math:`w_0` and in the implicit step (D62a).
"""

from __future__ import annotations

import numpy as np

from ..._typing import FloatArray, Namespace

__all__ = ["bottom_wrench", "damping_matrix", "posed_wrench", "yaw_inertia_to_world"]


def yaw_inertia_to_world(inertia: FloatArray, cs: FloatArray, xp: Namespace = np) -> FloatArray:
    """Second moments :math:`\\mathbf J_c` from the yaw frame to the world frame.

    Parameters
    ----------
    inertia : ndarray (N, nb, 3, 3, 3)
        :math:`\\mathbf J_c` in the foot's yaw frame [m^4].
    cs : ndarray (N, nb, 2)
        Cosine and sine of each foot's yaw [-].
    xp : module, keyword-only
        Array namespace (numpy, or ``jax.numpy`` for the MJX coupling).

    Returns
    -------
    ndarray (N, nb, 3, 3, 3)
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
    r"""Damping of the wrench in the body twist, :math:`K=\sum_c D_c(b_cb_c^T+\mathbf J_c/A_c)`.

    Parameters
    ----------
    D : ndarray (N, nb, 3)
        Velocity derivative of each channel's force on the posed foot, :math:`\le0` [N s/m].
    b : ndarray (N, nb, 3, 6)
        Channel rows (:func:`~.implicit.channel_rows`).
    area : ndarray (N, nb, 3)
        Channel weights :math:`A_c` [m^2].
    inertia_w : ndarray (N, nb, 3, 3, 3)
        :math:`\mathbf J_c` in the world frame [m^4].
    xp : module, keyword-only
        Array namespace.

    Returns
    -------
    ndarray (N, nb, 6, 6)
        Symmetric, negative semi-definite [N s/m, N s, N m s].
    """
    K = xp.einsum("...c,...ci,...cj->...ij", D, b, b)
    per_area = xp.where(area > 0.0, D / xp.where(area > 0.0, area, 1.0), 0.0)
    spin = xp.einsum("...c,...cij->...ij", per_area, inertia_w)  # on the rotation block
    zero = xp.zeros_like(spin)
    return K + xp.concatenate(
        [xp.concatenate([zero, zero], axis=-1), xp.concatenate([zero, spin], axis=-1)], axis=-2
    )


def posed_wrench(F: FloatArray, b: FloatArray, xp: Namespace = np) -> FloatArray:
    """The wrench :math:`\\sum_c F_c b_c` of channel forces acting at their points.

    Parameters
    ----------
    F : ndarray (N, nb, 3)
        Force along each channel axis (foot's yaw frame) [N].
    b : ndarray (N, nb, 3, 6)
        Channel rows (:func:`~.implicit.channel_rows`).

    Returns
    -------
    ndarray (N, nb, 6)
        Force [N] and moment about the center of mass [N m], world frame.
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

    Parameters
    ----------
    low : ndarray (N, nb, 3)
        Lowest point relative to the center of mass, world frame [m].
    tw : ndarray (N, nb, 6)
        Body twist (:func:`~.kinematics.com_twist`).
    pen : ndarray (N, nb)
        Penetration below the bottom [m] (> 0 in contact).
    stiffness, damping : float
        :math:`k` [N/m], :math:`c` [N s/m].
    xp : module, keyword-only
        Array namespace.

    Returns
    -------
    wrench : ndarray (N, nb, 6)
        Explicit wrench [N, N m].
    K : ndarray (N, nb, 6, 6)
        Its damping where it acts (:math:`-c\,b b^T`), for the implicit step.
    """
    ez = xp.broadcast_to(xp.asarray([0.0, 0.0, 1.0]), low.shape)
    b = xp.concatenate([ez, xp.cross(low, ez)], axis=-1)
    vz = xp.einsum("...i,...i->...", b, tw)
    f = stiffness * pen - damping * vz
    on = (pen > 0) & (f > 0)
    wrench = xp.where(on, f, 0.0)[..., None] * b
    K = -xp.where(on, damping, 0.0)[..., None, None] * (b[..., :, None] * b[..., None, :])
    return wrench, K
