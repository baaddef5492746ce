"""The mud's one terrain step under JAX: :func:`terrain_step` and a scanned :func:`simulate`.

Part of the JAX backend (:mod:`mudrft.backends.jax` re-exports every name).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..constitutive.dynamics import evaluation
from ..constitutive.kernel import channel_constants
from ..terrains.mud import MudChannels, initial_channels, mud_step
from ._jax_base import JaxParams, _jnp, check_params, enable_x64

if TYPE_CHECKING:
    from jax import Array
    from jax.typing import ArrayLike as JaxArrayLike

    from .forces import ForceRule

__all__ = ["TerrainState", "initial_terrain_state", "simulate", "terrain_step"]


#: State of :func:`terrain_step`: the mud under the feet (a JAX pytree).
TerrainState = MudChannels


def initial_terrain_state(
    position: JaxArrayLike, characteristic_length: float, *, xi0: float = 0.0
) -> MudChannels:
    """Undisturbed mud under tips at ``position`` (..., 3) [m], as JAX arrays.

    Parameters
    ----------
    position : array_like, shape (..., 3)
        Tip positions [m].
    characteristic_length : float
        :math:`L_c` [m].
    xi0 : float, keyword-only
        Structure of undisturbed mud [-].
    """
    jnp = _jnp()
    pos = jnp.asarray(position, dtype=float)
    depth = jnp.maximum(-pos[..., 2], 0.0)
    return initial_channels(pos[..., 0], pos[..., 1], depth, characteristic_length, xi0, xp=jnp)


def terrain_step(
    params: JaxParams,
    state: MudChannels,
    position: JaxArrayLike,
    velocity: JaxArrayLike,
    dt: JaxArrayLike,
    *,
    force_fn: ForceRule,
    characteristic_length: float,
    acceleration: bool | None = None,
    reset_on_exit: bool = True,
    xi0: float = 0.0,
    heading_speed: float = 1e-6,
    thixotropy: str = "ode",
    clock: str = "contact",
) -> tuple[MudChannels, tuple[Array, Array, Array]]:
    """One step of :class:`mudrft.MudTerrain` for a rigid foot, traceable by JAX.

    It is :func:`mudrft.terrains.mud.mud_step` with ``xp=jax.numpy`` (the one terrain step),
    followed by the foot's force function.

    Parameters
    ----------
    params : JaxParams
        Channel parameters with a trailing axis of 3 (``to_jax(mud)``).
    state : MudChannels
        From :func:`initial_terrain_state` or a previous step.
    position, velocity : array_like, shape (..., 3)
        Tip position [m] and velocity [m/s] at the end of the step.
    dt : float
        Step [s].
    force_fn : callable, keyword-only
        ``force_fn(depth, stress, heading) -> force (..., 3)`` [N] in JAX, e.g.
        ``functools.partial(mesh_force, vertices, faces)``.
    characteristic_length : float, keyword-only
        :math:`L_c` [m].
    acceleration, reset_on_exit, xi0, heading_speed, thixotropy, clock : keyword-only
        As :class:`mudrft.MudTerrain` (static under jit: Python values, not traced).

    Returns
    -------
    state : MudChannels
    (force, stress, depth) : tuple of arrays
        Force [N] (..., 3), channel stresses [Pa] (..., 3), depth [m] (...).
    """
    check_params(params, channels=True)
    qs, restart, kappa = evaluation(thixotropy, clock, acceleration)
    jax = enable_x64()
    jnp = _jnp()
    pos = jnp.asarray(position, dtype=float)
    vel = jnp.asarray(velocity, dtype=float)
    hor = channel_constants(jax.tree_util.tree_map(lambda a: a[..., 0], params))
    ver = channel_constants(jax.tree_util.tree_map(lambda a: a[..., 2], params))
    ch, sx, sy, sz, depth = mud_step(
        (hor, ver), state, pos[..., 0], pos[..., 1], pos[..., 2], vel[..., 0], vel[..., 1],
        vel[..., 2], dt, characteristic_length, kappa, xi0, reset_on_exit, heading_speed, 1.0,
        qs, restart, xp=jnp,
    )  # fmt: skip
    stress = jnp.stack([sx, sy, sz], axis=-1)
    force = force_fn(depth, stress, ch.heading) * ch.in_mud[..., None]
    return ch, (force, stress, depth)


def simulate(
    params: JaxParams,
    time: JaxArrayLike,
    position: JaxArrayLike,
    velocity: JaxArrayLike,
    *,
    force_fn: ForceRule,
    characteristic_length: float,
    acceleration: bool | None = None,
    reset_on_exit: bool = True,
    xi0: float = 0.0,
    heading_speed: float = 1e-6,
    thixotropy: str = "ode",
    clock: str = "contact",
) -> tuple[Array, Array, Array]:
    """Run :func:`terrain_step` along a trajectory with :func:`jax.lax.scan`.

    Same sampling as :func:`mudrft.simulate`: the state starts at ``position[0]`` and step
    ``k`` ends at sample ``k`` with ``dt = time[k] - time[k-1]``. Traceable: wrap it in
    :func:`jax.jit` (``force_fn`` closed over) and differentiate it with respect to
    ``params``, the foot geometry in ``force_fn`` or the trajectory.

    Parameters
    ----------
    params : JaxParams
        Channel parameters (``to_jax(mud)``).
    time : array_like, shape (n,)
        Increasing times [s].
    position, velocity : array_like, shape (n, ..., 3)
        Tip position [m] and velocity [m/s] at the samples.
    force_fn, characteristic_length, acceleration, reset_on_exit, xi0, heading_speed :
        As :func:`terrain_step`.
    thixotropy, clock :
        As :func:`terrain_step`.

    Returns
    -------
    force, stress, depth : arrays of shape (n, ..., 3), (n, ..., 3), (n, ...)
        The first sample is the initial state (zero force).
    """
    jax = enable_x64()
    jnp = _jnp()
    t = jnp.asarray(time, dtype=float)
    pos = jnp.asarray(position, dtype=float)
    vel = jnp.asarray(velocity, dtype=float)
    st0 = initial_terrain_state(pos[0], characteristic_length, xi0=xi0)

    def body(
        st: MudChannels, inp: tuple[Array, Array, Array]
    ) -> tuple[MudChannels, tuple[Array, Array, Array]]:
        p, v, dt = inp
        return terrain_step(
            params,
            st,
            p,
            v,
            dt,
            force_fn=force_fn,
            characteristic_length=characteristic_length,
            acceleration=acceleration,
            reset_on_exit=reset_on_exit,
            xi0=xi0,
            heading_speed=heading_speed,
            thixotropy=thixotropy,
            clock=clock,
        )

    _, (f, s, d) = jax.lax.scan(body, st0, (pos[1:], vel[1:], t[1:] - t[:-1]))
    zf = jnp.zeros((1, *f.shape[1:]))
    return (
        jnp.concatenate([zf, f]),
        jnp.concatenate([zf, s]),
        jnp.concatenate([jnp.maximum(-pos[:1, ..., 2], 0.0), d]),
    )
