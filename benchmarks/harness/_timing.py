"""Timing helpers shared by the benchmark modules: best-of-repeats timer, JAX sync."""

from __future__ import annotations

import importlib.util
import time
from collections.abc import Callable
from typing import Any

__all__ = ["CLOCK", "Progress", "best", "block", "have", "say", "timed"]

#: ``progress(message)``, or None for silence.
Progress = Callable[[str], None] | None

#: The clock of :func:`best` [s]: wall time. ``benchmarks/before_after.py --clock thread``
#: sets :func:`time.thread_time` (CPU time of the calling thread: robust to other load on a
#: shared machine, but blind to work done on other threads, numba prange and XLA).
CLOCK: Callable[[], float] = time.perf_counter


def best(
    fn: Callable[[], Any],
    *,
    budget: float,
    repeat: int = 5,
    sync: Callable[[Any], Any] | None = None,
) -> float:
    """Best time per call [s]: ``repeat`` rounds of about ``budget / repeat`` s after a warm-up.

    Times are read from :data:`CLOCK` (wall time unless a script changed it).

    Parameters
    ----------
    fn : callable
        The work, called without arguments.
    budget : float, keyword-only
        Total time to spend on the timed rounds [s] (at least one call per round).
    repeat : int, keyword-only
        Rounds; the fastest is kept (robust to other load on the machine).
    sync : callable, keyword-only
        Called on the last result of a round before the clock stops (JAX: block until the
        device is done).
    """
    clock = CLOCK
    out = fn()
    if sync is not None:
        sync(out)
    t0 = time.perf_counter()
    out = fn()
    if sync is not None:
        sync(out)
    one = max(time.perf_counter() - t0, 1e-8)
    number = max(1, int(budget / repeat / one))
    fastest = float("inf")
    for _ in range(repeat):
        t0 = clock()
        for _ in range(number):
            out = fn()
        if sync is not None:
            sync(out)
        fastest = min(fastest, (clock() - t0) / number)
    return fastest


def timed(fn: Callable[[], Any]) -> float:
    """Wall time of one call [s]."""
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def block(x: Any) -> Any:
    """Wait for JAX arrays in ``x`` to be computed."""
    import jax

    return jax.block_until_ready(x)


def have(module: str) -> bool:
    """Whether an optional module (numba, jax, mujoco) can be imported."""
    return importlib.util.find_spec(module) is not None


def say(progress: Progress, message: str) -> None:
    """Report a finished stage when a progress callback was given."""
    if progress is not None:
        progress(message)
