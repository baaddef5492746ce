"""The points of a sweep and their chunks (one chunk = one task = one block of the store).

A grid has one dimension per swept parameter, cut into blocks of about
``points_per_task`` points; a sample (Latin hypercube or scrambled Sobol,
:mod:`scipy.stats.qmc`, seeded) has one dimension ``point``. The same spec gives the same
points and chunks on any machine.

>>> d = Design("grid", (Axis("a", "float", values=np.arange(5.0)),
...                     Axis("b", "float", values=np.arange(4.0))), points_per_task=3)
>>> d.chunks, d.n_chunks
((1, 2), 10)
>>> d.chunk_points(1)
[{'a': 0.0, 'b': 2.0}, {'a': 0.0, 'b': 3.0}]
"""

from __future__ import annotations

import inspect
import math
from dataclasses import dataclass
from functools import cached_property
from itertools import product
from typing import Any

import numpy as np

#: With ``points_per_task`` unset, a sweep is cut into about this many tasks of at most
#: ``MAX_POINTS_PER_TASK`` points (a few seconds of a closed-form foot's gaits).
AUTO_TASKS = 32
MAX_POINTS_PER_TASK = 64


@dataclass(frozen=True, eq=False)
class Axis:
    """A swept parameter ``name`` of ``kind`` ("float", "int", "str"): grid ``values``, or
    a range ``[low, high]`` [SI] a sample draws from (a grid range keeps it for the
    record), spaced or drawn uniformly in the logarithm with ``log``."""

    name: str
    kind: str
    values: np.ndarray | None = None
    low: float | None = None
    high: float | None = None
    log: bool = False

    def as_json(self) -> dict[str, Any]:
        """The axis as plain data."""
        out: dict[str, Any] = {"name": self.name, "kind": self.kind}
        if self.values is not None:
            out["values"] = self.values.tolist()
        if self.low is not None:
            out.update(low=self.low, high=self.high, log=self.log)
        return out

    def draw(self, u: np.ndarray) -> np.ndarray:
        """Map uniform numbers ``u`` in [0, 1) onto the range."""
        lo, hi = float(self.low), float(self.high)  # type: ignore[arg-type]
        if self.kind == "int":
            return np.minimum(np.floor(lo + u * (hi - lo + 1)), hi).astype(np.int64)
        if self.log:
            return np.exp(math.log(lo) + u * (math.log(hi) - math.log(lo)))
        return lo + u * (hi - lo)


def block(shape: tuple[int, ...], chunks: tuple[int, ...], i: int) -> tuple[slice, ...]:
    """The block of chunk ``i`` of an array of ``shape`` cut into ``chunks`` (C order)."""
    index = np.unravel_index(int(i), [math.ceil(s / c) for s, c in zip(shape, chunks, strict=True)])  # fmt: skip
    return tuple(slice(int(k) * c, min((int(k) + 1) * c, s)) for k, c, s in zip(index, chunks, shape, strict=True))  # fmt: skip


@dataclass(frozen=True, eq=False)
class Design:
    """Points and chunks of a sweep: a ``design`` ("grid", "lhs", "sobol") over ``axes``,
    ``n`` points from ``seed`` for a sample, about ``points_per_task`` points a chunk (0:
    ``ceil(points / AUTO_TASKS)`` clipped to [1, MAX_POINTS_PER_TASK])."""

    design: str
    axes: tuple[Axis, ...]
    n: int | None = None
    seed: int | None = None
    points_per_task: int = 0

    @property
    def dims(self) -> tuple[str, ...]:
        """Dimensions of the result: the swept parameters (grid) or ``("point",)``."""
        return tuple(a.name for a in self.axes) if self.design == "grid" else ("point",)

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the result."""
        if self.design == "grid":
            return tuple(len(a.values) for a in self.axes)  # type: ignore[arg-type]
        return (int(self.n),)  # type: ignore[arg-type]

    @property
    def n_points(self) -> int:
        """Number of points."""
        return math.prod(self.shape)

    @cached_property
    def sample(self) -> dict[str, np.ndarray]:
        """A sample design's points: the values of every swept parameter, shape (n,)."""
        if self.design == "grid":
            return {}
        from scipy.stats import qmc

        d, n = len(self.axes), int(self.n)  # type: ignore[arg-type]
        # scipy names the generator rng= from 1.15 and seed= before (mudrft supports 1.10)
        key = "rng" if "rng" in inspect.signature(qmc.LatinHypercube).parameters else "seed"
        gen = {key: np.random.default_rng(self.seed)}
        if self.design == "lhs":
            u = qmc.LatinHypercube(d, **gen).random(n)
        else:
            u = qmc.Sobol(d, scramble=True, **gen).random_base2(int(math.log2(n)))
        return {a.name: a.draw(u[:, i]) for i, a in enumerate(self.axes)}

    def coords(self) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Coordinates of the swept parameters: ``name -> (dims, values)``."""
        if self.design == "grid":
            return {a.name: ((a.name,), a.values) for a in self.axes}  # type: ignore[misc]
        return {name: (("point",), v) for name, v in self.sample.items()}

    @property
    def chunk_size(self) -> int:
        """Target points per chunk (and per task)."""
        if self.points_per_task:
            return int(self.points_per_task)
        return min(max(math.ceil(self.n_points / AUTO_TASKS), 1), MAX_POINTS_PER_TASK)

    @cached_property
    def chunks(self) -> tuple[int, ...]:
        """Chunk shape: blocks filled from the last dimension, balanced within each."""
        budget = self.chunk_size
        if self.design != "grid":
            return (min(budget, self.n_points),)
        out = [1] * len(self.shape)
        for d in reversed(range(len(self.shape))):
            size = self.shape[d]
            if budget <= 1:
                break
            blocks = math.ceil(size / budget)
            out[d] = math.ceil(size / blocks)
            budget //= out[d]
        return tuple(out)

    @property
    def n_chunks(self) -> int:
        """Number of chunks (tasks)."""
        return math.prod(math.ceil(s / c) for s, c in zip(self.shape, self.chunks, strict=True))

    def chunk_slices(self, i: int) -> tuple[slice, ...]:
        """The block of chunk ``i`` (C order over the chunk grid)."""
        return block(self.shape, self.chunks, i)

    def chunk_shape(self, i: int) -> tuple[int, ...]:
        """Shape of the block of chunk ``i``."""
        return tuple(s.stop - s.start for s in self.chunk_slices(i))

    def chunk_points(self, i: int) -> list[dict[str, Any]]:
        """The points of chunk ``i`` (C order within the block), as plain Python values."""
        sl = self.chunk_slices(i)
        if self.design == "grid":
            names = [a.name for a in self.axes]
            cols = [a.values[s].tolist() for a, s in zip(self.axes, sl, strict=True)]  # type: ignore[index]
            return [dict(zip(names, combo, strict=True)) for combo in product(*cols)]
        cols2 = {k: arr[sl[0]].tolist() for k, arr in self.sample.items()}
        return [dict(zip(cols2, row, strict=True)) for row in zip(*cols2.values(), strict=True)]
