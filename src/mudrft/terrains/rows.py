r"""Feet in mud as rows of floats: the compiled path of :class:`~mudrft.MudTerrain` (numba
compiles :func:`run` over time steps and feet; the physics is :func:`~.mud.mud_step`).

* state: the horizontal and vertical channels (7 each, :class:`ChannelState`), entry x,
  entry y, line, heading, in_mud;
* constants: the horizontal then the vertical :class:`ChannelConstants`;
* options (:func:`config_row`): L_c [m], kappa, xi0, reset, heading_speed [m/s],
  quasi_static, restart;
* geometry (:func:`foot_rows`): ``(kind, g0, g1, g2)``, kind 0-2 a closed form, 3 a mesh
  foot (``g0``: trailing, with its facets (m, 10)), 4 the morphing foot (its
  :class:`~mudrft.feet.morphing.row.MorphingRow`);
* foot state (``N_FOOT``): deflection [m], pad angle [rad], most spread [rad];
* output (``N_OUT``): force (3) [N], stress (3) [Pa], depth [m].
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from .._typing import FloatArray
from .._xp import pyfloat
from ..constitutive.kernel import ChannelConstants
from ..constitutive.state import ChannelState
from ..feet.closed_form import closed_form_force
from ..feet.facet import facet_factors, facet_force, submerged_area
from ..feet.mesh import MeshFoot
from ..feet.morphing import MorphingFoot
from ..feet.morphing.equilibrium import contact_on_floats, seal_factor
from ..feet.morphing.row import MorphingRow, row_array
from ..feet.shapes import Flat, SemiCylinder, SemiSphere
from ..feet.surface import PreparedTriangles
from .mud import MudChannels, mud_step

if TYPE_CHECKING:
    from ..feet.base import Foot
    from .mud import MudTerrain

__all__ = [
    "MESH", "MORPHING", "N_CONST", "N_FOOT", "N_OUT", "N_STATE", "STATE_HEADING", "STATE_IN_MUD",
    "STATE_RETRACTION", "channels_of_rows", "compilable", "config_row", "constant_row", "foot_rows",
    "foot_step", "run", "state_rows", "upright_rows"
]  # fmt: skip

N_CHANNEL = len(ChannelState._fields)
N_STATE = 2 * N_CHANNEL + 5
STATE_HEADING = N_STATE - 2
STATE_RETRACTION = 2 * N_CHANNEL - 1  # the vertical channel's clock_w: t - t_w [s]
STATE_IN_MUD = N_STATE - 1
N_CONST = 2 * len(ChannelConstants._fields)
N_FOOT = 3
N_OUT = 7
#: Geometry kinds of the mesh and the morphing foot (0-2 are the closed forms).
MESH, MORPHING = 3.0, 4.0


def constant_row(hor: ChannelConstants, ver: ChannelConstants) -> FloatArray:
    """Horizontal and vertical constants as rows, shape batch + (N_CONST,)."""
    fields = [np.asarray(v, dtype=float) for v in (*hor, *ver)]
    return np.ascontiguousarray(np.stack(np.broadcast_arrays(*fields), axis=-1))


def config_row(terrain: MudTerrain, foot: Foot) -> FloatArray:
    """The options row of a :class:`~mudrft.MudTerrain` for a foot (see module docstring)."""
    t = terrain
    flags = [float(t.reset_on_exit), t.heading_speed, float(t.quasi_static), float(t.restart)]
    return np.array([t.length(foot), t.kappa, t.xi0, *flags])


def state_rows(ch: MudChannels) -> FloatArray:
    """Channels (floats, or arrays (N,)) as rows (N, N_STATE)."""
    fields = [*ch.h, *ch.z, ch.entry_x, ch.entry_y, ch.line, ch.heading, ch.in_mud]
    return np.ascontiguousarray(
        np.stack(np.broadcast_arrays(*map(np.asarray, fields)), -1), dtype=float
    ).reshape(-1, N_STATE)


def channels_of_rows(rows: FloatArray) -> MudChannels:
    """The inverse of :func:`state_rows`: floats from one row, arrays (N,) from rows (N, N_STATE)."""
    a = np.asarray(rows, dtype=float)
    return channels_at(a.tolist() if a.ndim == 1 else a.T)


def compilable(foot: Foot) -> bool:
    """Whether :func:`foot_rows` describes ``foot`` (a closed form, mesh or morphing foot)."""
    return type(foot) in (Flat, SemiCylinder, SemiSphere, MeshFoot, MorphingFoot)


def foot_rows(foot: Foot) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """``(geometry (4,), facets (m, 10), morphing row, foot state (N_FOOT,))`` of a foot;
    zeros (or no facets) where the foot has none."""
    facets = np.zeros((0, 10))
    mrow = np.zeros(len(MorphingRow._fields))
    fst = np.zeros(N_FOOT)
    if isinstance(foot, MorphingFoot):
        geom = np.array([MORPHING, 0.0, 0.0, 0.0])
        mrow = row_array(foot)
        s = foot.initial_foot_state()
        fst = np.array([s.deflection, s.pad_angle, s.most_spread], dtype=float)
    elif isinstance(foot, MeshFoot):
        geom = np.array([MESH, float(foot.trailing), 0.0, 0.0])
        facets = upright_rows(foot._prep)
    else:
        geom = np.array(foot.kernel_geometry, dtype=float)  # type: ignore[attr-defined]
    return geom, facets, mrow, fst


def upright_rows(prepared: PreparedTriangles) -> FloatArray:
    """Rows (m, 10) of prepared facets: z_a, z_b, z_c, k_low, k_high, flat_area, n_h, h_x,
    h_y, w_z (:class:`~mudrft.feet.surface.PreparedTriangles`)."""
    p = prepared
    cols = (p.za, p.zb, p.zc, p.k_low, p.k_high, p.flat_area, p.nh, p.hx, p.hy, p.wz)
    return np.ascontiguousarray(np.stack(cols, axis=-1), dtype=float)


# ---- the compiled part: plain functions on floats and float arrays (mudrft._jit) ----


def constants_at(c: FloatArray, r: int, o: int) -> ChannelConstants:
    """One channel's constants from row ``r`` of ``c`` at offset ``o`` (0 or 12)."""
    x = c[r]
    return ChannelConstants(
        x[o], x[o + 1], x[o + 2], x[o + 3], x[o + 4], x[o + 5], x[o + 6], x[o + 7], x[o + 8],
        x[o + 9], x[o + 10], x[o + 11],
    )  # fmt: skip


def channels_at(s: FloatArray | Sequence[float]) -> MudChannels:
    """The mud under one foot from its state row ``s``."""
    return MudChannels(
        ChannelState(s[0], s[1], s[2], s[3], s[4], s[5], s[6]),
        ChannelState(s[7], s[8], s[9], s[10], s[11], s[12], s[13]),
        s[14], s[15], s[16], s[17], s[18],
    )  # fmt: skip


def morphing_at(r: FloatArray) -> MorphingRow:
    """The :class:`~mudrft.feet.morphing.row.MorphingRow` of a float row (its 24 fields)."""
    return MorphingRow(
        r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12],
        r[13], r[14], r[15], r[16], r[17], r[18], r[19], r[20], r[21], r[22], r[23],
    )  # fmt: skip


def mesh_force(
    up: FloatArray, depth: float, sx: float, sy: float, sz: float, heading: float,
    trailing: bool,
) -> tuple[float, float, float]:  # fmt: skip
    """Force of the mud on a mesh foot [N]: eqs. (6)-(7) summed over its facets ``up``."""
    ux, uy = pyfloat.cos(heading), pyfloat.sin(heading)
    fx, fy, fz = 0.0, 0.0, 0.0
    for f in range(up.shape[0]):
        r = up[f]
        if r[0] >= depth:  # not submerged
            continue
        sub = submerged_area(r[0], r[1], r[2], r[3], r[4], r[5], depth, pyfloat)
        fn, ft = facet_factors(r[7], r[8], ux, uy, trailing, pyfloat)
        a, b, c = facet_force(sub, r[6], r[7], r[8], r[9], sx, sy, sz, fn, ft, pyfloat)
        fx += a
        fy += b
        fz += c
    return fx, fy, fz


def foot_step(
    c: FloatArray, r: int, s: FloatArray, px: float, py: float, pz: float, vx: float,
    vy: float, vz: float, dt: float, cfg: FloatArray, geom: FloatArray, up: FloatArray,
    mrow: FloatArray, fs: FloatArray, row: FloatArray, frow: FloatArray,
) -> tuple[float, float, float, float, float, float, float]:  # fmt: skip
    """:meth:`mudrft.MudTerrain.step_unchecked` of one foot on rows (new states into ``row``,
    ``frow``): ``(fx, fy, fz, sx, sy, sz, depth)`` [N, Pa, m]."""
    m = morphing_at(mrow)
    seal = 1.0
    if geom[0] == MORPHING:
        seal = seal_factor(fs[1], fs[2], m.pad_length, m.seal_length, pyfloat)
    new, sx, sy, sz, depth = mud_step(
        (constants_at(c, r, 0), constants_at(c, r, 12)), channels_at(s), px, py, pz, vx, vy,
        vz, dt, cfg[0], cfg[1], cfg[2], cfg[3] != 0.0, cfg[4], seal, cfg[5] != 0.0,
        cfg[6] != 0.0, pyfloat,
    )  # fmt: skip
    frow[0], frow[1], frow[2] = fs[0], fs[1], fs[2]
    if geom[0] == MESH:
        fx, fy, fz = mesh_force(up, depth, sx, sy, sz, new.heading, geom[1] != 0.0)
    elif geom[0] == MORPHING:
        fx, fy, fz, frow[0], frow[1], frow[2] = contact_on_floats(
            m, fs[0], fs[2], depth, sx, sy, sz, new.heading, new.z.clock_w, pyfloat
        )
    else:
        fx, fy, fz = closed_form_force(
            int(geom[0]), geom[1], geom[2], geom[3], depth, sx, sy, sz, new.heading, pyfloat
        )
    k = 0
    for chan in (new.h, new.z):
        for v in chan:
            row[k] = v
            k += 1
    row[14], row[15], row[16] = new.entry_x, new.entry_y, new.line
    row[17], row[18] = new.heading, new.in_mud
    inside = new.in_mud
    return (fx * inside, fy * inside, fz * inside, sx, sy, sz, depth)


def run(
    c: FloatArray, st: FloatArray, fst: FloatArray, pos: FloatArray, vel: FloatArray,
    dts: FloatArray, cfg: FloatArray, geom: FloatArray, up: FloatArray, mrow: FloatArray,
    out: FloatArray,
) -> None:  # fmt: skip
    """T steps of N feet of one shape: ``pos``, ``vel`` (T, N, 3) [m, m/s], ``dts`` (T,) [s].

    ``c`` (1 or N, N_CONST), ``st`` (N, N_STATE) and ``fst`` (N, N_FOOT) are updated in
    place, ``out`` (T, N, N_OUT) receives the outputs. A step that is not finite stops the
    run with NaN in its force and the states before it.
    """
    n = pos.shape[1]
    stride = 0 if c.shape[0] == 1 else 1
    row, frow = np.empty(N_STATE), np.empty(N_FOOT)
    for t in range(pos.shape[0]):
        for i in range(n):
            o = out[t, i]
            fx, fy, fz, sx, sy, sz, depth = foot_step(
                c, i * stride, st[i], pos[t, i, 0], pos[t, i, 1], pos[t, i, 2], vel[t, i, 0],
                vel[t, i, 1], vel[t, i, 2], dts[t], cfg, geom, up, mrow, fst[i], row, frow,
            )  # fmt: skip
            o[0], o[1], o[2], o[3], o[4], o[5], o[6] = fx, fy, fz, sx, sy, sz, depth
            if not np.isfinite(fx + fy + fz):
                return
            for q in range(N_STATE):  # no slice assignment: numba's shape check
                st[i, q] = row[q]  # formats its error message, 4 s more to compile
            fst[i, 0], fst[i, 1], fst[i, 2] = frow[0], frow[1], frow[2]


def along_path(
    terrain: MudTerrain, foot: Foot, position: FloatArray, velocity: FloatArray, dts: FloatArray
) -> FloatArray | None:
    """The compiled output rows (T, N_OUT) of one foot from undisturbed mud along ``position``
    [m], ``velocity`` [m/s] and steps ``dts`` (T,) [s]; None without rows."""
    from .._jit import jit_or_interpreted

    if not compilable(foot) or any(
        np.ndim(v) for v in (*terrain.constants[0], *terrain.constants[1])
    ):
        return None
    start = terrain.initial_state(foot, position[0])
    st = state_rows(start.channels)
    geom, up, mrow, fst = foot_rows(foot)
    c = constant_row(*terrain.constants).reshape(1, -1)
    pos = np.ascontiguousarray(position[1:, None, :], dtype=float)
    vel = np.ascontiguousarray(velocity[1:, None, :], dtype=float)
    out = np.zeros((len(pos), 1, N_OUT))
    dt = np.ascontiguousarray(dts, dtype=float)
    jit_or_interpreted(run, len(pos))(
        c, st, fst.reshape(1, -1), pos, vel, dt, config_row(terrain, foot), geom, up, mrow, out
    )
    return out[:, 0]
