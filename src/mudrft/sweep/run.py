"""Run a sweep: chunks of points as tasks, in this process or on Dask.

The calling process writes each chunk to the store as its task returns, so workers need
no shared file system; on Dask a window of a few tasks per worker is in flight.
"""

from __future__ import annotations

import logging
import math
import multiprocessing
import os
import shutil
import warnings
from collections import Counter
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

import numpy as np

from .._progress import make_progress
from .._validation import MudrftError, positive_int, require_extra
from .evaluate import ChunkResult, SweepContext, evaluate_chunk
from .spec import SweepSpec, load_spec
from .store import StoreLike, chunk_status, create_store, load_result, open_store, write_chunk

if TYPE_CHECKING:
    import distributed
    import xarray as xr
    import zarr

logger = logging.getLogger("mudrft.sweep")

#: What starting, warming and closing a local cluster costs [s] (4.2-5.7 s for two workers
#: on two cores: ``benchmarks/bench_sweep.py --startup``).
CLUSTER_START_S = 5.0


class SweepWarning(UserWarning):
    """A warning raised at some points of a sweep (reported once per distinct message)."""


_MAIN_GUARD = (
    "each worker process of the local cluster starts by importing the script that started "
    "the sweep, so a script must call mudrft.sweep(...) under 'if __name__ == \"__main__\":' "
    "(or pass scheduler='serial' to run every point in this process)"
)


@contextmanager
def _client(
    client: distributed.Client | None, scheduler: str | None, workers: int | None
) -> Iterator[distributed.Client]:
    """The client to use: the one given, one connected to ``scheduler``, or a local cluster."""
    if client is not None:
        yield client
        return
    distributed = require_extra("distributed", needed_for="mudrft.sweep")
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
    *,
    cpus: int | None = None,
) -> list[int]:
    """Run ``pending`` chunks here; with ``cpus``, return the rest once they would take
    longer than ``CLUSTER_START_S * cpus / (cpus - 1)`` at the last chunk's rate."""
    for k, i in enumerate(pending):
        result = evaluate_chunk(context, spec.chunk_points(i))
        done(i, result)
        rest = pending[k + 1 :]
        if cpus is None or cpus < 2 or k == 0 or not rest:
            continue
        left = result.seconds / len(result.errors) * sum(math.prod(spec.chunk_shape(j)) for j in rest)  # fmt: skip
        if left > CLUSTER_START_S * cpus / (cpus - 1):
            logger.info("sweep: about %.0f s of points left; they go to a local cluster of %d workers", left, cpus)  # fmt: skip
            return rest
    return []


def _run_dask(
    client: distributed.Client,
    spec: SweepSpec,
    context: SweepContext,
    pending: list[int],
    done: Callable[[int, ChunkResult], None],
) -> None:
    from distributed import as_completed

    n_workers = max(len(client.scheduler_info(n_workers=-1).get("workers", {})), 1)
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

    window = 4 * n_workers + 4  # tasks in flight: enough to keep the workers busy
    queue = as_completed([f for _ in range(window) if (f := submit()) is not None])
    try:
        for fut in queue:
            i = futures.pop(fut)
            result = fut.result()
            fut.release()
            done(i, result)
            if (nxt := submit()) is not None:
                queue.add(nxt)
    finally:
        for f in futures:  # interrupted: leave no work behind on the cluster
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

    With none of ``client``, ``scheduler`` and ``workers``, chunks run in this process
    until the points left would take longer than a local cluster's start-up
    (:data:`CLUSTER_START_S`); the rest run on a local cluster of one worker per CPU. A
    script that may start one calls the sweep under ``if __name__ == "__main__":``.

    Parameters
    ----------
    spec : path-like, dict or SweepSpec
        The spec: a TOML file, a dict of the same shape, or :func:`load_spec`'s result.
    store : path-like, zarr store or None, keyword-only
        Where results are written chunk by chunk (a ``.zarr`` directory); None: in memory.
    client : distributed.Client or None, keyword-only
        Run the tasks on this client (left open).
    scheduler : str or None, keyword-only
        A Dask scheduler's address (``"tcp://host:8786"``), or ``"serial"``: in this process.
    workers : int or None, keyword-only
        Run on a local cluster of this many worker processes.
    resume, overwrite : bool, keyword-only
        Continue a store made from the same spec, computing only the chunks it lacks or
        has damaged; or replace it (only a mudrft sweep store is ever removed).
    progress : bool or callable, keyword-only
        ``True`` logs progress through the ``mudrft`` logger; a callable gets the fraction.

    Returns
    -------
    xarray.Dataset
        One dimension per swept parameter (or ``point`` for a sample), one variable per
        metric, and ``error``: NaN metrics and the error where a point failed (warned
        about, :class:`SweepWarning`); units, the spec and ``failed_points`` in the attributes.

    Raises
    ------
    MudrftError
        For a bad spec or option, an existing store without ``resume`` or ``overwrite``, a
        store of another spec or without its metadata, a missing optional package, or a
        local cluster whose workers do not start.
    """
    if getattr(multiprocessing.current_process(), "_inheriting", False):  # a spawned worker
        raise MudrftError(
            "mudrft.sweep was called while a new worker process was importing the script "
            f"that started it: {_MAIN_GUARD}"
        )
    spec = load_spec(spec)
    for module in ("xarray", "zarr", "dask"):
        require_extra(module, needed_for="mudrft.sweep")
    if spec.motion == "walk":
        require_extra("mujoco", needed_for="mudrft.sweep")
    if client is not None and scheduler is not None:
        raise MudrftError("give client or scheduler, not both")
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise MudrftError(f"scheduler (CLI: --scheduler) must be a Dask scheduler address such as 'tcp://host:8786', or 'serial', got {scheduler!r}")  # fmt: skip
    if workers is not None and (client is not None or scheduler is not None):
        raise MudrftError("workers (CLI: --workers) sets the size of a local cluster; it cannot go with client or scheduler (--scheduler)")  # fmt: skip
    if workers is not None:
        workers = positive_int("workers (CLI: --workers)", workers)
    for name, flag in (("resume", resume), ("overwrite", overwrite)):
        if not isinstance(flag, bool):
            raise MudrftError(f"{name} must be True or False, got {flag!r}")
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
    group, pending, created = _prepare(store, spec, resume=resume, overwrite=overwrite)
    report = make_progress(progress, "sweep")
    n_done = spec.n_points - sum(math.prod(spec.chunk_shape(i)) for i in pending)
    seen: Counter[str] = Counter()
    written = 0

    def finished(i: int, result: ChunkResult) -> None:
        nonlocal written, n_done
        write_chunk(group, spec, i, result)
        written += 1
        n_done += len(result.errors)
        seen.update(result.warnings)
        if report is not None:
            report(n_done / spec.n_points)

    if pending:
        context = spec.context()
        auto = client is None and scheduler is None and workers is None
        try:
            if scheduler == "serial" or auto:
                cpus = (os.cpu_count() or 1) if auto else None
                pending = _run_serial(spec, context, pending, finished, cpus=cpus)
            if pending:
                with _client(client, scheduler, workers) as c:
                    _run_dask(c, spec, context, pending, finished)
        except BaseException:
            # a store this call made and nothing was written to is removed (a failed run
            # leaves nothing behind); a store with finished chunks is kept for resume
            if created is not None and written == 0:
                shutil.rmtree(created, ignore_errors=True)
            elif created is not None or resume:
                logger.warning("sweep stopped after %d chunk(s); resume=True (CLI: --resume) continues it", written)  # fmt: skip
            raise
    for message, chunks in seen.items():
        warnings.warn(f"in {chunks} chunk(s) of the sweep: {message}", SweepWarning, stacklevel=2)
    group.attrs["complete"] = 1
    ds = load_result(group.store)
    errors = ds["error"].values.ravel()
    failed = int(np.count_nonzero(errors != ""))
    group.attrs["failed_points"] = ds.attrs["failed_points"] = failed
    if failed:
        first = next(e for e in errors if e)
        head = (
            f"every point of the sweep failed ({failed})"
            if failed == spec.n_points
            else f"{failed} of {spec.n_points} points of the sweep failed (NaN metrics; each error in 'error')"
        )  # fmt: skip
        warnings.warn(f"{head}; the first error: {first}", SweepWarning, stacklevel=2)
    return ds


def _prepare(
    store: StoreLike | None, spec: SweepSpec, *, resume: bool, overwrite: bool
) -> tuple[zarr.Group, list[int], str | os.PathLike[str] | None]:
    """The store's group, the chunks to compute, and the path of a store made here."""
    if resume and overwrite:
        raise MudrftError("give resume or overwrite, not both")
    if resume and store is None:
        raise MudrftError("resume needs the store of the sweep to continue (store=PATH)")
    if store is None:
        import zarr

        store = zarr.storage.MemoryStore()
    elif resume and isinstance(store, str | os.PathLike) and os.path.exists(store):
        group = open_store(store, spec)
        done, damaged, _ = chunk_status(group)
        if damaged:
            logger.warning(
                "sweep: %d damaged chunk(s) of %s are computed again: %s",
                len(damaged), os.fspath(store), "; ".join(f"chunk {i}: {w}" for i, w in list(damaged.items())[:5]),
            )  # fmt: skip
        pending = [i for i in range(spec.n_chunks) if not done[i]]
        if pending:
            group.attrs["complete"] = 0
        return group, pending, None
    group = create_store(store, spec, overwrite=overwrite)
    created = store if isinstance(store, str | os.PathLike) else None
    return group, list(range(spec.n_chunks)), created
