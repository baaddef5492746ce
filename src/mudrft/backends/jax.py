r"""JAX backend (optional extra ``jax``): the library's own rules with ``xp=jax.numpy``, jitted,
vmapped and differentiable. Parameters travel as a :class:`JaxParams` pytree
(:func:`to_jax`); the first call switches JAX to 64-bit floats process-wide (decision D70).

Examples
--------
>>> import mudrft
>>> from mudrft.backends import jax as mjax
>>> p = mjax.to_jax(mudrft.paper_parameters(0.25))
>>> st, out = mjax.step(p, mjax.initial_state(), 0.1, 1.0, 0.1)
>>> bool(out.total > 0)
True
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validation import (
    MudrftError,
    check_characteristic_length,
    check_finite,
    check_in_range,
    check_increasing,
    check_positive,
)
from ..constitutive import dynamics
from ..constitutive.dynamics import ChannelHistory, evaluation
from ..constitutive.kernel import ChannelConstants, channel_constants
from ..constitutive.state import ChannelState, ChannelStress
from ..feet.base import Foot
from ..feet.surface import integrate_triangles
from ..terrains.mud import MudChannels, initial_channels, mud_step
from ._jax_base import (
    JaxParams,
    _jnp,
    check_params,
    enable_x64,
    from_jax,
    initial_state,
    is_tracer,
    safe_namespace,
    to_jax,
)
from .forces import force_function

if TYPE_CHECKING:
    from jax import Array
    from jax.typing import ArrayLike as JaxArrayLike

    from .forces import ForceRule

__all__ = [
    "JaxParams", "TerrainState", "batched_step", "enable_x64", "from_jax", "initial_state",
    "initial_terrain_state", "mesh_force", "mud_constants", "run", "safe_namespace",
    "simulate", "step", "terrain_step", "to_jax",
]  # fmt: skip


@functools.cache
def _compiled() -> dict[str, Any]:
    jax = enable_x64()
    import jax.numpy as jnp

    static = ("acceleration", "thixotropy", "clock")

    def one_step(
        p: JaxParams, st: ChannelState, g: Array, gd: Array, dt: Array, seal: Array,
        acceleration: bool | None, thixotropy: str, clock: str,
    ) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
        return dynamics.step(
            p, st, g, gd, dt, seal=seal, acceleration=acceleration,  # type: ignore[arg-type]
            thixotropy=thixotropy, clock=clock, xp=jnp,
        )  # fmt: skip

    step_jit = jax.jit(one_step, static_argnames=static)

    def vstep(
        p: JaxParams, st: ChannelState, g: Array, gd: Array, dt: Array, seal: Array,
        acceleration: bool | None, thixotropy: str, clock: str,
    ) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
        member = functools.partial(
            one_step, acceleration=acceleration, thixotropy=thixotropy, clock=clock
        )
        return jax.vmap(member, in_axes=(0, 0, 0, 0, None, 0))(p, st, g, gd, dt, seal)  # type: ignore[no-any-return]

    vstep_jit = jax.jit(vstep, static_argnames=static)

    def run_impl(
        p: JaxParams, t: Array, g: Array, st0: ChannelState, seal: Array,
        acceleration: bool | None, thixotropy: str, clock: str,
    ) -> tuple[Array, Array, Array, Array, Array]:  # fmt: skip
        dts = t[1:] - t[:-1]
        dts_b = dts.reshape(dts.shape + (1,) * (g.ndim - 1))
        rates = (g[1:] - g[:-1]) / dts_b

        def body(
            st: ChannelState, inp: tuple[Array, Array, Array, Array]
        ) -> tuple[ChannelState, tuple[Array, Array, Array, Array, Array]]:
            gk, rk, dtk, sk = inp
            st, s = one_step(p, st, gk, rk, dtk, sk, acceleration, thixotropy, clock)
            return st, (s.total, s.elastic, s.thixotropic, s.suction, st.xi)

        _, outs = jax.lax.scan(body, st0, (g[1:], rates, dts_b, seal[1:]))
        first = jnp.zeros((1, *g.shape[1:]))
        total, el, th, su, xi = (jnp.concatenate([first, o], axis=0) for o in outs)
        xi = xi.at[0].set(jnp.broadcast_to(st0.xi, g.shape[1:]))
        return total, el, th, su, xi

    run_jit = jax.jit(run_impl, static_argnames=static)

    def mesh_impl(v: Array, f: Array, d: Array, s: Array, h: Array, trailing: bool) -> Array:
        return integrate_triangles(v[f], d, s, h, trailing=trailing, xp=safe_namespace())

    mesh_jit = jax.jit(mesh_impl, static_argnames=("trailing",))
    return {"step": step_jit, "vstep": vstep_jit, "run": run_jit, "mesh_force": mesh_jit}


def _check_state(state: ChannelState, made_by: str) -> None:
    if not isinstance(state, ChannelState):
        raise MudrftError(f"state must be a ChannelState ({made_by}), got {type(state).__name__}")


def step(
    params: JaxParams, state: ChannelState, gamma: JaxArrayLike, gamma_dot: JaxArrayLike,
    dt: JaxArrayLike, *, seal: JaxArrayLike = 1.0, acceleration: bool | None = None,
    thixotropy: str = "ode", clock: str = "contact",
) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
    """Jit-compiled constitutive step (:func:`mudrft.constitutive.dynamics.step`).

    ``params`` (:func:`to_jax`) broadcast with the ``state``; ``gamma`` [-] at the end of the
    step, ``gamma_dot`` [1/s] over it, ``dt`` [s] > 0, ``seal`` in [0, 1] [-]; the static
    options as :func:`mudrft.constitutive.dynamics.evaluation`. Concrete inputs are checked,
    traced ones cannot be. Returns the new state and the stresses [Pa].
    """
    check_params(params)
    _check_state(state, "initial_state(...)")
    for name, value in (("gamma", gamma), ("gamma_dot", gamma_dot)):
        if not is_tracer(value):
            check_finite(name, value)
    if not is_tracer(dt):
        check_positive("dt", dt, unit="s")
    if not is_tracer(seal):
        check_in_range("seal", seal, 0.0, 1.0)
    return _compiled()["step"](  # type: ignore[no-any-return]
        params, state, gamma, gamma_dot, dt, seal, acceleration, thixotropy, clock
    )


def batched_step(
    params: JaxParams, state: ChannelState, gamma: JaxArrayLike, gamma_dot: JaxArrayLike,
    dt: JaxArrayLike, *, seal: JaxArrayLike | None = None, acceleration: bool | None = None,
    thixotropy: str = "ode", clock: str = "contact",
) -> tuple[ChannelState, ChannelStress]:  # fmt: skip
    """:func:`step` mapped with :func:`jax.vmap` over a leading axis of N channels.

    ``params``, ``state``, ``gamma`` [-], ``gamma_dot`` [1/s] and ``seal`` [-] (default
    ones) have a leading axis N (parameters may also be scalars); ``dt`` [s] is one number
    shared by the batch. Other options and the returns as :func:`step`.
    """
    check_params(params)
    jnp = _jnp()
    g = jnp.asarray(gamma, dtype=float)
    if g.ndim == 0:
        raise MudrftError("gamma must have a leading batch axis (N, ...), got a scalar")
    s = jnp.broadcast_to(jnp.asarray(1.0 if seal is None else seal, dtype=float), g.shape)
    n = g.shape[0]
    if jnp.ndim(dt):
        raise MudrftError(
            f"dt must be one step shared by the batch [s], a number, got an array of shape "
            f"{jnp.shape(dt)} (each member's dt was applied to every member); for a step per "
            "member, call step(...), which broadcasts dt with gamma"
        )
    _check_state(state, "initial_state((N, ...))")
    for name, f in zip(ChannelState._fields, state, strict=True):
        if jnp.shape(f)[:1] != (n,):
            raise MudrftError(
                f"state.{name} must have a leading axis of length {n} (one state per member "
                f"of the batch, initial_state(({n}, ...))), got shape {jnp.shape(f)}"
            )
    for name, f in zip(JaxParams._fields, params, strict=True):
        if jnp.ndim(f) and jnp.shape(f)[0] != n:
            raise MudrftError(
                f"params.{name} must be a scalar or have a leading axis of length {n} (one set "
                f"per member of the batch), got shape {jnp.shape(f)}"
            )
    p = JaxParams(
        *(jnp.broadcast_to(jnp.asarray(f, float), (n, *jnp.shape(f)[1:])) for f in params)
    )
    return _compiled()["vstep"](
        p, state, g, jnp.asarray(gamma_dot, dtype=float), dt, s, acceleration, thixotropy, clock
    )  # type: ignore[no-any-return]


def run(
    params: JaxParams, time: JaxArrayLike, gamma: JaxArrayLike, *,
    state: ChannelState | None = None, seal: JaxArrayLike = 1.0,
    acceleration: bool | None = None, thixotropy: str = "ode", clock: str = "contact",
    xi0: float = 0.0,
) -> ChannelHistory:  # fmt: skip
    """:func:`mudrft.constitutive.dynamics.run` as a compiled :func:`jax.lax.scan`,
    differentiable with respect to ``params``, ``gamma`` and ``state``.

    ``time`` (n,) [s] increasing, ``gamma`` (n, ...) [-]; ``state`` defaults to undisturbed
    mud (structure ``xi0`` [-]) at ``gamma[0]``; ``seal`` [-] a scalar or (n, ...); the other
    options as :func:`step`. Returns a :class:`~mudrft.constitutive.dynamics.ChannelHistory`.

    >>> import numpy as np, mudrft
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> h = run(to_jax(mudrft.paper_parameters(0.25)), t, 0.2 * t)
    >>> h.total.shape
    (11,)
    """
    jnp = _jnp()
    check_params(params)
    if not is_tracer(time):
        time = check_increasing("time", time)
        if time.size < 2:
            raise MudrftError(f"time must have at least 2 samples, got {time.size}")
    if not is_tracer(gamma):
        g_np = check_finite("gamma", gamma)
        if g_np.shape[:1] != np.shape(time):
            raise MudrftError(
                f"gamma must have the same length as time along its first axis, got gamma shape "
                f"{g_np.shape} and time shape {np.shape(time)}"
            )
    if not is_tracer(xi0):
        check_in_range("xi0", xi0, 0.0, 1.0)
    t, g = jnp.asarray(time, dtype=float), jnp.asarray(gamma, dtype=float)
    dynamics.check_parameter_shapes(
        {k: jnp.shape(f) for k, f in zip(JaxParams._fields, params, strict=True)}, g.shape[1:]
    )
    z = jnp.zeros(g.shape[1:])
    if state is None:
        state = ChannelState(g[0] + z, g[0] + z, z + xi0, z, z, z, z)
    else:  # a state built without clocks carries them as Python zeros: give them its shape
        state = state._replace(clock=z + state.clock, clock_w=z + state.clock_w)
    sl = jnp.broadcast_to(jnp.asarray(seal, dtype=float), g.shape)
    total, el, th, su, xi = _compiled()["run"](
        params, t, g, state, sl, acceleration, thixotropy, clock
    )
    return ChannelHistory(t, g, total, el, th, su, xi)


def mesh_force(
    vertices: JaxArrayLike, faces: JaxArrayLike, depth: JaxArrayLike, stress: JaxArrayLike,
    heading: JaxArrayLike, *, trailing: bool = False,
) -> Array:  # fmt: skip
    """Force of the mud on a triangulated foot [N] (..., 3), differentiable in ``vertices``:
    :func:`mudrft.feet.surface.integrate_triangles` on ``vertices[faces]``.

    ``vertices`` (v, 3) [m] with the tip at z = 0, integer ``faces`` (m, 3) wound outward,
    tip ``depth`` [m], ``stress`` (..., 3) [Pa], ``heading`` [rad]; ``trailing`` as the foot's.
    """
    jnp = _jnp()
    v = jnp.asarray(vertices, dtype=float)
    if v.ndim != 2 or v.shape[1] != 3:
        raise MudrftError(f"vertices must have shape (v, 3) [m], got shape {v.shape}")
    if is_tracer(faces):
        f = faces
    else:  # JAX would clip or wrap bad indices silently
        f = np.asarray(faces)
        if f.ndim != 2 or f.shape[1] != 3 or f.dtype.kind not in "iu":
            raise MudrftError(
                f"faces must be integers of shape (m, 3), got {f.dtype} of shape {f.shape}"
            )
        if f.size and (f.min() < 0 or f.max() >= v.shape[0]):
            raise MudrftError(
                f"faces must index the {v.shape[0]} vertices (0 to {v.shape[0] - 1}), got "
                f"{int(f.min())} to {int(f.max())}"
            )
    if not (is_tracer(vertices) or is_tracer(f)) and v.size and np.size(f):
        used = np.asarray(vertices, dtype=float)[np.unique(np.asarray(f))]
        low, size = float(used[:, 2].min()), float(np.ptp(used, axis=0).max())
        if abs(low) > 1e-9 * size:
            raise MudrftError(
                f"vertices must have the tip (lowest point) at z = 0 [m], got a lowest z of "
                f"{low:.6g} m: depth is the tip's, so the foot would sit {abs(low):.3g} m "
                f"{'higher' if low > 0 else 'lower'}; use MeshFoot(vertices, faces).vertices "
                "(shifted to the tip)"
            )
    if np.shape(stress)[-1:] != (3,):
        raise MudrftError(f"stress must have shape (..., 3) [Pa], got shape {np.shape(stress)}")
    return _compiled()["mesh_force"](v, jnp.asarray(f), depth, stress, heading, trailing)


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
