r"""The speed benchmarks of mudrft (``mudrft bench``), and the machine's limits.

This package lives in the source checkout, not in the installed library:
``mudrft bench`` (:mod:`mudrft.cli.bench`) loads it from ``benchmarks/harness`` beside
``src/`` and says what to do when the checkout is not there. ``run_benchmarks`` runs, in
order:

* the machine's limits (:mod:`.machine`): memory bandwidth (numpy copy and triad of arrays
  far larger than the caches), peak float64 rate (a large matmul), and the cost of the
  elementary functions the physics calls;
* the constitutive step per call and per channel of a batch of 300,000 channels on every
  path of the one definition, and the mesh integration at about 1e3 and 1e5 facets
  (:mod:`.physics`);
* batches of 1, 1e3 and 1e5 flat feet (:class:`mudrft.backends.batch.BatchedMud`, numpy,
  numba and JAX backends; JAX on whatever device it has), ``batch_speedup_1e4``, one foot
  per step (``MudTerrain``, a batch of one on numba, ``simulate``) and the MuJoCo overhead ratio
  (:mod:`.feet`);
* robot-steps per second with mud at 1, 64 and 1,024 robots, the CPU coupling and MJX (with
  and without mud; MJX on whatever device JAX finds) (:mod:`.robots`);
* a roofline estimate (:mod:`.roofline`).

Timings are the best of several repeats (robust to other load on the machine). Only public
library calls are timed, except the JAX batch, which steps ``BatchedMud``'s jitted function
on device-resident state to leave host copies out. Nothing here changes results. Tests
never assert on these times (docs/performance.md holds them).
"""

from __future__ import annotations

import datetime as _dt
import os
import time
from typing import Any

from ._timing import Progress, say
from .feet import BATCH_SIZES, bench_batches, bench_mujoco, bench_single_foot, bench_speedup
from .machine import machine_info, measure_bandwidth, measure_functions, measure_peak_flops
from .physics import BATCH_CHANNELS, MESH_RESOLUTIONS, bench_constitutive, bench_mesh
from .robots import ROBOT_COUNTS, bench_robots
from .roofline import FUNCTION_CALLS, ROOFLINE, roofline

__all__ = [
    "BATCH_CHANNELS",
    "BATCH_SIZES",
    "FUNCTION_CALLS",
    "MESH_RESOLUTIONS",
    "ROBOT_COUNTS",
    "ROOFLINE",
    "bench_batches",
    "bench_constitutive",
    "bench_mesh",
    "bench_mujoco",
    "bench_robots",
    "bench_single_foot",
    "bench_speedup",
    "machine_info",
    "measure_bandwidth",
    "measure_functions",
    "measure_peak_flops",
    "roofline",
    "run_benchmarks",
    "summary_lines",
]

#: Version of the JSON layout written by ``mudrft bench --json`` (2: harness in benchmarks/,
#: keys of the constitutive step renamed after the one-physics rewrite, ``simulate_us``).
SCHEMA = 2


def run_benchmarks(*, quick: bool = False, progress: Progress = None) -> dict[str, Any]:
    """Run every benchmark and return the results (the JSON of ``mudrft bench``).

    Parameters
    ----------
    quick : bool, keyword-only
        Shorter timing budgets and smaller bandwidth arrays; every size (300,000 channels,
        1e3/1e5 facets, 1, 1e3, 1e5 and 1e4 feet, 1, 64 and 1,024 robots) is kept, so quick
        and full numbers compare. About four minutes on 2 cores, most of it compiling the six
        MJX programs of the robot benchmark (without mujoco-mjx, under a minute).
    progress : callable, keyword-only
        ``progress(message)`` after each stage (the CLI logs it to stderr).

    Returns
    -------
    dict
        ``machine``, ``limits``, ``functions``, ``constitutive``, ``mesh``, ``batch``,
        ``speedup``, ``single_foot``, ``mujoco``, ``robots``, ``roofline``, the headline numbers
        ``batch_speedup_1e4`` (numpy backend) and ``mujoco_overhead_ratio`` (or None), and
        ``seconds`` (wall time of the run [s]).
    """
    t_start = time.perf_counter()
    budget = 0.05 if quick else 0.4
    res: dict[str, Any] = {
        "schema": SCHEMA,
        "quick": bool(quick),
        "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    say(progress, "mudrft bench: machine")
    res["machine"] = machine_info()
    res["jax_devices"] = res["machine"].get("jax_devices")
    res["limits"] = {
        **measure_bandwidth(n=2**25 if quick else 2**26, repeat=3 if quick else 5),
        **measure_peak_flops(n=1536 if quick else 2048, repeat=2 if quick else 3),
    }
    res["functions"] = measure_functions(n=2**16 if quick else 2**18, budget=budget / 2)
    say(progress, "  bandwidth, peak and elementary functions: done")
    res["constitutive"] = bench_constitutive(quick, budget, progress)
    res["mesh"] = bench_mesh(quick, budget, progress)
    res["batch"] = bench_batches(quick, budget, progress)
    res["speedup"] = bench_speedup(quick, budget, progress)
    res["batch_speedup_1e4"] = res["speedup"]["speedup_numpy"]
    res["single_foot"] = bench_single_foot(quick, budget, progress)
    res["mujoco"] = bench_mujoco(quick, progress)
    res["mujoco_overhead_ratio"] = res["mujoco"]["ratio"]
    res["robots"] = bench_robots(quick, progress)
    res["roofline"] = roofline(res)
    res["seconds"] = time.perf_counter() - t_start
    if hasattr(os, "getloadavg"):
        res["machine"]["load_average_1min_end"] = round(os.getloadavg()[0], 2)
    return res


def _joined(values: dict[str, Any], suffix: str, fmt: str) -> str:
    return ", ".join(
        f"{k.removesuffix(suffix)} {v:{fmt}}" for k, v in values.items() if k.endswith(suffix)
    )


def summary_lines(res: dict[str, Any]) -> list[str]:
    """Human-readable summary of :func:`run_benchmarks` results, one line per topic."""
    m, lim, con = res["machine"], res["limits"], res["constitutive"]
    lines = [
        f"machine: {m.get('cpu_model', '?')}, {m.get('logical_cpus')} logical CPUs, "
        f"{m.get('memory_GiB', '?')} GiB, load average {m.get('load_average_1min', '?')}; "
        f"JAX devices: {res.get('jax_devices')}",
        f"limits: copy {lim['copy_GBps']:.1f} GB/s, triad {lim['triad_GBps']:.1f} GB/s, "
        f"matmul {lim['matmul_GFLOPs']:.1f} GFLOP/s",
        "constitutive step (one plate, per call): " + _joined(con, "_one_plate_us", ".2f") + " us",
        f"constitutive step (batch of {con['batch_channels']} channels, ns/channel): "
        + _joined(con, "_batch_ns_per_channel", ".1f"),
    ]
    for r in res["mesh"].values():
        lines.append(
            f"mesh, {r['facets']} facets: "
            + ", ".join(
                f"{b} {r[f'{b}_us']:.0f} us ({r[f'{b}_ns_per_facet']:.1f} ns/facet)"
                for b in ("numpy", "jax")
                if f"{b}_us" in r
            )
        )
    for b, r in res["batch"].items():
        lines.append(
            f"batch {b}: "
            + ", ".join(
                f"N={n}: {v['step_us']:.0f} us/step ({v['us_per_foot']:.3g} us/foot)"
                for n, v in r.items()
            )
        )
    sp = res["speedup"]
    lines.append(
        f"single-foot loop: {sp['single_foot_loop_us_per_foot']:.1f} us/foot; batch_speedup_1e4 = "
        f"{res['batch_speedup_1e4']:.0f} (numpy)"
        + "".join(
            f", {sp[k]:.0f} ({k.removeprefix('speedup_')})"
            for k in sp
            if k.startswith("speedup_") and k != "speedup_numpy"
        )
    )
    lines.append("single foot per step (us): " + _joined(res["single_foot"], "_us", ".2f"))
    mj = res["mujoco"]
    with_contact = (mj.get("details") or {}).get("ratio_with_contact")
    lines.append(
        f"mujoco_overhead_ratio: {mj['ratio']}"
        + (f" (step with the contact: {with_contact:.3f})" if with_contact else "")
        + (f" ({mj['note']})" if mj.get("note") else "")
    )
    lines += _robot_lines(res.get("robots", {}))
    for k, r in res["roofline"].items():
        fb = "".join(
            f", {kind} functions {r[f'functions_{kind}_ns']:.1f} ns"
            for kind in ("numpy", "scalar")
            if f"functions_{kind}_ns" in r
        )
        lines.append(
            f"roofline {k}: {r['bytes']:.0f} B, {r['flops']:.0f} flop, "
            f"limit {r['limit_ns']:.2f} ns ({r['bound']}){fb}; measured/limit: "
            + ", ".join(f"{b} {v:.3f}" for b, v in r["ratio_to_limit"].items())
        )
    lines.append(f"total {res['seconds']:.1f} s")
    return lines


def _robot_lines(rob: dict[str, Any]) -> list[str]:
    """Robot-steps per second of the couplings (:func:`bench_robots`)."""
    out = []
    names = {"cpu_mud": "CPU coupling with mud", "mjx_mud": "MJX with mud",
             "mjx_no_mud": "MJX without mud"}  # fmt: skip
    for key, name in names.items():
        if key in rob:
            where = f" ({rob.get('device')}, {rob.get('dtype')})" if key != "cpu_mud" else ""
            out.append(
                f"robot-steps/s, {name}{where}: "
                + ", ".join(f"N={n}: {v['robot_steps_per_s']:.3g}" for n, v in rob[key].items())
            )
    if rob.get("note"):
        out.append(f"robots: {rob['note']}")
    return out
