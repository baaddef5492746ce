"""Run a sweep: chunks of points as tasks on Dask, results into the store as they finish.

The calling process (the *driver*) makes the store, submits one task per unfinished chunk
(:func:`~.evaluate.evaluate_chunk`, a plain function) to a ``dask.distributed`` client,
and writes each chunk's block when its task returns, so workers need no access to the
store and a real cluster needs no shared file system. At most a few tasks per worker are
in flight; the rest are submitted as others finish, so a sweep of 1e6 points holds only a
window of its points in memory. Without Dask (``scheduler="serial"``) the driver runs the
same chunks itself, in order.
"""

from __future__ import annotations

import logging
import math
import os
import shutil
import time
import warnings
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from types import ModuleType
from typing import TYPE_CHECKING, Any

from .._progress import Progress, make_progress
from .._validation import MudrftError
from .evaluate import ChunkResult, SweepContext, evaluate_chunk
from .spec import SweepSpec, load_spec

if TYPE_CHECKING:
    import distributed
    import numpy as np
    import xarray as xr
    import zarr
    from numpy.typing import NDArray

    from .store import StoreLike

__all__ = ["SweepWarning", "run_sweep"]

logger = logging.getLogger("mudrft.sweep")


class SweepWarning(UserWarning):
    """A warning raised at some points of a sweep (reported once per distinct message)."""


def _require(module: str) -> ModuleType:
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:
        extra = "mujoco" if module == "mujoco" else "sweep"
        raise MudrftError(
            f"mudrft.sweep needs the optional package {module}, which is not installed: "
            f"pip install 'mudrft[{extra}]'"
        ) from exc


#: What a script that runs a sweep on the local cluster needs (decision D116).
_MAIN_GUARD = (
    "each worker process of the local cluster starts by importing the script that started "
    "the sweep, so a script must call mudrft.sweep(...) under 'if __name__ == \"__main__\":' "
    "(or pass scheduler='serial' to run every point in this process)"
)


def _check_not_bootstrapping() -> None:
    """Refuse a sweep started while a new process imports its parent's main script.

    Dask's worker processes are spawned: each imports the ``__main__`` module of the
    process that made the cluster. A script that calls :func:`run_sweep` at its top level,
    without the ``__main__`` guard, would start the same sweep again in every worker (it
    met the driver's store and failed with "store exists", and the driver only saw
    "Nanny failed to start"). :mod:`multiprocessing` marks that import phase with
    ``current_process()._inheriting`` (its own check of the same mistake reads it).
    """
    import multiprocessing

    if getattr(multiprocessing.current_process(), "_inheriting", False):
        raise MudrftError(
            "mudrft.sweep was called while a new worker process was importing the script "
            f"that started it: {_MAIN_GUARD}"
        )


class _Bar:
    """Progress of the points: a text bar through the ``mudrft`` logger, or a callable."""

    def __init__(self, report: Callable[[float], None] | None, total: int, done: int) -> None:
        self.report, self.total, self.done, self.failed = report, total, done, 0
        self.start_done, self.t0, self.last = done, time.perf_counter(), -math.inf
        self.step = 5.0

    def add(self, points: int, failed: int) -> None:
        self.done += points
        self.failed += failed
        if self.report is None:
            return
        frac = self.done / self.total if self.total else 1.0
        if not isinstance(self.report, Progress):
            self.report(frac)
            return
        pct = 100 * frac
        if pct < self.last + self.step and self.done < self.total:
            return
        self.last = pct
        rate = (self.done - self.start_done) / max(time.perf_counter() - self.t0, 1e-9)
        left = (self.total - self.done) / rate if rate > 0 else math.inf
        bar = "#" * int(frac * 20)
        self.report.note(
            f"  sweep [{bar:<20s}] {pct:3.0f} % ({self.done} of {self.total} points, "
            f"{self.failed} failed, {rate:.3g} points/s, {left:.0f} s left)"
        )


@contextmanager
def _client(
    client: distributed.Client | None, scheduler: str | None, workers: int | None
) -> Iterator[distributed.Client]:
    """The client to use: the one given, one connected to ``scheduler``, or a local cluster."""
    if client is not None:
        yield client
        return
    distributed = _require("distributed")
    if scheduler:
        try:
            connected = distributed.Client(scheduler)
        except (ValueError, TypeError) as exc:  # a malformed address: distributed's parser
            raise MudrftError(
                f"scheduler (CLI: --scheduler) {scheduler!r} is not a Dask scheduler address "
                f"such as 'tcp://host:8786' (or 'serial'): {exc}"
            ) from exc
        with connected as c:
            yield c
        return
    n = workers or os.cpu_count() or 1
    try:
        cluster = distributed.LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",  # a free port (the HTTP server starts anyway)
            silence_logs=logging.ERROR,
        )
    except RuntimeError as exc:  # "Nanny failed to start." and nothing else to go on
        raise MudrftError(
            f"the local Dask cluster could not start its {n} worker process(es) ({exc}); "
            f"most often because {_MAIN_GUARD}"
        ) from exc
    with cluster as running, distributed.Client(running) as c:
        yield c


def _run_serial(
    spec: SweepSpec,
    context: SweepContext,
    pending: list[int],
    done: Callable[[int, ChunkResult], None],
) -> None:
    for i in pending:
        done(i, evaluate_chunk(context, spec.chunk_points(i)))


def _run_dask(
    client: distributed.Client,
    spec: SweepSpec,
    context: SweepContext,
    pending: list[int],
    done: Callable[[int, ChunkResult], None],
) -> None:
    from distributed import as_completed

    n_workers = max(len(client.scheduler_info(n_workers=-1).get("workers", {})), 1)
    window = 4 * n_workers + 4  # tasks in flight: enough to keep workers busy
    ctx = client.scatter(context, broadcast=True)
    todo = iter(pending)
    futures: dict[distributed.Future[ChunkResult], int] = {}

    def submit() -> distributed.Future[ChunkResult] | None:
        i = next(todo, None)
        if i is None:
            return None
        f = client.submit(evaluate_chunk, ctx, spec.chunk_points(i), pure=False)
        futures[f] = i
        return f

    queue = as_completed([f for _ in range(window) if (f := submit()) is not None])
    try:
        for fut in queue:
            i = futures.pop(fut)
            result = fut.result()
            fut.release()
            done(i, result)
            nxt = submit()
            if nxt is not None:
                queue.add(nxt)
    finally:
        for f in futures:  # interrupted: do not leave work behind on the cluster
            f.cancel()


def run_sweep(
    spec: str | os.PathLike[str] | Mapping[str, Any] | SweepSpec,
    *,
    store: StoreLike | None = None,
    client: distributed.Client | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    resume: bool = False,
    overwrite: bool = False,
    progress: bool | Callable[[float], None] = False,
) -> xr.Dataset:
    """Run a design sweep and return its labelled results (also ``mudrft.sweep(...)``).

    Parameters
    ----------
    spec : path-like, dict or SweepSpec
        The spec: a TOML file, a dict of the same shape, or :func:`load_spec`'s result.
    store : path-like, zarr store or None, keyword-only
        Where results are written chunk by chunk (a ``.zarr`` directory). None keeps them
        in memory (nothing to resume).
    client : distributed.Client or None, keyword-only
        Run the tasks on this client (it is left open).
    scheduler : str or None, keyword-only
        Address of a running Dask scheduler (``"tcp://host:8786"``), or ``"serial"`` to
        run every chunk in this process without Dask. Default: a local cluster.
    workers : int or None, keyword-only
        Worker processes of the local cluster (one thread each); default: the CPU count.
    resume : bool, keyword-only
        Continue an existing store made from the same spec, computing only the chunks it
        lacks (a missing store starts a new sweep).
    overwrite : bool, keyword-only
        Replace an existing store (only a mudrft sweep store is ever removed).
    progress : bool or callable, keyword-only
        ``True`` logs a progress bar through the ``mudrft`` logger; a callable is called
        with the fraction of points done.

    Returns
    -------
    xarray.Dataset
        One dimension per swept parameter (or ``point`` for a sample), one variable per
        metric, ``error``; units, the mudrft version, the spec and the parameter sources
        in the attributes (see :mod:`mudrft.sweep.store`).

    Raises
    ------
    MudrftError
        For a bad spec, an existing store without ``resume``/``overwrite``, a store made
        from another spec, a missing optional package (``pip install 'mudrft[sweep]'``), a
        local cluster whose worker processes do not start, or a call made while a worker
        process imports the script that started the sweep: a script that runs a sweep on
        the local cluster calls it under ``if __name__ == "__main__":`` (decision D116).
    """
    _check_not_bootstrapping()
    spec = load_spec(spec)
    for module in ("xarray", "zarr", "dask"):
        _require(module)
    if spec.motion == "walk":
        _require("mujoco")
    if client is not None and scheduler is not None:
        raise MudrftError("give client or scheduler, not both")
    if workers is not None and (client is not None or scheduler is not None):
        raise MudrftError("workers sets the size of the local cluster; it cannot go with client or scheduler")  # fmt: skip
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):  # fmt: skip
        raise MudrftError(f"workers must be an integer >= 1, got {workers!r}")
    _check_options(store, client, resume=resume, overwrite=overwrite, progress=progress)
    from . import store as S

    group, done_mask, created = _prepare(S, store, spec, resume=resume, overwrite=overwrite)
    pending = [i for i in range(spec.n_chunks) if not done_mask[i]]
    n_done = sum(math.prod(spec.chunk_shape(i)) for i in range(spec.n_chunks) if done_mask[i])
    bar = _Bar(make_progress(progress, "sweep"), spec.n_points, n_done)
    seen: dict[str, int] = {}
    written = 0

    def finished(i: int, result: ChunkResult) -> None:
        nonlocal written
        S.write_chunk(group, spec, i, result)
        written += 1
        for w in result.warnings:
            seen[w] = seen.get(w, 0) + 1
        bar.add(len(result.errors), sum(1 for e in result.errors if e))

    if pending:
        context = spec.context()
        try:
            if scheduler == "serial":
                _run_serial(spec, context, pending, finished)
            else:
                _require("distributed")
                with _client(client, scheduler, workers) as c:
                    _run_dask(c, spec, context, pending, finished)
        except BaseException:
            # a store this call made and nothing was written to (an unreachable scheduler,
            # a cluster that does not start, an interrupt before the first chunk) is removed:
            # a failed run leaves nothing behind; a store with finished chunks is kept for
            # ``resume``
            if created is not None and written == 0:
                shutil.rmtree(created, ignore_errors=True)
            elif created is not None or resume:
                logger.warning("sweep stopped after %d chunk(s); resume=True (CLI: --resume) continues it", written)  # fmt: skip
            raise
    for message, chunks in seen.items():
        warnings.warn(f"in {chunks} chunk(s) of the sweep: {message}", SweepWarning, stacklevel=2)
    failed = S.mark_complete(group, spec)
    ds = S.load_result(group.store)
    if failed and failed == spec.n_points:  # a fixed value wrong for every point, often
        first = next(str(e) for e in ds["error"].values.ravel() if e)
        warnings.warn(
            f"every point of the sweep failed ({failed}); the first error: {first}",
            SweepWarning,
            stacklevel=2,
        )
    return ds


def _check_options(store: object, client: object, **flags: object) -> None:
    """The options numpy, zarr or Dask would have failed on deep inside (or taken
    silently: ``resume="no"`` resumed), named."""
    for name in ("resume", "overwrite"):
        if not isinstance(flags[name], bool):
            raise MudrftError(f"{name} must be True or False, got {flags[name]!r}")
    progress = flags["progress"]
    if not (isinstance(progress, bool) or progress is None or callable(progress)):
        raise MudrftError(f"progress must be True, False or a callable f(fraction), got {progress!r}")  # fmt: skip
    if isinstance(store, str | os.PathLike):
        if not os.fspath(store):
            raise MudrftError("store must be the path of a .zarr directory, got an empty string")
    elif store is not None:
        from zarr.abc.store import Store

        if not isinstance(store, Store):
            raise MudrftError(f"store must be the path of a .zarr directory, a zarr store or None, got {type(store).__name__}: {store!r}")  # fmt: skip
    if client is not None and not callable(getattr(client, "submit", None)):
        raise MudrftError(f"client must be a distributed.Client, got {type(client).__name__}: {client!r}")  # fmt: skip


def _prepare(
    S: ModuleType, store: StoreLike | None, spec: SweepSpec, *, resume: bool, overwrite: bool
) -> tuple[zarr.Group, NDArray[np.bool_], str | os.PathLike[str] | None]:
    import numpy as np

    if resume and overwrite:
        raise MudrftError("give resume or overwrite, not both")
    if resume and store is None:
        raise MudrftError("resume needs the store of the sweep to continue (store=PATH)")
    if store is None:
        import zarr

        store = zarr.storage.MemoryStore()
    elif resume and isinstance(store, str | os.PathLike) and os.path.exists(store):
        group = S.open_store(store, spec)
        return group, S.done_chunks(group, spec), None
    group = S.create_store(store, spec, overwrite=overwrite)
    created = store if isinstance(store, str | os.PathLike) else None
    return group, np.zeros(spec.n_chunks, dtype=bool), created
