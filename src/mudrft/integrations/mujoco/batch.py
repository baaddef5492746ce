r"""The coupling of mud with many robots of one MuJoCo model: :class:`MudBatch`.

Each physics step, MuJoCo's passive callback (:mod:`.callback`) runs the compiled kernel
(:mod:`.compiled`) for every robot: it reads the feet's pose and twist, steps their mud,
takes the implicit step of the wrench with the passivity bound and writes ``xfrc_applied``.
:class:`MudBatch` places the feet, starts the mud (:meth:`MudBatch.reset`) and checks each
step that MuJoCo did not diverge.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..._progress import logger
from ..._typing import FloatArray
from ..._validation import MudrftError
from ...citations import register
from ...terrains import as_terrain
from ...terrains.field import MudField, same_options, surface_at
from ...trajectories import check_unburied
from ._lazy import _mujoco
from .backend import CompiledCoupling, MudContact, not_compilable
from .options import (
    check_attach_options,
    check_count,
    check_data,
    check_integrator,
    check_removed,
    check_spring_step,
    check_timestep,
    diverged_error,
)
from .placement import (
    BodyFoot,
    attached_foot,
    coupled_tip,
    describe,
    group_triangles,
)
from .pose import POSE_RESOLUTION, matvec, on_planes

if TYPE_CHECKING:
    import mujoco

    from ...feet.base import Foot
    from ...parameters import Mud
    from ...terrains import MudTerrain

__all__ = ["MudBatch", "MudContact"]

#: What the warning of a buried foot advises (:meth:`MudBatch._check_buried`).
BURIED_HINT = (
    "; a firmer mud (lower water content), a bed (attach's bottom= [m] below the surface) "
    "or a taller foot keeps it within its height"
)


class MudBatch:
    """Mud under named bodies of ``n`` MjData of one model, vectorized across robots.

    Parameters
    ----------
    model : mujoco.MjModel
        The model shared by all robots.
    bodies : "auto", str, int or a sequence of them
        The bodies that touch the mud, each by its name, the name of one of its geoms (then
        its foot) or its id (a body without a name); ``"auto"`` finds the feet
        (:func:`~.placement.auto_feet`) and logs them (:attr:`feet`).
    mud : Mud, MudTerrain or MudField
        The mud (:func:`mudrft.paper_mud`), a :class:`mudrft.MudTerrain`, or patches of mud
        and rigid ground (:class:`~mudrft.terrains.field.MudField`).
    n : int
        Number of robots.
    feet : Foot, sequence of Foot or None
        Foot of every body (one for all, or one per body); ``None`` derives each from the
        body's geoms (:func:`body_foot`).
    surface : float
        Height of the mud surface in the world [m].
    bottom : float or None
        Depth of a rigid bottom below the surface [m], or ``None`` for bottomless mud.
    bottom_stiffness : float
        Stiffness of that bottom [N/m].
    bottom_damping : float
        Damping of that bottom [N s/m] (treated implicitly).
    resolution : int
        Mesh resolution of curved closed-form feet (D60a).
    foot_geoms : mapping or None
        ``{body: geom name, or a list of them}``: a body's foot geoms where its lowest
        colliding geoms are not (D124).
    backend : {"auto", "numba"}
        The compiled coupling, either way (kept for 0.2's callers; ``"numpy"`` was removed).
    floor : {"warn", "below", "keep"}
        A floor geom at or above the mud's surface carries the feet in place of the mud:
        ``"warn"`` says so, ``"below"`` lowers it :data:`~.options.BED_DEPTH` (0.5 m) under
        the surface (the model is changed in place), ``"keep"`` keeps it quietly.

    Warns
    -----
    PlausibilityWarning
        A body welded to the world (D113); a timestep above 10 ms (D123); a floor at or
        above the surface (``floor="warn"``); from :meth:`step`, :meth:`advance` and
        :attr:`last`, a foot deeper than its own height
        (:class:`~mudrft.trajectories.BuriedFootWarning`, once a foot until :meth:`reset`).

    Raises
    ------
    MudrftError
        For gravity not along -z, MuJoCo's RK4 integrator, or an option of 0.2 that was
        removed (``implicit``, ``mobility``, ``lookahead``); from :meth:`step` when MuJoCo
        reports a diverged simulation or the wrench is not finite.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        bodies: str | int | Sequence[str | int],
        mud: Mud | MudTerrain | MudField,
        *,
        n: int = 1,
        feet: Foot | Sequence[Foot | None] | None = None,
        surface: float = 0.0,
        bottom: float | None = None,
        bottom_stiffness: float = 1e5,
        bottom_damping: float = 2e3,
        resolution: int = POSE_RESOLUTION,
        foot_geoms: Mapping[str, str | int] | None = None,
        backend: str = "auto",
        floor: str = "warn",
        **removed: object,
    ) -> None:
        mj = _mujoco()
        check_removed("attach", removed)
        opts = check_attach_options(
            model,
            bodies, feet, surface=surface, bottom=bottom, bottom_stiffness=bottom_stiffness,
            bottom_damping=bottom_damping, resolution=resolution, foot_geoms=foot_geoms,
            floor=floor,
        )  # fmt: skip
        check_integrator(model)
        feet_list = opts.feet
        n = check_count("n", n)
        self.model = model
        self._mj = mj
        self._checked: tuple[int, ...] = ()  # ids of the MjData checked last (see _check)
        self._checked_datas: list[mujoco.MjData] = []
        self._opt = model.opt  # a view of the model's options (reading model.opt makes one)
        self.field = mud if isinstance(mud, MudField) else None
        self._fields: list[MudField | None] = [self.field] * int(n)  # each robot's (use_field)
        self.terrain = mud.terrain if isinstance(mud, MudField) else as_terrain(mud)
        register("todorov2012mujoco")
        self.n = int(n)
        self.surface, self.bottom = opts.surface, opts.bottom
        self.bottom_stiffness, self.bottom_damping = opts.bottom_stiffness, opts.bottom_damping
        # one foot object per identical geometry, so equal feet share one terrain call
        cache: dict[object, Foot] = {}
        placed = []
        for b, f, g in zip(opts.bodies, feet_list, opts.geoms, strict=True):
            bf = attached_foot(model, b, f, resolution=opts.resolution, geom=g)
            if f is None and _hashable_repr(bf.foot):
                up = None if bf.upright is None else np.asarray(bf.upright).tobytes()
                bf = BodyFoot(**{**bf.__dict__, "foot": cache.setdefault((repr(bf.foot), up, bf.ball), bf.foot)})  # fmt: skip
            placed.append(bf)
        self.bodies: tuple[BodyFoot, ...] = tuple(placed)
        if opts.auto:
            logger.info("feet='auto' chose:\n  %s", "\n  ".join(self.feet))
        self._ids = np.array([b.body_id for b in self.bodies])
        self._roots = np.array(model.body_rootid)[self._ids]
        self._ball = np.array([b.ball for b in self.bodies])
        self._tip = np.stack([coupled_tip(b) for b in self.bodies])
        # the depth [m] past which a foot is buried (check_unburied's margin), and which warned
        self._too_deep = np.array([float(b.foot.height) for b in self.bodies]) * (1 + 1e-9)
        self._buried = np.zeros(len(self.bodies), dtype=bool)
        self._fwd = np.stack([b.forward for b in self.bodies])
        groups: dict[int, list[int]] = {}
        for i, placed_body in enumerate(self.bodies):
            groups.setdefault(id(placed_body.foot), []).append(i)
        self._groups = [(self.bodies[idx[0]].foot, np.array(idx)) for idx in groups.values()]
        self._timestep = check_timestep(model)  # reset checks again if it changed (D123)
        check_spring_step(model, self.bodies)
        self._states: list[Any] = [None] * len(self._groups)
        self._pose = [group_triangles(self.bodies, idx) for _, idx in self._groups]
        # per robot MuJoCo's counters of a bad qpos, qvel and qacc (it resets such a state)
        self._warn: list[tuple[mujoco.MjWarningStat, ...]] = []
        self._warnings: list[list[int]] = []
        if backend not in ("auto", "numba"):
            why = " (the numpy coupling was removed in 0.3)" if backend == "numpy" else ""
            raise MudrftError(f"backend must be 'auto' or 'numba', got {backend!r}{why}")
        why = not_compilable(self.terrain, self.bodies)
        if why:
            raise MudrftError(why)
        self.backend = "numba"
        self._compiled = CompiledCoupling(self)
        self._depth = self._compiled.out[..., 18]  # a view: the kernel writes in place
        self._dv_min = 1e-4  # smallest secant step in velocity [m/s] (D63)
        self.time_steps = 0
        self._single = False  # MudCoupling: outputs of shape (nbody, ...)
        self._reset_with: object = None  # the argument of reset(), checked once

    @property
    def feet(self) -> tuple[str, ...]:
        """What each coupled body's foot is: its body, geoms and foot, one line each."""
        return tuple(describe(self.model, b) for b in self.bodies)

    @property
    def last(self) -> MudContact | None:
        """What the mud did in the last step (:class:`MudContact`), or ``None`` before it.

        The compiled coupling builds it from its outputs when it is read, also after a
        plain ``mujoco.mj_step``.
        """
        c = self._compiled
        if not c.clock[:, 0].any():
            return None
        self._check_buried(self._depth)  # plain mj_step has not checked
        return c.contact(0 if self._single else None)

    # -- reading MuJoCo ---------------------------------------------------------------
    def _read(self, datas: Sequence[mujoco.MjData]) -> tuple[FloatArray, FloatArray]:
        """Each foot's tip [m] in the world, and in the foot's yaw frame with the height of
        its lowest point above the surface [m], (N, nb, 3): what the kernel starts from."""
        X = np.stack([d.xpos for d in datas])[:, self._ids]
        R = np.stack([d.xmat for d in datas])[:, self._ids].reshape(len(datas), -1, 3, 3)
        tip = X + matvec(R, self._tip)
        Xp, Rp, tp = X, R, tip
        if any(f is not None and f.heights.any() for f in self._fields):  # uneven (compiled)
            C = np.stack([d.xipos for d in datas])[:, self._ids]
            Xp, Rp, _, tp = self._on_planes(X, R, C, tip)
        fw = matvec(Rp, self._fwd)
        h = np.maximum(np.hypot(fw[..., 0], fw[..., 1]), 1e-12)
        c, s = fw[..., 0] / h, fw[..., 1] / h  # the foot's heading (yaw)
        x, y = tip[..., 0], tip[..., 1]
        low = np.empty(tip.shape[:2])  # the lowest vertex, as the kernel poses the foot
        for (tri, _), (_, idx) in zip(self._pose, self._groups, strict=True):
            if self._ball[idx[0]]:  # a ball centered at the tip
                low[:, idx] = (tp[:, idx, 2] - self.surface) + np.min(tri[..., 2], axis=(-1, -2))
                continue
            r = Rp[:, idx, 2, None, None, :]
            z = (r[..., 0] * tri[..., 0] + r[..., 1] * tri[..., 1]) + r[..., 2] * tri[..., 2]
            low[:, idx] = np.min(z, axis=(-1, -2)) + (Xp[:, idx, 2] - self.surface)
        return tip, np.stack([c * x + s * y, c * y - s * x, low], axis=-1)

    def _on_planes(
        self, X: FloatArray, R: FloatArray, C: FloatArray, tip: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """The bodies posed as the compiled kernel poses each foot on its robot's uneven
        field (:func:`.pose.on_planes`)."""
        slope = np.empty((3, *tip.shape[:2]))  # height [m], dh/dx, dh/dy under each tip
        for i in np.ndindex(*tip.shape[:2]):
            f = self._fields[i[0]]  # robot i[0]'s field
            assert f is not None
            ny, nx = f.cells.shape
            slope[(slice(None), *i)] = surface_at(tip[i][0], tip[i][1], f.grid, ny, nx, f.heights)  # fmt: skip
        hs, gx, gy = slope
        X, R, C, tip = on_planes(X, R, C, tip, hs, gx, gy, self.surface)[:4]
        return X, R, C, tip

    # -- public API -------------------------------------------------------------------
    def reset(self, datas: mujoco.MjData | Sequence[mujoco.MjData]) -> None:
        """Start with undisturbed mud under the feet in their current pose (calls mj_forward)."""
        mj = _mujoco()
        self._reset_with = datas if isinstance(datas, self._mj.MjData) else None
        datas = self._check(datas)
        self._timestep = check_timestep(self.model, checked=self._timestep)
        check_integrator(self.model)  # again: the model's options may have changed
        for d in datas:
            mj.mj_forward(self.model, d)
        tip, pos = self._read(datas)
        for gi, (foot, idx) in enumerate(self._groups):
            self._states[gi] = self.terrain.initial_state(foot, pos[:, idx])
        self._compiled.reset(datas, self._states, pos, tip)
        W = mj.mjtWarning
        bad = [int(w) for w in (W.mjWARN_BADQPOS, W.mjWARN_BADQVEL, W.mjWARN_BADQACC)]
        # MuJoCo's reset of a bad state clears its counters, then counts 1: the coupling
        # watches them from 0, and clears them again when it has raised
        self._warn = [tuple(d.warning[k] for k in bad) for d in datas]
        self._warnings = [[0, 0, 0] for _ in datas]
        self._clear_warnings()
        self.time_steps = 0
        for d in datas:
            d.xfrc_applied[self._ids] = 0.0

    def use_field(self, field: MudField, robot: int | None = None) -> None:
        """Step robot ``robot`` (None: every robot) on ``field`` from the next step on: a
        field of the shape of the one given to ``attach`` (the same grid of cells and number
        of regions) and its mud options, such as :meth:`MudField.randomized` draws. Call it
        before :meth:`reset` for a new episode; the feet's mud state goes on."""
        if self.field is None:
            raise MudrftError("use_field needs a coupling attached to a MudField")
        if not isinstance(field, MudField):
            raise MudrftError(f"field must be a MudField, got {type(field).__name__}")
        if not same_options(field.terrain, self.terrain):
            raise MudrftError("field's MudTerrain options differ from the attached field's")
        if robot is not None and not (isinstance(robot, int) and 0 <= robot < self.n):
            raise MudrftError(f"robot must be None or an index in [0, {self.n}), got {robot!r}")
        robots = np.arange(self.n) if robot is None else np.array([robot])
        self._compiled.use_field(field, robots)
        for k in robots:
            self._fields[int(k)] = field

    def detach(self) -> None:
        """Take the mud out of MuJoCo's step: the compiled coupling stays in the MjData given
        to :meth:`reset` (and keeps this coupling alive) until ``detach``, or until another
        coupling's ``reset`` takes that MjData; :meth:`reset` attaches it again."""
        self._compiled.detach()

    def _check(self, datas: mujoco.MjData | Sequence[mujoco.MjData]) -> list[mujoco.MjData]:
        if isinstance(datas, self._mj.MjData):
            datas = [datas]
        if not isinstance(datas, Sequence):
            raise MudrftError(f"data must be a mujoco.MjData or a list of them, got {type(datas).__name__}")  # fmt: skip
        datas = list(datas)
        if len(datas) != self.n:
            raise MudrftError(f"expected {self.n} MjData, got {len(datas)}")
        ids = tuple(map(id, datas))
        if ids == self._checked:  # the MjData checked last time (an MjData keeps its model)
            return datas
        if len(set(ids)) != len(datas):
            raise MudrftError("each robot needs its own MjData; the same one was given twice")
        for d in datas:
            check_data(self.model, d)
        self._checked = ids
        self._checked_datas = datas  # held, so that their ids stay theirs
        return datas

    def apply(self, datas: mujoco.MjData | Sequence[mujoco.MjData]) -> MudContact:
        """Advance the mud once and write ``xfrc_applied`` after ``mj_step1`` (or
        ``mj_forward``), before ``mj_step2``. MuJoCo's passive callback has done so in
        ``mj_step1`` already: this repeats that step, with the same result."""
        datas = self._check(datas)
        if self._warn:
            self._check_diverged(datas)  # mj_step1 met a non-finite state and reset it
        if self._states[0] is None:
            raise MudrftError("call reset(data) before stepping the mud coupling")
        self._compiled.check()
        for d in datas:
            self._mj.mj_passive(self.model, d)
        self._compiled.check()
        self._check_buried(self._depth)
        self.time_steps += 1
        return self._compiled.contact(0 if self._single else None)

    def step(self, datas: mujoco.MjData | Sequence[mujoco.MjData], nstep: int = 1) -> MudContact:
        """``nstep`` physics steps of every robot, the mud advanced once per step.

        Raises
        ------
        MudrftError
            When MuJoCo reports bad accelerations (it would reset the state silently).
        """
        self.advance(datas, nstep)  # checks for a buried foot: read the contact directly
        return self._compiled.contact(0 if self._single else None)

    def advance(self, datas: mujoco.MjData | Sequence[mujoco.MjData], nstep: int = 1) -> None:
        """:meth:`step` without returning the contact (:attr:`last` builds it when read)."""
        if datas is not self._reset_with or self._reset_with is None:
            datas = self._check(datas)
        else:
            datas = self._checked_datas
        nstep = check_count("nstep", nstep)
        c = self._compiled
        if not c.datas:
            raise MudrftError("call reset(data) before stepping the mud coupling")
        if any(a is not b for a, b in zip(datas, c.datas, strict=True)):
            raise MudrftError(
                "the mud coupling steps the MjData given to reset(); got another MjData "
                "(call reset(data) with it first)"
            )
        c.check()
        step, m, warn, seen = self._mj.mj_step, self.model, self._warn, self._warnings
        for _ in range(nstep):
            for i, d in enumerate(datas):
                step(m, d)  # the passive callback steps the mud inside
                wq, wv, wa = warn[i]  # MuJoCo's bad qpos, qvel, qacc (it resets them)
                sq, sv, sa = seen[i]
                if wa.number != sa or wv.number != sv or wq.number != sq:
                    self.time_steps += 1
                    self._check_diverged(datas)
            self.time_steps += 1
        c.check()
        self._check_buried(self._depth)

    def _check_buried(self, depth: FloatArray) -> None:
        """Warn once a foot (in the coupling's life: not every episode) where its ``depth``
        (n, nb) [m] exceeds its height: the mud then reaches the leg, which the model does
        not describe (D26)."""
        over = depth > self._too_deep
        if not over.any():
            return
        for j in np.flatnonzero(over.any(axis=0) & ~self._buried):
            self._buried[j] = True
            b, i = self.bodies[j], int(np.argmax(depth[:, j]))
            name = repr(b.body) if b.body else f"id {b.body_id}"
            robot = "" if self.n == 1 else f" of robot {i}"
            check_unburied(
                type(b.foot).__name__, float(b.foot.height), float(depth[i, j]),
                how=f"mud coupling: body {name}{robot} sank", strict=False, hint=BURIED_HINT,
            )  # fmt: skip

    def _clear_warnings(self) -> None:  # in place: the compiled loop holds the lists
        for ws, seen in zip(self._warn, self._warnings, strict=True):
            for w in ws:
                w.number = 0
            seen[:] = [0, 0, 0]

    def _check_diverged(self, datas: list[mujoco.MjData]) -> None:
        """Raise where MuJoCo met a non-finite qpos or qvel, or bad accelerations, this step
        (it resets such a state and only prints a warning)."""
        for i, ws in enumerate(self._warn):
            for kind, w in enumerate(ws):
                if w.number != self._warnings[i][kind]:
                    self._clear_warnings()
                    t = self.time_steps * float(self._opt.timestep)
                    raise diverged_error(i, kind, w.lastinfo, t, self.last)


def _hashable_repr(foot: Foot) -> bool:
    # dataclass feet with eq=True print their parameters; equal reprs = equal geometry
    return type(foot).__repr__ is not object.__repr__ and "(" in repr(foot) and "=" in repr(foot)
