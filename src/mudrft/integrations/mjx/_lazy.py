"""JAX and MJX, imported on first use: importing mudrft never needs the ``mjx`` extra."""

from __future__ import annotations

import contextlib
import functools
import io
import os
from collections.abc import Callable
from types import ModuleType
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import jax.stages

    from ...backends._jax_base import _SafeNamespace


@functools.cache
def _mjx() -> ModuleType:
    """Import ``mujoco.mjx`` lazily with a helpful message (and a quiet stdout)."""
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            from mujoco import mjx
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError(
            "the MJX coupling needs mujoco-mjx matching the installed mujoco: "
            "pip install 'mudrft[mjx]'"
        ) from exc
    return mjx


def _jax() -> ModuleType:
    try:
        import jax
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the MJX coupling needs jax: pip install 'mudrft[mjx]'") from exc
    return jax


def x64_context(x64: bool) -> contextlib.AbstractContextManager[None]:
    """A context in which JAX computes in float64 if ``x64``, else in float32."""
    jax = _jax()
    context: Any = getattr(jax, "enable_x64", None)
    if context is None:  # older JAX has it in jax.experimental only
        import jax.experimental

        context = jax.experimental.enable_x64
    return context(x64)


@functools.cache
def _xp() -> _SafeNamespace:
    """``jax.numpy`` with the JAX backend's gradient-safe square root and arccos, in the
    precision JAX is configured for (D81).
    """
    _jax()
    import jax.numpy as jnp

    from ...backends._jax_base import _SafeNamespace

    return _SafeNamespace(jnp)


#: XLA options for a quick compile on a CPU: LLVM's cheap pipeline. It halves the compile
#: time of the coupling's programs (tens of seconds for the biped) but makes batched steps
#: up to ten times slower, so it is opt-in: ``MUDRFT_FAST_COMPILE=1`` (the test suite sets
#: it; decision D81).
FAST_COMPILE_OPTIONS = {
    "xla_backend_optimization_level": 0,
    "xla_llvm_disable_expensive_passes": True,
}


def jit(fn: Callable[..., Any], **kw: Any) -> jax.stages.Wrapped:
    """:func:`jax.jit`, with :data:`FAST_COMPILE_OPTIONS` on a CPU when the environment
    variable ``MUDRFT_FAST_COMPILE`` is ``1``."""
    jax = _jax()
    fast = os.environ.get("MUDRFT_FAST_COMPILE", "") == "1"
    if fast and jax.default_backend() == "cpu" and "compiler_options" not in kw:
        kw["compiler_options"] = dict(FAST_COMPILE_OPTIONS)
    return jax.jit(fn, **kw)


def available() -> bool:
    """True when jax and ``mujoco.mjx`` import."""
    try:
        _mjx()
    except ImportError:
        return False
    return True
