r""":class:`BatchedMud` advances N feet of one shape, each with its own mud, state and motion.

Backends: ``"numpy"`` (any foot), ``"numba"`` (compiled, multi-threaded from
:data:`~mudrft.backends.numba.PARALLEL_MIN` feet on), ``"jax"`` (closed-form and mesh feet,
under :func:`jax.jit`). ``snapshot()`` and ``restore()`` give bit-identical continuations.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple, Self

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._typing import FloatOrArray
from .._validation import MudrftError, check_choice, check_finite, check_memory, positive_number
from ..feet.base import Foot
from ..parameters.base import Mud, MudParameters
from ..terrains import MudTerrain, channel_parameters
from ..terrains.mud import MudChannels, MudState

if TYPE_CHECKING:
    from jax import Array

__all__ = ["BACKENDS", "BatchedMud", "Snapshot", "batched_channel_parameters", "batched_mud"]

#: Backends of :class:`BatchedMud`.
BACKENDS = ("numpy", "numba", "jax")
#: Memory a foot of a batch needs at most [bytes] (state, outputs, numpy temporaries).
BYTES_PER_FOOT = 2048


class Snapshot(NamedTuple):
    """A :class:`BatchedMud` after a step: ``state`` (read-only (N,) arrays, also a
    :class:`~mudrft.terrains.mud.MudState`), ``force`` [N], ``stress`` [Pa] (N, 3), ``depth``
    [m] (N,)."""

    state: MudState
    force: NDArray[np.float64]
    stress: NDArray[np.float64]
    depth: FloatOrArray


def _map_leaves(fn: Any, tree: Any) -> Any:
    """``fn`` applied to every leaf of nested named tuples."""
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return type(tree)(*(_map_leaves(fn, v) for v in tree))
    return fn(tree)


def _leaves(tree: Any) -> list[Any]:  # the leaves of nested named tuples
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return [leaf for v in tree for leaf in _leaves(v)]
    return [tree]


def _frozen(value: Any) -> Any:
    """A read-only float copy of an array (a Python float stays as it is)."""
    if isinstance(value, float):
        return value
    out = np.array(value, dtype=float)
    out.setflags(write=False)
    return out


def _copy_foot_state(foot_state: Any) -> Any:
    if isinstance(foot_state, tuple) and hasattr(foot_state, "_fields"):
        return _map_leaves(_frozen, foot_state)
    return copy.deepcopy(foot_state)


def _check_snapshot(snapshot: object, batch: tuple[int, ...]) -> MudChannels:
    """The channels of ``snapshot`` for feet of shape ``batch`` (one foot's broadcast)."""
    if not isinstance(snapshot, Snapshot) or not isinstance(snapshot.state, MudState):
        raise MudrftError(
            f"snapshot must be what BatchedMud.snapshot() returned, got {type(snapshot).__name__}"
        )
    ch = snapshot.state.channels
    shapes = {np.shape(leaf) for leaf in _leaves(ch)}
    if len(shapes) == 1 and shapes < {(), (1,)}:
        (one,) = shapes
        ch = _map_leaves(lambda v: np.broadcast_to(v, batch), ch)
    else:
        one = batch
    outputs = {np.shape(snapshot.force), np.shape(snapshot.stress)}
    if shapes != {one} or outputs != {(*one, 3)} or np.shape(snapshot.depth) != one:
        raise MudrftError(
            f"snapshot must hold the mud under BatchedMud's feet (state arrays of shape {batch}"
            f", or () for one foot), "
            f"got state arrays of shape(s) {sorted(shapes)}: a snapshot of another stepper?"
        )
    return ch


def batched_channel_parameters(mud: Mud | Sequence[Mud], n: int) -> MudParameters:
    """Channel parameters (x, y, z) of one Mud or ``n`` muds for ``n`` feet: (3,) or (n, 3).

    >>> import mudrft
    >>> muds = [mudrft.paper_mud(w) for w in (0.25, 0.3, 0.35)]
    >>> batched_channel_parameters(muds, 3).alpha.shape
    (3, 3)
    """
    return channel_parameters(batched_mud(mud, n))


def batched_mud(mud: Mud | Sequence[Mud], n: int) -> Mud:
    """One Mud for ``n`` feet from one Mud or ``n`` muds: fields scalars (shared) or arrays
    of shape (n,) (one set per foot)."""
    if isinstance(mud, Mud):
        out = mud
    elif (
        isinstance(mud, Sequence)
        and not isinstance(mud, str)
        and all(isinstance(m, Mud) for m in mud)
    ):
        if len(mud) != n:
            raise MudrftError(
                f"mud must be one Mud or a list of n = {n} muds, got a list of {len(mud)}"
            )
        vert = MudParameters.stack([m.vertical for m in mud])
        hor = MudParameters.stack([m.horizontal for m in mud])
        out = Mud(vert, hor, name=f"{n} muds")
    else:
        raise MudrftError(
            f"mud must be a Mud (mudrft.paper_mud) or a list of Mud, got {type(mud).__name__}"
        )
    shapes = {out.vertical.shape, out.horizontal.shape}
    if not shapes <= {(), (n,)}:
        raise MudrftError(
            f"mud parameters must be scalars or arrays of shape ({n},) for n = {n} feet, got "
            f"fields of shape {sorted(shapes)}"
        )
    return out


class BatchedMud:
    """N feet of one shape in mud, advanced together; ``force`` [N], ``stress`` [Pa] (N, 3)
    and ``depth`` [m] (N,) hold the last step's outputs.

    Parameters
    ----------
    mud : Mud, sequence of Mud, or MudTerrain
        One shared Mud, a Mud with fields of shape (N,), N muds, or a
        :class:`mudrft.MudTerrain` (its mud and options).
    foot : Foot
        The foot shape shared by the batch.
    n : int
        Number of feet N.
    position : array_like, shape (N, 3) or (3,), keyword-only
        Initial tip positions [m]; default (0, 0, 0).
    backend : {"numpy", "numba", "jax"}, keyword-only
        Kernel (see the module docstring).
    **options
        Options of :class:`mudrft.MudTerrain` (``characteristic_length`` [m], ...).

    Examples
    --------
    >>> import numpy as np, mudrft
    >>> sim = BatchedMud(mudrft.paper_mud(0.25), mudrft.feet.Flat(), 4)
    >>> pos = np.zeros((4, 3)); vel = np.zeros((4, 3)); vel[:, 2] = -0.02
    >>> for k in range(1, 6):
    ...     pos[:, 2] = -0.02 * k * 1e-3
    ...     f = sim.step(pos, vel, 1e-3)
    >>> f.shape, bool(np.all(f[:, 2] > 0))
    ((4, 3), True)
    """

    def __init__(
        self, mud: Mud | MudTerrain | Sequence[Mud], foot: Foot, n: int, *,
        position: ArrayLike | None = None, backend: str = "numpy", **options: Any,
    ) -> None:  # fmt: skip
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
            raise MudrftError(f"n must be an integer >= 1 (number of feet), got {n!r}")
        check_memory(
            f"a batch of n = {n} feet", BYTES_PER_FOOT * float(n), hint="step fewer feet at once"
        )
        if not isinstance(foot, Foot):
            raise MudrftError(
                f"foot must be a mudrft foot (mudrft.feet.Flat(), ...), got {type(foot).__name__}"
            )
        self.backend = check_choice("backend", backend, BACKENDS)
        self._args = (mud, foot, int(n), self.backend, options)  # to unpickle
        self.n, self.foot = int(n), foot
        if not isinstance(mud, MudTerrain | Mud):
            mud = batched_mud(mud, self.n)
        known = [f.name for f in dataclasses.fields(MudTerrain) if f.name != "mud"]
        unknown = sorted(set(options) - set(known))
        if unknown:
            raise MudrftError(f"unknown mud option(s) {unknown}; the options are {known}")
        if isinstance(mud, MudTerrain):
            if options:
                raise MudrftError(
                    f"{sorted(options)} cannot be set here: mud is a MudTerrain, which carries "
                    "its own options; set them there (MudTerrain(mud, ...)) or pass the Mud"
                )
            base = mud
        else:
            base = MudTerrain(mud, **options)
        self.terrain = dataclasses.replace(base, mud=batched_mud(base.mud, self.n))
        self.params = channel_parameters(self.terrain.mud)
        self._one: MudTerrain | None = None  # one foot on numpy: the step on Python floats
        if self.backend == "numpy" and self.n == 1:
            given = self._args[0]
            one = given[0] if isinstance(given, Sequence) and len(given) == 1 else base.mud
            if isinstance(one, Mud) and one.vertical.shape == one.horizontal.shape == ():
                self._one = dataclasses.replace(base, mud=one)
        self.characteristic_length = self.terrain.length(foot)
        self._setup_backend()
        self.reset(np.zeros(3) if position is None else position)

    def _setup_backend(self) -> None:
        if self.backend == "numba":
            from ..terrains import rows
            from .numba import feet_loop

            if not rows.compilable(self.foot):
                raise MudrftError(
                    f"backend 'numba' runs the feet of mudrft.feet, got {type(self.foot).__name__};"
                    " use backend='numpy'"
                )
            t = self.terrain
            self._geom, self._up, self._mrow, self._fst0 = rows.foot_rows(self.foot)
            self._cfg = rows.config_row(t, self.foot)
            self._c = rows.constant_row(*t.constants).reshape(-1, rows.N_CONST)
            self._nb_step = feet_loop(self.n)
        elif self.backend == "jax":
            from . import jax as mjax
            from .forces import force_function

            fn = force_function(self.foot, xp=mjax.safe_namespace())
            if fn is None:
                raise MudrftError(
                    f"backend 'jax' supports the flat, semi-cylinder, semi-sphere and mesh feet, "
                    f"got {type(self.foot).__name__}; use backend='numpy'"
                )
            jax = mjax.enable_x64()
            from jax.flatten_util import ravel_pytree

            jp, t, lc = mjax.to_jax(self.params), self.terrain, self.characteristic_length
            names = ("acceleration", "thixotropy", "clock", "reset_on_exit", "xi0", "heading_speed")
            opts = {k: getattr(t, k) for k in names}
            # the state crosses the jit boundary as one flat array (dispatch costs per leaf)
            unravel = ravel_pytree(t.initial_state(self.foot, np.zeros((self.n, 3))).channels)[1]

            def one(
                flat: Array, pos: Array, vel: Array, dt: float
            ) -> tuple[Array, tuple[Array, Array, Array]]:
                st, out = mjax.terrain_step(
                    jp, unravel(flat), pos, vel, dt, force_fn=fn, characteristic_length=lc, **opts
                )
                return ravel_pytree(st)[0], out

            self._jax_step = jax.jit(one)
            self._jax_ravel = lambda st: ravel_pytree(st)[0]
            self._jax_unravel = unravel

    def _inputs(self, name: str, value: ArrayLike) -> NDArray[np.float64]:
        if (  # the usual case, checked in a few microseconds (per-step coupling)
            type(value) is np.ndarray
            and value.dtype == np.float64
            and value.shape in ((self.n, 3), (3,))
            and np.isfinite(value).all()
        ):
            if value.ndim == 2:
                return value
            return value.reshape(1, 3) if self.n == 1 else np.broadcast_to(value, (self.n, 3))
        a = check_finite(name, value)
        if a.shape == (3,):
            a = np.broadcast_to(a, (self.n, 3))
        if a.shape != (self.n, 3):
            raise MudrftError(f"{name} must have shape ({self.n}, 3) or (3,), got shape {a.shape}")
        return a

    def reset(self, position: ArrayLike) -> None:
        """Put every foot above undisturbed mud with its tip at ``position`` (N, 3) or (3,) [m]."""
        pos = np.array(self._inputs("position", position))
        n = self.n
        self.force, self.stress = np.zeros((n, 3)), np.zeros((n, 3))
        self.depth = np.maximum(-pos[:, 2], 0.0)
        if self._one is not None:
            self._state = self._one.initial_state(self.foot, pos[0])
            return
        self._state = self.terrain.initial_state(self.foot, pos)
        if self.backend == "jax":
            self._jst = self._jax_ravel(self._state.channels)
        elif self.backend == "numba":
            from ..terrains.rows import N_OUT, state_rows

            self._st = state_rows(self._state.channels)
            self._fst = np.tile(self._fst0, (n, 1))
            self._out = np.zeros((1, n, N_OUT))

    def step(self, position: ArrayLike, velocity: ArrayLike, dt: float) -> NDArray[np.float64]:
        """Advance every foot by ``dt`` [s] to ``position`` [m] at ``velocity`` [m/s] ((N, 3) or
        (3,)); return the forces of the mud on them (N, 3) [N], also in :attr:`force`."""
        pos, vel = self._inputs("position", position), self._inputs("velocity", velocity)
        if not (type(dt) is float and 0.0 < dt < math.inf):
            dt = positive_number("dt", dt, unit="s")
        if self.backend == "numba":
            self._nb_step(
                self._c, self._st, self._fst, np.ascontiguousarray(pos)[None],
                np.ascontiguousarray(vel)[None], np.array([dt]), self._cfg, self._geom,
                self._up, self._mrow, self._out,
            )  # fmt: skip
            o = self._out[0]
            self.force, self.stress, self.depth = o[:, 0:3].copy(), o[:, 3:6].copy(), o[:, 6].copy()
        elif self.backend == "jax":
            self._jst, (f, s, d) = self._jax_step(self._jst, pos, vel, dt)
            self.force, self.stress, self.depth = np.asarray(f), np.asarray(s), np.asarray(d)
        else:  # numpy: the batch's arrays, or one foot on Python floats (_one)
            terrain, p, v = self.terrain, pos, vel
            if self._one is not None:
                terrain, p, v = self._one, pos[0], vel[0]
            self._state, out = terrain.step_unchecked(self.foot, self._state, p, v, dt)
            self.force = np.asarray(out.force, dtype=float).reshape(self.n, 3)
            self.stress = np.asarray(out.stress, dtype=float).reshape(self.n, 3)
            self.depth = np.asarray(out.depth, dtype=float).reshape(self.n)
        if not np.all(np.isfinite(self.force)):
            raise MudrftError(
                "the batched step produced non-finite forces; check the parameters and dt"
            )
        return self.force

    def snapshot(self) -> Snapshot:
        """Every foot's state after the last step, a read-only copy to :meth:`restore` later."""
        foot_state = None
        if self.backend == "numba":
            from ..feet.morphing.equilibrium import MorphingState
            from ..terrains.rows import MORPHING, channels_of_rows

            ch, f = channels_of_rows(self._st), self._fst
            if self._geom[0] == MORPHING:
                foot_state = MorphingState(f[:, 0], f[:, 1], f[:, 2])
        elif self.backend == "jax":
            ch = self._jax_unravel(self._jst)
        else:
            ch, foot_state = self._state.channels, self._state.foot
        n = (self.n,)
        ch = _map_leaves(lambda v: _frozen(np.broadcast_to(np.asarray(v, dtype=float), n)), ch)
        state = MudState(channels=ch, foot=_copy_foot_state(foot_state))
        return Snapshot(state, _frozen(self.force), _frozen(self.stress), _frozen(self.depth))

    def restore(self, snapshot: Snapshot) -> None:
        """Put every foot back into the state of ``snapshot`` (of the same feet, any backend, or
        of one foot)."""
        n = (self.n,)
        ch = _check_snapshot(snapshot, n)
        foot_state = _copy_foot_state(snapshot.state.foot)
        if self.backend == "numba":
            from ..terrains.rows import N_OUT, state_rows

            self._st, self._out = state_rows(ch), np.zeros((1, self.n, N_OUT))
            self._fst = np.tile(self._fst0, (self.n, 1))
            if foot_state is not None:  # a MorphingState: deflection, pad_angle, most_spread
                for k, v in enumerate(foot_state):
                    self._fst[:, k] = np.broadcast_to(np.asarray(v, dtype=float), n)
        elif self.backend == "jax":
            self._jst = self._jax_ravel(ch)
        elif self._one is not None:
            self._state = MudState(channels=_map_leaves(lambda v: float(v[0]), ch), foot=foot_state)
        else:
            self._state = MudState(channels=ch, foot=foot_state)
        self.force = np.array(np.broadcast_to(snapshot.force, (*n, 3)), dtype=float)
        self.stress = np.array(np.broadcast_to(snapshot.stress, (*n, 3)), dtype=float)
        self.depth = np.array(np.broadcast_to(snapshot.depth, n), dtype=float)

    # copies and pickles own their state (a snapshot, restored) and share the rest
    def __copy__(self) -> Self:
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new.restore(self.snapshot())
        return new

    def __deepcopy__(self, memo: dict[int, Any]) -> Self:
        return self.__copy__()

    def __getstate__(self) -> dict[str, Any]:
        return {"args": self._args, "snapshot": self.snapshot()}

    def __setstate__(self, state: dict[str, Any]) -> None:
        mud, foot, n, backend, options = state["args"]
        self.__init__(mud, foot, n, backend=backend, **options)  # type: ignore[misc]
        self.restore(state["snapshot"])

    def __repr__(self) -> str:
        return f"BatchedMud(n={self.n}, foot={self.foot!r}, backend={self.backend!r})"
