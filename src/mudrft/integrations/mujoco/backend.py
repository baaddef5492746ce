"""The compiled coupling's arrays (D68a): what the kernel reads and writes each step, and
what the mud did in the last step (:class:`MudContact`)."""

from __future__ import annotations

import ctypes
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple, cast

import numpy as np
from numpy.typing import NDArray

from ..._progress import logger
from ..._typing import FloatArray, IndexArray
from ..._validation import MudrftError
from ...feet.mesh import MeshFoot
from ...feet.morphing import MorphingFoot
from ...feet.morphing.row import MorphingRow, row_array
from ...feet.surface import prepare_triangles
from ...terrains.field import MudField, uniform
from ...terrains.mud import MudTerrain
from ...terrains.rows import N_STATE, config_row, state_rows, upright_rows
from .callback import callback, clock_size, install, register, unregister
from .compiled import ARGS, N_OUT, pack, work_size
from .linalg import mujoco_functions
from .placement import coupled_tip, coupled_triangles

if TYPE_CHECKING:
    import mujoco

    from ...feet.base import Foot
    from ...feet.shapes import _ClosedFormFoot
    from ...terrains import Terrain
    from ...terrains.mud import MudState
    from .batch import MudBatch
    from .placement import BodyFoot

#: Why a step raised: a wrench that is not finite.
NON_FINITE = (
    "the mud coupling produced a non-finite force; the simulation diverged "
    "(check the model, the time step and the mud parameters)"
)


class MudContact(NamedTuple):
    """What the mud did in the last step, per robot and body (world frame).

    Shapes are ``(nbody, ...)`` for :class:`~mudrft.integrations.mujoco.MudCoupling` and
    ``(nrobot, nbody, ...)`` for :class:`MudBatch`.

    Attributes
    ----------
    force : ndarray (..., 3)
        Force written to ``xfrc_applied`` (stabilised, D62; bounded, D62c) [N].
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


def not_compilable(terrain: Terrain, bodies: Sequence[BodyFoot]) -> str:
    """Why the compiled coupling cannot step this terrain and these feet ("" if it can)."""
    if not isinstance(terrain, MudTerrain):
        return (
            f"the MuJoCo coupling steps the mud (a Mud, MudTerrain or MudField), got "
            f"{type(terrain).__name__}; other terrains run through mudrft.simulate"
        )
    try:
        mujoco_functions()
    except ImportError as exc:
        return f"the MuJoCo coupling calls MuJoCo's own library, which was not found ({exc})"
    for b in bodies:
        elementwise = bool(getattr(b.foot, "elementwise", False))
        if not (elementwise or isinstance(b.foot, MeshFoot | MorphingFoot)) or b.triangles is None:
            return (
                f"the MuJoCo coupling takes closed-form feet (Flat, SemiCylinder, SemiSphere), "
                f"mesh feet (MeshFoot) and the MorphingFoot; body {b.body!r} has a "
                f"{type(b.foot).__name__}: give its surface as a MeshFoot"
            )
    return ""


def _geometry_row(foot: Foot) -> list[float]:
    """``(kind, g0, g1, g2)`` of a foot: a closed form's, (3, trailing, 0, 0) for a
    mesh foot, (4, 0, 0, 0) for the morphing foot.
    """
    if isinstance(foot, MeshFoot):
        return [3.0, float(foot.trailing), 0.0, 0.0]
    if isinstance(foot, MorphingFoot):
        return [4.0, 0.0, 0.0, 0.0]
    return [float(v) for v in cast("_ClosedFormFoot", foot).kernel_geometry]


class CompiledCoupling:
    """Arrays and state of the compiled coupling of one :class:`~.batch.MudBatch`."""

    def __init__(self, batch: MudBatch) -> None:
        m = batch.model
        self.batch = batch
        self.callback = callback()
        bodies = batch.bodies
        tris = [cast(FloatArray, coupled_triangles(b)) for b in bodies]
        self.ids = np.array([[b.body_id, int(m.body_rootid[b.body_id]), int(b.ball)] for b in bodies])  # fmt: skip
        self.tip = np.ascontiguousarray([coupled_tip(b) for b in bodies], dtype=float)
        self.fwd = np.ascontiguousarray([b.forward for b in bodies], dtype=float)
        self.tri_adr = np.concatenate([[0], np.cumsum([len(tri) for tri in tris])]).astype(np.int64)
        self.tri_b = np.ascontiguousarray(np.concatenate(tris))
        ups = [upright_rows(prepare_triangles(b.upright)) for b in bodies]
        self.up_adr = np.concatenate([[0], np.cumsum([len(u) for u in ups])]).astype(np.int64)
        self.tri_up = np.ascontiguousarray(np.concatenate(ups))
        t = cast(MudTerrain, batch.terrain)
        grid, cells, rows = uniform(t) if batch.field is None else batch.field.arrays()
        heights = np.zeros((1, 1)) if batch.field is None else batch.field.heights
        n, nb = batch.n, len(bodies)
        # one copy a robot, C-contiguous and written in place by use_field
        self.grids, self.cells, self.rows, self.hts = (
            np.repeat(a[None], n, axis=0) for a in (grid, cells, rows, heights)
        )
        self.cfg = np.array([config_row(t, b.foot) for b in bodies])
        self.geom = np.array([_geometry_row(b.foot) for b in bodies])
        no_morph = np.zeros(len(MorphingRow._fields))
        morph = [
            row_array(b.foot) if isinstance(b.foot, MorphingFoot) else no_morph for b in bodies
        ]
        self.morph = np.ascontiguousarray(morph, dtype=float)
        self.mud = np.zeros((n, nb, N_STATE))
        self.fst = np.zeros((n, nb, 3))  # morphing feet: deflection, pad angle, seal memory
        self.odo = np.zeros((n, nb, 5))  # foot-frame x, y [m], world tip x, y, z [m]
        self.tw_prev = np.zeros((n, nb, 6))
        self.wv_prev = np.zeros((n, nb, 6))
        self.tank = np.zeros(n)  # energy the mud may give each robot back [J] (D62c, D62d)
        self.out = np.zeros((n, nb, N_OUT))
        self.work = np.zeros((n, work_size(m.nv, len(self.tri_b), nb)))  # one per thread
        self.clock = np.zeros((n, clock_size(nb)))
        self.addr = np.zeros((n, 7), dtype=np.int64)
        self.sizes = np.array([m.nbody, m.nv, m._address, *mujoco_functions()], dtype=np.int64)
        self.opts = np.zeros(9)
        arrays = [getattr(self, "ids" if name == "bodies" else name) for name, _, _ in ARGS]
        for a, (name, dt, nd) in zip(arrays, ARGS, strict=True):
            assert a.dtype == np.dtype(dt) and a.ndim == nd and a.flags.c_contiguous, name
        self.packed = pack(arrays)  # the arrays never move: written in place from now on
        self.datas: list[mujoco.MjData] = []
        self._rows: list[tuple[int, ...]] = []

    def reset(
        self, datas: Sequence[mujoco.MjData], states: Sequence[MudState], pos: FloatArray,
        tips: FloatArray,
    ) -> None:  # fmt: skip
        """Start from the terrain's ``states``, tip positions ``pos`` in the foot
        frames and ``tips`` in the world [m], and register ``datas`` with the callback."""
        b = self.batch
        for (_, idx), st in zip(b._groups, states, strict=True):
            self.mud[:, idx] = state_rows(st.channels).reshape(b.n, len(idx), N_STATE)
            if st.foot is not None:  # a morphing foot's MorphingState
                for i, v in enumerate(st.foot):
                    self.fst[:, idx, i] = np.broadcast_to(v, (b.n, len(idx)))
        self.odo[..., :2] = pos[..., :2]
        self.odo[..., 2:] = tips
        for a in (self.tw_prev, self.wv_prev, self.tank, self.out, self.clock):
            a[:] = 0.0
        self.clock[:, 1] = np.nan  # no step yet
        fields = ("xpos", "xmat", "xipos", "cvel", "subtree_com", "xfrc_applied")
        self.datas = list(datas)  # keep them alive: the kernel reads their memory
        for k, d in enumerate(datas):
            for i, f in enumerate(fields):
                a = getattr(d, f)
                if a.dtype != np.float64 or not a.flags.c_contiguous:
                    raise MudrftError(f"MjData.{f} must be contiguous float64 for the mud coupling")
                self.addr[k, i] = a.ctypes.data
            self.addr[k, 6] = d._address
        m = b.model
        bottom = -1.0 if b.bottom is None else b.bottom
        g = np.asarray(m.opt.gravity, dtype=float)
        self.opts[:] = (
            float(m.opt.timestep), b.surface, bottom, b.bottom_stiffness, b.bottom_damping,
            b._dv_min, g[0], g[1], g[2],
        )  # fmt: skip
        p, size = int(self.packed.ctypes.data), len(self.packed)
        entries = [(d._address, p, size, k, _time_address(d)) for k, d in enumerate(datas)]
        install(b._mj)
        register(entries, self._rows, self)

    def use_field(self, field: MudField, robots: IndexArray) -> None:
        """Robots ``robots`` step on ``field`` from now on (its arrays' shapes: the coupling's)."""
        grid, cells, rows = field.arrays()
        h = field.heights
        if cells.shape != self.cells.shape[1:] or rows.shape != self.rows.shape[1:] or h.shape != self.hts.shape[1:]:  # fmt: skip
            raise MudrftError(
                f"field must have the coupling's shape: {self.cells.shape[1:]} cells, "
                f"{self.rows.shape[1]} regions and {self.hts.shape[1:]} heights, got "
                f"{cells.shape} cells, {rows.shape[0]} regions and {h.shape} heights"
            )
        self.grids[robots], self.cells[robots], self.rows[robots] = grid, cells, rows
        self.hts[robots] = h

    def detach(self) -> None:
        """Take the mud out of MuJoCo's step for the MjData of the last :meth:`reset`."""
        unregister(self._rows)
        self.datas = []

    def check(self) -> None:
        """Raise if the callback is no longer MuJoCo's, or a wrench was not finite."""
        if self.batch._mj.get_mjcb_passive() is not self.callback:
            raise MudrftError(
                "mujoco.set_mjcb_passive was called after reset(): the mud coupling runs in "
                "MuJoCo's passive callback; call reset(data) again to reinstall it"
            )
        if self.out[..., 22].any():
            raise MudrftError(NON_FINITE)

    def contact(self, index: int | None = None) -> MudContact:
        """The last outputs as a :class:`MudContact` (copies), of every robot
        or of robot ``index``.
        """
        o = self.out.copy() if index is None else self.out[index].copy()
        # tuple.__new__: the named tuple's own __new__ takes keywords and costs a microsecond
        return tuple.__new__(MudContact, (
            o[..., 0:3], o[..., 3:6], o[..., 6:9], o[..., 9:12], o[..., 12:15], o[..., 15:18],
            o[..., 18], o[..., 19:22],
        ))  # fmt: skip


def _time_address(d: mujoco.MjData) -> int:
    """The address of ``d.time`` (the double before ``d.energy`` in ``mjData``), checked;
    0 where this MuJoCo lays it out otherwise."""
    address = int(d.energy.ctypes.data) - 8
    cell = ctypes.c_double.from_address(address)
    saved = d.time
    try:
        for probe in (0.3183098861837907, 2.718281828459045):
            d.time = probe
            if cell.value != probe:
                logger.warning("mjData.time not found: repeated calls are told by the feet's state")
                return 0
    finally:
        d.time = saved
    return address
