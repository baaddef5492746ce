r"""The coupling of mud with many robots of one MuJoCo model: :class:`MudBatch`.

Every step reads the kinematics of all robots (:mod:`.kinematics`), steps the terrain
once per foot type for all robots and bodies together, stabilises the force with the
linearly implicit step of its dissipative part (decisions D61-D63 in docs/model.md,
summarised in :mod:`mudrft.integrations.mujoco`) and writes ``xfrc_applied``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..._validation import MudrftError, check_finite, check_nonnegative, check_positive
from ...citations import register
from ...terrains import as_terrain
from ._lazy import _mujoco
from .implicit import force_and_derivative, implicit_force, secant_steps
from .kinematics import _cross, body_frames, body_mobility, chain_mobility
from .placement import BodyFoot, body_foot, lowest_points

__all__ = ["MudBatch", "MudContact"]


class MudContact(NamedTuple):
    """What the mud did in the last step, per robot and body (world frame).

    Shapes are ``(nbody, ...)`` for :class:`~mudrft.integrations.mujoco.MudCoupling` and
    ``(nrobot, nbody, ...)`` for :class:`MudBatch`.

    Attributes
    ----------
    force : ndarray (..., 3)
        Force written to ``xfrc_applied`` (stabilised) [N].
    explicit_force : ndarray (..., 3)
        Force of the mud model at the start of the step (what :class:`mudrft.MudTerrain`
        returns for the same motion) plus the rigid bottom [N].
    torque : ndarray (..., 3)
        Moment about the body's center of mass written to ``xfrc_applied`` [N m].
    point : ndarray (..., 3)
        Point of application (center of pressure) [m].
    tip : ndarray (..., 3)
        Tip position; its z is that of the lowest point of the foot [m].
    velocity : ndarray (..., 3)
        Tip velocity [m/s].
    depth : ndarray (...)
        Depth of the lowest point below the mud surface [m].
    stress : ndarray (..., 3)
        Channel stresses in the foot frame [Pa].
    """

    force: NDArray[np.float64]
    explicit_force: NDArray[np.float64]
    torque: NDArray[np.float64]
    point: NDArray[np.float64]
    tip: NDArray[np.float64]
    velocity: NDArray[np.float64]
    depth: NDArray[np.float64]
    stress: NDArray[np.float64]


class MudBatch:
    """Mud under named bodies of ``n`` MjData of one model, vectorized across robots.

    Every step reads the kinematics of all robots, calls the terrain once per foot type
    for all robots and bodies together, and writes ``xfrc_applied`` of each MjData.

    Parameters
    ----------
    model : mujoco.MjModel
        The model shared by all robots.
    bodies : sequence of str
        Names of the bodies that touch the mud.
    mud : Mud or Terrain
        The mud (:func:`mudrft.paper_mud`), a configured :class:`mudrft.MudTerrain`, or
        any terrain.
    n : int, keyword-only
        Number of robots.
    feet : Foot, sequence of Foot or None, keyword-only
        Foot of every body (one for all, or one per body); ``None`` derives each from the
        body's geoms (see :func:`body_foot`).
    surface : float, keyword-only
        Height of the mud surface in the world [m].
    bottom : float or None, keyword-only
        Depth of a rigid bottom below the surface [m] (a one-sided penalty on the lowest
        point of the foot), or ``None`` for bottomless mud.
    bottom_stiffness : float, keyword-only
        Stiffness of that bottom [N/m] (explicit).
    bottom_damping : float, keyword-only
        Damping of that bottom [N s/m] (treated implicitly like the mud's).
    implicit : bool, keyword-only
        Apply the semi-implicit treatment of the velocity-dependent part (default).
        ``False`` writes the explicit force, exactly what :class:`mudrft.MudTerrain` gives.
    mobility : {"chain", "body"}, keyword-only
        Tip mobility :math:`W` from the whole model (:math:`JM^{-1}J^T`, default) or from
        the body alone (cheaper, an upper bound: more damping in transients).
    center_of_pressure : {"axis", "foot", "tip"}, keyword-only
        Where the force acts: on the foot axis half-way up the submerged height (default,
        cheap), at the foot's own center of pressure (``foot.center_of_pressure``; exact
        for mesh-integrated feet but slower), or at the tip.
    """

    def __init__(
        self,
        model: Any,
        bodies: Sequence[str],
        mud: Any,
        *,
        n: int = 1,
        feet: Any = None,
        surface: float = 0.0,
        bottom: float | None = None,
        bottom_stiffness: float = 1e5,
        bottom_damping: float = 2e3,
        implicit: bool = True,
        mobility: str = "chain",
        center_of_pressure: str = "axis",
    ) -> None:
        mj = _mujoco()
        if not isinstance(model, mj.MjModel):
            raise MudrftError(f"model must be a mujoco.MjModel, got {type(model).__name__}")
        if isinstance(bodies, str):
            bodies = [bodies]
        bodies = list(bodies)
        if not bodies:
            raise MudrftError("bodies must name at least one body, got an empty list")
        if len(set(bodies)) != len(bodies):
            raise MudrftError(f"bodies must be distinct, got {bodies}")
        if not isinstance(n, (int, np.integer)) or n < 1:
            raise MudrftError(f"n must be an integer >= 1, got {n!r}")
        if mobility not in ("chain", "body"):
            raise MudrftError(f"mobility must be 'chain' or 'body', got {mobility!r}")
        if feet is None or hasattr(feet, "contact_force"):
            feet_list = [feet] * len(bodies)
        else:
            feet_list = list(feet)
            if len(feet_list) != len(bodies):
                raise MudrftError(
                    f"feet must be one foot or one per body ({len(bodies)}), got {len(feet_list)}"
                )
        self.model = model
        self.terrain = as_terrain(mud)
        register("todorov2012mujoco")
        self.n = int(n)
        self.surface = float(check_finite("surface", surface))
        self.bottom = None if bottom is None else float(check_positive("bottom", bottom, unit="m"))
        self.bottom_stiffness = float(
            check_nonnegative("bottom_stiffness", bottom_stiffness, unit="N/m")
        )
        self.bottom_damping = float(
            check_nonnegative("bottom_damping", bottom_damping, unit="N s/m")
        )
        self.implicit = bool(implicit)
        self.mobility = mobility
        if center_of_pressure not in ("axis", "foot", "tip"):
            raise MudrftError(
                f"center_of_pressure must be 'axis', 'foot' or 'tip', got {center_of_pressure!r}"
            )
        self.use_cop = center_of_pressure if center_of_pressure != "tip" else ""
        # one foot object per identical geometry, so equal feet share one terrain call
        cache: dict[Any, Any] = {}
        placed = []
        for b, f in zip(bodies, feet_list, strict=True):
            bf = body_foot(model, b, f)
            key = repr(bf.foot) if f is None else id(f)
            foot = (
                cache.setdefault(key, bf.foot) if f is None and _hashable_repr(bf.foot) else bf.foot
            )
            placed.append(BodyFoot(**{**bf.__dict__, "foot": foot}))
        self.bodies: tuple[BodyFoot, ...] = tuple(placed)
        self._ids = np.array([b.body_id for b in self.bodies])
        self._roots = np.array(model.body_rootid)[self._ids]
        self._tip = np.stack([b.tip for b in self.bodies])
        self._fwd = np.stack([b.forward for b in self.bodies])
        groups: dict[int, list[int]] = {}
        for i, placed_body in enumerate(self.bodies):
            groups.setdefault(id(placed_body.foot), []).append(i)
        self._groups = [(self.bodies[idx[0]].foot, np.array(idx)) for idx in groups.values()]
        nb = len(self.bodies)
        self._states: list[Any] = [None] * len(self._groups)
        self._foot_xy = np.zeros((self.n, nb, 2))
        self._world_xy = np.zeros((self.n, nb, 2))
        self._v_prev = np.zeros((self.n, nb, 3))
        self._wf_prev = np.zeros((self.n, nb, 3))
        self._has_prev = False
        self._jac = np.zeros((3, model.nv))
        self._minv_jt = np.zeros((3, model.nv))
        self._dv_min = 1e-4  # smallest secant step in velocity [m/s] (D63)
        self.last: MudContact | None = None
        self.time_steps = 0

    # -- reading MuJoCo ---------------------------------------------------------------
    def _read(self, datas: Sequence[Any]) -> dict[str, Any]:
        X, R, C, V, S = body_frames(datas, self._ids, self._roots)
        tip = X + (R @ self._tip[..., None])[..., 0]
        low = lowest_points(self.bodies, X, R, tip)
        w, vlin = V[..., :3], V[..., 3:]
        v_tip = vlin + _cross(w, tip - S)
        r = low - S  # z velocity of the material point that is lowest (envelope theorem)
        vz_low = vlin[..., 2] + w[..., 0] * r[..., 1] - w[..., 1] * r[..., 0]
        W = None
        if self.implicit:
            if self.mobility == "chain":
                W = chain_mobility(self.model, datas, self._ids, tip, self._jac, self._minv_jt)
            else:
                W = body_mobility(self.model, datas, self._ids, tip, C)
        return {"R": R, "com": C, "tip": tip, "low": low, "v_tip": v_tip, "vz_low": vz_low, "W": W}

    # -- public API -------------------------------------------------------------------
    def reset(self, datas: Sequence[Any]) -> None:
        """Start with undisturbed mud under the feet in their current pose (calls mj_forward)."""
        mj = _mujoco()
        datas = self._check(datas)
        for d in datas:
            mj.mj_forward(self.model, d)
        k = self._read(datas)
        pos, _vel, _cs = self._foot_frame(k, fresh=True)
        for gi, (foot, idx) in enumerate(self._groups):
            self._states[gi] = self.terrain.initial_state(foot, pos[:, idx])
        self._world_xy = k["tip"][..., :2]
        self._has_prev = False
        self._wf_prev[:] = 0.0
        self.last = None
        for d in datas:
            d.xfrc_applied[self._ids] = 0.0

    def _check(self, datas: Any) -> list[Any]:
        mj = _mujoco()
        if isinstance(datas, mj.MjData):
            datas = [datas]
        datas = list(datas)
        if len(datas) != self.n:
            raise MudrftError(f"expected {self.n} MjData, got {len(datas)}")
        return datas

    def _foot_frame(
        self, k: dict[str, np.ndarray], *, fresh: bool
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Tip position and velocity in the foot frame, and (cos, sin) of the foot's yaw."""
        fw = (k["R"] @ self._fwd[..., None])[..., 0]
        h = np.maximum(np.hypot(fw[..., 0], fw[..., 1]), 1e-12)
        cs = np.stack([fw[..., 0] / h, fw[..., 1] / h], axis=-1)  # the foot's heading (yaw)
        c, s = cs[..., 0], cs[..., 1]
        tip, v = k["tip"], k["v_tip"]
        if fresh:
            xy = tip[..., :2]
            fxy = np.stack(
                [c * xy[..., 0] + s * xy[..., 1], c * xy[..., 1] - s * xy[..., 0]], axis=-1
            )
        else:
            # odometry in the foot frame: a yawing foot sees no jump in its position (D65);
            # out of the mud the position restarts from the rotated world position
            was_in = self._in_mud()[..., None]
            xy = np.where(was_in, tip[..., :2] - self._world_xy, tip[..., :2])
            base = np.where(was_in, self._foot_xy, 0.0)
            fxy = base + np.stack(
                [c * xy[..., 0] + s * xy[..., 1], c * xy[..., 1] - s * xy[..., 0]], axis=-1
            )
        self._foot_xy = fxy
        pos = np.concatenate([fxy, k["low"][..., 2:] - self.surface], axis=-1)
        vel = np.stack(
            [c * v[..., 0] + s * v[..., 1], c * v[..., 1] - s * v[..., 0], k["vz_low"]], axis=-1
        )
        return pos, vel, cs

    def _in_mud(self) -> np.ndarray:
        out = np.zeros((self.n, len(self.bodies)), dtype=bool)
        for (_, idx), st in zip(self._groups, self._states, strict=True):
            im = getattr(st, "in_mud", None)
            out[:, idx] = np.broadcast_to(im, (self.n, len(idx))) if im is not None else True
        return out

    def apply(self, datas: Sequence[Any]) -> MudContact:
        """Advance the mud once and write ``xfrc_applied`` for the current state.

        Call after ``mj_step1`` (or ``mj_forward``) and before ``mj_step2``; :meth:`step`
        does all three.
        """
        return self._apply(self._check(datas))

    def _apply(self, datas: list[Any]) -> MudContact:
        if self._states[0] is None:
            raise MudrftError("call reset(data) before stepping the mud coupling")
        dt = float(self.model.opt.timestep)
        k = self._read(datas)
        pos, vel, cs = self._foot_frame(k, fresh=False)
        self._world_xy = k["tip"][..., :2]
        c, s = cs[..., 0], cs[..., 1]
        N, nb = pos.shape[:2]
        f0 = np.empty((N, nb, 3))
        jd = np.zeros((N, nb, 3))
        stress = np.empty((N, nb, 3))
        cop = np.zeros((N, nb, 3))
        depth = np.maximum(-pos[..., 2], 0.0)
        if self.implicit:
            step = secant_steps(self._wf_prev, cs, dt, self._dv_min)
        for gi, (foot, idx) in enumerate(self._groups):
            st = self._states[gi]
            p, v = (pos, vel) if len(idx) == nb else (pos[:, idx], vel[:, idx])
            if self.implicit:
                sk = step if len(idx) == nb else step[:, idx]
                new, f0[:, idx], jd[:, idx], sg = force_and_derivative(
                    self.terrain, foot, st, p, v, sk, dt
                )
            else:
                new, out = self.terrain.step(foot, st, p, v, dt)
                f0[:, idx] = np.asarray(out.force)
                sg = np.asarray(out.stress)
            self._states[gi] = new
            stress[:, idx] = sg
            if self.use_cop:
                d = depth[:, idx]
                if self.use_cop == "foot":
                    heading = np.broadcast_to(getattr(new, "heading", 0.0), d.shape)
                    cp = np.asarray(foot.center_of_pressure(d, sg, heading), dtype=float)
                    cop[:, idx] = np.where((d > 0)[..., None], cp, 0.0)
                else:  # on the axis, half-way up the submerged height
                    cop[:, idx, 2] = 0.5 * np.minimum(d, float(foot.height))
        if self.bottom is not None:
            pen = depth - self.bottom
            on = pen > 0
            fb = np.where(
                on,
                np.maximum(self.bottom_stiffness * pen - self.bottom_damping * vel[..., 2], 0.0),
                0.0,
            )
            f0[..., 2] += fb
            jd[..., 2] -= np.where(on & (fb > 0), self.bottom_damping, 0.0)
        f0_w = np.stack(
            [c * f0[..., 0] - s * f0[..., 1], s * f0[..., 0] + c * f0[..., 1], f0[..., 2]], axis=-1
        )
        if self.implicit:
            if self._has_prev:
                acc = (k["v_tip"] - self._v_prev) / dt - self._wf_prev
            else:
                acc = np.broadcast_to(np.asarray(self.model.opt.gravity, dtype=float), f0_w.shape)
            # linearly implicit step of the dissipative part (D62)
            W = k["W"]
            force = implicit_force(f0_w, jd, cs, W, acc, dt)
            self._wf_prev = (W @ force[..., None])[..., 0]
        else:
            force = f0_w
        self._v_prev = k["v_tip"]
        self._has_prev = True
        tip = np.concatenate([k["tip"][..., :2], k["low"][..., 2:]], axis=-1)
        point = tip.copy()
        point[..., 0] += c * cop[..., 0] - s * cop[..., 1]
        point[..., 1] += s * cop[..., 0] + c * cop[..., 1]
        point[..., 2] += cop[..., 2]
        torque = _cross(point - k["com"], force)
        wrench = np.concatenate([force, torque], axis=-1)
        if not np.all(np.isfinite(wrench)):
            raise MudrftError(
                "the mud coupling produced a non-finite force; the simulation diverged "
                "(check the model, the time step and the mud parameters)"
            )
        for i, d in enumerate(datas):
            d.xfrc_applied[self._ids] = wrench[i]
        self.time_steps += 1
        self.last = MudContact(
            force=force,
            explicit_force=f0_w,
            torque=torque,
            point=point,
            tip=tip,
            velocity=k["v_tip"],
            depth=depth,
            stress=stress,
        )
        return self.last

    def step(self, datas: Sequence[Any], nstep: int = 1) -> MudContact:
        """``nstep`` physics steps of every robot, the mud advanced once per step."""
        return self._step(self._check(datas), nstep)

    def _step(self, datas: list[Any], nstep: int) -> MudContact:
        mj = _mujoco()
        m = self.model
        rk4 = int(m.opt.integrator) == int(mj.mjtIntegrator.mjINT_RK4)
        out = self.last
        for _ in range(int(nstep)):
            if rk4:  # mj_step1/mj_step2 do not support RK4: full forward, then mj_step
                for d in datas:
                    mj.mj_forward(m, d)
                out = self._apply(datas)
                for d in datas:
                    mj.mj_step(m, d)
            else:
                for d in datas:
                    mj.mj_step1(m, d)
                out = self._apply(datas)
                for d in datas:
                    mj.mj_step2(m, d)
        assert out is not None
        return out


def _hashable_repr(foot: Any) -> bool:
    # dataclass feet with eq=True print their parameters; equal reprs = equal geometry
    return type(foot).__repr__ is not object.__repr__ and "(" in repr(foot) and "=" in repr(foot)
