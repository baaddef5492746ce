"""numba-compiled versions of the scalar kernels (optional extra ``numba``).

The kernels of :mod:`mudrft.backends.kernels` are plain Python functions on floats and
flat indexable containers. This module compiles the *same* functions with ``numba.njit``
(no second copy of the rules): each function is rebuilt with its global names bound to
the compiled versions of the kernels it calls, then jitted. The kernels index flat arrays
by offsets and never slice them, so the parallel loops create no array views (whose shared
reference counts would serialise the threads; decision D75). Compilation happens on the
first call of each kernel (about 4 s in all) and lasts for the process. (Inlining the inner
kernels, ``inline="always"``, gave no measurable speed-up for a five-fold compile time.)

:func:`compiled` returns a dict with

``fast_foot_step(c, w, pos, vel, dt) -> int``
    one foot (:func:`~mudrft.backends.kernels.fast_foot_step`; used by
    :class:`~mudrft.backends.fast.FastMudFoot`);
``batch_step(c, st, out, geom, cfg, pos, vel, dt)``
    N feet in a multi-threaded (``prange``) loop: ``c`` flat constants (one foot's
    ``N_FOOT_CONST`` for a shared mud, or N of them), ``st`` (N N_STATE,), ``out``
    (N N_OUT,), ``geom`` (3,), ``cfg`` (6,) (:data:`~mudrft.backends.kernels.CFG_NAMES`),
    ``pos``/``vel`` (N, 3);
``batch_step_serial(...)``
    the same on one thread (no thread start-up: faster for small batches);
``channel_step(c, co, st, o, gamma, gamma_dot, dt, seal, kappa) -> float``
    one channel;
``channel_batch(c, st, gamma, gamma_dot, dt, kappa, total)``
    M channels (``c`` N_CONST or M N_CONST flat, ``st`` (5 M,)), ``prange`` loop.
"""

from __future__ import annotations

import functools
import types
from typing import Any

from . import kernels

__all__ = ["PARALLEL_MIN", "available", "compiled"]

#: Batches at least this large use the multi-threaded loop (smaller ones: one thread).
PARALLEL_MIN = 4096

prange = range  # rebound to numba.prange when compiled
scalar_foot_step = kernels.scalar_foot_step
scalar_channel_step = kernels.scalar_channel_step
N_CONST = kernels.N_CONST
N_FOOT_CONST = kernels.N_FOOT_CONST
N_STATE = kernels.N_STATE
N_OUT = kernels.N_OUT


def available() -> bool:
    """Whether numba can be imported."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _batch_step(
    c: Any, st: Any, out: Any, geom: Any, cfg: Any, pos: Any, vel: Any, dt: float
) -> None:
    """N feet (compiled with a parallel loop; see module docstring)."""
    n = pos.shape[0]
    shared = c.shape[0] == N_FOOT_CONST
    kind = int(cfg[0])
    lc = cfg[1]
    kappa = cfg[2]
    xi0 = cfg[3]
    reset = cfg[4] != 0.0
    hs = cfg[5]
    for i in prange(n):
        co = 0 if shared else i * N_FOOT_CONST
        scalar_foot_step(
            c,
            co,
            st,
            i * N_STATE,
            kind,
            geom,
            pos[i, 0],
            pos[i, 1],
            pos[i, 2],
            vel[i, 0],
            vel[i, 1],
            vel[i, 2],
            dt,
            lc,
            kappa,
            xi0,
            reset,
            hs,
            out,
            i * N_OUT,
        )


def _channel_batch(
    c: Any, st: Any, gamma: Any, gamma_dot: Any, dt: float, kappa: float, total: Any
) -> None:
    """M independent channels (compiled with a parallel loop)."""
    m = gamma.shape[0]
    shared = c.shape[0] == N_CONST
    for i in prange(m):
        co = 0 if shared else i * N_CONST
        total[i] = scalar_channel_step(c, co, st, 5 * i, gamma[i], gamma_dot[i], dt, 1.0, kappa)


def _rebind(fn: Any, **deps: Any) -> Any:
    g = dict(fn.__globals__)
    g.update(deps)
    return types.FunctionType(fn.__code__, g, fn.__name__, fn.__defaults__, fn.__closure__)


@functools.cache
def compiled() -> dict[str, Any]:
    """Compile the kernels with numba (lazily, once per process) and return them by name.

    Raises
    ------
    ImportError
        If numba is not installed.
    """
    try:
        import numba
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the numba kernels need numba: pip install 'mudrft[numba]'") from exc
    inner = numba.njit(cache=False, error_model="numpy")
    sign = inner(kernels._sign)
    theta = inner(kernels._theta_c)
    channel_k = inner(_rebind(kernels.scalar_channel_step, _sign=sign))
    force_k = inner(_rebind(kernels.scalar_foot_force, _theta_c=theta, _sign=sign))
    foot_k = inner(
        _rebind(kernels.scalar_foot_step, scalar_channel_step=channel_k, scalar_foot_force=force_k)
    )
    njit = inner
    pjit = numba.njit(cache=False, error_model="numpy", parallel=True)
    return {
        "channel_step": njit(_rebind(kernels.scalar_channel_step, _sign=sign)),
        "fast_foot_step": njit(_rebind(kernels.fast_foot_step, scalar_foot_step=foot_k)),
        "batch_step": pjit(_rebind(_batch_step, scalar_foot_step=foot_k, prange=numba.prange)),
        "batch_step_serial": njit(_rebind(_batch_step, scalar_foot_step=foot_k, prange=range)),
        "channel_batch": pjit(
            _rebind(_channel_batch, scalar_channel_step=channel_k, prange=numba.prange)
        ),
    }
