"""Benchmarks of whole feet in mud: batches, the single-foot paths, simulate, MuJoCo.

* ``bench_batches``: :class:`mudrft.backends.batch.BatchedMud` steps of 1, 1e3 and 1e5 flat
  feet on the numpy, numba and JAX backends (JAX: device-resident state, no host copies);
* ``bench_speedup``: ``batch_speedup_1e4``, the time per foot of a Python loop over
  single-foot :meth:`mudrft.MudTerrain.step` calls divided by the time per foot of one
  batched call of 10,000 feet, in the same run;
* ``bench_single_foot``: one flat foot per step through ``MudTerrain.step`` (Python floats),
  :class:`mudrft.backends.BatchedMud` of one foot on numba, and
  :func:`mudrft.simulate` of the paper's gait divided by its number of steps;
* ``bench_mujoco``: ``mujoco_overhead_ratio`` from :func:`.mujoco_cost.mujoco_overhead_ratio`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._timing import Progress, best, block, have, say

__all__ = ["BATCH_SIZES", "bench_batches", "bench_mujoco", "bench_single_foot", "bench_speedup"]

#: Feet per BatchedMud step.
BATCH_SIZES = (1, 1000, 100_000)
#: Feet in the batched call of ``batch_speedup_1e4``.
SPEEDUP_FEET = 10_000


def _backends() -> list[str]:
    return ["numpy"] + [b for b in ("numba", "jax") if have(b)]


def moving_feet(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Tip positions 1-3 cm deep [m] and velocities in every direction [m/s], each (n, 3)."""
    rng = np.random.default_rng(seed)
    pos = np.column_stack(
        [rng.uniform(-0.01, 0.01, n), rng.uniform(-0.01, 0.01, n), -rng.uniform(0.01, 0.03, n)]
    )
    vel = rng.normal(scale=0.05, size=(n, 3))
    return pos, vel


def batch_time(backend: str, n: int, budget: float) -> float:
    """Seconds per ``BatchedMud.step`` of ``n`` flat feet on ``backend``, dt = 1 ms."""
    import mudrft
    from mudrft.backends.batch import BatchedMud

    pos, vel = moving_feet(n)
    sim = BatchedMud(
        mudrft.paper_mud(0.3),
        mudrft.feet.Flat(),
        n,
        position=pos + np.array([0, 0, 0.001]),
        backend=backend,
    )
    sim.step(pos, vel, 1e-3)
    if backend != "jax":
        return best(lambda: sim.step(pos, vel, 1e-3), budget=budget)
    import jax.numpy as jnp

    pj, vj = jnp.asarray(pos), jnp.asarray(vel)
    holder = {"st": sim._jst}

    def run() -> Any:
        holder["st"], (f, _, _) = sim._jax_step(holder["st"], pj, vj, 1e-3)
        return f

    return best(run, budget=budget, sync=block)


def bench_batches(quick: bool, budget: float, progress: Progress) -> dict[str, Any]:
    """Per backend and batch size: ``step_us`` [us per step] and ``us_per_foot`` [us]."""
    out: dict[str, Any] = {}
    for b in _backends():
        res: dict[str, Any] = {}
        for n in BATCH_SIZES:
            t = batch_time(b, n, budget)
            res[str(n)] = {"step_us": 1e6 * t, "us_per_foot": 1e6 * t / n}
        out[b] = res
        say(progress, f"  batches of 1, 1e3, 1e5 feet, {b}: done")
    return out


def single_foot_loop_time(k: int, budget: float) -> float:
    """Seconds per foot of a Python loop over ``k`` single-foot ``MudTerrain.step`` calls."""
    import mudrft

    foot = mudrft.feet.Flat()
    terrain = mudrft.MudTerrain(mudrft.paper_mud(0.3))
    pos, vel = moving_feet(k)
    states = [terrain.initial_state(foot, p + np.array([0, 0, 0.001])) for p in pos]

    def loop() -> None:
        for i in range(k):
            states[i], _ = terrain.step(foot, states[i], pos[i], vel[i], 1e-3)

    return best(loop, budget=budget, repeat=3) / k


def bench_speedup(quick: bool, budget: float, progress: Progress) -> dict[str, Any]:
    """``batch_speedup_1e4`` of every backend (see module docstring).

    Returns
    -------
    dict
        ``single_foot_loop_us_per_foot`` [us], ``batch_1e4_{backend}_us_per_foot`` [us] and
        ``speedup_{backend}`` [-].
    """
    loop = single_foot_loop_time(200 if quick else 1000, budget)
    out: dict[str, Any] = {"single_foot_loop_us_per_foot": 1e6 * loop}
    for b in _backends():
        t = batch_time(b, SPEEDUP_FEET, budget) / SPEEDUP_FEET
        out[f"batch_1e4_{b}_us_per_foot"] = 1e6 * t
        out[f"speedup_{b}"] = loop / t
    say(progress, "  batch speedup at 1e4 feet: done")
    return out


def bench_single_foot(quick: bool, budget: float, progress: Progress) -> dict[str, Any]:
    """One flat foot per step [us]: ``mud_terrain_us``, ``one_numba_us``, ``simulate_us``.

    ``mud_terrain_us`` is :meth:`mudrft.MudTerrain.step` (Python floats, validated),
    ``one_numba_us`` a :class:`~mudrft.backends.BatchedMud` of one foot on numba (the
    single-foot stepper for per-step coupling).

    ``simulate_us`` is one :func:`mudrft.simulate` of the paper's gait at 0.2 m/s (651
    samples, dt = 1 ms, W = 25 %) divided by its number of steps: the terrain step plus
    the loop's own work (trajectory, result arrays), validation done once per run.
    """
    import mudrft
    from mudrft.backends import BatchedMud

    foot, mud = mudrft.feet.Flat(), mudrft.paper_mud(0.3)
    terrain = mudrft.MudTerrain(mud)
    pos = np.array([0.001, 0.0, -0.01])
    vel = np.array([0.02, 0.01, -0.03])
    st = terrain.initial_state(foot, np.zeros(3))
    out: dict[str, Any] = {
        "mud_terrain_us": 1e6 * best(lambda: terrain.step(foot, st, pos, vel, 1e-3), budget=budget)
    }
    one = BatchedMud(terrain, foot, 1, backend="numba")
    out["one_numba_us"] = 1e6 * best(lambda: one.step(pos, vel, 1e-3), budget=budget)
    gait = mudrft.gait(speed=0.2)
    mud25 = mudrft.paper_mud(0.25)
    steps = len(gait.time) - 1
    t = best(lambda: mudrft.simulate(foot, mud25, gait), budget=4 * budget, repeat=3)
    out["simulate_us"] = 1e6 * t / steps
    out["simulate_steps"] = steps
    say(progress, "  single foot and simulate: done")
    return out


def bench_mujoco(quick: bool, progress: Progress) -> dict[str, Any]:
    """``mujoco_overhead_ratio`` (with mud / without) from the MuJoCo integration's benchmark.

    Returns
    -------
    dict
        ``ratio`` (None with a ``note`` when MuJoCo is missing or the benchmark failed),
        ``source`` and the benchmark's own ``details``.
    """
    if not have("mujoco"):
        return {"ratio": None, "note": "mujoco is not installed"}
    where = "benchmarks/harness/mujoco_cost.py: mujoco_overhead_ratio"
    try:
        from .mujoco_cost import mujoco_overhead_ratio

        res = mujoco_overhead_ratio(seconds=0.5 if quick else 2.0)
    except Exception as exc:  # a broken optional benchmark must not sink the others
        return {"ratio": None, "note": f"{where} failed: {type(exc).__name__}: {exc}"}
    ratio = res.get("mujoco_overhead_ratio", res.get("ratio"))
    say(progress, "  MuJoCo coupling overhead: done")
    return {"ratio": None if ratio is None else float(ratio), "source": where, "details": res}
