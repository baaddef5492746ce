r"""The feet in the compiled coupling: channel areas of the upright foot, and the secant
nudge (D63); compiled into :func:`.compiled.coupling_kernel` with ``xp`` bound to
:mod:`mudrft._xp`.
"""

from __future__ import annotations

from typing import TypeAlias

from ..._typing import FloatArray
from ..._xp import pyfloat
from ...feet.closed_form import closed_form_force
from ...feet.facet import submerged_area
from ...feet.morphing.equilibrium import contact_on_floats, seal_factor
from ...feet.morphing.pads import morphing_force
from ...terrains.mud import mud_channel_stress
from ...terrains.rows import (
    MESH,
    MORPHING,
    STATE_HEADING,
    STATE_RETRACTION,
    channels_at,
    constants_at,
    foot_step,
    mesh_force,
    morphing_at,
    upright_rows,
)
from .pose import channel_weights

__all__ = ["upright_rows"]

#: What a foot step returns: force fx, fy, fz [N], stresses sx, sy, sz [Pa], depth [m].
FootStep: TypeAlias = tuple[float, float, float, float, float, float, float]


def _upright_area(up: FloatArray, depth: float, a: FloatArray) -> None:
    """Channel weights of the upright foot at ``depth`` (:func:`.pose.upright_area`)
    from its facet rows ``up`` (:func:`~mudrft.terrains.rows.upright_rows`) into ``a``.
    """
    a[0], a[1], a[2] = 0.0, 0.0, 0.0
    for f in range(up.shape[0]):
        r = up[f]
        if r[0] >= depth:  # above the surface
            continue
        sub = submerged_area(r[0], r[1], r[2], r[3], r[4], r[5], depth, pyfloat)
        w0, w1, w2 = channel_weights(sub, r[6], r[7], r[8], r[9], pyfloat)
        a[0] += w0
        a[1] += w1
        a[2] += w2


def _mud_force(c: FloatArray, s: FloatArray, p: FloatArray, u: FloatArray, dt: float,
               cfg: FloatArray, geom: FloatArray, up: FloatArray, row: FloatArray,
               mrow: FloatArray, fs: FloatArray, frow: FloatArray) -> FootStep:  # fmt: skip
    """:func:`~mudrft.terrains.rows.foot_step` of tip position ``p`` [m] and velocity ``u``
    [m/s] (the coupling's arrays)."""
    return foot_step(
        c, 0, s, p[0], p[1], p[2], u[0], u[1], u[2], dt, cfg, geom, up, mrow, fs, row, frow
    )


def _nudged_force(q: int, c: FloatArray, s: FloatArray, p: FloatArray, u: FloatArray,
                  dt: float, cfg: FloatArray, geom: FloatArray, up: FloatArray, r0: FootStep,
                  mrow: FloatArray, fs: FloatArray, row: FloatArray,
                  frow: FloatArray) -> float:  # fmt: skip
    """Force component ``q`` [N] of the mud step when only channel ``q``'s rate
    differs from the step that returned ``r0`` (D63): that channel stepped alone, the other
    stresses ``r0``'s; a morphing foot balances its column again for a vertical nudge.
    """
    m = morphing_at(mrow)
    seal = 1.0
    if geom[0] == MORPHING:
        seal = seal_factor(fs[1], fs[2], m.pad_length, m.seal_length, pyfloat)
    sq, heading = mud_channel_stress(
        q, (constants_at(c, 0, 0), constants_at(c, 0, 12)), channels_at(s), p[0], p[1], p[2],
        u[0], u[1], u[2], dt, cfg[0], cfg[1], cfg[2], cfg[3] != 0.0, cfg[4], seal,
        cfg[5] != 0.0, cfg[6] != 0.0, pyfloat,
    )  # fmt: skip
    sx = sq if q < 2 else r0[3]  # the one horizontal stress, in both components
    sy = sq if q < 2 else r0[4]
    sz = sq if q == 2 else r0[5]
    if q == 2:
        heading = row[STATE_HEADING]
    depth = r0[6]
    if geom[0] == MESH:
        fx, fy, fz = mesh_force(up, depth, sx, sy, sz, heading, geom[1] != 0.0)
    elif geom[0] == MORPHING and q == 2:  # the morphing foot, its column balanced again
        fx, fy, fz, _, _, _ = contact_on_floats(
            m, fs[0], fs[2], depth, sx, sy, sz, heading, row[STATE_RETRACTION], pyfloat
        )
    elif geom[0] == MORPHING:  # the morphing foot at the balance of the step
        fx, fy, fz = morphing_force(m, depth, frow[1], sx, sy, sz, heading, pyfloat)
    else:  # a closed form
        fx, fy, fz = closed_form_force(
            int(geom[0]), geom[1], geom[2], geom[3], depth, sx, sy, sz, heading, pyfloat
        )
    inside = 1.0 if depth > 0.0 else 0.0
    return (fx if q == 0 else (fy if q == 1 else fz)) * inside
