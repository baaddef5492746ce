"""Design sweeps on Dask: points per second with 1 and 2 workers, and the cost of a task.

Run ``python benchmarks/bench_sweep.py [--quick] [--repeat R] [--json FILE]`` from a
checkout with the ``sweep`` extra. Figures (docs/performance.md):

* ``serial_points_per_s``: the sweep without Dask (``scheduler="serial"``), the physics
  alone plus the store writes;
* ``points_per_s[1]``, ``points_per_s[2]``: the same sweep on a ``LocalCluster`` of 1 and
  2 worker processes (one thread each), the cluster already started and its workers warm
  (mudrft imported); ``speedup_2_over_1`` their ratio. End to end: the store's creation
  and the final load (about 1 s together) are in the time;
* ``task_overhead_ms``: what one more task costs, from the same points run as 1-point
  tasks and as a single task on the 1-worker cluster,
  ``(T(1 point/task) - T(all in one)) / (tasks - 1)``; it includes the scheduler round
  trip, the pickling of points and results, and the driver's store write of the chunk;
* ``pool_points_per_s[1]``, ``[2]``: the same chunks on a plain ``ProcessPoolExecutor`` of
  1 and 2 processes, without Dask or store (the control: how much parallel speed the
  machine gives the physics at that moment), measured in alternation with the Dask runs;
* ``noop_task_ms``: a Dask task that does nothing, submitted one at a time (the floor);
* ``worker_ms_per_point``: the tasks' compute time on the workers per point, per run: the
  cost of a point as the workers saw it (it rises when other processes share the cores);
* ``workers_busy_fraction``: that compute time over ``wall x workers``: how well the sweep
  keeps its workers fed, whatever the machine's load.

Closed-form feet only (flat, semi-cylinder, semi-sphere). Each figure is the best of
``--repeat`` runs, the 1- and 2-worker runs in alternation, because the machine is shared:
the load average is recorded before and after.

``--startup`` measures instead what decides whether a sweep without options starts a
cluster (``mudrft.sweep.run.CLUSTER_START_S``):

* ``cluster_cost_s``: a local cluster of one worker per CPU started, mudrft imported and
  one point computed in each worker, and closed;
* ``seconds[N]``: sweeps of N points run serially, on that cluster (``workers=``) and by
  default (no options), each from a fresh store.
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import platform
import shutil
import tempfile
import time
from pathlib import Path
from typing import Any


def spec(speeds: int, points_per_task: int = 0) -> dict[str, Any]:
    """Closed-form feet x water content x speed: ``3 * 4 * speeds`` points."""
    run: dict[str, Any] = {"metrics": ["peak_support", "max_suction", "energy", "sinking"]}
    if points_per_task:
        run["points_per_task"] = points_per_task
    return {
        "sweep": run,
        "foot": {"kind": ["flat", "semi-cylinder", "semi-sphere"]},
        "mud": {"water_content": {"low": 0.25, "high": 0.45, "num": 4}},
        "motion": {
            "speed": [round(0.13 + 0.13 * k / max(speeds - 1, 1), 4) for k in range(speeds)]
        },
    }


def timed_sweep(s: dict[str, Any], **kw: Any) -> float:
    import mudrft

    work = Path(tempfile.mkdtemp(prefix="bench-sweep-"))
    try:
        t0 = time.perf_counter()
        ds = mudrft.sweep(s, store=work / "s.zarr", **kw)
        dt = time.perf_counter() - t0
    finally:
        shutil.rmtree(work, ignore_errors=True)
    assert int(ds.attrs["failed_points"]) == 0
    return dt


def worker_ms_per_point(s: dict[str, Any], client: Any, n_points: int) -> tuple[float, float]:
    """Wall time of one sweep [s] and the workers' compute time per point [ms] in it.

    The second number is the time the tasks ran on the workers (Dask's task stream),
    divided by the points: it rises when the workers share the cores with other processes.
    """
    from distributed import get_task_stream

    with get_task_stream(client) as ts:
        wall = timed_sweep(s, client=client)
    busy = sum(
        ss["stop"] - ss["start"]
        for t in ts.data
        if "evaluate_chunk" in str(t["key"])
        for ss in t["startstops"]
        if ss["action"] == "compute"
    )
    return wall, 1e3 * busy / n_points


def cluster(n: int) -> Any:
    from distributed import Client, LocalCluster

    c = LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    )
    client = Client(c)
    client.run(lambda: __import__("mudrft.sweep.evaluate"))  # warm: imports done
    timed_sweep(spec(1), client=client)  # warm: the first points of each worker
    return c, client


def _warm() -> None:
    import mudrft.sweep.evaluate  # noqa: F401


def pool(n: int) -> Any:
    """A plain process pool of ``n`` processes, warm: the control without Dask."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ex = ProcessPoolExecutor(n, mp_context=multiprocessing.get_context("spawn"))
    list(ex.map(_sleep_then_warm, range(n)))
    return ex


def _sleep_then_warm(_: int) -> None:
    time.sleep(0.5)  # so that each process of the pool takes one
    _warm()


def pool_seconds(ex: Any, s: dict[str, Any]) -> float:
    """The sweep's chunks on a plain process pool, no store: the physics' parallel speed."""
    from mudrft.sweep import load_spec
    from mudrft.sweep.evaluate import evaluate_chunk

    spec = load_spec(s)
    ctx = spec.context()
    t0 = time.perf_counter()
    chunks = [spec.chunk_points(i) for i in range(spec.n_chunks)]
    list(ex.map(evaluate_chunk, [ctx] * len(chunks), chunks))
    return time.perf_counter() - t0


def noop_task_ms(client: Any, n: int = 200) -> float:
    t0 = time.perf_counter()
    for _ in range(n):
        client.submit(int, 1, pure=False).result()
    return 1e3 * (time.perf_counter() - t0) / n


def startup(repeat: int, quick: bool) -> dict[str, Any]:
    """What a local cluster costs before it computes, and sweeps of N points three ways."""
    from distributed import Client, LocalCluster

    from mudrft.sweep import load_spec
    from mudrft.sweep.evaluate import evaluate_chunk

    n = os.cpu_count() or 1
    one = load_spec(spec(1))
    costs = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        with (
            LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                         dashboard_address=":0", silence_logs=logging.ERROR) as c,
            Client(c) as client,
        ):  # fmt: skip
            client.run(_warm)
            points = [one.chunk_points(0)[:1]] * n
            client.gather(client.map(evaluate_chunk, [one.context()] * n, points, pure=False))
        costs.append(time.perf_counter() - t0)
    timed_sweep(spec(1), scheduler="serial")  # warm this process
    seconds: dict[int, dict[str, float]] = {}
    for speeds in (1, 4) if quick else (1, 4, 8, 16, 32):
        s = spec(speeds)
        runs = {"serial": {"scheduler": "serial"}, "cluster": {"workers": n}, "default": {}}
        seconds[12 * speeds] = {
            k: round(min(timed_sweep(s, **kw) for _ in range(repeat)), 2) for k, kw in runs.items()
        }
    return {"workers": n, "cluster_cost_s": [round(c, 2) for c in costs], "seconds": seconds}


def main() -> dict[str, Any]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer points (a trial run)")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each figure; best kept")
    ap.add_argument("--startup", action="store_true", help="a cluster's start-up cost only")
    ap.add_argument("--json", help="also write the results here")
    args = ap.parse_args()
    if args.startup:
        load0 = os.getloadavg()[0]
        out = startup(args.repeat, args.quick)
        out["machine"] = {"cpu": _cpu(), "load_average_1min_before": round(load0, 2),
                          "load_average_1min_after": round(os.getloadavg()[0], 2)}  # fmt: skip
        print(json.dumps(out, indent=2))
        if args.json:
            Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
        return out
    speeds = 4 if args.quick else 32  # 48 or 384 points: long enough that the fixed costs
    # of a sweep (store made, result loaded: about 1 s) weigh little against the points
    s = spec(speeds)
    n_points = 12 * speeds
    load0 = os.getloadavg()[0]
    out: dict[str, Any] = {
        "machine": {
            "cpu": _cpu(),
            "logical_cpus": os.cpu_count(),
            "python": platform.python_version(),
            "load_average_1min_before": round(load0, 2),
        },
        "points": n_points,
    }
    import dask

    import mudrft

    out["machine"]["dask"] = dask.__version__
    timed_sweep(spec(1), scheduler="serial")  # warm: imports, first points
    serial = timed_sweep(s, scheduler="serial")
    out["serial_points_per_s"] = round(n_points / serial, 2)
    pools = {n: pool(n) for n in (1, 2)}
    c1, k1 = cluster(1)
    c2, k2 = cluster(2)
    times: dict[int, list[float]] = {1: [], 2: []}
    plain: dict[int, list[float]] = {1: [], 2: []}
    busy: dict[int, list[float]] = {1: [], 2: []}
    frac: dict[int, list[float]] = {1: [], 2: []}
    try:
        for _ in range(args.repeat):
            for n, client in ((1, k1), (2, k2)):
                plain[n].append(pool_seconds(pools[n], s))
                wall, ms = worker_ms_per_point(s, client, n_points)
                times[n].append(wall)
                busy[n].append(ms)
                frac[n].append(ms * n_points / 1e3 / (wall * n))
        out["points_per_s"] = {n: round(n_points / min(t), 2) for n, t in times.items()}
        out["wall_s"] = {n: [round(x, 2) for x in t] for n, t in times.items()}
        out["worker_ms_per_point"] = {n: [round(x, 1) for x in b] for n, b in busy.items()}
        out["workers_busy_fraction"] = {n: [round(x, 3) for x in f] for n, f in frac.items()}
        out["speedup_2_over_1"] = round(out["points_per_s"][2] / out["points_per_s"][1], 3)
        out["pool_points_per_s"] = {n: round(n_points / min(t), 2) for n, t in plain.items()}
        out["pool_wall_s"] = {n: [round(x, 2) for x in t] for n, t in plain.items()}
        pp = out["pool_points_per_s"]
        out["pool_speedup_2_over_1"] = round(pp[2] / pp[1], 3)
        per = 24 if args.quick else 48
        small = spec(per // 12)
        ones = min(timed_sweep({**small, "sweep": {**small["sweep"], "points_per_task": 1}}, client=k1) for _ in range(args.repeat))  # fmt: skip
        whole = min(timed_sweep({**small, "sweep": {**small["sweep"], "points_per_task": per}}, client=k1) for _ in range(args.repeat))  # fmt: skip
        out["task_overhead_ms"] = round(1e3 * (ones - whole) / (per - 1), 2)
        out["task_overhead_points"] = per
        out["noop_task_ms"] = round(min(noop_task_ms(k1) for _ in range(args.repeat)), 3)
    finally:
        for client, c in ((k1, c1), (k2, c2)):
            client.close()
            c.close()
        for ex in pools.values():
            ex.shutdown()
    out["machine"]["load_average_1min_after"] = round(os.getloadavg()[0], 2)
    out["mudrft"] = mudrft.__version__
    print(json.dumps(out, indent=2))
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=2) + "\n")
    return out


def _cpu() -> str:
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


if __name__ == "__main__":
    main()
