"""The MuJoCo coupling's step in numpy: the reference the compiled kernel is compared with.

Until 0.3 this was the coupling's ``backend="numpy"``. It steps the same equations as the
compiled kernel (``integrations/mujoco/compiled.py``) from their array form, the one the
MJX coupling runs (``integrations/mjx/pose.py``, ``wrench.py``), between ``mj_step1`` and ``mj_step2``,
and calls the terrain's own ``step`` with each velocity raised by the secant step for the
derivative (D61, D63). :func:`attach` and :func:`attach_batch` take ``backend="numpy"``
for it and pass anything else to mudrft's own.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mudrft._validation import MudrftError
from mudrft.integrations import mujoco as coupling_module
from mudrft.integrations.mjx.pose import posed_channels
from mudrft.integrations.mjx.wrench import applied_wrench, channel_motion, com_twist, foot_odometry
from mudrft.integrations.mujoco.backend import NON_FINITE, MudContact
from mudrft.integrations.mujoco.batch import MudBatch
from mudrft.integrations.mujoco.options import check_count, check_integrator, check_timestep
from mudrft.integrations.mujoco.pose import matvec, secant_steps

from .conftest import mujoco  # None without MuJoCo: the test modules skip before using it

#: Smallest secant step in velocity [m/s] (D63), the compiled coupling's.
DV_MIN = 1e-4


def _central_point(force, torque, com, near):
    """Point of the wrench's central axis nearest to ``near`` [m] (``near`` without force)."""
    f2 = np.einsum("...i,...i->...", force, force)
    has = f2 > 1e-300
    safe = np.where(has, f2, 1.0)[..., None]
    r0 = com + np.cross(force, torque) / safe
    t = np.einsum("...i,...i->...", near - r0, force)[..., None] / safe
    return np.where(has[..., None], r0 + t * force, near)


def _tree_map(fn, tree):
    if tree is None:
        return None
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return type(tree)(*(_tree_map(fn, t) for t in tree))
    if isinstance(tree, tuple | list):
        return type(tree)(_tree_map(fn, t) for t in tree)
    return fn(tree)


def force_and_derivative(terrain, foot, state, pos, vel, step, dt):
    r"""Step the terrain, with each velocity component of ``vel`` [m/s] also raised by
    ``step`` [m/s]; ``pos`` [m], (N, nb, 3), foot frame. Returns the new state, the force
    [N], :math:`\partial F_i/\partial v_i` [N s/m] and the stresses [Pa]."""
    vk = np.repeat(vel[None], 4, axis=0)
    for c in range(3):
        vk[c + 1, ..., c] += step[..., c]
    batch = pos.shape[:-1]

    def four(x):  # a state leaf, broadcast to the batch, 4 copies
        a = np.asarray(x)
        a = a if a.shape[: len(batch)] == batch else np.broadcast_to(a, batch + a.shape)
        return np.repeat(a[None], 4, axis=0)

    new, out = terrain.step(foot, _tree_map(four, state), np.broadcast_to(pos, vk.shape), vk, dt)
    new = _tree_map(lambda x: x[0] if np.ndim(x) else x, new)
    fk = np.asarray(out.force)
    jd = (np.stack([fk[1, ..., 0], fk[2, ..., 1], fk[3, ..., 2]], axis=-1) - fk[0]) / step
    return new, fk[0], jd, np.asarray(out.stress)[0]


def chain_mobility(model, datas, ids, com):
    """Mobility :math:`J_iM^{-1}J_j^T` (N, nb, nb, 6, 6) of the bodies at their centers of
    mass ``com`` [m], from the whole model (D62, D62d)."""
    nb = len(ids)
    jac = np.zeros((nb, 6, model.nv))
    minv_jt = np.zeros((nb, 6, model.nv))
    W = np.empty((len(datas), nb, nb, 6, 6))
    for k, d in enumerate(datas):
        for j, b in enumerate(ids):
            mujoco.mj_jac(model, d, jac[j, :3], jac[j, 3:], com[k, j], int(b))
            mujoco.mj_solveM(model, d, minv_jt[j], jac[j])
        W[k] = np.einsum("iav,jbv->ijab", jac, minv_jt)
    return W


class NumpyCoupling(MudBatch):
    """The reference coupling: :class:`MudBatch`'s placement, stepped in numpy."""

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        self.backend = "numpy"

    def reset(self, datas):
        self._reset_with = None
        datas = self._check(datas)
        self._timestep = check_timestep(self.model, checked=self._timestep)
        check_integrator(self.model)
        for d in datas:
            mujoco.mj_forward(self.model, d)
        k = self._reading(datas)
        pos = self._foot_position(k, fresh=True)
        for gi, (foot, idx) in enumerate(self._groups):
            self._states[gi] = self.terrain.initial_state(foot, pos[:, idx])
        self._world_xy = k["tip"][..., :2]
        self._has_prev = False
        n, nb = self.n, len(self.bodies)
        self._tw_prev, self._wv_prev, self._tank = np.zeros((n, nb, 6)), np.zeros((n, nb, 6)), np.zeros(n)  # fmt: skip
        W = mujoco.mjtWarning
        bad = [int(w) for w in (W.mjWARN_BADQPOS, W.mjWARN_BADQVEL, W.mjWARN_BADQACC)]
        self._warn = [tuple(d.warning[i] for i in bad) for d in datas]
        self._warnings = [[0, 0, 0] for _ in datas]
        self._clear_warnings()
        self._ref_last = None
        self.time_steps = 0
        for d in datas:
            d.xfrc_applied[self._ids] = 0.0

    @property
    def last(self):
        return self._ref_last

    def _reading(self, datas):
        X = np.stack([d.xpos for d in datas])[:, self._ids]
        R = np.stack([d.xmat for d in datas])[:, self._ids].reshape(len(datas), -1, 3, 3)
        C = np.stack([d.xipos for d in datas])[:, self._ids]
        V = np.stack([d.cvel for d in datas])[:, self._ids]
        S = np.stack([d.subtree_com for d in datas])[:, self._roots]
        tip = X + matvec(R, self._tip)
        Xp, Rp, Cp, tp = X, R, C, tip
        if any(f is not None and f.heights.any() for f in self._fields):
            Xp, Rp, Cp, tp = self._on_planes(X, R, C, tip)
        fw = matvec(Rp, self._fwd)
        h = np.maximum(np.hypot(fw[..., 0], fw[..., 1]), 1e-12)
        cs = np.stack([fw[..., 0] / h, fw[..., 1] / h], axis=-1)
        geo, ratio = self._posed(Xp, Rp, Cp, tp, cs)
        W = chain_mobility(self.model, datas, self._ids, C)
        return {"com": C, "tip": tip, "cs": cs, "tw": com_twist(V, S, C), "W": W, "geo": geo, "ratio": ratio}  # fmt: skip

    def _posed(self, X, R, C, tip, cs):
        groups = [
            (tri, up, idx, bool(self._ball[idx[0]]))
            for (tri, up), (_, idx) in zip(self._pose, self._groups, strict=True)
        ]
        X = np.where(self._ball[:, None], tip, X) if self._ball.any() else X  # balls: centers
        return posed_channels(groups, X, R, C, cs, self.surface)

    def _foot_position(self, k, *, fresh):
        was_in = None
        if not fresh:
            was_in = np.zeros((self.n, len(self.bodies)), dtype=bool)
            for (_, idx), st in zip(self._groups, self._states, strict=True):
                im = getattr(st, "in_mud", None)
                was_in[:, idx] = np.broadcast_to(im, (self.n, len(idx))) if im is not None else True  # fmt: skip
        self._foot_xy = foot_odometry(
            k["cs"], k["tip"][..., :2], was_in, getattr(self, "_world_xy", None),
            getattr(self, "_foot_xy", None),
        )  # fmt: skip
        return np.concatenate([self._foot_xy, k["geo"].low[..., 2:]], axis=-1)

    def apply(self, datas):
        datas = self._check(datas)
        if self._warn:
            self._check_diverged(datas)
        return self._step_mud(datas)

    def _step_mud(self, datas):
        if self._states[0] is None:
            raise MudrftError("call reset(data) before stepping the mud coupling")
        dt = float(self.model.opt.timestep)
        k = self._reading(datas)
        geo, cs, tw, com = k["geo"], k["cs"], k["tw"], k["com"]
        rel, b, vel = channel_motion(cs, geo.point, com, tw, self.surface)
        pos = self._foot_position(k, fresh=False)
        self._world_xy = k["tip"][..., :2]
        N, nb = pos.shape[:2]
        f_up, jd, stress = np.empty((N, nb, 3)), np.zeros((N, nb, 3)), np.empty((N, nb, 3))
        depth = np.maximum(-pos[..., 2], 0.0)
        step = secant_steps(vel, DV_MIN)
        for gi, (foot, idx) in enumerate(self._groups):
            new, f_up[:, idx], jd[:, idx], stress[:, idx] = force_and_derivative(
                self.terrain, foot, self._states[gi], pos[:, idx], vel[:, idx], step[:, idx], dt
            )
            self._states[gi] = new
        if self._has_prev:  # the other forces' twist acceleration, from the last step (D62)
            acc = (tw - self._tw_prev) / dt - self._wv_prev
        else:
            acc = np.zeros_like(tw)
            acc[..., :3] = np.asarray(self.model.opt.gravity, dtype=float)
        wrench, w0, self._tank, self._wv_prev = applied_wrench(
            k["ratio"], f_up, jd, b, geo, cs, tw, com, depth, k["W"], acc, self._tank, dt,
            surface=self.surface, bottom=self.bottom, stiffness=self.bottom_stiffness,
            damping=self.bottom_damping,
        )  # fmt: skip
        self._tw_prev, self._has_prev = tw, True
        if not np.all(np.isfinite(wrench)):
            raise MudrftError(NON_FINITE)
        for i, d in enumerate(datas):
            d.xfrc_applied[self._ids] = wrench[i]
        self.time_steps += 1
        force, torque = wrench[..., :3], wrench[..., 3:]
        c = MudContact(
            force=force,
            explicit_force=w0[..., :3],
            torque=torque,
            point=_central_point(force, torque, com, com + rel[..., 2, :]),
            tip=np.concatenate([k["tip"][..., :2], geo.low[..., 2:] + self.surface], axis=-1),
            velocity=vel,
            depth=depth,
            stress=stress,
        )
        self._ref_last = MudContact(*(a[0] for a in c)) if self._single else c
        self._check_buried(depth)
        return self._ref_last

    def step(self, datas, nstep=1):
        self.advance(datas, nstep)
        return self._ref_last

    def advance(self, datas, nstep=1):
        datas = self._check(datas)
        for _ in range(check_count("nstep", nstep)):
            for d in datas:
                mujoco.mj_step1(self.model, d)
            self._step_mud(datas)
            for d in datas:
                mujoco.mj_step2(self.model, d)
            self._check_diverged(datas)

    def detach(self):
        pass


def attach_batch(model, bodies, mud, *, n, backend: str = "auto", **kw: Any):
    """:func:`mudrft.integrations.mujoco.attach_batch`, or the reference for ``"numpy"``."""
    if backend != "numpy":
        return coupling_module.attach_batch(model, bodies, mud, n=n, backend=backend, **kw)
    return NumpyCoupling(model, bodies, mud, n=n, **kw)


def attach(model, bodies, mud, *, backend: str = "auto", **kw: Any):
    """:func:`mudrft.integrations.mujoco.attach`, or the reference for ``"numpy"``."""
    if backend != "numpy":
        return coupling_module.attach(model, bodies, mud, backend=backend, **kw)
    ref = NumpyCoupling(model, bodies, mud, n=1, **kw)
    ref._single = True
    return ref
