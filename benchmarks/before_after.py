"""Before/after a rewrite: the same measurements on two source trees, alternated.

Run from the checkout, with the old tree checked out beside it::

    git worktree add /tmp/old ecac30f
    python benchmarks/before_after.py --old-src /tmp/old/src [--rounds 2] [--budget 0.1]
        [--json FILE]

Each round runs one process per tree (``PYTHONPATH`` set to its ``src``), old then new, so
both see about the same load on the machine; the best of the rounds is kept per number.
It prints a markdown table (times, and new/old: above 1 means slower) and the ratio of
each round's pair (old and new measured one after the other) to show the spread.

``--clock thread`` times with the CPU time of the calling thread instead of wall time:
on a shared machine it drops the time other jobs hold the core, but it misses work on
other threads, so it is meaningful for the single-threaded paths only (not for numba's
``prange`` loops or JAX, whose XLA runs on its own threads).

The whole-foot measurements (``BatchedMud``, ``FastMudFoot``, ``MudTerrain.step``,
``simulate``) run the harness's own functions (:mod:`harness.feet`) on both trees: the
public API they call did not change. The constitutive step is timed per tree, because the
paths differ: before the one-physics rewrite (commit ``ecac30f``), a fused numpy kernel
(``backends.kernels.fused_step``), a hand-written float kernel
(``kernels.scalar_channel_step``) and its numba compilation (``backends.numba_kernels``);
after it, the one ``constitutive.kernel.channel_update`` on numpy arrays, on Python floats
(``xp=pyfloat``) and compiled by ``backends.numba.compile_scalar``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import harness._timing
import numpy as np
from harness._timing import best, block, have

HERE = Path(__file__).resolve().parent
M = 300_000  # channels in the batched constitutive step
LABELS = {
    "step_one_plate_us": "`constitutive.step`, one channel, per call [us]",
    "step_batch_ns": "`constitutive.step`, 300,000 channels [ns/channel]",
    "kernel_batch_ns": "unvalidated numpy kernel (before: `fused_step`; after: `channel_update`), 300,000 channels [ns/channel]",
    "float_one_plate_us": "Python floats (before: `scalar_channel_step`; after: `on_floats(channel_update)`), per call [us]",
    "numba_one_plate_us": "numba, one channel from arrays, per call [us]",
    "numba_namedtuple_us": "numba, `compile_scalar(channel_update)` called with named tuples [us]",
    "numba_batch_ns": "numba, prange loop over 300,000 channels [ns/channel]",
    "jax_one_plate_us": "JAX `step`, one channel, per call [us]",
    "jax_batch_ns": "JAX `step`, 300,000 channels [ns/channel]",
}


def _constitutive(which: str, budget: float) -> dict[str, float]:
    import mudrft
    from mudrft.constitutive import initial_state, step

    p = mudrft.paper_parameters(0.25)
    rng = np.random.default_rng(1)
    bst = initial_state((M,))
    g, gd = rng.uniform(0.0, 0.5, M), rng.normal(size=M)
    st = initial_state()
    out = {
        "step_one_plate_us": 1e6 * best(lambda: step(p, st, 0.1, 1.0, 1e-3), budget=budget),
        "step_batch_ns": 1e9 * best(lambda: step(p, bst, g, gd, 1e-3), budget=budget) / M,
    }
    if which == "old":
        from mudrft.backends import kernels

        c = kernels.channel_constants(p)
        row = [float(v) for v in kernels.constant_rows(c)]
        cs = [0.0] * 5
        out["kernel_batch_ns"] = (
            1e9 * best(lambda: kernels.fused_step(c, bst, g, gd, 1e-3), budget=budget) / M
        )
        out["float_one_plate_us"] = 1e6 * best(
            lambda: kernels.scalar_channel_step(row, 0, cs, 0, 0.1, 1.0, 1e-3, 1.0, 1.0),
            budget=budget,
        )
        if have("numba"):
            from mudrft.backends.numba_kernels import compiled

            nb = compiled()
            rows = np.asarray(kernels.constant_rows(c), dtype=float)
            s1, sm, tot = np.zeros(5), np.zeros(5 * M), np.zeros(M)
            one, batch = nb["channel_step"], nb["channel_batch"]
            out["numba_one_plate_us"] = 1e6 * best(
                lambda: one(rows, 0, s1, 0, 0.1, 1.0, 1e-3, 1.0, 1.0), budget=budget
            )
            out["numba_batch_ns"] = (
                1e9 * best(lambda: batch(rows, sm, g, gd, 1e-3, 1.0, tot), budget=budget) / M
            )
    else:
        from mudrft.constitutive import kernel
        from mudrft.constitutive.state import ChannelState

        try:  # since the float specialization: what one foot on floats runs
            from mudrft._specialize import on_floats

            update = on_floats(kernel.channel_update)
        except ImportError:
            from mudrft._xp import pyfloat

            def update(*a: Any) -> Any:
                return kernel.channel_update(*a, xp=pyfloat)

        c = kernel.channel_constants(p)
        cf = kernel.ChannelConstants(*(float(v) for v in c))
        sf = ChannelState(*[0.0] * len(ChannelState._fields))
        out["kernel_batch_ns"] = (
            1e9 * best(lambda: kernel.channel_update(c, bst, g, gd, 1e-3), budget=budget) / M
        )
        out["float_one_plate_us"] = 1e6 * best(
            lambda: update(cf, sf, 0.1, 1.0, 1e-3), budget=budget
        )
        if have("numba"):
            from harness.physics import _numba_drivers

            upd, one, batch = _numba_drivers()
            n = len(ChannelState._fields)
            row, s1, sm, tot = np.array(cf, dtype=float), np.zeros(n), np.zeros((M, n)), np.zeros(M)
            out["numba_one_plate_us"] = 1e6 * best(
                lambda: one(row, s1, 0.1, 1.0, 1e-3), budget=budget
            )
            out["numba_namedtuple_us"] = 1e6 * best(
                lambda: upd(cf, sf, 0.1, 1.0, 1e-3, 1.0, 1.0), budget=budget
            )
            out["numba_batch_ns"] = (
                1e9 * best(lambda: batch(row, sm, g, gd, 1e-3, tot), budget=budget) / M
            )
    if have("jax"):
        import jax.numpy as jnp

        from mudrft.backends import jax as mjax

        jp, js, jsm = mjax.to_jax(p), mjax.initial_state(), mjax.initial_state((M,))
        gj, gdj = jnp.asarray(g), jnp.asarray(gd)
        out["jax_one_plate_us"] = 1e6 * best(
            lambda: mjax.step(jp, js, 0.1, 1.0, 1e-3)[1].total, budget=budget, sync=block
        )
        out["jax_batch_ns"] = (
            1e9
            * best(lambda: mjax.step(jp, jsm, gj, gdj, 1e-3)[1].total, budget=budget, sync=block)
            / M
        )
    return out


def measure(which: str, budget: float) -> dict[str, float]:
    """Every number of one tree (the ``mudrft`` on ``sys.path``); ``which`` is old or new."""
    from harness.feet import BATCH_SIZES, batch_time, bench_single_foot

    out = _constitutive(which, budget)
    for b in ["numpy"] + [b for b in ("numba", "jax") if have(b)]:
        for n in BATCH_SIZES:
            out[f"batch_{b}_{n}_us_per_foot"] = 1e6 * batch_time(b, n, budget) / n
    single = bench_single_foot(True, budget, None)
    out.update({k: v for k, v in single.items() if k.endswith("_us")})
    return out


def _label(key: str) -> str:
    if key in LABELS:
        return LABELS[key]
    if key.startswith("batch_"):
        _, b, n, _ = key.split("_", 3)
        return f"`BatchedMud` {b}, {int(n):,} feet [us/foot]"
    names = {
        "mud_terrain_us": "`MudTerrain.step`, one flat foot [us]",
        "fast_python_us": "`FastMudFoot` python, per step [us]",
        "fast_numba_us": "`FastMudFoot` numba, per step [us]",
        "simulate_us": "`simulate`, flat foot, gait, per step [us]",
    }
    return names.get(key, key)


def _fmt(v: float | None) -> str:
    return "-" if v is None else f"{v:.3g}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old-src", help="the old tree's src/ directory")
    ap.add_argument("--new-src", default=str(HERE.parent / "src"), help="the new tree's src/")
    ap.add_argument("--rounds", type=int, default=2, help="alternated rounds per tree")
    ap.add_argument("--budget", type=float, default=0.1, help="timing budget per number [s]")
    ap.add_argument("--json", help="write both trees' numbers to this JSON file")
    ap.add_argument("--clock", choices=("wall", "thread"), default="wall", help="see above")
    ap.add_argument("--measure", choices=("old", "new"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.measure:
        if args.clock == "thread":
            harness._timing.CLOCK = time.thread_time
        print(json.dumps(measure(args.measure, args.budget)))
        return 0
    if not args.old_src:
        ap.error("--old-src is required")
    runs: dict[str, list[dict[str, float]]] = {"old": [], "new": []}
    loads = []
    for r in range(args.rounds):
        for which, src in (("old", args.old_src), ("new", args.new_src)):
            env = {**os.environ, "PYTHONPATH": f"{Path(src).resolve()}{os.pathsep}{HERE}"}
            print(f"round {r + 1}: {which} ({src})", file=sys.stderr, flush=True)
            cmd = [sys.executable, __file__, "--measure", which, "--budget", str(args.budget)]
            cmd += ["--clock", args.clock]
            done = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True)
            runs[which].append(json.loads(done.stdout.strip().splitlines()[-1]))
            loads.append(os.getloadavg()[0])
    best_of = {w: {k: min(r[k] for r in rs if k in r) for k in rs[0]} for w, rs in runs.items()}
    keys = list(dict.fromkeys([*best_of["old"], *best_of["new"]]))
    print(f"clock: {args.clock}; load average during the runs: {min(loads):.1f}-{max(loads):.1f}")
    print("| what | before | after | after/before | per round |\n|---|---:|---:|---:|---:|")
    for k in keys:
        o, n = best_of["old"].get(k), best_of["new"].get(k)
        ratio = f"{n / o:.2f}" if o and n else "-"
        pairs = sorted(
            b[k] / a[k] for a, b in zip(runs["old"], runs["new"], strict=True) if k in a and k in b
        )
        spread = f"{pairs[0]:.2f}-{pairs[-1]:.2f}" if pairs else "-"
        print(f"| {_label(k)} | {_fmt(o)} | {_fmt(n)} | {ratio} | {spread} |")
    if args.json:
        Path(args.json).write_text(
            json.dumps({"runs": runs, "best": best_of, "load": loads}, indent=2) + "\n"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
