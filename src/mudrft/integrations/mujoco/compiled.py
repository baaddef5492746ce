"""The compiled coupling: one numba call per physics step for all feet of a robot (D68a),
the numpy coupling's steps on floats in the same order of operations."""

from __future__ import annotations

import math
from typing import Any, TypeAlias

import numpy as np

from ..._typing import FloatArray, IndexArray
from ..._xp import pyfloat
from ...feet.closed_form import closed_form_force
from ...feet.facet import (
    clip_constants,
    clip_facet,
    facet_frame,
    sort_by_height,
    submerged_area,
)
from ...feet.morphing.equilibrium import contact_on_floats, seal_factor
from ...feet.morphing.pads import morphing_force
from ...terrains.field import field_row, plane_frame, surface_at
from ...terrains.mud import mud_channel_stress
from ...terrains.rows import (
    MESH,
    MORPHING,
    N_CONST,
    N_STATE,
    STATE_HEADING,
    STATE_IN_MUD,
    STATE_RETRACTION,
    channels_at,
    constants_at,
    foot_step,
    mesh_force,
    morphing_at,
)
from .linalg import (
    _about,
    _back,
    _borrow,
    _cut,
    _iptr,
    _mj_jac,
    _mj_solve_m,
    _ptr,
    _robot_step,
    carray,
)
from .pose import ball_channels, channel_weights, secant_steps

__all__ = ["ARGS", "N_OUT", "OFFSETS", "WORK_FIXED", "pack", "work_size"]

#: What a foot step returns: force fx, fy, fz [N], stresses sx, sy, sz [Pa], depth [m].
FootStep: TypeAlias = tuple[float, float, float, float, float, float, float]

#: Floats per body in the output row: the fields of :class:`.contact.MudContact`, a status.
N_OUT = 23


def _geometry(
    tri: FloatArray,
    M: FloatArray,
    sh: FloatArray,
    v: FloatArray,
    scratch: FloatArray,
    out: FloatArray,
) -> None:
    """Channel weights of posed triangles ``M x + sh`` into ``out``: A (3), p (3 x 3),
    J (3 x 3 x 3), lowest vertex (3) (:func:`mudrft.integrations.mjx.pose.channel_geometry`);
    ``v`` (9) and ``scratch`` (m, 6) are work arrays.
    """
    m = tri.shape[0]
    for q in range(12):
        out[q] = 0.0
    lowz, lx, ly = np.inf, 0.0, 0.0
    for f in range(m):
        for k in range(3):
            for i in range(3):
                v[3 * k + i] = (
                    M[i, 0] * tri[f, k, 0] + M[i, 1] * tri[f, k, 1] + M[i, 2] * tri[f, k, 2]
                ) + sh[i]
            if v[3 * k + 2] < lowz:
                lowz, lx, ly = v[3 * k + 2], v[3 * k], v[3 * k + 1]
        if v[2] >= 0.0 and v[5] >= 0.0 and v[8] >= 0.0:  # above the surface: no weight
            for c in range(6):
                scratch[f, c] = 0.0
            continue
        _nx, _ny, _nz, area, nh, hx, hy, wz = facet_frame(
            v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], pyfloat
        )
        s0, s1, s2, s3, s4, s5, s6, s7, s8 = sort_by_height(
            v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], pyfloat
        )
        kl, kh, fa = clip_constants(s2, s5, s8, area, pyfloat)
        sub, cx, cy, cz = clip_facet(s0, s1, s2, s3, s4, s5, s6, s7, s8, kl, kh, fa, 0.0, pyfloat)
        w0, w1, w2 = channel_weights(sub, nh, hx, hy, wz, pyfloat)
        scratch[f, 0], scratch[f, 1], scratch[f, 2] = w0, w1, w2
        scratch[f, 3], scratch[f, 4], scratch[f, 5] = cx, cy, cz
        for c in range(3):
            w = scratch[f, c]
            out[c] += w
            out[3 + 3 * c] += w * cx
            out[4 + 3 * c] += w * cy
            out[5 + 3 * c] += w * cz
    for c in range(3):
        a = out[c]
        if a > 0.0:
            out[3 + 3 * c] /= a
            out[4 + 3 * c] /= a
            out[5 + 3 * c] /= a
        else:
            out[3 + 3 * c], out[4 + 3 * c], out[5 + 3 * c] = lx, ly, lowz
    for q in range(12, 39):
        out[q] = 0.0
    for f in range(m):
        for c in range(3):
            w = scratch[f, c]
            if w == 0.0:
                continue
            rx = scratch[f, 3] - out[3 + 3 * c]
            ry = scratch[f, 4] - out[4 + 3 * c]
            rz = scratch[f, 5] - out[5 + 3 * c]
            if c == 0:  # r x e_c
                v[0], v[1], v[2] = 0.0, rz, -ry
            elif c == 1:
                v[0], v[1], v[2] = -rz, 0.0, rx
            else:
                v[0], v[1], v[2] = ry, -rx, 0.0
            for a in range(3):
                for e in range(3):
                    out[12 + 9 * c + 3 * a + e] += w * v[a] * v[e]
    out[39], out[40], out[41] = lx, ly, lowz


def _ball_geometry(radius: float, sh: FloatArray, out: FloatArray) -> None:
    """:func:`_geometry` of a ball of ``radius`` [m] centered at ``sh`` [m]
    (:func:`.pose.ball_channels`)."""
    ah, az, zh, zz, jhz, jhh, jz = ball_channels(radius, sh[2], pyfloat)
    for q in range(42):
        out[q] = 0.0
    out[0], out[1], out[2] = ah, ah, az
    for c in range(3):
        out[3 + 3 * c], out[4 + 3 * c], out[5 + 3 * c] = sh[0], sh[1], zz if c == 2 else zh
    out[16], out[20], out[21], out[29], out[30], out[34] = jhz, jhh, jhz, jhh, jz, jz
    out[39], out[40], out[41] = sh[0], sh[1], sh[2] - radius


def _upright_area(up: FloatArray, depth: float, a: FloatArray) -> None:
    """Channel weights of the upright foot at ``depth`` from its facet rows ``up``
    (:func:`~mudrft.terrains.rows.upright_rows`) into ``a``
    (:func:`mudrft.integrations.mjx.pose.upright_area`).
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


def _kernel(
    addr: IndexArray, sizes: IndexArray, bodies: IndexArray, tip: FloatArray, fwd: FloatArray, tri_adr: IndexArray,
    tri_b: FloatArray, up_adr: IndexArray, tri_up: FloatArray,
    rows: FloatArray, cfg: FloatArray, geom: FloatArray, morph: FloatArray, opts: FloatArray,
    mud: FloatArray, fst: FloatArray, odo: FloatArray, tw_prev: FloatArray,
    wv_prev: FloatArray, tank: FloatArray, out: FloatArray, work: FloatArray,
    clock: FloatArray, cells: IndexArray, grids: FloatArray, hts: FloatArray, k: int,
) -> int:  # fmt: skip
    """One coupling step of every body of robot ``k``; the number of non-finite wrenches.

    ``addr[k]``: addresses of xpos, xmat, xipos, cvel, subtree_com, xfrc_applied and the
    ``mjData``; ``sizes``: (nbody, nv, addresses of the ``mjModel``, ``mj_jac``, ``mj_solveM``);
    ``bodies[j]``: (id, root, ball); body ``j``'s triangles are
    ``tri_b[tri_adr[j]:tri_adr[j+1]]``, its upright rows likewise; ``opts``: (dt, surface,
    bottom (< 0: none), k_b, c_b, dv_min, gravity (3)); ``grids[k]``, ``cells[k]`` and
    ``rows[k]``: robot ``k``'s field (:func:`~mudrft.terrains.field.field_row`), ``hts[k]``
    its surface's heights (:func:`~mudrft.terrains.field.surface_at`). ``mud``, ``fst``, ``odo``,
    ``tw_prev``, ``wv_prev`` and ``tank`` are updated in place; ``out``: (N, nb, N_OUT).
    """
    dt, surface = opts[0], opts[1]
    bottom, kb, cb, dv_min = opts[2], opts[3], opts[4], opts[5]
    has_prev = clock[k, 0] != 0.0
    nb = mud.shape[1]
    nbody, nv, mptr, jac_fn, solve_fn = sizes[0], sizes[1], sizes[2], sizes[3], sizes[4]
    # work arrays, carved from ``work`` in the order :func:`work_size` counts them, and the
    # arrays below: borrowed views (:func:`.linalg._borrow`), no reference counts to update
    ntri = tri_b.shape[0]
    at = work.ctypes.data + 8 * k * work.shape[1]
    FJ, at = _cut(at, (nb, 6, nv))
    FM, at = _cut(at, (nb, 6, nv))
    scratch, at = _cut(at, (ntri, 6))
    geo, at = _cut(at, (42,))
    aup, at = _cut(at, (3,))
    v, at = _cut(at, (9,))
    cj, at = _cut(at, (1, N_CONST))
    row, at = _cut(at, (N_STATE,))
    frow, at = _cut(at, (3,))
    tw, at = _cut(at, (6,))
    tipw, at = _cut(at, (3,))
    sh, at = _cut(at, (3,))
    ratio, at = _cut(at, (3,))
    u, at = _cut(at, (3,))
    un, at = _cut(at, (3,))
    pos, at = _cut(at, (3,))
    F, at = _cut(at, (3,))
    D, at = _cut(at, (3,))
    w0, at = _cut(at, (6,))
    bl, at = _cut(at, (6,))
    M, at = _cut(at, (3, 3))
    E, at = _cut(at, (3, 3))
    spread, at = _cut(at, (3, 3))
    b, at = _cut(at, (3, 6))
    K, at = _cut(at, (6, 6))
    FK, at = _cut(at, (nb, 6, 6))
    FW0, at = _cut(at, (nb, 6))
    FACC, at = _cut(at, (nb, 6))
    FTW, at = _cut(at, (nb, 6))
    FWR, at = _cut(at, (nb, 6))
    FWV, at = _cut(at, (nb, 6))
    FC, at = _cut(at, (nb, 3))
    FPOS, at = _cut(at, (nb,))
    RJ, at = _cut(at, (6 * nb,))
    WF, at = _cut(at, (6 * nb, 6 * nb))
    AJ, at = _cut(at, (6 * nb, 6 * nb))
    Q, at = _cut(at, (3, 3))
    Xq, at = _cut(at, (3,))
    Cq, at = _cut(at, (3,))
    Rq, at = _cut(at, (9,))
    twq, at = _cut(at, (6,))
    tipq, at = _cut(at, (3,))
    KB, at = _cut(at, (6, 6))
    mud, fst, odo, out = _borrow(mud), _borrow(fst), _borrow(odo), _borrow(out)
    tw_prev, wv_prev, tank = _borrow(tw_prev), _borrow(wv_prev), _borrow(tank)
    cfg, geom, morph, rk = _borrow(cfg), _borrow(geom), _borrow(morph), _borrow(rows[k])
    tri_b, tri_up, tip, fwd = _borrow(tri_b), _borrow(tri_up), _borrow(tip), _borrow(fwd)
    E[:, :] = 0.0
    bad = 0
    xpos = carray(_ptr(addr[k, 0]), (nbody, 3))  # type: ignore[call-arg]
    xmat = carray(_ptr(addr[k, 1]), (nbody, 9))
    xipos = carray(_ptr(addr[k, 2]), (nbody, 3))
    cvel = carray(_ptr(addr[k, 3]), (nbody, 6))
    subtree = carray(_ptr(addr[k, 4]), (nbody, 3))
    xfrc = carray(_ptr(addr[k, 5]), (nbody, 6))
    dptr = addr[k, 6]
    ny, nx = cells.shape[1], cells.shape[2]
    active = 0
    for j in range(nb):
        body, root = bodies[j, 0], bodies[j, 1]
        X, R, C = xpos[body], xmat[body], xipos[body]
        V, S = cvel[body], subtree[root]
        # twist at the center of mass
        dx, dy, dz = C[0] - S[0], C[1] - S[1], C[2] - S[2]
        tw[0] = V[3] + (V[1] * dz - V[2] * dy)
        tw[1] = V[4] + (V[2] * dx - V[0] * dz)
        tw[2] = V[5] + (V[0] * dy - V[1] * dx)
        tw[3], tw[4], tw[5] = V[0], V[1], V[2]
        for i in range(3):
            tipw[i] = X[i] + (R[3 * i] * tip[j, 0] + R[3 * i + 1] * tip[j, 1]
                              + R[3 * i + 2] * tip[j, 2])  # fmt: skip
        # an uneven surface: the foot posed in the frame of the tangent plane under its tip,
        # rotated about the surface point P there and moved down to the plane z = surface
        hs, gx, gy = surface_at(tipw[0], tipw[1], grids[k], ny, nx, hts[k])
        tilted = hs != 0.0 or gx != 0.0 or gy != 0.0
        twl, tipl = tw, tipw
        if tilted:
            q = plane_frame(gx, gy, pyfloat)
            for i in range(9):
                Q[i // 3, i % 3] = q[i]
            ps = surface + hs
            _about(Q, X, tipw[0], tipw[1], ps, surface, Xq)
            _about(Q, C, tipw[0], tipw[1], ps, surface, Cq)
            _about(Q, tipw, tipw[0], tipw[1], ps, surface, tipq)
            for i in range(3):
                for l in range(3):
                    Rq[3 * i + l] = Q[i, 0] * R[l] + Q[i, 1] * R[3 + l] + Q[i, 2] * R[6 + l]
                twq[i] = Q[i, 0] * tw[0] + Q[i, 1] * tw[1] + Q[i, 2] * tw[2]
                twq[3 + i] = Q[i, 0] * tw[3] + Q[i, 1] * tw[4] + Q[i, 2] * tw[5]
            X, C, R, twl, tipl = Xq, Cq, Rq, twq, tipq
        fw0 = R[0] * fwd[j, 0] + R[1] * fwd[j, 1] + R[2] * fwd[j, 2]
        fw1 = R[3] * fwd[j, 0] + R[4] * fwd[j, 1] + R[5] * fwd[j, 2]
        h = max(math.hypot(fw0, fw1), 1e-12)
        c, s = fw0 / h, fw1 / h
        # the posed foot in the yaw frame (origin: center of mass horizontally, surface);
        # a ball (centered at ``tip``) is the same in every pose
        ball = bodies[j, 2] != 0
        for i in range(3):
            M[0, i] = c * R[i] + s * R[3 + i]
            M[1, i] = -s * R[i] + c * R[3 + i]
            M[2, i] = R[6 + i]
        if ball:
            ox, oy, oz = tipl[0] - C[0], tipl[1] - C[1], tipl[2] - surface
        else:
            ox, oy, oz = X[0] - C[0], X[1] - C[1], X[2] - surface
        sh[0], sh[1], sh[2] = c * ox + s * oy, -s * ox + c * oy, oz
        if ball:
            _ball_geometry(geom[j, 1], sh, geo)
        else:
            _geometry(tri_b[tri_adr[j] : tri_adr[j + 1]], M, sh, v, scratch, geo)
        depth = max(-geo[41], 0.0)
        upj = tri_up[up_adr[j] : up_adr[j + 1]]
        if ball:
            ratio[0], ratio[1], ratio[2] = 1.0, 1.0, 1.0
        else:
            _upright_area(upj, depth, aup)
            for q in range(3):
                ratio[q] = geo[q] / aup[q] if aup[q] > 0.0 else 0.0
        # channel points relative to the center of mass, rows b_c, channel velocities
        E[0, 0], E[0, 1], E[1, 0], E[1, 1], E[2, 2] = c, s, -s, c, 1.0
        for q in range(3):
            px, py, pz = geo[3 + 3 * q], geo[4 + 3 * q], geo[5 + 3 * q]
            rx, ry, rz = c * px - s * py, s * px + c * py, pz + (surface - C[2])
            ex, ey, ez = E[q, 0], E[q, 1], E[q, 2]
            b[q, 0], b[q, 1], b[q, 2] = ex, ey, ez
            b[q, 3], b[q, 4], b[q, 5] = ry * ez - rz * ey, rz * ex - rx * ez, rx * ey - ry * ex
            acc = 0.0
            for i in range(6):
                acc += b[q, i] * twl[i]
            u[q] = acc
        # odometry of the tip in the foot frame (D65): its world motion, in the plane's frame
        o = odo[k, j]
        was_in = mud[k, j, STATE_IN_MUD] > 0.5
        xy0 = tipw[0] - o[2] if was_in else tipw[0]
        xy1 = tipw[1] - o[3] if was_in else tipw[1]
        if tilted:
            xy2 = tipw[2] - o[4] if was_in else tipw[2]
            xy0, xy1 = (
                Q[0, 0] * xy0 + Q[0, 1] * xy1 + Q[0, 2] * xy2,
                Q[1, 0] * xy0 + Q[1, 1] * xy1 + Q[1, 2] * xy2,
            )
        b0 = o[0] if was_in else 0.0
        b1 = o[1] if was_in else 0.0
        pos[0], pos[1], pos[2] = b0 + (c * xy0 + s * xy1), b1 + (c * xy1 - s * xy0), geo[41]
        o[0], o[1], o[2], o[3], o[4] = pos[0], pos[1], tipw[0], tipw[1], tipw[2]
        # the mud under the tip (its share: the rest is rigid ground), and the secant
        # derivative toward rest (D63, D119); out of the mud every force is 0
        share = field_row(tipw[0], tipw[1], grids[k], cells[k], rk, cj[0])
        fs, mrow = fst[k, j], morph[j]
        r0 = foot_step(
            cj, 0, mud[k, j], pos[0], pos[1], pos[2], u[0], u[1], u[2], dt, cfg[j], geom[j],
            upj, mrow, fs, row, frow,
        )  # fmt: skip
        for q in range(3):
            F[q] = share * ratio[q] * r0[q]
            D[q] = 0.0
        if was_in or depth > 0.0:
            for q in range(3):
                st = secant_steps(u[q], dv_min, pyfloat)
                un[0], un[1], un[2] = u[0], u[1], u[2]
                un[q] += st
                fq = _nudged_force(
                    q, cj, mud[k, j], pos, un, dt, cfg[j], geom[j], upj, r0, mrow, fs, row, frow
                )
                D[q] = share * ratio[q] * min((fq - r0[q]) / st, 0.0)
        for i in range(N_STATE):
            mud[k, j, i] = row[i]
        if geom[j, 0] == 4.0:
            fs[0], fs[1], fs[2] = frow[0], frow[1], frow[2]
        for i in range(6):
            w0[i] = F[0] * b[0, i] + F[1] * b[1, i] + F[2] * b[2, i]
        for i in range(6):
            for l in range(6):
                K[i, l] = (
                    D[0] * b[0, i] * b[0, l] + D[1] * b[1, i] * b[1, l] + (D[2] * b[2, i] * b[2, l])
                )
        spread[:, :] = 0.0
        for q in range(3):
            pa = D[q] / geo[q] if geo[q] > 0.0 else 0.0
            if pa == 0.0:
                continue
            base = 12 + 9 * q
            for i in range(3):  # R_z J R_z^T
                for l in range(3):
                    acc = 0.0
                    for m1 in range(3):
                        for m2 in range(3):
                            acc += E[m1, i] * geo[base + 3 * m1 + m2] * E[m2, l]
                    spread[i, l] += pa * acc
        for i in range(3):
            for l in range(3):
                K[3 + i, 3 + l] += spread[i, l]
                w0[3 + i] += spread[i, l] * twl[3 + l]
        if bottom >= 0.0:  # rigid bottom on the lowest point (D67)
            lx, ly = c * geo[39] - s * geo[40], s * geo[39] + c * geo[40]
            bl[0], bl[1], bl[2], bl[3], bl[4], bl[5] = 0.0, 0.0, 1.0, ly, -lx, 0.0
            vz = 0.0
            for i in range(6):
                vz += bl[i] * twl[i]
            pen = depth - bottom
            fb = kb * pen - cb * vz
            if pen > 0.0 and fb > 0.0:
                for i in range(6):
                    w0[i] += fb * bl[i]
                    for l in range(6):
                        K[i, l] -= cb * bl[i] * bl[l]
        if tilted:  # back to the world: w0 <- B^T w0, K <- B^T K B, B = diag(Q, Q)
            _back(Q, w0, K, KB)
        # keep what the robot's joint step needs (D62d); a foot with no wrench and no
        # damping (in the air) has nothing to solve
        idle = True
        for i in range(6):
            FW0[j, i], FTW[j, i] = w0[i], tw[i]
            idle = idle and w0[i] == 0.0
            for l in range(6):
                FK[j, i, l] = K[i, l]
                idle = idle and FK[j, i, l] == 0.0
            if has_prev:
                FACC[j, i] = (tw[i] - tw_prev[k, j, i]) / dt - wv_prev[k, j, i]
            else:
                FACC[j, i] = opts[6 + i] if i < 3 else 0.0
        active += 0 if idle else 1
        FPOS[j] = -1.0 if idle else 0.0
        FC[j, 0], FC[j, 1], FC[j, 2] = xipos[body, 0], xipos[body, 1], xipos[body, 2]
        # outputs that do not depend on the applied wrench (the central point: provisional)
        r = out[k, j]
        r[3], r[4], r[5] = w0[0], w0[1], w0[2]
        r[9] = C[0] + (c * geo[9] - s * geo[10])
        r[10] = C[1] + (s * geo[9] + c * geo[10])
        r[11] = C[2] + (geo[11] + (surface - C[2]))
        r[12], r[13], r[14] = tipl[0], tipl[1], geo[41] + surface
        if tilted:  # the points back to the world
            ps = surface + hs
            for a in (9, 12):
                ex, ey, ez = r[a] - tipw[0], r[a + 1] - tipw[1], r[a + 2] - surface
                r[a] = tipw[0] + Q[0, 0] * ex + Q[1, 0] * ey + Q[2, 0] * ez
                r[a + 1] = tipw[1] + Q[0, 1] * ex + Q[1, 1] * ey + Q[2, 1] * ez
                r[a + 2] = ps + Q[0, 2] * ex + Q[1, 2] * ey + Q[2, 2] * ez
        r[15], r[16], r[17] = u[0], u[1], u[2]
        r[18] = depth
        r[19], r[20], r[21] = r0[3], r0[4], r0[5]
    # the implicit step of all the robot's feet together, and its passivity bound
    if active > 0:
        for j in range(nb):
            body = bodies[j, 0]
            if FPOS[j] < 0.0:  # no wrench: no row in the robot's system
                continue
            # J and M^-1 J^T of every foot in the mud (the cross blocks, D62d)
            jp = FJ[j].ctypes.data
            _mj_jac(jac_fn, mptr, dptr, jp, jp + 24 * nv, FC[j].ctypes.data, body)
            for i in range(6):
                for d in range(nv):
                    FM[j, i, d] = FJ[j, i, d]
            _mj_solve_m(solve_fn, mptr, dptr, FM[j].ctypes.data, 6)
        tank[k] = _robot_step(
            nb, nv, dt, FJ, FM, FK, FW0, FACC, FTW, FPOS, WF, AJ, RJ, FWR, FWV, tank[k]
        )
        for j in range(nb):
            for i in range(6):
                wv_prev[k, j, i] = FWV[j, i]
    else:
        tank[k] = 0.0
        for j in range(nb):
            for i in range(6):
                FWR[j, i] = FW0[j, i]
                wv_prev[k, j, i] = 0.0
    for j in range(nb):
        body = bodies[j, 0]
        wr, r = FWR[j], out[k, j]
        finite = True
        for i in range(6):
            tw_prev[k, j, i] = FTW[j, i]
            finite = finite and math.isfinite(wr[i])
            xfrc[body, i] = wr[i]
        for i in range(3):
            r[i], r[6 + i] = wr[i], wr[3 + i]
        f2 = wr[0] * wr[0] + wr[1] * wr[1] + wr[2] * wr[2]
        if f2 > 1e-300:  # the central axis' point nearest to the provisional one
            C = FC[j]
            cx = wr[1] * wr[5] - wr[2] * wr[4]
            cy = wr[2] * wr[3] - wr[0] * wr[5]
            cz = wr[0] * wr[4] - wr[1] * wr[3]
            r0x, r0y, r0z = C[0] + cx / f2, C[1] + cy / f2, C[2] + cz / f2
            tt = ((r[9] - r0x) * wr[0] + (r[10] - r0y) * wr[1] + (r[11] - r0z) * wr[2]) / f2
            r[9], r[10], r[11] = r0x + tt * wr[0], r0y + tt * wr[1], r0z + tt * wr[2]
        r[22] = 0.0 if finite else 1.0
        bad += 0 if finite else 1
    clock[k, 0] = 1.0
    return bad


#: Floats of the kernel's work arrays beyond those that grow with the model (see
#: :func:`work_size`), in the three groups :func:`_kernel` carves in order: geo, aup, v (54),
#: the foot's constants (N_CONST), a state row and a morphing foot's state row (3); tw ... bl
#: (42); M, E, spread, b, K (81); Q, Xq, Cq, Rq, twq, tipq, KB (69).
WORK_FIXED = (57 + N_CONST + N_STATE) + 42 + 81 + 69


def work_size(nv: int, ntri: int, nb: int) -> int:
    """Length of the kernel's ``work`` array for ``nv`` degrees of freedom, ``ntri``
    triangles and ``nb`` foot bodies.
    """
    return 6 * ntri + WORK_FIXED + nb * (12 * nv + 76) + 72 * nb * nb


#: The kernel's arguments: (name, dtype, ndim), in the order of :func:`_kernel`.
ARGS = (
    ("addr", "i8", 2), ("sizes", "i8", 1), ("bodies", "i8", 2), ("tip", "f8", 2), ("fwd", "f8", 2),
    ("tri_adr", "i8", 1), ("tri_b", "f8", 3), ("up_adr", "i8", 1), ("tri_up", "f8", 2),
    ("rows", "f8", 3), ("cfg", "f8", 2), ("geom", "f8", 2), ("morph", "f8", 2),
    ("opts", "f8", 1), ("mud", "f8", 3), ("fst", "f8", 3), ("odo", "f8", 3), ("tw_prev", "f8", 3), ("wv_prev", "f8", 3),
    ("tank", "f8", 1), ("out", "f8", 3), ("work", "f8", 2), ("clock", "f8", 2), ("cells", "i8", 3),
    ("grids", "f8", 2), ("hts", "f8", 3),
)  # fmt: skip
#: Where each argument's address and shape start in the packed array (:func:`pack`).
OFFSETS = tuple(sum(1 + nd for _, _, nd in ARGS[:i]) for i in range(len(ARGS)))


def pack(arrays: list[Any]) -> IndexArray:
    """The kernel's arrays (in the order of :data:`ARGS`) as one int64 array of each one's
    address and shape (one argument for numba to pass); the caller keeps them alive."""
    out: list[int] = []
    for a in arrays:
        out += [int(a.ctypes.data), *a.shape]
    return np.array(out, dtype=np.int64)


def _f1(p: IndexArray, k: int) -> FloatArray:
    return carray(_ptr(p[k]), (p[k + 1],))  # type: ignore[call-arg]


def _f2(p: IndexArray, k: int) -> FloatArray:
    return carray(_ptr(p[k]), (p[k + 1], p[k + 2]))  # type: ignore[call-arg]


def _f3(p: IndexArray, k: int) -> FloatArray:
    return carray(_ptr(p[k]), (p[k + 1], p[k + 2], p[k + 3]))  # type: ignore[call-arg]


def _i1(p: IndexArray, k: int) -> IndexArray:
    return carray(_iptr(p[k]), (p[k + 1],))  # type: ignore[call-arg]


def _i2(p: IndexArray, k: int) -> IndexArray:
    return carray(_iptr(p[k]), (p[k + 1], p[k + 2]))  # type: ignore[call-arg]


def _i3(p: IndexArray, k: int) -> IndexArray:
    return carray(_iptr(p[k]), (p[k + 1], p[k + 2], p[k + 3]))  # type: ignore[call-arg]
