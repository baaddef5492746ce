r"""Mud under named bodies of an MJX model: :class:`MjxCoupling` and :func:`attach`.

Feet are placed by the CPU coupling's :func:`~mudrft.integrations.mujoco.body_foot`;
:meth:`~MjxCoupling.step` runs ``fwd_position``, ``fwd_velocity``, the mud's wrench and the
rest of MJX's step (Euler or implicitfast). The mud constants are an argument, so each robot
of a batch may carry its own water content and gradients flow to them. In the precision JAX
is configured for (D81), over 0.5 s of the standing biped the coupling follows the CPU
coupling's joints to 2e-5 and depths to 6e-6 m (tests/integrations/test_mjx.py).
"""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from types import ModuleType
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np

from ..._validation import MudrftError, check_finite
from ...citations import register
from ...feet.mesh import MeshFoot
from ...feet.surface import prepare_triangles
from ...terrains import as_terrain
from ...terrains.field import MudField, same_options
from ...terrains.mud import MudTerrain
from ..mujoco._lazy import _mujoco
from ..mujoco.options import (
    check_attach_options,
    check_count,
    check_data,
    check_removed,
    check_timestep,
)
from ..mujoco.placement import attached_foot, coupled_tip, coupled_triangles
from ..mujoco.pose import POSE_RESOLUTION
from ._lazy import _jax, _mjx, _xp, jit
from .physics import Group, MjxContact, MjxMudState, Static, initial_state, mud_wrench

if TYPE_CHECKING:
    import jax.stages
    import mujoco
    import mujoco.mjx
    from jax import Array

    from ..._typing import ArrayLike
    from ...backends.forces import ForceRule
    from ...constitutive.kernel import ChannelConstants
    from ...feet.base import Foot
    from ...parameters import Mud

#: The mud's (horizontal, vertical) channel constants: floats, or traced arrays.
Constants: TypeAlias = "tuple[ChannelConstants, ChannelConstants]"
#: A field's ``(grid, cells, rows, heights)`` (:meth:`MjxCoupling.field_arrays`).
FieldArrays: TypeAlias = "tuple[Array, Array, Array, Array]"

__all__ = ["MjxCoupling", "attach"]


def _force_rule(foot: Foot) -> ForceRule:
    from ...backends.forces import force_function

    fn = force_function(foot, xp=_xp())
    if fn is None or not (getattr(foot, "elementwise", False) or isinstance(foot, MeshFoot)):
        raise MudrftError(
            "the MJX coupling supports closed-form feet (Flat, SemiCylinder, SemiSphere) and "
            f"mesh feet (MeshFoot), got a {type(foot).__name__}: use the CPU coupling "
            "(mudrft.integrations.mujoco.attach) for it"
        )
    return fn


class MjxCoupling:
    """Mud under named bodies of one MuJoCo model, stepped with MJX.

    Parameters
    ----------
    model : mujoco.MjModel
        The model (the coupling also holds its MJX copy, :attr:`mjx_model`).
    bodies : sequence of str
        Names of the bodies that touch the mud.
    mud : Mud, MudTerrain or MudField
        The mud (:func:`mudrft.paper_mud`), a configured :class:`mudrft.MudTerrain`, or a
        field of patches (:class:`mudrft.MudField`; each robot of a batch may step on its own
        draw, :meth:`field_arrays`).
    feet, surface, bottom, bottom_stiffness, bottom_damping, resolution, foot_geoms :
        keyword-only, as :class:`mudrft.integrations.mujoco.MudBatch`.

    Examples
    --------
    >>> import mujoco, mudrft
    >>> from mudrft.integrations import mjx as mm
    >>> xml = '''<mujoco><worldbody><body name="foot" pos="0 0 0.013">
    ...   <freejoint/><geom type="box" size="0.0325 0.04 0.013" mass="1"/></body></worldbody></mujoco>'''
    >>> coupling = mm.attach(mujoco.MjModel.from_xml_string(xml), "foot", mudrft.paper_mud(0.25))
    >>> d = coupling.put_data()
    >>> d, st, out = coupling.rollout(d, coupling.init(d), 200)  # doctest: +SKIP
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        bodies: Sequence[str] | str,
        mud: Mud | MudTerrain | MudField,
        *,
        feet: Foot | Sequence[Foot | None] | None = None,
        surface: float = 0.0,
        bottom: float | None = None,
        bottom_stiffness: float = 1e5,
        bottom_damping: float = 2e3,
        resolution: int = POSE_RESOLUTION,
        foot_geoms: Mapping[str, str | int] | None = None,
        **removed: object,
    ) -> None:
        _mujoco()  # a clear error if mujoco is missing
        check_removed("the MJX coupling", removed)
        opts = check_attach_options(
            model,
            bodies, feet, surface=surface, bottom=bottom, bottom_stiffness=bottom_stiffness,
            bottom_damping=bottom_damping, resolution=resolution, foot_geoms=foot_geoms,
        )  # fmt: skip
        self.field = mud if isinstance(mud, MudField) else None
        terrain = mud.terrain if isinstance(mud, MudField) else as_terrain(mud)
        if not isinstance(terrain, MudTerrain):
            raise MudrftError(
                f"the MJX coupling needs the mud (a Mud or MudTerrain), got {type(terrain).__name__}"
            )
        placed = [
            attached_foot(model, b, f, resolution=opts.resolution, geom=g)
            for b, f, g in zip(opts.bodies, opts.feet, opts.geoms, strict=True)
        ]
        groups: dict[tuple[str, bool], list[int]] = {}
        for i, p in enumerate(placed):  # equal feet (same parameters) share one mud call
            if p.triangles is None:
                raise MudrftError(f"body {p.body!r} has a foot without a surface")
            key = repr(p.foot) if "=" in repr(p.foot) else str(id(p.foot))
            groups.setdefault((key, p.ball), []).append(i)
        built = []
        for (_, ball), idx in groups.items():
            foot = placed[idx[0]].foot
            built.append(
                Group(
                    idx=np.array(idx),
                    lc=float(terrain.length(foot)),
                    force_fn=_force_rule(foot),
                    triangles=np.stack([np.asarray(coupled_triangles(placed[i])) for i in idx]),
                    upright=prepare_triangles(np.asarray(placed[idx[0]].upright, dtype=float)),
                    ball=ball,
                )
            )
        ids = np.array([p.body_id for p in placed])
        self.model = model
        self.terrain = terrain
        self.bodies = tuple(placed)
        self.static = Static(
            ids=ids,
            roots=np.array(model.body_rootid)[ids],
            tip=np.stack([coupled_tip(p) for p in placed]),
            ball=np.array([p.ball for p in placed]),
            forward=np.stack([p.forward for p in placed]),
            groups=tuple(built),
            surface=opts.surface,
            bottom=opts.bottom,
            bottom_stiffness=opts.bottom_stiffness,
            bottom_damping=opts.bottom_damping,
            terrain=terrain,
            uneven=bool(self.field is not None and self.field.heights.any()),
        )
        _check_integrator(model.opt.integrator)
        check_timestep(model)  # as the CPU coupling (D123); put_model fixes the step
        self.mjx_model = _mjx().put_model(model)
        self._field_arrays: FieldArrays | None = None
        if self.field is not None:  # made once: an eager step would rebuild them every call
            self._field_arrays = self.field_arrays()
        register("todorov2012mujoco")

    # -- data and constants -----------------------------------------------------------
    @property
    def constants(self) -> Constants:
        """The mud's ``(horizontal, vertical)`` channel constants, as Python floats."""
        horizontal, vertical = (type(c)(*(float(v) for v in c)) for c in self.terrain.constants)
        return horizontal, vertical

    def field_arrays(self, field: MudField | None = None) -> FieldArrays:
        """``field`` (default: the attached one) as the JAX arrays ``(grid, cells, rows,
        heights)`` that :meth:`step` takes; a field of the attached field's shape, so that a
        compiled step serves it (stack them for a batch)."""
        if self.field is None:
            raise MudrftError("field_arrays needs a coupling attached to a MudField")
        if field is None and self._field_arrays is not None:
            return self._field_arrays
        f = self.field if field is None else field
        if not isinstance(f, MudField):
            raise MudrftError(f"field must be a MudField, got {type(f).__name__}")
        if not same_options(f.terrain, self.terrain):
            raise MudrftError("field's MudTerrain options differ from the attached field's")
        grid, cells, rows = f.arrays()
        _, cells0, rows0 = self.field.arrays()
        h, h0 = f.heights, self.field.heights
        if cells.shape != cells0.shape or rows.shape != rows0.shape or h.shape != h0.shape:
            raise MudrftError(
                f"field must have the attached field's shape: {cells0.shape} cells, "
                f"{rows0.shape[0]} regions and {h0.shape} heights, got {cells.shape} cells, "
                f"{rows.shape[0]} regions and {h.shape} heights"
            )
        xp = _xp()
        return xp.asarray(grid), xp.asarray(cells), xp.asarray(rows), xp.asarray(h)

    def put_data(self, data: mujoco.MjData | None = None) -> mujoco.mjx.Data:
        """An ``mjx.Data`` of ``data`` (default: a fresh ``MjData`` of the model)."""
        mj = _mujoco()
        if data is None:
            data = mj.MjData(self.model)
            mj.mj_forward(self.model, data)
        check_data(self.model, data)
        for name in ("qpos", "qvel"):  # NaN would run on silently under JAX
            check_finite(f"data.{name}", getattr(data, name))
        return _mjx().put_data(self.model, data)

    # -- pure functions ---------------------------------------------------------------
    def init(self, d: mujoco.mjx.Data, *, field: FieldArrays | None = None) -> MjxMudState:
        """Undisturbed mud under the feet of ``d`` in their current pose (jittable), on
        ``field`` (:meth:`field_arrays`; default the attached field) where it is uneven."""
        mjx = _mjx()
        _check_mjx_data(mjx, d)
        mx = self.mjx_model
        if field is None and self.field is not None:
            field = self.field_arrays()
        return initial_state(self.static, mjx.com_pos(mx, mjx.kinematics(mx, d)), field)

    def wrench(
        self,
        d: mujoco.mjx.Data,
        state: MjxMudState,
        constants: Constants | None = None,
        *,
        model: mujoco.mjx.Model | None = None,
        field: FieldArrays | None = None,
    ) -> tuple[Array, MjxMudState, MjxContact]:
        """``(xfrc_applied, state, contact)`` for ``d`` after ``fwd_position`` and
        ``fwd_velocity`` (see :func:`.physics.mud_wrench`)."""
        mx = self.mjx_model if model is None else model
        consts = self.constants if constants is None else constants
        if field is None and self.field is not None:
            field = self.field_arrays()
        return mud_wrench(self.static, consts, mx, d, state, field)

    def step(
        self,
        d: mujoco.mjx.Data,
        state: MjxMudState,
        constants: Constants | None = None,
        *,
        model: mujoco.mjx.Model | None = None,
        field: FieldArrays | None = None,
    ) -> tuple[mujoco.mjx.Data, MjxMudState, MjxContact]:
        """One physics step with the mud (jittable, vmappable, differentiable).

        Parameters
        ----------
        d : mjx.Data
            One robot (or, under :func:`jax.vmap`, each of many).
        state : MjxMudState
            From :meth:`init` or the last step.
        constants : (ChannelConstants, ChannelConstants) or None
            Mud constants (default :attr:`constants`); traced arrays
            (``mudrft.backends.jax.mud_constants``) to differentiate by the mud's parameters.
        model : mjx.Model or None
            Default :attr:`mjx_model`.
        field : (grid, cells, rows, heights) or None
            The field under this robot (:meth:`field_arrays`; traced, so one compilation
            serves every field of the shape); default the attached field, if any.

        Returns
        -------
        d : mjx.Data
            After the step, in the input's dtypes.
        state : MjxMudState
        contact : MjxContact
            Its ``unstable`` flag: the mud state was held and no wrench applied.
        """
        mjx = _mjx()
        _check_mjx_data(mjx, d)
        if not isinstance(state, MjxMudState):
            raise MudrftError(f"state must be an MjxMudState (coupling.init(d)), got {type(state).__name__}")  # fmt: skip
        mx = self.mjx_model if model is None else model
        d0 = d
        _check_integrator(mx.opt.integrator)
        d = mjx.fwd_position(mx, d)
        d = mjx.sensor_pos(mx, d)
        d = mjx.fwd_velocity(mx, d)
        d = mjx.sensor_vel(mx, d)
        xfrc, state, out = self.wrench(d, state, constants, model=mx, field=field)
        d = d.replace(xfrc_applied=xfrc)
        d = _finish(mjx, mx, d)
        return _cast(d, d0), state, out

    def rollout(
        self,
        d: mujoco.mjx.Data,
        state: MjxMudState,
        n: int,
        *,
        ctrl: ArrayLike | None = None,
        constants: Constants | None = None,
        field: FieldArrays | None = None,
    ) -> tuple[mujoco.mjx.Data, MjxMudState, MjxContact]:
        """``n`` steps under :func:`jax.lax.scan`, jit-compiled once per shape.

        ``d``, ``state``, ``constants``, ``field`` as :meth:`step`; ``ctrl`` (n, nu): the controls of each
        step (None keeps ``d.ctrl``). Returns the data and state after the last step and the
        contacts, each with a leading axis of ``n``.
        """
        n = check_count("n", n)
        if ctrl is not None:
            shape = tuple(np.shape(ctrl))
            if shape != (n, self.model.nu):
                raise MudrftError(
                    f"ctrl must have shape (n, nu) = ({n}, {self.model.nu}), got {shape}"
                )
        return self._rollout_jit(d, state, n, ctrl, constants, field)

    @functools.cached_property
    def _rollout_jit(self) -> jax.stages.Wrapped:
        jax = _jax()

        def run(
            d: mujoco.mjx.Data,
            state: MjxMudState,
            n: int,
            ctrl: Array | None,
            constants: Constants | None,
            field: FieldArrays | None,
        ) -> tuple[mujoco.mjx.Data, MjxMudState, MjxContact]:
            def body(
                carry: tuple[mujoco.mjx.Data, MjxMudState], u: Array | None
            ) -> tuple[tuple[mujoco.mjx.Data, MjxMudState], MjxContact]:
                dd, st = carry
                if u is not None:
                    dd = dd.replace(ctrl=u)
                dd, st, out = self.step(dd, st, constants, field=field)
                return (dd, st), out

            (d, state), out = jax.lax.scan(body, (d, state), ctrl, length=n)
            return d, state, out

        return jit(run, static_argnums=(2,))


def _cast(d: mujoco.mjx.Data, d0: mujoco.mjx.Data) -> mujoco.mjx.Data:
    """``d`` in the dtypes of ``d0`` (so that it can be a scan carry)."""
    out: mujoco.mjx.Data = _jax().tree_util.tree_map(lambda new, old: new.astype(old.dtype), d, d0)
    return out


def _check_integrator(integrator: Any) -> None:
    """Refuse MuJoCo's ``implicit`` (MJX has none) and ``RK4`` integrators."""
    name = getattr(integrator, "name", None) or _mujoco().mjtIntegrator(int(integrator)).name
    if name.upper().replace("MJINT_", "") in ("IMPLICIT", "RK4"):
        raise MudrftError(
            f"the MJX coupling steps with the 'Euler' or 'implicitfast' integrator, got "
            f"{name!r}; set model.opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST"
        )


def _finish(mjx: ModuleType, mx: mujoco.mjx.Model, d: mujoco.mjx.Data) -> mujoco.mjx.Data:
    """The rest of ``mjx.step`` after the velocity stage (``mj_step2``)."""
    it = mjx.IntegratorType
    d = mjx.fwd_actuation(mx, d)
    d = mjx.fwd_acceleration(mx, d)
    impl = getattr(d, "_impl", None)
    efc = getattr(impl, "efc_J", None)
    if efc is not None and efc.size == 0:
        d = d.replace(qacc=d.qacc_smooth)
    else:
        d = mjx.solve(mx, d)
        d = mjx.sensor_acc(mx, d)
    if mx.opt.integrator == it.EULER:
        return mjx.euler(mx, d)
    return mjx.implicit(mx, d)


def attach(
    model: mujoco.MjModel,
    bodies: Sequence[str] | str,
    mud: Mud | MudTerrain | MudField,
    **kw: Any,
) -> MjxCoupling:
    """Attach mud to named bodies of a MuJoCo model for MJX; see :class:`MjxCoupling`."""
    return MjxCoupling(model, bodies, mud, **kw)


def _check_mjx_data(mjx: ModuleType, d: object) -> None:
    """``d`` must be an ``mjx.Data`` in the precision JAX computes in now."""
    if not isinstance(d, mjx.Data):
        raise MudrftError(
            f"d must be an mjx.Data (coupling.put_data(data) makes one), got {type(d).__name__}"
        )
    jax = _jax()
    x64 = bool(jax.config.jax_enable_x64)
    if x64 and d.qpos.dtype == np.float32:
        raise MudrftError(
            "d is float32 but JAX now computes in float64: it was made before the process "
            "was switched (mudrft.backends.jax does so on its first call, D70), and the "
            "step would mix the two (a scan's carry then changes dtype). Make the data and "
            "the mud state again (coupling.put_data(...), coupling.init(d)), or run the "
            "float32 robot inside jax.enable_x64(False)"
        )
