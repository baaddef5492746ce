"""The two steps of the coupling's implicit update that the compiled kernel and MJX's
array form share (D62c, D63); the rest of it is :mod:`mudrft.integrations.mjx.wrench` on
arrays and :func:`.linalg._robot_step` on floats."""

from __future__ import annotations

import numpy as np

from ..._typing import Namespace, XpArray

__all__ = ["passivity_scale", "secant_steps"]


def secant_steps(vel: XpArray, dv_min: float, xp: Namespace = np) -> XpArray:
    r"""Velocity steps [m/s] of the secant derivative toward rest (D63, D119), element-wise:
    :math:`-u` for channel velocities ``vel`` [m/s], ``dv_min`` [m/s] across rest near it.
    """
    across = xp.where(vel > 0.0, -dv_min, dv_min)
    return xp.where(xp.abs(vel) > dv_min, -vel, across)


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
