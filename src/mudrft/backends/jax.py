r"""JAX backend: jit-compiled, vmapped and differentiable versions of the mud model.

Optional extra ``jax`` (``pip install 'mudrft[jax]'``); ``jax`` is imported on the first
call of a function of this module, not at import time. The backend reuses the library's
own update rules with ``xp=jax.numpy`` instead of rewriting them:

* :func:`step` is :func:`mudrft.constitutive.dynamics.step` compiled with :func:`jax.jit`;
  :func:`batched_step` maps it over a leading batch axis with :func:`jax.vmap` (one set of
  parameters, one state and one input per foot);
* :func:`run` is :func:`mudrft.constitutive.dynamics.run` as a :func:`jax.lax.scan`;
* :func:`mesh_force` integrates a triangulated foot with
  :func:`mudrft.feet.surface.integrate_triangles` (``xp=jax.numpy``), differentiable with
  respect to the vertices;
* :func:`terrain_step` and :func:`simulate` are :class:`mudrft.MudTerrain` (three channels
  per foot, entry point, reset on exit, heading) for a rigid foot given as a force function.

Parameters cannot travel as :class:`~mudrft.parameters.base.MudParameters` (its fields are
validated with numpy, which a tracer cannot pass), so :func:`to_jax` converts them into a
:class:`JaxParams` pytree with the same attribute names, including ``k_r``.

Precision: the first call of any function here switches JAX to 64-bit floats
(``jax.config.update("jax_enable_x64", True)``, a process-wide JAX setting; decision D70),
so results agree with the numpy backend to rounding.

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
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from .._validation import MudrftError, check_finite, check_in_range, check_increasing
from ..constitutive import dynamics
from ..constitutive.dynamics import ChannelHistory
from ..constitutive.state import ChannelState
from ..constitutive.kernel import channel_constants
from ..parameters.base import PARAMETER_UNITS, Mud, MudParameters
from ..terrains.mud import MudChannels, initial_channels, mud_step

__all__ = [
    "JaxParams",
    "TerrainState",
    "batched_step",
    "enable_x64",
    "from_jax",
    "initial_state",
    "initial_terrain_state",
    "mesh_force",
    "run",
    "safe_namespace",
    "simulate",
    "step",
    "terrain_step",
    "to_jax",
]


def enable_x64() -> Any:
    """Import jax, switch it to 64-bit floats (decision D70) and return the module.

    Raises
    ------
    ImportError
        If jax is not installed, with the command that installs it.
    """
    try:
        import jax
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the JAX backend needs jax: pip install 'mudrft[jax]'") from exc
    if not getattr(jax.config, "jax_enable_x64", False):
        jax.config.update("jax_enable_x64", True)
    return jax


def _jnp() -> Any:
    enable_x64()
    import jax.numpy as jnp

    return jnp


class JaxParams(NamedTuple):
    """Parameters of the mud model as a JAX pytree (same names and units as MudParameters).

    Every field is a float64 array: ``alpha`` [Pa], ``n`` [-], ``lam`` [s], ``eta_m``,
    ``eta_inf`` [Pa s], ``gamma_dot_c`` [1/s], ``tau_build``, ``tau_leak`` [s],
    ``epsilon`` [-], ``sigma_y`` [Pa], ``nu`` [1/s], ``k_a`` [1/s]. Fields may carry a batch
    (leading axes) and, for the three channels of a foot, a trailing axis of 3 (x, y, z).

    ``k_a`` is a field of its own: differentiating with respect to ``lam`` does not move
    ``k_a``; use :meth:`with_default_k_a` to tie it to ``1/lam`` (decision D8) inside a
    differentiated function (decision D72).
    """

    alpha: Any
    n: Any
    lam: Any
    eta_m: Any
    eta_inf: Any
    gamma_dot_c: Any
    tau_build: Any
    tau_leak: Any
    epsilon: Any
    sigma_y: Any
    nu: Any
    k_a: Any

    @property
    def k_r(self) -> Any:
        """Rejuvenation coefficient :math:`k_r=k_a/\\dot\\gamma_c` [-]."""
        return self.k_a / self.gamma_dot_c

    def with_default_k_a(self) -> JaxParams:
        """Copy with ``k_a = 1/lam`` (decision D8), traceable."""
        return self._replace(k_a=1.0 / self.lam)


def to_jax(params: MudParameters | Mud) -> JaxParams:
    """Convert a parameter set, or a mud's three channel sets, into a :class:`JaxParams`.

    Parameters
    ----------
    params : MudParameters or Mud
        One set (fields keep their shape), or a Mud: its (horizontal, horizontal,
        vertical) sets for the x, y, z channels of a foot (trailing axis of 3, as
        :func:`mudrft.terrains.channel_parameters`).

    Returns
    -------
    JaxParams
        float64 JAX arrays.

    Examples
    --------
    >>> import mudrft
    >>> p = to_jax(mudrft.paper_mud(0.25))
    >>> p.alpha.shape
    (3,)
    """
    from ..terrains import channel_parameters

    jnp = _jnp()
    if isinstance(params, Mud):
        params = channel_parameters(params)
    if not isinstance(params, MudParameters):
        raise MudrftError(f"params must be a MudParameters or a Mud, got {type(params).__name__}")
    return JaxParams(
        **{k: jnp.asarray(np.asarray(getattr(params, k), dtype=float)) for k in PARAMETER_UNITS}
    )


def from_jax(params: JaxParams, **meta: Any) -> MudParameters:
    """Convert a :class:`JaxParams` back into a validated :class:`MudParameters`.

    Parameters
    ----------
    params : JaxParams
        Concrete (not traced) parameters.
    **meta
        ``source``, ``water_content``, ``direction`` passed on to MudParameters.
    """
    fields: dict[str, Any] = {}
    for k in PARAMETER_UNITS:
        a = np.asarray(getattr(params, k), dtype=float)
        fields[k] = float(a) if a.ndim == 0 else a
    return MudParameters(**fields, **meta)  # type: ignore[arg-type]


def initial_state(
    shape: tuple[int, ...] = (), *, xi0: float = 0.0, gamma: Any = 0.0
) -> ChannelState:
    """Undisturbed channel state as JAX arrays (see :func:`mudrft.constitutive.initial_state`).

    Parameters
    ----------
    shape : tuple of int
        Batch shape.
    xi0 : float, keyword-only
        Initial structure in [0, 1] [-].
    gamma : float or array, keyword-only
        Initial displacement [-].
    """
    from ..constitutive.state import initial_state as np_initial

    jnp = _jnp()
    return ChannelState(*(jnp.asarray(a) for a in np_initial(shape, xi0=xi0, gamma=gamma)))


@functools.cache
def _compiled() -> dict[str, Any]:
    """Build the jit-compiled functions once (jax is imported here)."""
    jax = enable_x64()
    import jax.numpy as jnp

    def one_step(
        p: JaxParams, st: ChannelState, g: Any, gd: Any, dt: Any, seal: Any, acceleration: bool
    ) -> tuple[ChannelState, Any]:
        return dynamics.step(p, st, g, gd, dt, seal=seal, acceleration=acceleration, xp=jnp)  # type: ignore[arg-type]

    step_jit = jax.jit(one_step, static_argnames=("acceleration",))
    vstep = jax.vmap(one_step, in_axes=(0, 0, 0, 0, None, 0, None))
    vstep_jit = jax.jit(vstep, static_argnames=("acceleration",))

    def run_impl(
        p: JaxParams, t: Any, g: Any, st0: ChannelState, seal: Any, acceleration: bool
    ) -> tuple[Any, ...]:
        dts = t[1:] - t[:-1]
        dts_b = dts.reshape(dts.shape + (1,) * (g.ndim - 1))
        rates = (g[1:] - g[:-1]) / dts_b

        def body(st: ChannelState, inp: tuple[Any, ...]) -> tuple[ChannelState, tuple[Any, ...]]:
            gk, rk, dtk, sk = inp
            st, s = dynamics.step(p, st, gk, rk, dtk, seal=sk, acceleration=acceleration, xp=jnp)  # type: ignore[arg-type]
            return st, (s.total, s.elastic, s.thixotropic, s.suction, st.xi)

        _, outs = jax.lax.scan(body, st0, (g[1:], rates, dts_b, seal[1:]))
        first = jnp.zeros((1, *g.shape[1:]))
        total, el, th, su, xi = (jnp.concatenate([first, o], axis=0) for o in outs)
        xi = xi.at[0].set(jnp.broadcast_to(st0.xi, g.shape[1:]))
        return total, el, th, su, xi

    run_jit = jax.jit(run_impl, static_argnames=("acceleration",))

    def mesh_impl(v: Any, f: Any, d: Any, s: Any, h: Any, trailing: bool) -> Any:
        from ..feet.surface import integrate_triangles

        return integrate_triangles(v[f], d, s, h, trailing=trailing, xp=safe_namespace())

    mesh_jit = jax.jit(mesh_impl, static_argnames=("trailing",))
    return {"step": step_jit, "vstep": vstep_jit, "run": run_jit, "mesh_force": mesh_jit}


def step(
    params: JaxParams,
    state: ChannelState,
    gamma: Any,
    gamma_dot: Any,
    dt: Any,
    *,
    seal: Any = 1.0,
    acceleration: bool = True,
) -> tuple[ChannelState, Any]:
    """Jit-compiled constitutive step (:func:`mudrft.constitutive.dynamics.step`, ``xp=jax.numpy``).

    Parameters
    ----------
    params : JaxParams
        From :func:`to_jax`; fields broadcast with the state.
    state : ChannelState
        State at the start of the step (JAX or numpy arrays).
    gamma : array_like
        Dimensionless displacement at the end of the step [-].
    gamma_dot : array_like
        Dimensionless rate over the step [1/s].
    dt : float or array_like
        Step [s], > 0 (not checked: this function may be traced).
    seal : array_like, keyword-only
        Sealing factor in [0, 1] [-].
    acceleration : bool, keyword-only
        Keep the acceleration term (decision D6); static under jit.

    Returns
    -------
    state : ChannelState
        New state (JAX arrays).
    stress : ChannelStress
        Stresses [Pa].
    """
    return _compiled()["step"](params, state, gamma, gamma_dot, dt, seal, acceleration)  # type: ignore[no-any-return]


def batched_step(
    params: JaxParams,
    state: ChannelState,
    gamma: Any,
    gamma_dot: Any,
    dt: Any,
    *,
    seal: Any = None,
    acceleration: bool = True,
) -> tuple[ChannelState, Any]:
    """:func:`step` mapped with :func:`jax.vmap` over a leading axis of N independent channels.

    Parameters
    ----------
    params : JaxParams
        Fields of shape ``(N, ...)``: one parameter set per member of the batch.
    state : ChannelState
        Fields of shape ``(N, ...)``.
    gamma, gamma_dot : array_like, shape (N, ...)
        Displacement [-] and rate [1/s] per member.
    dt : float
        Step shared by the batch [s].
    seal : array_like, shape (N, ...), keyword-only
        Sealing factor per member [-]; default ones.
    acceleration : bool, keyword-only
        Keep the acceleration term (decision D6).

    Returns
    -------
    state, stress
        As :func:`step`, with the leading batch axis.
    """
    jnp = _jnp()
    g = jnp.asarray(gamma, dtype=float)
    s = (
        jnp.ones_like(g)
        if seal is None
        else jnp.broadcast_to(jnp.asarray(seal, dtype=float), g.shape)
    )
    n = g.shape[0]
    for name, f in zip(JaxParams._fields, params, strict=True):
        if jnp.ndim(f) and jnp.shape(f)[0] != n:
            raise MudrftError(
                f"params.{name} must be a scalar or have a leading axis of length {n} (one set "
                f"per member of the batch), got shape {jnp.shape(f)}"
            )
    p = JaxParams(
        *(
            jnp.broadcast_to(jnp.asarray(f, dtype=float), (n, *jnp.shape(f)[1:]))
            if jnp.ndim(f)
            else jnp.full((n,), f)
            for f in params
        )
    )
    return _compiled()["vstep"](
        p, state, g, jnp.asarray(gamma_dot, dtype=float), dt, s, acceleration
    )  # type: ignore[no-any-return]


def _is_tracer(x: Any) -> bool:
    jax = enable_x64()
    return isinstance(x, jax.core.Tracer)


def run(
    params: JaxParams,
    time: Any,
    gamma: Any,
    *,
    state: ChannelState | None = None,
    seal: Any = 1.0,
    acceleration: bool = True,
    xi0: float = 0.0,
) -> ChannelHistory:
    """:func:`mudrft.constitutive.dynamics.run` as a compiled :func:`jax.lax.scan`.

    Differentiable with respect to ``params``, ``gamma`` and ``state``.

    Parameters
    ----------
    params : JaxParams
        Model constants (:func:`to_jax`).
    time : array_like, shape (n,)
        Strictly increasing times [s] (checked when concrete).
    gamma : array_like, shape (n,) or (n, ...)
        Dimensionless displacement at the samples [-].
    state : ChannelState, optional, keyword-only
        Initial state; default undisturbed mud with ``xi0`` and ``gamma[0]``.
    seal : array_like, keyword-only
        Sealing factor, scalar or shape (n, ...) [-].
    acceleration : bool, keyword-only
        Keep the acceleration term (decision D6).
    xi0 : float, keyword-only
        Initial structure when ``state`` is None [-].

    Returns
    -------
    ChannelHistory
        Same fields as the numpy version, as JAX arrays.

    Examples
    --------
    >>> import numpy as np, mudrft
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> h = run(to_jax(mudrft.paper_parameters(0.25)), t, 0.2 * t)
    >>> h.total.shape
    (11,)
    """
    jnp = _jnp()
    if not _is_tracer(time):
        time = check_increasing("time", time)
        if time.size < 2:
            raise MudrftError(f"time must have at least 2 samples, got {time.size}")
    if not _is_tracer(gamma):
        g_np = check_finite("gamma", gamma)
        if g_np.shape[:1] != np.shape(time):
            raise MudrftError(
                f"gamma must have the same length as time along its first axis, got gamma shape "
                f"{g_np.shape} and time shape {np.shape(time)}"
            )
    if not _is_tracer(xi0):
        check_in_range("xi0", xi0, 0.0, 1.0)
    t = jnp.asarray(time, dtype=float)
    g = jnp.asarray(gamma, dtype=float)
    if state is None:
        z = jnp.zeros(g.shape[1:])
        state = ChannelState(gamma=g[0] + z, gamma_w=g[0] + z, xi=z + xi0, s_th=z, sigma_s=z)
    sl = jnp.broadcast_to(jnp.asarray(seal, dtype=float), g.shape)
    total, el, th, su, xi = _compiled()["run"](params, t, g, state, sl, acceleration)
    return ChannelHistory(
        time=t, gamma=g, total=total, elastic=el, thixotropic=th, suction=su, xi=xi
    )


# ---------------------------------------------------------------------------------------
# surface integration and the terrain step
# ---------------------------------------------------------------------------------------
def mesh_force(
    vertices: Any,
    faces: Any,
    depth: Any,
    stress: Any,
    heading: Any,
    *,
    trailing: bool = False,
) -> Any:
    """Force of the mud on a triangulated foot, in JAX (differentiable in ``vertices``).

    Calls :func:`mudrft.feet.surface.integrate_triangles` with ``xp=jax.numpy`` on the
    triangles ``vertices[faces]``.

    Parameters
    ----------
    vertices : array_like, shape (v, 3)
        Vertices in the foot frame, tip (lowest point) at the origin [m].
    faces : array_like of int, shape (m, 3)
        Triangles, counter-clockwise seen from outside.
    depth : float or array
        Tip depth [m].
    stress : array_like, shape (..., 3)
        Channel stresses (sx, sy, sz) [Pa].
    heading : float or array
        Horizontal heading of the motion [rad].
    trailing : bool, keyword-only
        Passed on to ``integrate_triangles`` (load trailing faces too).

    Returns
    -------
    array, shape (..., 3)
        Force in the world frame [N].
    """
    jnp = _jnp()
    return _compiled()["mesh_force"](
        jnp.asarray(vertices, dtype=float), jnp.asarray(faces), depth, stress, heading, trailing
    )


class _SafeNamespace:
    """``jax.numpy`` with a square root whose derivative at 0 is 0 instead of infinite.

    The surface rule takes square roots of sums of squares (facet area, horizontal part of a
    normal) that are exactly 0 for horizontal facets; ``jnp.sqrt`` has an infinite derivative
    there, and 0 x inf poisons every gradient with NaN even when the facet carries no load.
    The value is unchanged; the derivative at 0 becomes 0, a valid one-sided choice for the
    norms involved (decision D74). Likewise ``arccos`` (the curved feet's
    :math:`\theta_c=\\cos^{-1}(1-z/R)`) gets a zero derivative at +-1, where it is infinite:
    at the surface (z = 0) and at the rim.
    """

    def __init__(self, jnp: Any) -> None:
        self._jnp = jnp

    def __getattr__(self, name: str) -> Any:
        return getattr(self._jnp, name)

    def sqrt(self, x: Any) -> Any:
        jnp = self._jnp
        pos = x > 0
        return jnp.where(pos, jnp.sqrt(jnp.where(pos, x, 1.0)), 0.0)

    def arccos(self, x: Any) -> Any:
        import jax

        jnp = self._jnp
        inside = jnp.abs(x) < 1.0
        edge = jax.lax.stop_gradient(jnp.arccos(jnp.clip(x, -1.0, 1.0)))
        return jnp.where(inside, jnp.arccos(jnp.where(inside, x, 0.0)), edge)


@functools.cache
def safe_namespace() -> Any:
    """The array namespace the JAX backend gives the feet's rules (see ``_SafeNamespace``)."""
    return _SafeNamespace(_jnp())


#: State of :func:`terrain_step`: the mud under the feet (a JAX pytree).
TerrainState = MudChannels


def initial_terrain_state(
    position: Any, characteristic_length: Any, *, xi0: float = 0.0
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
    position: Any,
    velocity: Any,
    dt: Any,
    *,
    force_fn: Callable[[Any, Any, Any], Any],
    characteristic_length: Any,
    acceleration: bool = True,
    reset_on_exit: bool = True,
    xi0: float = 0.0,
    heading_speed: float = 1e-6,
) -> tuple[MudChannels, tuple[Any, Any, Any]]:
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
    acceleration, reset_on_exit, xi0, heading_speed : keyword-only
        As :class:`mudrft.MudTerrain`.

    Returns
    -------
    state : MudChannels
    (force, stress, depth) : tuple of arrays
        Force [N] (..., 3), channel stresses [Pa] (..., 3), depth [m] (...).
    """
    jax = enable_x64()
    jnp = _jnp()
    pos = jnp.asarray(position, dtype=float)
    vel = jnp.asarray(velocity, dtype=float)
    hor = channel_constants(jax.tree_util.tree_map(lambda a: a[..., 0], params))
    ver = channel_constants(jax.tree_util.tree_map(lambda a: a[..., 2], params))
    ch, sx, sy, sz, depth = mud_step(
        (hor, ver), state, pos[..., 0], pos[..., 1], pos[..., 2], vel[..., 0], vel[..., 1],
        vel[..., 2], dt, characteristic_length, 1.0 if acceleration else 0.0, xi0,
        reset_on_exit, heading_speed, 1.0, xp=jnp,
    )  # fmt: skip
    stress = jnp.stack([sx, sy, sz], axis=-1)
    force = force_fn(depth, stress, ch.heading) * ch.in_mud[..., None]
    return ch, (force, stress, depth)


def simulate(
    params: JaxParams,
    time: Any,
    position: Any,
    velocity: Any,
    *,
    force_fn: Callable[[Any, Any, Any], Any],
    characteristic_length: Any,
    acceleration: bool = True,
    reset_on_exit: bool = True,
    xi0: float = 0.0,
    heading_speed: float = 1e-6,
) -> tuple[Any, Any, Any]:
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

    def body(st: MudChannels, inp: tuple[Any, ...]) -> tuple[MudChannels, tuple[Any, Any, Any]]:
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
        )

    _, (f, s, d) = jax.lax.scan(body, st0, (pos[1:], vel[1:], t[1:] - t[:-1]))
    zf = jnp.zeros((1, *f.shape[1:]))
    return (
        jnp.concatenate([zf, f]),
        jnp.concatenate([zf, s]),
        jnp.concatenate([jnp.maximum(-pos[:1, ..., 2], 0.0), d]),
    )
