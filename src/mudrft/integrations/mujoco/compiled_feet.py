r"""The feet in the compiled coupling: one mud step of a foot and its force (D68a, D68d).

:func:`_mud_force` steps the mud under one foot from its state row and returns the force of
the foot's model: a closed form, a mesh foot's facets (:func:`_mesh_force`), or the morphing
foot's column balance and force (:func:`~mudrft.feet.morphing.equilibrium.contact_on_floats`);
:func:`_nudged_force` is the one-channel step of a secant nudge (D63); :func:`_upright_area`
gives the upright foot's channel areas from its facet rows (:func:`upright_rows`). Plain
Python on floats here; :func:`.compiled.coupling_kernel` compiles them with the physics they
call (bound by :func:`mudrft.backends.numba.compile_scalar`) into the kernel.
"""

from __future__ import annotations

from typing import TypeAlias

import numpy as np

from ..._typing import FloatArray
from ...backends.numba import _channels, _constants
from ...constitutive.kernel import ChannelConstants
from ...feet.closed_form import closed_form_force
from ...feet.facet import facet_factors, facet_force, fold_stresses, submerged_area
from ...feet.morphing.equilibrium import contact_on_floats, seal_factor
from ...feet.morphing.pads import morphing_force
from ...feet.morphing.row import MorphingRow
from ...feet.surface import PreparedTriangles
from ...terrains.mud import MudChannels, mud_channel_stress, mud_heading, mud_step
from .pose import channel_weights

__all__ = ["ROW_OF_SOURCE", "upright_rows"]

#: What :func:`_mud_force` returns: force fx, fy, fz [N], stresses sx, sy, sz [Pa], depth [m].
FootStep: TypeAlias = tuple[float, float, float, float, float, float, float]


def _upright_area(up: FloatArray, depth: float, a: FloatArray) -> None:
    """Channel weights of the upright foot at ``depth`` (:func:`.pose.upright_area`).

    ``up`` (m, 10): per prepared facet z_a, z_b, z_c, k_low, k_high, flat_area, n_h, h_x,
    h_y, w_z (:func:`upright_rows`).
    """
    a[0], a[1], a[2] = 0.0, 0.0, 0.0
    for f in range(up.shape[0]):
        r = up[f]
        if r[0] >= depth:  # above the surface
            continue
        sub = _area(r[0], r[1], r[2], r[3], r[4], r[5], depth)
        w0, w1, w2 = _weights(sub, r[6], r[7], r[8], r[9])
        a[0] += w0
        a[1] += w1
        a[2] += w2


def upright_rows(prepared: PreparedTriangles) -> FloatArray:
    """Rows (m, 10) of the prepared upright facets for :func:`_upright_area`."""
    p = prepared
    cols = (p.za, p.zb, p.zc, p.k_low, p.k_high, p.flat_area, p.nh, p.hx, p.hy, p.wz)
    return np.ascontiguousarray(np.stack(cols, axis=-1), dtype=float)


def _mesh_force(up: FloatArray, depth: float, sx: float, sy: float, sz: float, heading: float,
                trailing: bool) -> tuple[float, float, float]:  # fmt: skip
    """Force of the mud on an upright mesh foot [N]: the element rule summed over its
    prepared facets ``up`` (:func:`upright_rows`), as ``MeshFoot.force`` does."""
    sqx, sqy, ux, uy = _fold(sx, sy, heading)
    fx, fy, fz = 0.0, 0.0, 0.0
    for f in range(up.shape[0]):
        r = up[f]
        if r[0] >= depth:  # not submerged
            continue
        sub = _area(r[0], r[1], r[2], r[3], r[4], r[5], depth)
        fn, ft = _factors(r[7], r[8], ux, uy, trailing)
        a, b, c = _fforce(sub, r[6], r[7], r[8], r[9], sqx, sqy, sz, fn, ft)
        fx += a
        fy += b
        fz += c
    return fx, fy, fz


def _mud_force(c: FloatArray, s: FloatArray, p: FloatArray, u: FloatArray, dt: float,
               cfg: FloatArray, geom: FloatArray, up: FloatArray, row: FloatArray,
               mrow: FloatArray, fs: FloatArray, frow: FloatArray,
               ) -> FootStep:  # fmt: skip
    """One mud step of one foot from state row ``s`` (not modified), the new state written
    to ``row`` (N_STATE); returns (fx, fy, fz, sx, sy, sz, depth) [N, Pa, m].

    A morphing foot (``geom[0] == 4``) reads its :class:`MorphingRow` from ``mrow``, its
    state (deflection, pad angle, seal memory) from ``fs`` and writes the new one to
    ``frow``: the seal of the previous state scales the suction, as in
    :meth:`mudrft.MudTerrain.step_unchecked`.
    """
    hor, ver, ch, m, seal = _inputs(c, s, geom, mrow, fs)
    new, sx, sy, sz, depth = _step(
        (hor, ver), ch, p[0], p[1], p[2], u[0], u[1], u[2], dt,
        cfg[0], cfg[1], cfg[2], cfg[3] != 0.0, cfg[4], seal, cfg[5] != 0.0, cfg[6] != 0.0,
    )  # fmt: skip
    if geom[0] == 3.0:  # a mesh foot
        fx, fy, fz = _mesh_force(up, depth, sx, sy, sz, new.heading, geom[1] != 0.0)
    elif geom[0] == 4.0:  # the morphing foot: its column balance, then its force
        fx, fy, fz, frow[0], frow[1], frow[2] = _contact(
            m, fs[0], fs[2], depth, sx, sy, sz, new.heading
        )
    else:  # a closed form
        fx, fy, fz = _force(int(geom[0]), geom[1], geom[2], geom[3], depth, sx, sy, sz,
                            new.heading)  # fmt: skip
    k = 0
    for chan in (new.x, new.y, new.z):
        for v in chan:
            row[k] = v
            k += 1
    row[21], row[22], row[23], row[24] = new.entry_x, new.entry_y, new.heading, new.in_mud
    inside = new.in_mud
    return (fx * inside, fy * inside, fz * inside, sx * inside, sy * inside, sz * inside,
            depth)  # fmt: skip


def _nudged_force(q: int, c: FloatArray, s: FloatArray, p: FloatArray, u: FloatArray,
                  dt: float, cfg: FloatArray, geom: FloatArray, up: FloatArray, r0: FootStep,
                  mrow: FloatArray, fs: FloatArray, frow: FloatArray) -> float:  # fmt: skip
    """Force component ``q`` [N] of the mud step from state row ``s`` when only channel
    ``q``'s rate differs from the step that returned ``r0`` (:func:`_mud_force`): the one
    channel is stepped (:func:`~mudrft.terrains.mud.mud_channel_stress`), the heading
    follows the new velocity, and the other stresses are ``r0``'s (D63). A morphing foot
    balances its column again for a vertical nudge; a horizontal one leaves the balance,
    which depends on the vertical stress only, at ``frow``'s pad angle."""
    hor, ver, ch, m, seal = _inputs(c, s, geom, mrow, fs)
    sq = _channel(
        q, (hor, ver), ch, p[0], p[1], p[2], u[0], u[1], u[2], dt,
        cfg[0], cfg[1], cfg[2], cfg[3] != 0.0, seal, cfg[5] != 0.0, cfg[6] != 0.0,
    )  # fmt: skip
    sx = sq if q == 0 else r0[3]
    sy = sq if q == 1 else r0[4]
    sz = sq if q == 2 else r0[5]
    heading = _heading(s[23], u[0], u[1], cfg[4])
    depth = r0[6]
    if geom[0] == 3.0:  # a mesh foot
        fx, fy, fz = _mesh_force(up, depth, sx, sy, sz, heading, geom[1] != 0.0)
    elif geom[0] == 4.0 and q == 2:  # the morphing foot, its column balanced again
        fx, fy, fz, _, _, _ = _contact(m, fs[0], fs[2], depth, sx, sy, sz, heading)
    elif geom[0] == 4.0:  # the morphing foot at the balance of the step
        fx, fy, fz = _mforce(m, depth, frow[1], sx, sy, sz, heading)
    else:  # a closed form
        fx, fy, fz = _force(int(geom[0]), geom[1], geom[2], geom[3], depth, sx, sy, sz,
                            heading)  # fmt: skip
    inside = 1.0 if depth > 0.0 else 0.0
    return (fx if q == 0 else (fy if q == 1 else fz)) * inside


def _inputs(
    c: FloatArray, s: FloatArray, geom: FloatArray, mrow: FloatArray, fs: FloatArray
) -> tuple[ChannelConstants, ChannelConstants, MudChannels, MorphingRow, float]:
    """What a step of one foot reads: the horizontal and vertical constants of row ``c``,
    the channels of state row ``s``, the :class:`MorphingRow` of ``mrow`` and the seal
    factor [-] (a morphing foot's, of its previous state ``fs`` (D35); 1 for others)."""
    m = _row_of(mrow)
    seal = 1.0
    if geom[0] == 4.0:
        seal = _seal(fs[1], fs[2], pad_length=m.pad_length, seal_length=m.seal_length)
    return _constants(c, 0, 0), _constants(c, 0, 12), _channels(s), m, seal


def _row_of(r: FloatArray) -> MorphingRow:
    """The :class:`MorphingRow` of a float row (:func:`~.backend._morph_row`); numba takes
    no ``*r`` of an array: :func:`coupling_kernel` compiles the same call with the fields
    spelled out (:func:`_row_of_source`)."""
    return MorphingRow(*r)


def _row_of_source() -> str:
    """Source of :func:`_row_of` with ``MorphingRow(r[0], r[1], ...)`` spelled out."""
    fields = ", ".join(f"r[{i}]" for i in range(len(MorphingRow._fields)))
    return f"def _row_of(r):\n    return MorphingRow({fields})\n"


#: :func:`_row_of` with ``MorphingRow(r[0], r[1], ...)`` spelled out (numba takes no ``*r``)
ROW_OF_SOURCE = _row_of_source()

# the names the functions above call; the kernel binds them to the compiled physics
_area = submerged_area
_weights = channel_weights
_fold = fold_stresses
_factors = facet_factors
_fforce = facet_force
_step = mud_step
_channel = mud_channel_stress
_heading = mud_heading
_force = closed_form_force
_seal = seal_factor
_contact = contact_on_floats
_mforce = morphing_force
mesh_force, mud_force, nudged_force = _mesh_force, _mud_force, _nudged_force
