r"""numba backend: the one physics compiled on floats (optional extra ``numba``).

The model's equations are written once as element-wise functions of an array namespace
``xp`` (:mod:`mudrft._xp`). numba cannot take a module as an argument, so
:func:`compile_scalar` compiles the rewrite of :func:`mudrft._specialize.specialize`: the
function's own source without its ``xp`` keyword (and the ``xp=`` of the calls it makes),
``xp`` bound to a namespace of compiled scalar functions, every mudrft function it calls
compiled the same way, and the result compiled with :func:`numba.njit`. The Python-float
path runs the same rewrite uncompiled (:func:`mudrft._specialize.on_floats`). Source lines,
names and line numbers are the original ones; nothing is copied by hand (decision D80).

On top, two drivers hold state in flat float arrays so that a call from Python costs
about a microsecond: :func:`compiled_feet` steps N closed-form feet (a ``prange`` loop for
large N) and serves :class:`~mudrft.backends.batch.BatchedMud` and
:class:`~mudrft.backends.fast.FastMudFoot`.

Layout of a foot's state row (``N_STATE`` floats): the x, y, z channels (7 each:
gamma, gamma_w, xi, s_th, sigma_s, clock, clock_w), entry x, entry y, heading, in_mud. Output row
(``N_OUT``): force (3) [N], stress (3) [Pa], depth [m]. A constants row (``N_CONST``):
the horizontal then the vertical :class:`~mudrft.constitutive.kernel.ChannelConstants`.
"""

from __future__ import annotations

import functools
import math
import types
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._specialize import specialize
from .._xp import SCALAR_HELPERS
from ..constitutive.kernel import ChannelConstants
from ..constitutive.state import ChannelState
from ..feet.closed_form import closed_form_force
from ..terrains.mud import MudChannels, mud_step

if TYPE_CHECKING:
    from ..feet.base import Foot
    from ..terrains.mud import MudTerrain

__all__ = [
    "N_CHANNEL",
    "N_CONST",
    "N_OUT",
    "N_STATE",
    "PARALLEL_MIN",
    "STATE_IN_MUD",
    "available",
    "channels_of_rows",
    "compile_scalar",
    "compiled_feet",
    "config_row",
    "constant_row",
    "state_rows",
]

#: Batches at least this large use the multi-threaded loop (smaller ones: one thread).
PARALLEL_MIN = 4096
#: Floats in a channel's state (the fields of ChannelState).
N_CHANNEL = len(ChannelState._fields)
#: Floats in a foot's state row, output row and constants row.
N_STATE = 3 * N_CHANNEL + 4
#: Index of ``in_mud`` in a foot's state row (its last float).
STATE_IN_MUD = N_STATE - 1
N_OUT = 7
N_CONST = 2 * len(ChannelConstants._fields)


def available() -> bool:
    """Whether numba can be imported."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _numba() -> types.ModuleType:
    try:
        import numba
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the numba backend needs numba: pip install 'mudrft[numba]'") from exc
    return numba


@functools.cache
def scalar_namespace() -> types.ModuleType:
    """The element-wise namespace of :mod:`mudrft._xp` as compiled scalar functions."""
    numba = _numba()
    jit = numba.njit(inline="always")
    ns = types.ModuleType("mudrft_scalar_xp")
    for name, g in SCALAR_HELPERS.items():
        setattr(ns, name, jit(g))
    ns.abs = abs  # type: ignore[attr-defined]
    funcs: tuple[tuple[str, Callable[..., float]], ...] = (
        ("exp", math.exp), ("expm1", math.expm1), ("tanh", math.tanh), ("cos", math.cos),
        ("sin", math.sin), ("arccos", math.acos), ("arctan2", math.atan2),
        ("hypot", math.hypot), ("sqrt", math.sqrt),
    )  # fmt: skip
    for name, f in funcs:
        setattr(ns, name, f)
    return ns


def compile_scalar(fn: Callable[..., Any], *, inline: bool = False) -> Any:
    """Compile an element-wise mudrft function on floats with numba (see module docstring).

    Parameters
    ----------
    fn : function
        A function of the physics whose namespace is a keyword-only ``xp`` argument.
    inline : bool, keyword-only
        Have numba inline ``fn``, if it calls other functions of the physics, and every such
        function it calls, into their compiled callers (``inline="always"``). Functions that
        call none are left to LLVM, which inlines small ones itself. Inlined, the closed-form
        foot step takes about 30 % less time (as calls, they pass and return named tuples of
        7 to 25 floats), but a caller that makes many calls compiles for longer. The loop
        over feet and the single-foot driver here use it; the MuJoCo coupling's kernel, which
        calls the terrain step five times, does not (inlined, it compiled 12-20 s longer for
        a mud step about 20 % faster).

    Returns
    -------
    numba dispatcher
        The same function without ``xp``, compiled lazily for the argument types.
    """
    return _compile_scalar(fn, bool(inline))


# ``fn: Any``: specialize reads its source and globals (a FunctionType, where mypy sees a
# def as a Callable); the result is a numba dispatcher
@functools.cache
def _compile_scalar(fn: Any, inline: bool) -> Any:
    calls: list[Callable[..., Any]] = []

    def callee(g: Callable[..., Any]) -> Any:
        calls.append(g)
        return _compile_scalar(g, inline)

    plain = specialize(fn, scalar_namespace(), callee, rewrite_where=False, positional=True)
    if inline and not calls:  # a leaf: the same dispatcher as without inlining
        return _compile_scalar(fn, False)
    return _numba().njit(error_model="numpy", inline="always" if inline else "never")(plain)


def constant_row(hor: ChannelConstants, ver: ChannelConstants) -> NDArray[np.float64]:
    """Horizontal and vertical constants as rows of ``N_CONST`` floats, shape batch + (N_CONST,)."""
    fields = [np.asarray(v, dtype=float) for v in (*hor, *ver)]
    return np.ascontiguousarray(np.stack(np.broadcast_arrays(*fields), axis=-1))


def config_row(terrain: MudTerrain, foot: Foot) -> NDArray[np.float64]:
    """The ``cfg`` row of :func:`compiled_feet` for a :class:`~mudrft.MudTerrain` and a foot."""
    return np.array(
        [
            terrain.length(foot),
            terrain.kappa,
            terrain.xi0,
            float(terrain.reset_on_exit),
            terrain.heading_speed,
            float(terrain.quasi_static),
            float(terrain.restart),
        ]
    )


def state_rows(ch: MudChannels) -> NDArray[np.float64]:
    """A :class:`~mudrft.terrains.mud.MudChannels` (floats or arrays (N,)) as rows (N, N_STATE)."""
    fields = [*ch.x, *ch.y, *ch.z, ch.entry_x, ch.entry_y, ch.heading, ch.in_mud]
    return np.ascontiguousarray(
        np.stack(np.broadcast_arrays(*map(np.asarray, fields)), -1)
    ).reshape(-1, N_STATE)


def channels_of_rows(rows: NDArray[np.float64]) -> MudChannels:
    """The inverse of :func:`state_rows`: floats from one row (N_STATE,), arrays (N,) from
    rows (N, N_STATE) (views of ``rows``)."""
    a = np.asarray(rows, dtype=float)
    return _channels(a.tolist() if a.ndim == 1 else a.T)


# names the compiled loop binds to numba's prange and to the compiled physics (the plain
# Python versions here make the loop runnable, slowly, without numba)
prange = range


def _one_foot(
    c: NDArray[np.float64], r: int, s: NDArray[np.float64], o: NDArray[np.float64], x: float,
    y: float, z: float, vx: float, vy: float, vz: float, dt: float, cfg: NDArray[np.float64],
    geom: NDArray[np.float64],
) -> None:  # fmt: skip
    """One closed-form foot: state row ``s`` and output row ``o`` updated in place."""
    lc, kappa, xi0, reset, hs = cfg[0], cfg[1], cfg[2], cfg[3] != 0.0, cfg[4]
    qs, restart = cfg[5] != 0.0, cfg[6] != 0.0
    ch = _channels(s)
    hor = _constants(c, r, 0)
    ver = _constants(c, r, 12)
    new, sx, sy, sz, depth = _step(
        (hor, ver), ch, x, y, z, vx, vy, vz, dt, lc, kappa, xi0, reset, hs, 1.0, qs, restart
    )
    fx, fy, fz = _force(int(geom[0]), geom[1], geom[2], geom[3], depth, sx, sy, sz, new.heading)
    k = 0
    for chan in (new.x, new.y, new.z):
        for v in chan:
            s[k] = v
            k += 1
    s[21], s[22], s[23], s[24] = new.entry_x, new.entry_y, new.heading, new.in_mud
    o[0], o[1], o[2] = fx * new.in_mud, fy * new.in_mud, fz * new.in_mud
    o[3], o[4], o[5], o[6] = sx, sy, sz, depth


def _feet_loop(
    c: NDArray[np.float64],
    st: NDArray[np.float64],
    out: NDArray[np.float64],
    pos: NDArray[np.float64],
    vel: NDArray[np.float64],
    dt: float,
    cfg: NDArray[np.float64],
    geom: NDArray[np.float64],
) -> None:
    """N closed-form feet (compiled; ``prange`` is bound to numba's or to ``range``)."""
    n = pos.shape[0]
    stride = 0 if c.shape[0] == 1 else 1  # one mud for all feet, or one per foot
    for i in prange(n):
        _foot(
            c, i * stride, st[i], out[i], pos[i, 0], pos[i, 1], pos[i, 2], vel[i, 0],
            vel[i, 1], vel[i, 2], dt, cfg, geom,
        )  # fmt: skip


def _fast_foot(
    c: NDArray[np.float64],
    w: NDArray[np.float64],
    x: float,
    y: float,
    z: float,
    vx: float,
    vy: float,
    vz: float,
    dt: float,
) -> int:
    """One foot with its checks: 0 done, 1 bad input (nothing changed), 2 non-finite force.

    ``w`` (3, N_STATE) holds the state row, the output row (first N_OUT) and the options row
    (``cfg``, 7 floats, then ``geom``, 4): three arrays fewer to pass than the loop's signature.
    """
    if not (dt > 0.0 and math.isfinite(dt) and math.isfinite(x + y + z + vx + vy + vz)):
        return 1
    o = w[1]
    row = c.shape[0] - 1  # the one row, 0, typed int64 as in the loop: a literal 0 would
    # compile the foot step a second time
    _foot(c, row, w[0], o, x, y, z, vx, vy, vz, dt, w[2, :7], w[2, 7:11])
    return 0 if math.isfinite(o[0] + o[1] + o[2]) else 2


def _constants(c: NDArray[np.float64], r: int, o: int) -> ChannelConstants:
    """One channel's constants from row ``r`` of ``c`` at offset ``o``."""
    x = c[r]
    return ChannelConstants(
        x[o], x[o + 1], x[o + 2], x[o + 3], x[o + 4], x[o + 5], x[o + 6], x[o + 7], x[o + 8],
        x[o + 9], x[o + 10], x[o + 11],
    )  # fmt: skip


def _channels(s: NDArray[np.float64] | Sequence[float]) -> MudChannels:
    """The mud under one foot from its state row ``s`` (``N_STATE`` floats, :func:`state_rows`)."""
    return MudChannels(
        ChannelState(s[0], s[1], s[2], s[3], s[4], s[5], s[6]),
        ChannelState(s[7], s[8], s[9], s[10], s[11], s[12], s[13]),
        ChannelState(s[14], s[15], s[16], s[17], s[18], s[19], s[20]),
        s[21], s[22], s[23], s[24],
    )  # fmt: skip


_step = mud_step
_force = closed_form_force
_foot = _one_foot


@functools.cache
def _compiled_one_foot() -> Any:
    """:func:`_one_foot` compiled once, with the physics inlined, for every driver: its
    compilation is most of theirs."""
    numba = _numba()
    env = dict(_one_foot.__globals__)
    env.update(
        _step=compile_scalar(mud_step, inline=True),
        _force=compile_scalar(closed_form_force, inline=True),
        _constants=numba.njit(inline="always")(_constants),
        _channels=numba.njit(inline="always")(_channels),
    )
    return numba.njit(error_model="numpy")(types.FunctionType(_one_foot.__code__, env, "_one_foot"))


# ``fn: Any``: a plain function whose code and globals are read, which mypy sees as a
# Callable (no ``__code__``), not as the FunctionType it is
def _compile_driver(fn: Any, **extra: Any) -> types.FunctionType:
    """A driver of this module with the compiled foot step bound to its globals."""
    env = dict(fn.__globals__)
    env.update(_foot=_compiled_one_foot(), **extra)
    return types.FunctionType(fn.__code__, env, fn.__name__)


@functools.cache
def compiled_feet(parallel: bool = False) -> Any:
    """The compiled loop over N closed-form feet (see :func:`_feet_loop`).

    Signature ``loop(c, st, out, pos, vel, dt, cfg, geom)``: ``c`` (1 or N, N_CONST),
    ``st`` (N, N_STATE) and ``out`` (N, N_OUT) updated in place, ``pos``/``vel`` (N, 3)
    [m], [m/s], ``dt`` [s], ``cfg = (L_c [m], kappa, xi0, reset 0/1, heading_speed [m/s],
    quasi_static 0/1, restart 0/1)`` (:func:`config_row`),
    ``geom = (kind, g0, g1, g2)`` of :func:`~mudrft.feet.closed_form.closed_form_coefficients`.
    """
    numba = _numba()
    loop = _compile_driver(_feet_loop, prange=numba.prange if parallel else range)
    return numba.njit(error_model="numpy", parallel=parallel)(loop)


@functools.cache
def compiled_fast_foot() -> Any:
    """One checked foot step, for :class:`~mudrft.backends.fast.FastMudFoot` (see
    :func:`_fast_foot`): ``fast(c, w, x, y, z, vx, vy, vz, dt) -> int`` with the work array
    ``w`` (3, N_STATE) updated in place."""
    numba = _numba()
    f64 = numba.float64
    rows = f64[:, ::1]
    # one signature, compiled now: ints given by a user convert to floats instead of
    # compiling another specialization (seconds)
    sig = numba.int64(rows, rows, f64, f64, f64, f64, f64, f64, f64)
    return numba.njit(sig, error_model="numpy")(_compile_driver(_fast_foot))
