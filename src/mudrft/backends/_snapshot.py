"""Snapshots of the stateful stepper :class:`~mudrft.backends.BatchedMud`, for a controller or planner.

A planner saves the mud where the robot is, rolls out candidate futures from it and goes
back: ``snap = sim.snapshot()``, ``sim.restore(snap)``. A snapshot is a copy made of
read-only arrays (or Python floats), so no later step, of this stepper or of another, can
change it, and one snapshot restores any number of times to a bit-identical continuation.
"""

from __future__ import annotations

import copy
from typing import Any, NamedTuple, Self, overload

import numpy as np
from numpy.typing import NDArray

from .._typing import FloatArray, FloatOrArray
from .._validation import MudrftError
from ..terrains.mud import MudChannels, MudState

__all__ = [
    "Restorable",
    "Snapshot",
    "check_snapshot",
    "copy_foot_state",
    "frozen",
    "map_leaves",
]


class Snapshot(NamedTuple):
    """The state of a stepper after a step, as ``snapshot()`` returns it.

    Attributes
    ----------
    state : MudState
        The mud under the feet (:class:`~mudrft.terrains.mud.MudChannels` of read-only
        arrays of shape (N,)) and the foot mechanism's state (None for the
        rigid feet). The same channels as :meth:`mudrft.MudTerrain.initial_state`, so the
        state also steps on in :meth:`mudrft.MudTerrain.step`.
    force : ndarray (3,) or (N, 3)
        Force of the mud on the foot (feet) at the last step [N].
    stress : ndarray (3,) or (N, 3)
        Channel stresses (sx, sy, sz) at the last step [Pa].
    depth : float or ndarray (N,)
        Tip depth after the last step [m].
    """

    state: MudState
    force: NDArray[np.float64]
    stress: NDArray[np.float64]
    depth: FloatOrArray


def map_leaves(fn: Any, tree: Any) -> Any:
    """``fn`` applied to every leaf of nested named tuples (the channels' state)."""
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return type(tree)(*(map_leaves(fn, v) for v in tree))
    return fn(tree)


@overload
def frozen(value: float) -> float: ...
@overload
def frozen(value: FloatArray) -> FloatArray: ...
def frozen(value: FloatOrArray) -> FloatOrArray:
    """A read-only float copy of an array (a Python float stays as it is)."""
    if isinstance(value, float):
        return value
    out = np.array(value, dtype=float)
    out.setflags(write=False)
    return out


class Restorable:
    """Copies and pickles of a stepper through its snapshot.

    ``copy.copy``, ``copy.deepcopy`` and ``pickle`` give a stepper that shares the foot,
    the terrain and any compiled step (a pickle makes the step again from the arguments)
    and owns its state: a copy of ``snapshot()``, restored. A subclass has ``snapshot``,
    ``restore`` and ``_init_args``, the positional and keyword arguments it was made with.
    """

    def snapshot(self) -> Snapshot:  # pragma: no cover - every subclass has its own
        raise NotImplementedError

    def restore(self, snapshot: Snapshot) -> None:  # pragma: no cover - as snapshot
        raise NotImplementedError

    def _init_args(self) -> tuple[tuple[Any, ...], dict[str, Any]]:  # pragma: no cover
        raise NotImplementedError

    def __copy__(self) -> Self:
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        new.restore(self.snapshot())
        return new

    def __deepcopy__(self, memo: dict[int, Any]) -> Self:
        return self.__copy__()

    def __getstate__(self) -> dict[str, Any]:
        return {"args": self._init_args(), "snapshot": self.snapshot()}

    def __setstate__(self, state: dict[str, Any]) -> None:
        args, kwargs = state["args"]
        self.__init__(*args, **kwargs)  # type: ignore[misc]
        self.restore(state["snapshot"])


def check_snapshot(
    snapshot: object, batch: tuple[int, ...], owner: str, *, one_for_all: bool = False
) -> MudChannels:
    """The channels of ``snapshot`` after checking it is a :class:`Snapshot` whose channels
    have the shape ``batch`` of the stepper ``owner`` restores it into; ``one_for_all``
    takes the snapshot of one foot (shape () or (1,)) for every foot of the batch."""
    if not isinstance(snapshot, Snapshot) or not isinstance(snapshot.state, MudState):
        raise MudrftError(
            f"snapshot must be what {owner}.snapshot() returned, got {type(snapshot).__name__}"
        )
    ch = snapshot.state.channels
    shapes = {np.shape(leaf) for leaf in _leaves(ch)}
    if one_for_all and len(shapes) == 1 and shapes < {(), (1,)}:
        (one,) = shapes
        ch = map_leaves(lambda v: np.broadcast_to(v, batch), ch)
    else:
        one = batch
    outputs = {np.shape(snapshot.force), np.shape(snapshot.stress)}
    if shapes != {one} or outputs != {(*one, 3)} or np.shape(snapshot.depth) != one:
        raise MudrftError(
            f"snapshot must hold the mud under {owner}'s feet (state arrays of shape {batch}"
            f"{', or () for one foot' if one_for_all else ''}), "
            f"got state arrays of shape(s) {sorted(shapes)}: a snapshot of another stepper?"
        )
    return ch


def copy_foot_state(foot_state: Any) -> Any:
    """An independent copy of a foot mechanism's state (None for rigid feet)."""
    if foot_state is None:
        return None
    if isinstance(foot_state, tuple) and hasattr(foot_state, "_fields"):
        return map_leaves(frozen, foot_state)
    return copy.deepcopy(foot_state)


def _leaves(tree: Any) -> list[Any]:
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return [leaf for v in tree for leaf in _leaves(v)]
    return [tree]
