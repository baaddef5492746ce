r"""The terrain interface, and the mud model behind it.

Every terrain (the mud model of Chen et al. 2026 and the baselines in
:mod:`mudrft.baselines`) implements :class:`Terrain`, so :func:`mudrft.simulate`, the
MuJoCo coupling and every comparison accept any of them::

    state = terrain.initial_state(foot, position)
    state, out = terrain.step(foot, state, position, velocity, dt)   # out.force [N]

``position`` and ``velocity`` are those of the foot tip in the world frame, shape
``(3,)`` or ``(..., 3)`` for a batch of feet [m], [m/s]. The step is explicit: it uses
the motion over the step that ends at ``position``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple, Protocol, runtime_checkable

import numpy as np

from ._validation import MudrftError, check_finite, check_positive
from .backends.kernels import fused_step
from .citations import register
from .constitutive.state import ChannelState, initial_state
from .parameters.base import PARAMETER_UNITS, Mud, MudParameters

__all__ = ["MudState", "MudTerrain", "Terrain", "TerrainOutput", "as_terrain", "channel_parameters"]


class TerrainOutput(NamedTuple):
    """What a terrain step returns.

    Attributes
    ----------
    force : ndarray (..., 3)
        Force of the terrain on the foot, world frame [N].
    stress : ndarray (..., 3)
        Channel stresses (sx, sy, sz) [Pa] where the model has them (zeros otherwise).
    depth : ndarray (...)
        Tip depth below the surface [m].
    """

    force: np.ndarray
    stress: np.ndarray
    depth: np.ndarray


@runtime_checkable
class Terrain(Protocol):
    """Interface of every terrain model."""

    name: str

    def initial_state(self, foot: Any, position: Any) -> Any:
        """State before the first step, for a foot whose tip is at ``position`` [m]."""
        ...

    def step(
        self, foot: Any, state: Any, position: Any, velocity: Any, dt: float
    ) -> tuple[Any, TerrainOutput]:
        """Advance by ``dt`` [s] to a tip at ``position`` [m] moving at ``velocity`` [m/s]."""
        ...


def channel_parameters(mud: Mud) -> MudParameters:
    """Stack (horizontal, horizontal, vertical) into one set for the x, y, z channels.

    Each field gets a trailing axis of length 3, so one constitutive step advances the
    three channels of a foot (or of a batch of feet) at once.
    """
    h, v = mud.horizontal, mud.vertical
    fields = {}
    for k in PARAMETER_UNITS:
        a, b = np.asarray(getattr(h, k), dtype=float), np.asarray(getattr(v, k), dtype=float)
        a, b = np.broadcast_arrays(a, b)
        fields[k] = np.stack([a, a, b], axis=-1)
    return MudParameters(**fields, source=f"channels of {mud.name}")


class MudState(NamedTuple):
    """State of the mud under one foot (or a batch).

    Attributes
    ----------
    channels : ChannelState
        Channel states with a trailing axis (x, y, z).
    entry : ndarray (..., 2)
        Horizontal tip position where the foot entered the mud [m].
    heading : ndarray (...)
        Last horizontal heading of the motion [rad].
    in_mud : ndarray (...) of bool
        Whether the tip was below the surface after the last step.
    foot : Any
        Internal state of the foot mechanism (morphing foot), else None.
    """

    channels: ChannelState
    entry: np.ndarray
    heading: np.ndarray
    in_mud: np.ndarray
    foot: Any


@dataclass(frozen=True, eq=False)
class MudTerrain:
    r"""The mud model of Chen et al. (2026) as a terrain.

    Three stress channels run the constitutive model: x and y with the horizontal
    parameter set, z with the vertical one. Their dimensionless displacements are
    :math:`\gamma_x=(x-x_e)/L_c`, :math:`\gamma_y=(y-y_e)/L_c` (from the entry point
    :math:`(x_e,y_e)` where the tip entered the mud) and :math:`\gamma_z=d/L_c` (tip
    depth), with :math:`L_c` the foot's characteristic length. The foot turns the
    stresses into a force (closed forms or surface integration).

    Parameters
    ----------
    mud : Mud
        Vertical and horizontal parameter sets.
    characteristic_length : float or None
        :math:`L_c` [m]; ``None`` uses the foot's own.
    acceleration : bool
        Keep the acceleration term (decision D6).
    reset_on_exit : bool
        When the tip leaves the mud, reset the channels to undisturbed mud, so the next
        step lands in fresh mud (decision D11). Default True.
    xi0 : float
        Structure of undisturbed mud [-].
    heading_speed : float
        Below this horizontal speed [m/s] the last heading is kept.
    """

    mud: Mud
    characteristic_length: float | None = None
    acceleration: bool = True
    reset_on_exit: bool = True
    xi0: float = 0.0
    heading_speed: float = 1e-6
    name: str = "mud"

    def __post_init__(self) -> None:
        if not isinstance(self.mud, Mud):
            raise MudrftError(
                f"mud must be a Mud (see mudrft.paper_mud), got {type(self.mud).__name__}"
            )
        if self.characteristic_length is not None:
            check_positive("characteristic_length", self.characteristic_length, unit="m")
        object.__setattr__(self, "_params", channel_parameters(self.mud))
        # constants of the fused kernel (same update as constitutive.step, tested equal)
        from .backends.kernels import channel_constants

        object.__setattr__(self, "_consts", channel_constants(self._params))  # type: ignore[attr-defined]
        register("chen2026mud")

    @property
    def params(self) -> MudParameters:
        """The stacked (x, y, z) channel parameters."""
        return self._params  # type: ignore[attr-defined,no-any-return]

    def _lc(self, foot: Any) -> float:
        return float(self.characteristic_length or foot.characteristic_length)

    def initial_state(self, foot: Any, position: Any) -> MudState:
        """Undisturbed mud under a foot whose tip is at ``position`` (..., 3) [m]."""
        pos = check_finite("position", position)
        if pos.shape[-1:] != (3,):
            raise MudrftError(f"position must have shape (..., 3), got {pos.shape}")
        batch = pos.shape[:-1]
        lc = self._lc(foot)
        depth = np.maximum(-pos[..., 2], 0.0)
        g = np.zeros((*batch, 3))
        g[..., 2] = depth / lc
        ch = initial_state((*batch, 3), xi0=self.xi0, gamma=g)
        return MudState(
            channels=ch,
            entry=pos[..., :2].copy(),
            heading=np.zeros(batch),
            in_mud=depth > 0,
            foot=foot.initial_foot_state(),
        )

    def step(
        self, foot: Any, state: MudState, position: Any, velocity: Any, dt: float
    ) -> tuple[MudState, TerrainOutput]:
        """Advance the mud under the foot by ``dt`` [s]; see :class:`Terrain`.

        Inputs are not validated here (this is the inner loop); :func:`mudrft.simulate`
        validates trajectories once.
        """
        pos = np.asarray(position, dtype=float)
        vel = np.asarray(velocity, dtype=float)
        lc = self._lc(foot)
        depth = np.maximum(-pos[..., 2], 0.0)
        in_mud = depth > 0
        ch = state.channels
        entry = state.entry
        if self.reset_on_exit:
            fresh = ~state.in_mud  # was out of the mud before this step: fresh mud, new entry point
            if np.any(fresh):
                f3 = fresh[..., None]
                base = initial_state(ch.xi.shape, xi0=self.xi0)
                ch = ChannelState(*(np.where(f3, b, c) for b, c in zip(base, ch, strict=True)))
                entry = np.where(fresh[..., None], pos[..., :2] - vel[..., :2] * dt, entry)
        gamma = np.empty(pos.shape)
        gamma[..., :2] = (pos[..., :2] - entry) / lc
        gamma[..., 2] = depth / lc
        gdot = np.empty(pos.shape)
        gdot[..., :2] = vel[..., :2] / lc
        gdot[..., 2] = np.where(in_mud | state.in_mud, -vel[..., 2], 0.0) / lc
        hs = np.hypot(vel[..., 0], vel[..., 1])
        heading = np.where(
            hs > self.heading_speed, np.arctan2(vel[..., 1], vel[..., 0]), state.heading
        )
        seal = foot.seal_factor(state.foot)
        if isinstance(seal, float) and seal == 1.0:
            seal3: Any = 1.0
        else:
            seal3 = np.ones((*np.shape(seal), 3)) if np.ndim(seal) else np.ones(3)
            seal3[..., 2] = seal
        ch, total = fused_step(
            self._consts,  # type: ignore[attr-defined]
            ch, gamma, gdot, dt, seal=seal3, kappa=1.0 if self.acceleration else 0.0,
        )
        stress = total * in_mud[..., None]
        foot_state, force = foot.contact_force(state.foot, depth, stress, heading, dt)
        force = force * in_mud[..., None]
        new = MudState(channels=ch, entry=entry, heading=heading, in_mud=in_mud, foot=foot_state)
        return new, TerrainOutput(force=force, stress=stress, depth=depth)


def as_terrain(terrain: Any) -> Any:
    """Accept a :class:`Mud` (wrapped in :class:`MudTerrain`) or any :class:`Terrain`."""
    if isinstance(terrain, Mud):
        return MudTerrain(terrain)
    if isinstance(terrain, Terrain):
        return terrain
    raise MudrftError(
        "mud must be a Mud (mudrft.paper_mud) or a terrain with initial_state() and step() "
        f"(mudrft.terrains), got {type(terrain).__name__}"
    )
