"""Force functions of the feet for the batched and JAX backends: no validation, any ``xp``.

:func:`force_function` turns a foot into ``f(depth, stress, heading) -> force`` (world frame,
signed stresses, any heading, shapes broadcasting as in :meth:`mudrft.feet.base.Foot.force`)
built from the feet's own vectorized rules, called with an array namespace ``xp``:

* :class:`~mudrft.feet.Flat`, :class:`~mudrft.feet.SemiCylinder`,
  :class:`~mudrft.feet.SemiSphere`: the closed forms of :mod:`mudrft.feet.closed_form`
  (``flat_forces``, ``semicylinder_forces``, ``semisphere_forces``) mapped to the world as
  :func:`mudrft.feet.base.unfold_forces` does (decision D9), see :func:`unfold`;
* :class:`~mudrft.feet.MeshFoot`: :func:`mudrft.feet.surface.integrate_prepared` on the
  foot's prepared triangles (the vector rule, any heading, no folding).

Validation is left out on purpose: the batched hot loop validates its inputs once per call
(decision D71) and a JAX tracer cannot be validated.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["force_function", "unfold"]


def unfold(
    closed_form: Callable[[Any, Any, Any], Any],
    depth: Any,
    stress: Any,
    heading: Any,
    *,
    xp: Any = np,
) -> Any:
    r"""World force from a first-quadrant closed form, for any heading: the rule of
    :func:`mudrft.feet.base.unfold_forces` (decision D9) written for any array namespace.

    The closed forms are linear in the horizontal stresses; with their coefficients taken from
    unit stresses, :math:`F_x=-(a_x\sigma_x+b_x|\sigma_y|\operatorname{sgn}u_x)`,
    :math:`F_y=-(a_y\sigma_y+b_y|\sigma_x|\operatorname{sgn}u_y)`, :math:`F_z` unchanged,
    with the heading folded into :math:`[0,\pi/2]`.

    Parameters
    ----------
    closed_form : callable
        ``closed_form(depth, stress_units, phi) -> magnitudes`` [N] for stresses of shape
        (..., 2, 3) [Pa] and headings in [0, pi/2] of shape (..., 1) [rad].
    depth : array_like
        Tip depth [m].
    stress : array_like, shape (..., 3)
        Signed channel stresses [Pa].
    heading : array_like
        World heading [rad].
    xp : module, keyword-only
        Array namespace.

    Returns
    -------
    array, shape (..., 3)
        Force [N], as :meth:`mudrft.feet.base.Foot.force`.
    """
    s = xp.asarray(stress)
    h = xp.asarray(heading)
    d = xp.asarray(depth)
    shape = np.broadcast_shapes(s.shape[:-1], h.shape, d.shape)
    sx = xp.broadcast_to(s[..., 0], shape)
    sy = xp.broadcast_to(s[..., 1], shape)
    sz = xp.broadcast_to(s[..., 2], shape)
    h = xp.broadcast_to(h, shape)
    c, sn = xp.cos(h), xp.sin(h)
    phi = xp.arctan2(xp.abs(sn), xp.abs(c))
    one = xp.ones(shape)
    zero = xp.zeros(shape)
    units = xp.stack(
        [xp.stack([one, zero, sz], axis=-1), xp.stack([zero, one, sz], axis=-1)], axis=-2
    )
    m = closed_form(xp.broadcast_to(d, shape)[..., None], units, phi[..., None])
    fx = -(m[..., 0, 0] * sx + m[..., 1, 0] * xp.abs(sy) * xp.sign(c))
    fy = -(m[..., 1, 1] * sy + m[..., 0, 1] * xp.abs(sx) * xp.sign(sn))
    return xp.stack([fx, fy, m[..., 0, 2]], axis=-1)


def force_function(foot: Any, *, xp: Any = np) -> Callable[[Any, Any, Any], Any] | None:
    """``f(depth, stress, heading) -> world force (..., 3)`` [N] for a rigid foot, or None.

    Parameters
    ----------
    foot : Foot
        A foot of :mod:`mudrft.feet`.
    xp : module, keyword-only
        Array namespace (``numpy`` or ``jax.numpy``).

    Returns
    -------
    callable or None
        None for feet without a vectorized rule here (e.g. the morphing foot, whose state
        needs :meth:`~mudrft.feet.base.Foot.contact_force`).

    Examples
    --------
    >>> import mudrft
    >>> f = force_function(mudrft.feet.Flat())
    >>> f(0.01, [1e3, 1e3, 1e3], 0.0).round(3).tolist()
    [-1.45, -0.0, 5.2]
    """
    from ..feet import closed_form as cf
    from ..feet.mesh import MeshFoot
    from ..feet.surface import PreparedTriangles, integrate_prepared

    if type(foot) is cf.Flat:

        def rule(d: Any, s: Any, p: Any) -> Any:
            return cf.flat_forces(
                d, s, p, length=foot.length, width=foot.width, height=foot.height, xp=xp
            )
    elif type(foot) is cf.SemiCylinder:

        def rule(d: Any, s: Any, p: Any) -> Any:
            return cf.semicylinder_forces(
                d, s, p, radius=foot.radius, width=foot.width, height=foot.height, xp=xp
            )
    elif type(foot) is cf.SemiSphere:

        def rule(d: Any, s: Any, p: Any) -> Any:
            return cf.semisphere_forces(d, s, p, radius=foot.radius, height=foot.height, xp=xp)
    elif isinstance(foot, MeshFoot) and type(foot).force_unchecked is MeshFoot.force_unchecked:
        prep = PreparedTriangles(*(xp.asarray(a) for a in foot._prep))
        trailing = foot.trailing

        def mesh_rule(d: Any, s: Any, h: Any) -> Any:
            return integrate_prepared(prep, d, s, h, trailing=trailing, xp=xp)

        return mesh_rule
    else:
        return None

    def world(d: Any, s: Any, h: Any) -> Any:
        return unfold(rule, d, s, h, xp=xp)

    return world
