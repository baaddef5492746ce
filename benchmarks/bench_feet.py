"""Benchmark: force evaluation on triangle meshes of about 1,000 and 100,000 facets.

Every evaluation is one vectorized pass over all facets (no Python loop over facets);
batches are processed in cache-sized chunks of batch rows (``mudrft.feet.mesh.CHUNK``).

Run ``python benchmarks/bench_feet.py [--quick] [--json FILE] [--markdown FILE]``.
Timings are the best of several repeats (robust to other load on the machine); memory is
the peak of Python-side allocations (tracemalloc) during one call.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
import tracemalloc
from collections.abc import Callable
from typing import Any

import numpy as np

from mudrft.feet import MeshFoot
from mudrft.feet.meshgen import semisphere_mesh
from mudrft.feet.meshparts import overlapping_parts
from mudrft.feet.surface import integrate_triangles

#: semi-sphere mesh resolutions giving 968 and 100,352 facets (8 n^2)
RESOLUTIONS = {"1k": 11, "100k": 112}


def _best(fn: Callable[[], Any], *, repeat: int, budget: float) -> float:
    """Best time per call [s] over ``repeat`` rounds of about ``budget / repeat`` seconds."""
    fn()  # warm up (allocations, caches, JIT)
    t0 = time.perf_counter()
    fn()
    one = max(time.perf_counter() - t0, 1e-7)
    number = max(1, int(budget / repeat / one))
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best


def _peak_bytes(fn: Callable[[], Any]) -> int:
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return int(peak)


def run(
    *, quick: bool = False, progress: Callable[[str], None] | None = None
) -> list[dict[str, Any]]:
    """Run the benchmark; return one record per case.

    Parameters
    ----------
    quick : bool, optional
        Shorter timing budget and smaller batch (for CI smoke runs).
    progress : callable, optional
        Receives one line per stage.
    """
    say = progress or (lambda line: None)
    repeat, budget = (3, 0.3) if quick else (5, 2.0)
    batch = 100 if quick else 1000
    records: list[dict[str, Any]] = []
    for label, n in RESOLUTIONS.items():
        records.extend(_bench_mesh(label, n, batch=batch, repeat=repeat, budget=budget, say=say))
    return records


def _bench_mesh(
    label: str, n: int, *, batch: int, repeat: int, budget: float, say: Callable[[str], None]
) -> list[dict[str, Any]]:
    rng = np.random.default_rng(0)
    v, f = semisphere_mesh(0.045, 0.026, resolution=n)
    foot = MeshFoot(v, f, trailing=True)
    m = len(foot)
    s1 = np.array([1.2e3, 0.8e3, 2.0e3])
    db = rng.uniform(0.0, 0.03, batch)
    sb = rng.uniform(-2e3, 2e3, (batch, 3))
    hb = rng.uniform(-np.pi, np.pi, batch)
    tri = foot.triangles
    cases: dict[str, tuple[Callable[[], Any], int]] = {
        "force, one state": (lambda: foot.force(0.015, s1, 0.4), 1),
        "force_unchecked, one state": (lambda: foot.force_unchecked(0.015, s1, 0.4), 1),
        f"force, batch of {batch}": (lambda: foot.force(db, sb, hb), batch),
        "wrench (force, moment, CoP), one state": (lambda: foot.wrench(0.015, s1, 0.4), 1),
        "integrate_triangles from raw triangles": (
            lambda: integrate_triangles(tri, 0.015, s1, 0.4, trailing=True),
            1,
        ),
        "MeshFoot construction (checks, preparation)": (
            lambda: MeshFoot(v, f, trailing=True),
            1,
        ),
        "of which the overlapping-parts check (D136)": (lambda: overlapping_parts(v, f), 1),
    }
    records: list[dict[str, Any]] = []
    for name, (fn, states) in cases.items():
        say(f"bench_feet: {m} facets: {name}")
        t = _best(fn, repeat=repeat, budget=budget)
        records.append(
            {
                "mesh": label,
                "facets": m,
                "case": name,
                "states": states,
                "time_per_call_s": t,
                "time_per_state_s": t / states,
                "facet_evals_per_s": m * states / t,
                "peak_python_bytes": _peak_bytes(fn),
            }
        )
    try:
        import jax
        import jax.numpy as jnp
    except ImportError:  # optional backend
        return records
    say(f"bench_feet: {m} facets: jax.jit")
    jt = jnp.asarray(tri)
    g = jax.jit(lambda d, s, h: integrate_triangles(jt, d, s, h, trailing=True, xp=jnp))
    args = (jnp.asarray(0.015), jnp.asarray(s1), jnp.asarray(0.4))
    t = _best(lambda: g(*args).block_until_ready(), repeat=repeat, budget=budget)
    records.append(
        {
            "mesh": label,
            "facets": m,
            "states": 1,
            "case": f"jax.jit on {jax.default_backend()} (float32), one state",
            "time_per_call_s": t,
            "time_per_state_s": t,
            "facet_evals_per_s": m / t,
            "peak_python_bytes": None,
        }
    )
    return records


def markdown(records: list[dict[str, Any]]) -> str:
    """A Markdown table of the records."""
    lines = [
        "| facets | case | time per call | time per state | facet evaluations / s "
        "| peak Python memory |",
        "|---:|---|---:|---:|---:|---:|",
    ]
    for r in records:
        mem = "-" if r["peak_python_bytes"] is None else f"{r['peak_python_bytes'] / 1e6:.1f} MB"
        lines.append(
            f"| {r['facets']:,} | {r['case']} | {r['time_per_call_s'] * 1e3:.3g} ms | "
            f"{r['time_per_state_s'] * 1e6:.3g} us | {r['facet_evals_per_s']:.3g} | {mem} |"
        )
    return "\n".join(lines)


def machine() -> str:
    """One line describing the machine."""
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {np.__version__}, load average {load:.1f} at start"
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="short run")
    ap.add_argument("--json", help="write the records to this JSON file")
    ap.add_argument("--markdown", help="write the table to this Markdown file")
    args = ap.parse_args(argv)
    info = machine()
    records = run(quick=args.quick, progress=lambda line: print(line, file=sys.stderr))
    table = markdown(records)
    print(info)
    print(table)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"machine": info, "records": records}, fh, indent=1)
    if args.markdown:
        with open(args.markdown, "w") as fh:
            fh.write(f"Machine: {info}\n\n{table}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
