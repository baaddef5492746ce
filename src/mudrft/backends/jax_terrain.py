"""The mud's terrain step under JAX (re-exported by :mod:`mudrft.backends.jax`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._validation import (
    MudrftError,
    check_characteristic_length,
    check_finite,
    check_increasing,
    check_positive,
)
from ..constitutive.dynamics import evaluation
from ..constitutive.kernel import ChannelConstants, channel_constants
from ..feet.base import Foot
from ..terrains.mud import MudChannels, initial_channels, mud_step
from ._jax_base import JaxParams, _jnp, check_params, enable_x64, is_tracer, safe_namespace
from .forces import force_function

if TYPE_CHECKING:
    from jax import Array
    from jax.typing import ArrayLike as JaxArrayLike

    from .forces import ForceRule

__all__ = ["TerrainState", "initial_terrain_state", "mud_constants", "simulate", "terrain_step"]


#: State of :func:`terrain_step`: the mud under the feet (a JAX pytree).
TerrainState = MudChannels


def _xyz(name: str, value: JaxArrayLike, unit: str) -> Array:
    """``value`` as a float array of shape (..., 3), checked (a traced one for its shape)."""
    jnp = _jnp()
    a = jnp.asarray(value if is_tracer(value) else check_finite(name, value), dtype=float)
    if a.shape[-1:] != (3,):
        raise MudrftError(
            f"{name} must have shape (..., 3) [{unit}], its x, y and z components, got shape "
            f"{a.shape}"
        )
    return a


def _length(characteristic_length: float) -> float:
    """:math:`L_c` [m], checked when concrete."""
    if isinstance(characteristic_length, Foot):
        raise MudrftError(
            "characteristic_length must be a length [m], got a "
            f"{type(characteristic_length).__name__}: use foot.characteristic_length, or pass "
            "the foot as force_fn, which then gives its own"
        )
    if is_tracer(characteristic_length) or np.ndim(characteristic_length):
        return characteristic_length
    return check_characteristic_length("mudrft.backends.jax", characteristic_length)


def foot_rule(
    force_fn: Foot | ForceRule, characteristic_length: float | None
) -> tuple[ForceRule, float]:
    """The force rule and :math:`L_c` [m] of :func:`terrain_step`: a foot (or its
    ``force`` method) gives its own rule and length; a function needs the length."""
    owner, name = getattr(force_fn, "__self__", None), getattr(force_fn, "__name__", "")
    if isinstance(owner, Foot) and name in ("force", "force_unchecked"):
        force_fn = owner  # foot.force is numpy: the foot's own rule instead
    if isinstance(force_fn, Foot):
        fn = force_function(force_fn, xp=safe_namespace())
        if fn is None:
            raise MudrftError(
                f"force_fn: the {type(force_fn).__name__} has no force rule under JAX (its "
                "internal state is solved with numpy); the flat, semi-cylinder, semi-sphere "
                "and mesh feet have one"
            )
        if characteristic_length is None:
            characteristic_length = force_fn.characteristic_length
        return fn, _length(characteristic_length)
    if not callable(force_fn):
        raise MudrftError(
            "force_fn must be a foot (mudrft.feet.Flat(), ...) or a function f(depth [m], "
            "stress (..., 3) [Pa], heading [rad]) -> force (..., 3) [N] written with "
            f"jax.numpy, got {type(force_fn).__name__}"
        )
    if characteristic_length is None:
        raise MudrftError(
            "characteristic_length [m] must be given with a force function (a foot passed as "
            "force_fn gives its own, foot.characteristic_length)"
        )
    return force_fn, _length(characteristic_length)


def mud_constants(params: JaxParams) -> tuple[ChannelConstants, ChannelConstants]:
    """The mud's ``(horizontal, vertical)`` channel constants from ``params = to_jax(mud)``
    (``constants=`` of :meth:`mudrft.integrations.mjx.MjxCoupling.step`); traceable."""
    check_params(params, channels=True)
    tree_map = enable_x64().tree_util.tree_map
    hor = channel_constants(tree_map(lambda a: a[..., 0], params))
    ver = channel_constants(tree_map(lambda a: a[..., 2], params))
    return hor, ver


def initial_terrain_state(
    position: JaxArrayLike, characteristic_length: float, *, xi0: float = 0.0
) -> MudChannels:
    """Undisturbed mud (structure ``xi0`` [-]) under tips at ``position`` (..., 3) [m], for
    a foot of ``characteristic_length`` [m], as JAX arrays."""
    jnp = _jnp()
    pos = _xyz("position", position, "m")
    depth, lc = jnp.maximum(-pos[..., 2], 0.0), _length(characteristic_length)
    return initial_channels(pos[..., 0], pos[..., 1], depth, lc, xi0, xp=jnp)


def terrain_step(
    params: JaxParams, state: MudChannels, position: JaxArrayLike, velocity: JaxArrayLike,
    dt: JaxArrayLike, *, force_fn: Foot | ForceRule,
    characteristic_length: float | None = None, acceleration: bool | None = None,
    reset_on_exit: bool = True, xi0: float = 0.0, heading_speed: float = 1e-6,
    thixotropy: str = "ode", clock: str = "contact",
) -> tuple[MudChannels, tuple[Array, Array, Array]]:  # fmt: skip
    """One step of :class:`mudrft.MudTerrain` for a rigid foot, traceable by JAX:
    :func:`mudrft.terrains.mud.mud_step` with ``xp=jax.numpy``, then the foot's force rule.

    Parameters
    ----------
    params : JaxParams
        Channel parameters, ``to_jax(mud)``.
    state : MudChannels
        From :func:`initial_terrain_state` or a previous step.
    position, velocity : array_like, shape (..., 3)
        Tip position [m] and velocity [m/s] at the end of the step.
    dt : float
        Step [s], > 0.
    force_fn : Foot or callable, keyword-only
        A rigid foot of :mod:`mudrft.feet`, or ``force_fn(depth, stress, heading) -> force
        (..., 3)`` [N] written with ``jax.numpy``.
    characteristic_length : float, keyword-only
        :math:`L_c` [m], may be traced; default the foot's (needed with a function).
    acceleration, reset_on_exit, xi0, heading_speed, thixotropy, clock : keyword-only
        As :class:`mudrft.MudTerrain` (static under jit).

    Returns
    -------
    state : MudChannels
    (force, stress, depth) : tuple of arrays
        Force [N] (..., 3), channel stresses [Pa] (..., 3), depth [m] (...).
    """
    check_params(params, channels=True)
    qs, restart, kappa = evaluation(thixotropy, clock, acceleration)
    fn, lc = foot_rule(force_fn, characteristic_length)
    jax, jnp = enable_x64(), _jnp()
    pos, vel = _xyz("position", position, "m"), _xyz("velocity", velocity, "m/s")
    if not is_tracer(dt):
        check_positive("dt", dt, unit="s")
    batch = jnp.shape(state.in_mud)
    try:
        np.broadcast_shapes(batch, pos.shape[:-1], vel.shape[:-1])
    except ValueError:
        raise MudrftError(
            f"state is the mud under tips of shape {batch} (initial_terrain_state), but "
            f"position has shape {pos.shape} and velocity {vel.shape}: one (x, y, z) per tip"
        ) from None
    ch, sx, sy, sz, depth = mud_step(
        mud_constants(params), state, pos[..., 0], pos[..., 1], pos[..., 2], vel[..., 0], vel[..., 1],
        vel[..., 2], dt, lc, kappa, xi0, reset_on_exit, heading_speed, 1.0,
        qs, restart, xp=jnp,
    )  # fmt: skip
    stress = jnp.stack([sx, sy, sz], axis=-1)
    try:
        force = fn(depth, stress, ch.heading) * ch.in_mud[..., None]
    except jax.errors.TracerArrayConversionError as exc:
        raise MudrftError(
            "force_fn must compute with jax.numpy, but it turned a traced value into a numpy "
            "array (a numpy rule such as foot.force or force_function(foot)); pass the foot "
            "itself, force_fn=foot, or force_function(foot, xp=mudrft.backends.jax."
            "safe_namespace())"
        ) from exc
    return ch, (force, stress, depth)


def simulate(
    params: JaxParams, time: JaxArrayLike, position: JaxArrayLike, velocity: JaxArrayLike, *,
    force_fn: Foot | ForceRule, characteristic_length: float | None = None,
    acceleration: bool | None = None, reset_on_exit: bool = True, xi0: float = 0.0,
    heading_speed: float = 1e-6, thixotropy: str = "ode", clock: str = "contact",
) -> tuple[Array, Array, Array]:  # fmt: skip
    """Run :func:`terrain_step` along ``time`` (n,) [s], ``position`` [m] and ``velocity``
    [m/s] (n, ..., 3) with :func:`jax.lax.scan` (differentiable; jit the caller, or every
    call compiles again); options as :func:`terrain_step`. Returns ``force`` [N], ``stress``
    [Pa] (n, ..., 3) and ``depth`` [m] (n, ...), sample 0 the initial state (zero force).
    """
    jax, jnp = enable_x64(), _jnp()
    if not is_tracer(time):
        time = check_increasing("time", time)
    t = jnp.asarray(time, dtype=float)
    pos = _xyz("position", position, "m")
    vel = _xyz("velocity", velocity, "m/s")
    if t.ndim != 1 or t.shape[0] < 2 or pos.shape[:1] != t.shape or vel.shape != pos.shape:
        raise MudrftError(
            "time must have shape (n,) with n >= 2 and position and velocity shape (n, ..., 3) "
            f"(one row per sample), got time {t.shape}, position {pos.shape} and velocity "
            f"{vel.shape}"
        )
    force_fn, characteristic_length = foot_rule(force_fn, characteristic_length)
    st0 = initial_terrain_state(pos[0], characteristic_length, xi0=xi0)

    def body(
        st: MudChannels, inp: tuple[Array, Array, Array]
    ) -> tuple[MudChannels, tuple[Array, Array, Array]]:
        p, v, dt = inp
        return terrain_step(
            params, st, p, v, dt, force_fn=force_fn,
            characteristic_length=characteristic_length, acceleration=acceleration,
            reset_on_exit=reset_on_exit, xi0=xi0, heading_speed=heading_speed,
            thixotropy=thixotropy, clock=clock,
        )  # fmt: skip

    _, (f, s, d) = jax.lax.scan(body, st0, (pos[1:], vel[1:], t[1:] - t[:-1]))
    zf, d0 = jnp.zeros((1, *f.shape[1:])), jnp.maximum(-pos[:1, ..., 2], 0.0)
    return jnp.concatenate([zf, f]), jnp.concatenate([zf, s]), jnp.concatenate([d0, d])
