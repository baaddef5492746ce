r"""The wrench of the mud on a posed foot, and its damping in the body twist (D60a, D62a).

The terrain's force :math:`F^{up}` on the upright foot at the posed foot's depth is scaled
per channel by :math:`\rho_c=A_c/A_c^{up}` and acts at the channel's point
(:mod:`.pose`):

.. math:: w_0=\sum_c \rho_cF^{up}_c\,b_c,\qquad
          b_c=(\mathbf e_c,\ \mathbf r_c\times\mathbf e_c).

Its damping :math:`D_c\,b_cb_c^T` (:math:`D_c\le0`), spread over the submerged elements,
adds :math:`(D_c/A_c)\mathbf J_c` on the rotation (D62a).
"""

from __future__ import annotations

import numpy as np

from ..._typing import FloatArray, Namespace

__all__ = ["bottom_wrench", "damping_matrix", "posed_wrench", "yaw_inertia_to_world"]


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
