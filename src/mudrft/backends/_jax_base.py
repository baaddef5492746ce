"""Foundation of the JAX backend (:mod:`mudrft.backends.jax`): float64, parameters as a
pytree, the safe namespace."""

from __future__ import annotations

import functools
from types import ModuleType
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .._typing import ArrayLike, XpArray
from .._validation import MudrftError
from ..constitutive.state import ChannelState
from ..constitutive.state import initial_state as np_initial
from ..parameters.base import PARAMETER_UNITS, Mud, MudParameters
from ..terrains import channel_parameters

if TYPE_CHECKING:
    from jax import Array

__all__ = [
    "JaxParams", "enable_x64", "from_jax", "initial_state", "is_tracer", "safe_namespace",
    "to_jax",
]  # fmt: skip


def enable_x64() -> ModuleType:
    """Import jax, switch it to 64-bit floats (decision D70) and return the module."""
    try:
        import jax
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the JAX backend needs jax: pip install 'mudrft[jax]'") from exc
    if not getattr(jax.config, "jax_enable_x64", False):
        jax.config.update("jax_enable_x64", True)
    return jax


def is_tracer(x: object) -> bool:
    """Whether ``x`` is a JAX tracer, whose values cannot be checked."""
    return isinstance(x, enable_x64().core.Tracer)


def _jnp() -> ModuleType:
    enable_x64()
    import jax.numpy as jnp

    return jnp


class JaxParams(NamedTuple):
    """Parameters of the mud model as a JAX pytree of float64 arrays (the names and units of
    MudParameters; for x, y, z channels a trailing axis of 3). ``k_a`` does not follow
    ``lam`` under differentiation: :meth:`with_default_k_a` ties it (decision D72)."""

    alpha: XpArray
    n: XpArray
    lam: XpArray
    eta_m: XpArray
    eta_inf: XpArray
    gamma_dot_c: XpArray
    tau_build: XpArray
    tau_leak: XpArray
    epsilon: XpArray
    sigma_y: XpArray
    nu: XpArray
    k_a: XpArray

    @property
    def k_r(self) -> XpArray:
        """Rejuvenation coefficient :math:`k_r=k_a/\\dot\\gamma_c` [-]."""
        return self.k_a / self.gamma_dot_c

    def with_default_k_a(self) -> JaxParams:
        """Copy with ``k_a = 1/lam`` (decision D8), traceable."""
        return self._replace(k_a=1.0 / self.lam)


def to_jax(params: MudParameters | Mud) -> JaxParams:
    """A parameter set, or a Mud's x, y, z channel sets (a trailing axis of 3), as a
    :class:`JaxParams` of float64 JAX arrays.

    >>> import mudrft
    >>> to_jax(mudrft.paper_mud(0.25)).alpha.shape
    (3,)
    """
    jnp = _jnp()
    if isinstance(params, Mud):
        params = channel_parameters(params)
    if not isinstance(params, MudParameters):
        raise MudrftError(f"params must be a MudParameters or a Mud, got {type(params).__name__}")
    return JaxParams(
        **{k: jnp.asarray(np.asarray(getattr(params, k), dtype=float)) for k in PARAMETER_UNITS}
    )


def check_params(params: object, *, channels: bool = False) -> None:
    """``params`` must be a :class:`JaxParams`; with ``channels``, ``to_jax(mud)`` (a
    trailing axis of 3). Reads the type and the static shape only."""
    if not isinstance(params, JaxParams):
        raise MudrftError(
            f"params must be a JaxParams (mudrft.backends.jax.to_jax(...)), got {type(params).__name__}"
        )
    if channels and _jnp().shape(params.alpha)[-1:] != (3,):
        raise MudrftError(
            "params must hold the mud's x, y, z channel sets (to_jax(mud), a trailing axis "
            f"of 3), got alpha of shape {_jnp().shape(params.alpha)}"
        )


def from_jax(params: JaxParams, **meta: Any) -> MudParameters:
    """Concrete :class:`JaxParams` back into a validated :class:`MudParameters`; ``meta``
    (``source``, ``water_content``, ``direction``) is passed on."""
    fields = {k: np.asarray(getattr(params, k), dtype=float) for k in PARAMETER_UNITS}
    return MudParameters(**fields, **meta)  # type: ignore[arg-type]  # 0-d fields: floats


def initial_state(
    shape: tuple[int, ...] = (), *, xi0: float = 0.0, gamma: ArrayLike = 0.0
) -> ChannelState:
    """Undisturbed channel state of batch ``shape`` as JAX arrays, with structure ``xi0``
    [-] and displacement ``gamma`` [-] (:func:`mudrft.constitutive.initial_state`)."""
    jnp = _jnp()
    return ChannelState(*(jnp.asarray(a) for a in np_initial(shape, xi0=xi0, gamma=gamma)))


class _SafeNamespace:
    """``jax.numpy`` whose ``sqrt`` has derivative 0 at 0 and ``arccos`` derivative 0 at
    +-1 instead of infinite, so that unloaded facets do not poison gradients with NaN
    (decision D74); values are unchanged."""

    def __init__(self, jnp: ModuleType) -> None:
        self._jnp = jnp

    def __getattr__(self, name: str) -> Any:  # any function of jax.numpy
        return getattr(self._jnp, name)

    def sqrt(self, x: Array | float) -> Array:
        jnp, pos = self._jnp, x > 0
        return jnp.where(pos, jnp.sqrt(jnp.where(pos, x, 1.0)), 0.0)

    def arccos(self, x: Array | float) -> Array:
        import jax

        jnp = self._jnp
        inside = jnp.abs(x) < 1.0
        edge = jax.lax.stop_gradient(jnp.arccos(jnp.clip(x, -1.0, 1.0)))
        return jnp.where(inside, jnp.arccos(jnp.where(inside, x, 0.0)), edge)


@functools.cache
def safe_namespace() -> _SafeNamespace:
    """The array namespace the JAX backend gives the feet's rules (``jax.numpy``, safe
    ``sqrt`` and ``arccos`` derivatives)."""
    return _SafeNamespace(_jnp())
