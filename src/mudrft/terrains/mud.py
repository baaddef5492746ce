r"""The mud model of Chen et al. (2026) as a terrain: :func:`mud_step`, the one definition of
how the mud under a foot advances (element-wise over any ``xp``), and its options.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .._typing import Namespace, XpArray
from .._validation import MudrftError, check_characteristic_length, number_in_range, positive_number
from .._xp import pyfloat
from ..citations import register
from ..constitutive import kernel
from ..constitutive.contact import contact_rate, enter, in_contact
from ..constitutive.dynamics import evaluation
from ..constitutive.kernel import ChannelConstants, channel_constants
from ..constitutive.state import ChannelState
from ..feet.base import Foot
from ..parameters.base import PARAMETER_UNITS, Mud, MudParameters
from .base import TerrainOutput, check_motion, tip_position

__all__ = [
    "MudChannels", "MudState", "MudTerrain", "channel_parameters", "initial_channels",
    "mud_channel_stress", "mud_step", "vertical_viscosity"
]  # fmt: skip


def channel_parameters(mud: Mud) -> MudParameters:
    """(horizontal, horizontal, vertical) stacked on a trailing axis of 3: the x, y, z channels."""
    h, v = mud.horizontal, mud.vertical
    fields: dict[str, Any] = {}
    for k in PARAMETER_UNITS:
        a, b = np.broadcast_arrays(*(np.asarray(getattr(p, k), dtype=float) for p in (h, v)))
        fields[k] = np.stack([a, a, b], axis=-1)
    return MudParameters(**fields, source=f"channels of {mud.name}")


def vertical_viscosity(mud: Mud, *, quasi_static: bool = False) -> float:
    r"""The vertical stress's instantaneous viscosity [Pa s], the largest of a batch:
    :math:`\eta_\infty` (D6), or :math:`\eta_\infty+\eta_m` when ``quasi_static`` (D15)."""
    eta = np.asarray(mud.vertical.eta_inf, dtype=float)
    if quasi_static:
        eta = eta + np.asarray(mud.vertical.eta_m, dtype=float)
    return float(np.max(eta))


class MudChannels(NamedTuple):
    """State of the mud under one foot (floats) or a batch (arrays of one shape): the
    horizontal and vertical channels ``h``, ``z``, the ``entry_x``, ``entry_y`` of the tip
    [m], the ``line`` of the horizontal displacement and the ``heading`` of its stress [rad],
    and ``in_mud`` (1.0 or 0.0)."""

    h: ChannelState
    z: ChannelState
    entry_x: XpArray
    entry_y: XpArray
    line: XpArray
    heading: XpArray
    in_mud: XpArray


class MudState(NamedTuple):
    """State of :class:`MudTerrain`: the mud's ``channels`` (:class:`MudChannels`) and the
    ``foot`` mechanism's own state (the morphing foot's, else None)."""

    channels: MudChannels
    foot: Any


def mud_step(
    ch: ConstantsPair, st: MudChannels, px: XpArray, py: XpArray, pz: XpArray, vx: XpArray,
    vy: XpArray, vz: XpArray, dt: XpArray, lc: XpArray, kappa: XpArray, xi0: XpArray,
    reset: bool, heading_speed: XpArray, seal: XpArray, quasi_static: bool = False,
    restart: bool = False, xp: Namespace = np,
) -> tuple[MudChannels, XpArray, XpArray, XpArray, XpArray]:  # fmt: skip
    r"""Advance the mud under a foot tip by ``dt``: the one terrain step (no validation).

    Two channels (Sec. II-C): the horizontal one at :math:`\gamma_h=\pm|\mathbf r|/L_c`, the
    tip's offset from the entry point along its line, the vertical one at :math:`\gamma_z=d/L_c`,
    :math:`d=\max(-z,0)`; docs/model.md, section 5, defines them (decisions D9, D9a, D11, D52).

    Parameters
    ----------
    ch : ConstantsPair
        ``(horizontal, vertical)`` :class:`~mudrft.constitutive.kernel.ChannelConstants`.
    st : MudChannels
        State at the start of the step.
    px, py, pz : array_like
        Tip position at the end of the step [m].
    vx, vy, vz : array_like
        Tip velocity over the step [m/s].
    dt, lc : float
        Step [s] and characteristic length :math:`L_c` [m].
    kappa, xi0, reset, heading_speed, quasi_static, restart
        :class:`MudTerrain`'s ``kappa`` [-], ``xi0`` [-], ``reset_on_exit``,
        ``heading_speed`` [m/s], ``quasi_static`` and ``restart`` (decisions D6, D11, D15).
    seal : array_like
        Sealing factor of the vertical channel in [0, 1] [-].
    xp : module
        Element-wise namespace (:mod:`mudrft._xp`).

    Returns
    -------
    state : MudChannels
    sx, sy, sz : array_like
        Stresses [Pa] (0 out of the mud); the horizontal one in ``sx`` and ``sy`` alike.
    depth : array_like
        Tip depth [m].
    """
    chh, cz, gh, rh, gz, rz, ex, ey, line, ut, depth, in_mud = _channel_motion(
        st, px, py, pz, vx, vy, vz, dt, lc, xi0, reset, heading_speed, xp
    )
    hor, ver = ch
    chh, sh = kernel.channel_step(hor, chh, gh, rh, dt, 1.0, kappa, quasi_static, restart, xp)
    cz, sz = kernel.channel_step(ver, cz, gz, rz, dt, seal, kappa, quasi_static, restart, xp)
    s, heading = horizontal_stress(sh.total, hor.eta_inf * ut / lc, line, xp)
    inside = xp.where(in_mud, 1.0, 0.0)
    new = MudChannels(chh, cz, ex, ey, line, heading, inside)
    return new, s * inside, s * inside, sz.total * inside, depth


def horizontal_stress(
    along: XpArray, across: XpArray, line: XpArray, xp: Namespace = np
) -> tuple[XpArray, XpArray]:
    r"""Magnitude [Pa] and direction [rad] of :math:`\sigma_l\hat{\mathbf l}+\sigma_t\hat{\mathbf t}`
    (D9a), from the stresses ``along`` and ``across`` [Pa] the ``line`` [rad]."""
    m2 = along * along + across * across
    nonzero = m2 > 0.0  # the root and the angle of safe values: finite JAX gradients at 0
    heading = line + xp.where(
        nonzero, xp.arctan2(xp.where(nonzero, across, 0.0), xp.where(nonzero, along, 1.0)), 0.0
    )
    return xp.where(nonzero, xp.sqrt(xp.where(nonzero, m2, 1.0)), 0.0), heading


def _channel_motion(
    st: MudChannels, px: XpArray, py: XpArray, pz: XpArray, vx: XpArray, vy: XpArray, vz: XpArray, dt: XpArray, lc: XpArray,
    xi0: XpArray, reset: bool, heading_speed: XpArray, xp: Namespace = np,
) -> tuple[XpArray, ...]:  # fmt: skip
    """What :func:`mud_step` feeds the channels: their states, displacements and rates, the
    entry point, the line, the speed across it [m/s], the depth and whether in the mud."""
    depth = xp.maximum(-pz, 0.0)
    in_mud = in_contact(depth)
    was_in = st.in_mud > 0.5
    chh, cz = st.h, st.z
    ex, ey, last = st.entry_x, st.entry_y, st.line
    if reset:
        fresh = st.in_mud < 0.5
        chh, cz = enter(chh, fresh, xi0, xp), enter(cz, fresh, xi0, xp)
        ex, ey = xp.where(fresh, px - vx * dt, ex), xp.where(fresh, py - vy * dt, ey)
        moving = vx * vx + vy * vy > heading_speed * heading_speed  # else keep it (D52)
        turn = xp.arctan2(xp.where(moving, vy, 0.0), xp.where(moving, vx, 1.0))
        last = xp.where(fresh & moving, turn, last)
    rx, ry = px - ex, py - ey
    r2 = rx * rx + ry * ry
    away = r2 > 0.0  # roots and angles of safe values: finite JAX gradients at the entry
    r = xp.sqrt(xp.where(away, r2, 1.0))
    side = xp.where(rx * xp.cos(last) + ry * xp.sin(last) < 0.0, -1.0, 1.0)
    line = xp.where(
        away, xp.arctan2(side * xp.where(away, ry, 0.0), side * xp.where(away, rx, 1.0)), last
    )
    lx, ly = xp.cos(line), xp.sin(line)
    rate_h, gamma_h = (lx * vx + ly * vy) / lc, xp.where(away, side * r, 0.0) / lc
    ut = lx * vy - ly * vx  # the speed across the line [m/s]
    gdz = contact_rate(-vz / lc, was_in, in_mud, xp)
    return chh, cz, gamma_h, rate_h, depth / lc, gdz, ex, ey, line, ut, depth, in_mud


def mud_channel_stress(
    c: int, ch: ConstantsPair, st: MudChannels, px: XpArray, py: XpArray, pz: XpArray, vx: XpArray, vy: XpArray,
    vz: XpArray, dt: XpArray, lc: XpArray, kappa: XpArray, xi0: XpArray, reset: bool,
    heading_speed: XpArray, seal: XpArray, quasi_static: bool = False, restart: bool = False,
    xp: Namespace = np,
) -> tuple[XpArray, XpArray]:  # fmt: skip
    """The stress [Pa] :func:`mud_step` returns in ``sx``/``sy`` (``c`` 0 or 1, with the
    heading [rad]) or ``sz`` (``c`` 2, with the line [rad]), one channel step alone (D63)."""
    chh, cz, gh, rh, gz, rz, _ex, _ey, line, ut, _depth, in_mud = _channel_motion(
        st, px, py, pz, vx, vy, vz, dt, lc, xi0, reset, heading_speed, xp
    )
    hor, ver = ch
    inside = xp.where(in_mud, 1.0, 0.0)
    if c < 2:
        _, sh = kernel.channel_step(hor, chh, gh, rh, dt, 1.0, kappa, quasi_static, restart, xp)
        s, heading = horizontal_stress(sh.total, hor.eta_inf * ut / lc, line, xp)
        return s * inside, heading
    _, s = kernel.channel_step(ver, cz, gz, rz, dt, seal, kappa, quasi_static, restart, xp)
    return s.total * inside, line


ConstantsPair = tuple[ChannelConstants, ChannelConstants]


def initial_channels(
    px: XpArray, py: XpArray, depth: XpArray, lc: float, xi0: float, xp: Namespace = np
) -> MudChannels:
    """Undisturbed mud under a tip at horizontal ``(px, py)`` [m] and ``depth`` [m] >= 0."""
    zero = 0.0 * depth

    def fresh(g: XpArray) -> ChannelState:
        return ChannelState(g, g, zero + xi0, zero, zero, zero, zero)

    inside = xp.where(in_contact(depth), 1.0, 0.0)
    return MudChannels(fresh(zero), fresh(depth / lc), px + zero, py + zero, zero, zero, inside)


@dataclass(frozen=True, eq=False)
class MudTerrain:
    r"""The mud model of Chen et al. (2026) as a terrain (:func:`mud_step`): x and y channels
    run the horizontal parameter set, z the vertical one.

    Parameters
    ----------
    mud : Mud
        Vertical and horizontal parameter sets.
    characteristic_length : float or None
        :math:`L_c` [m]; ``None`` uses the foot's own.
    acceleration, thixotropy, clock
        The evaluation (:func:`~mudrft.constitutive.dynamics.evaluation`; decisions D6, D15).
    reset_on_exit : bool
        Land in undisturbed mud after the tip left it (decision D11).
    xi0 : float
        Structure of undisturbed mud, in [0, 1] [-].
    heading_speed : float
        Below this horizontal speed [m/s] the last heading is kept; > 0.

    Examples
    --------
    >>> import mudrft
    >>> MudTerrain(mudrft.paper_mud(0.25), xi0=5.0)
    Traceback (most recent call last):
    ...
    mudrft._validation.MudrftError: xi0 must lie in [0.0, 1.0], got 5.0
    """

    mud: Mud
    characteristic_length: float | None = None
    acceleration: bool | None = None
    reset_on_exit: bool = True
    xi0: float = 0.0
    heading_speed: float = 1e-6
    name: str = "mud"
    thixotropy: str = "ode"
    clock: str = "contact"

    def __post_init__(self) -> None:
        if not isinstance(self.mud, Mud):
            raise MudrftError(
                f"mud must be a Mud (see mudrft.paper_mud), got {type(self.mud).__name__}"
            )
        if self.characteristic_length is not None:
            lc = check_characteristic_length("MudTerrain", self.characteristic_length)
            object.__setattr__(self, "characteristic_length", lc)
        kappa = evaluation(self.thixotropy, self.clock, self.acceleration)[2]
        object.__setattr__(self, "acceleration", kappa == 1.0)
        if not isinstance(self.reset_on_exit, bool | np.bool_):
            raise MudrftError(f"reset_on_exit must be True or False, got {self.reset_on_exit!r}")
        object.__setattr__(self, "reset_on_exit", bool(self.reset_on_exit))
        object.__setattr__(self, "xi0", number_in_range("xi0", self.xi0, 0.0, 1.0))
        hs = positive_number("heading_speed", self.heading_speed, unit="m/s")
        object.__setattr__(self, "heading_speed", hs)
        if not isinstance(self.name, str):
            raise MudrftError(f"name must be a string, got {self.name!r}")
        register("chen2026mud")

    @property
    def params(self) -> MudParameters:
        """The stacked (x, y, z) channel parameters (trailing axis of 3)."""
        return channel_parameters(self.mud)

    @cached_property
    def constants(self) -> ConstantsPair:
        """``(horizontal, vertical)`` channel constants of :func:`mud_step`."""
        return channel_constants(self.mud.horizontal), channel_constants(self.mud.vertical)

    @property
    def kappa(self) -> float:
        """1.0 with the acceleration term (decision D6), else 0.0."""
        return 1.0 if self.acceleration else 0.0

    @property
    def quasi_static(self) -> bool:
        """True for the paper's quasi-static evaluation, eqs. (9)-(11) (decision D15)."""
        return self.thixotropy == "quasi-static"

    @property
    def restart(self) -> bool:
        """True when the clock of eq. (9) restarts at the retraction (decision D15)."""
        return self.clock == "retraction"

    def length(self, foot: Foot) -> float:
        """:math:`L_c` [m]: the terrain's own, else the foot's."""
        return float(self.characteristic_length or foot.characteristic_length)

    def initial_state(self, foot: Foot, position: ArrayLike) -> MudState:
        """Undisturbed mud under a foot whose tip is at ``position`` (3,) or (..., 3) [m]."""
        pos = tip_position(position)
        lc = self.length(foot)
        if pos.shape == (3,):
            x, y, z = (float(v) for v in pos)
            ch = initial_channels(x, y, max(-z, 0.0), lc, self.xi0, xp=pyfloat)
        else:
            depth = np.maximum(-pos[..., 2], 0.0)
            ch = initial_channels(pos[..., 0], pos[..., 1], depth, lc, self.xi0)
        return MudState(channels=ch, foot=foot.initial_foot_state())

    def step(
        self, foot: Foot, state: MudState, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[MudState, TerrainOutput]:
        """Advance the mud under the foot by ``dt`` [s] (:class:`~mudrft.terrains.Terrain`);
        validated, unlike :meth:`step_unchecked`."""
        if not isinstance(foot, Foot):
            raise MudrftError(
                f"foot must be a mudrft foot (mudrft.feet.Flat(), ...), got {type(foot).__name__}"
            )
        pos, vel, step = check_motion(position, velocity, dt)
        if not isinstance(state, MudState):
            raise MudrftError(
                "state must be the MudState of MudTerrain.initial_state or of the previous step, "
                f"got {type(state).__name__}"
            )
        batch = getattr(state.channels.in_mud, "shape", ())  # a bool for one foot on floats
        if batch != pos.shape[:-1]:  # tips that do not broadcast to the mud's are refused
            try:
                shape = np.broadcast_shapes(batch, pos.shape[:-1])
            except ValueError:
                raise MudrftError(
                    f"state is the mud under tips of shape {batch} (initial_state), but position "
                    f"has shape {pos.shape}: one (x, y, z) per tip"
                ) from None
            pos, vel = np.broadcast_to(pos, (*shape, 3)), np.broadcast_to(vel, (*shape, 3))
        return self.step_unchecked(foot, state, pos, vel, step)

    def step_unchecked(
        self, foot: Foot, state: MudState, position: ArrayLike, velocity: ArrayLike, dt: float
    ) -> tuple[MudState, TerrainOutput]:
        """:meth:`step` without validation (finite (..., 3) inputs and dt > 0 assumed)."""
        pos, vel = np.asarray(position, dtype=float), np.asarray(velocity, dtype=float)
        seal = foot.seal_factor(state.foot)
        common = (self.length(foot), self.kappa, self.xi0, self.reset_on_exit, self.heading_speed)
        flags = (self.quasi_static, self.restart)
        if pos.shape == (3,) and np.ndim(seal) == 0:  # one foot: the step on Python floats
            x, y, z = pos.tolist()
            u, v, w = vel.tolist()
            ch, sx, sy, sz, depth = mud_step(
                self.constants, state.channels, x, y, z, u, v, w, float(dt), *common,
                float(seal), *flags, pyfloat,
            )  # fmt: skip
            stress = np.array([sx, sy, sz])
            if foot.elementwise and state.foot is None:
                f = foot.force_components(depth, sx, sy, sz, ch.heading, xp=pyfloat)
                out = TerrainOutput(np.array(f) * ch.in_mud, stress, np.asarray(depth, dtype=float))
                return MudState(channels=ch, foot=None), out
        else:
            ch, sx, sy, sz, depth = mud_step(
                self.constants, state.channels, pos[..., 0], pos[..., 1], pos[..., 2],
                vel[..., 0], vel[..., 1], vel[..., 2], dt, *common, seal, *flags,
            )  # fmt: skip
            stress = np.stack([sx, sy, sz], axis=-1)
        d = np.asarray(depth, dtype=float)
        foot_state, force = foot.contact_force(
            state.foot, d, stress, ch.heading, dt, retraction=ch.z.clock_w
        )
        out = TerrainOutput(force * np.asarray(ch.in_mud)[..., None], stress, d)
        return MudState(channels=ch, foot=foot_state), out
