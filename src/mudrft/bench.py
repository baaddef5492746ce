r"""Speed benchmarks of mudrft, and the machine's limits they are measured against.

``mudrft bench [--quick] [--json FILE]`` runs:

* the machine's limits: memory bandwidth (numpy copy and triad of arrays far larger than
  the caches) and peak floating-point rate (a large float64 matmul);
* the constitutive step of one plate (one channel) per call, on every backend, and the
  throughput of a large batch of channels;
* the surface integration of a mesh foot with about 1e3 and 1e5 facets;
* batches of 1, 1e3 and 1e5 flat feet (:class:`mudrft.backends.batch.BatchedMud`, numpy,
  numba and JAX backends; JAX on whatever device it has, GPU included);
* ``batch_speedup_1e4``: time per foot of a Python loop over single-foot
  :meth:`mudrft.MudTerrain.step` calls divided by time per foot in one batched call of
  10,000 feet, in the same run;
* the single-foot fast path (:class:`mudrft.backends.fast.FastMudFoot`) per step;
* ``mujoco_overhead_ratio``: time per biped step with mud divided by without, when the
  MuJoCo coupling provides a benchmark (``null`` with a note otherwise);
* a roofline estimate: bytes moved and floating-point operations per channel-step,
  facet-step and foot-step against the measured bandwidth and peak, and the ratio of the
  measured throughput to that limit.

Timings are the best of several repeats (robust to other load on the machine). The
library calls are the public ones; nothing here changes results.

Examples
--------
>>> import mudrft.bench as b
>>> b.ROOFLINE["channel_step"]["flops"] > 0
True
"""

from __future__ import annotations

import datetime as _dt
import importlib
import importlib.util
import os
import platform
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "FUNCTION_CALLS",
    "ROOFLINE",
    "machine_info",
    "measure_bandwidth",
    "measure_functions",
    "measure_peak_flops",
    "roofline",
    "run_benchmarks",
]

#: Work per unit of the three kernels (see docs/performance.md for the count).
#: ``bytes``: minimal DRAM traffic of a one-pass kernel (state read and written, inputs and
#: outputs, per-foot parameters not cached); ``flops``: arithmetic operations, with every
#: transcendental function (exp, expm1, tanh, pow, acos, atan2, sqrt, sin, cos) counted as
#: ``TRANSCENDENTAL_FLOPS`` operations, about what a vectorized libm spends on one.
TRANSCENDENTAL_FLOPS = 15
ROOFLINE: dict[str, dict[str, float]] = {
    # state 5 doubles in and out, gamma and rate in, stress out, 13 constants per channel
    "channel_step": {"bytes": (5 + 5 + 2 + 1 + 13) * 8, "basic": 52, "transcendental": 9},
    # z of three vertices, normal (3), area in; 3 force components accumulated in registers
    "facet_step": {"bytes": (3 + 3 + 1) * 8, "basic": 62, "transcendental": 1},
    # 3 channels + 19-double foot state in/out + position, velocity in + 7 outputs
    "foot_step": {
        "bytes": 3 * 13 * 8 + (19 + 19 + 6 + 7) * 8,
        "basic": 3 * 52 + 70,
        "transcendental": 3 * 9 + 8,
    },
}
for _v in ROOFLINE.values():
    _v["flops"] = _v["basic"] + TRANSCENDENTAL_FLOPS * _v["transcendental"]

#: Elementary functions each kernel calls (worst case: every tanh evaluated; the flat foot).
FUNCTION_CALLS: dict[str, dict[str, int]] = {
    "channel_step": {"exp": 3, "expm1": 1, "pow": 1, "tanh": 3},
    "facet_step": {"sqrt": 1},
    "foot_step": {
        "exp": 9,
        "expm1": 3,
        "pow": 3,
        "tanh": 9,
        "hypot": 1,
        "atan2": 2,
        "cos": 5,
        "sin": 1,
    },
}

#: Semi-sphere mesh resolutions giving 968 and 100,352 facets (8 r^2).
MESH_RESOLUTIONS = {"1e3": 11, "1e5": 112}
BATCH_SIZES = (1, 1000, 100_000)


# ---------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------
def _best(
    fn: Callable[..., Any],
    *,
    budget: float,
    repeat: int = 5,
    sync: Callable[[Any], Any] | None = None,
) -> float:
    """Best time per call [s]: ``repeat`` rounds of about ``budget / repeat`` s after a warm-up."""
    out = fn()
    if sync is not None:
        sync(out)
    t0 = time.perf_counter()
    out = fn()
    if sync is not None:
        sync(out)
    one = max(time.perf_counter() - t0, 1e-8)
    number = max(1, int(budget / repeat / one))
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            out = fn()
        if sync is not None:
            sync(out)
        best = min(best, (time.perf_counter() - t0) / number)
    return best


def _block(x: Any) -> Any:
    import jax

    return jax.block_until_ready(x)


def _have(mod: str) -> bool:
    return importlib.util.find_spec(mod) is not None


def _say(progress: Callable[[str], None] | None, msg: str) -> None:
    if progress is not None:
        progress(msg)


# ---------------------------------------------------------------------------------------
# the machine
# ---------------------------------------------------------------------------------------
def machine_info() -> dict[str, Any]:
    """CPU model, logical CPUs, memory, library versions and JAX devices of this machine."""
    info: dict[str, Any] = {
        "platform": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "logical_cpus": os.cpu_count(),
        "cpu_model": platform.processor() or "",
    }
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    info["cpu_model"] = line.split(":", 1)[1].strip()
                    break
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemTotal"):
                    info["memory_GiB"] = round(int(line.split()[1]) / 2**20, 1)
                    break
    except OSError:
        pass
    if hasattr(os, "getloadavg"):
        # other processes on the machine share its cores: multi-threaded timings depend on it
        info["load_average_1min"] = round(os.getloadavg()[0], 2)
    for mod in ("numba", "jax"):
        if _have(mod):
            info[mod] = importlib.import_module(mod).__version__
    if _have("jax"):
        import jax

        info["jax_devices"] = [str(d) for d in jax.devices()]
        info["jax_backend"] = jax.default_backend()
    return info


def measure_bandwidth(*, n: int = 2**26, repeat: int = 5) -> dict[str, float]:
    """Memory bandwidth [GB/s] from a numpy copy and a STREAM-like triad.

    Parameters
    ----------
    n : int, keyword-only
        Array length (float64); the default (512 MiB per array) is far beyond the caches.
    repeat : int, keyword-only
        Repeats; the best is kept.

    Returns
    -------
    dict
        ``copy_GBps`` (2 n 8 bytes moved per copy), ``triad_GBps`` (3 n 8 bytes, STREAM
        convention, for ``a = b + s c`` done by numpy in two passes) [GB/s].
    """
    a = np.ones(n)
    b = np.empty(n)
    c = np.full(n, 2.0)
    np.copyto(b, a)
    t_copy = min(_timed(lambda: np.copyto(b, a)) for _ in range(repeat))

    def triad() -> None:
        np.multiply(c, 3.0, out=b)
        np.add(b, a, out=b)

    triad()
    t_triad = min(_timed(triad) for _ in range(repeat))
    return {
        "copy_GBps": 2 * n * 8 / t_copy / 1e9,
        "triad_GBps": 3 * n * 8 / t_triad / 1e9,
        "array_MiB": n * 8 / 2**20,
    }


def _timed(fn: Callable[[], Any]) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def measure_peak_flops(*, n: int = 2048, repeat: int = 3) -> dict[str, float]:
    """Peak float64 rate [GFLOP/s] of a large matmul (2 n^3 operations), all cores (BLAS).

    Parameters
    ----------
    n : int, keyword-only
        Matrix size.
    repeat : int, keyword-only
        Repeats; the best is kept.
    """
    rng = np.random.default_rng(0)
    a = rng.random((n, n))
    b = rng.random((n, n))
    a @ b
    t = min(_timed(lambda: a @ b) for _ in range(repeat))
    return {"matmul_GFLOPs": 2.0 * n**3 / t / 1e9, "matmul_n": n}


_NUMPY_FUNCTIONS: dict[str, Callable[[np.ndarray, np.ndarray], Any]] = {
    "exp": lambda x, o: np.exp(x, out=o),
    "expm1": lambda x, o: np.expm1(x, out=o),
    "pow": lambda x, o: np.power(x, 0.53, out=o),
    "tanh": lambda x, o: np.tanh(x, out=o),
    "sqrt": lambda x, o: np.sqrt(x, out=o),
    "hypot": lambda x, o: np.hypot(x, 0.7, out=o),
    "atan2": lambda x, o: np.arctan2(x, 0.7, out=o),
    "cos": lambda x, o: np.cos(x, out=o),
    "sin": lambda x, o: np.sin(x, out=o),
}
_SCALAR_SOURCE = {
    "exp": "math.exp(-v)",
    "expm1": "math.expm1(v)",
    "pow": "v ** 0.53",
    "tanh": "math.tanh(v)",
    "sqrt": "math.sqrt(v)",
    "hypot": "math.hypot(v, 0.7)",
    "atan2": "math.atan2(v, 0.7)",
    "cos": "math.cos(v)",
    "sin": "math.sin(v)",
}


def measure_functions(*, n: int = 2**18, budget: float = 0.05) -> dict[str, dict[str, float]]:
    """Cost of the elementary functions the kernels call [ns per evaluation].

    ``numpy``: vectorized throughput on arrays of ``n`` values in (0.01, 2) (SIMD where numpy
    has it); ``scalar``: one value at a time in a numba loop (the libm the scalar kernels use),
    when numba is installed.
    """
    x = np.random.default_rng(0).uniform(0.01, 2.0, n)
    o = np.empty_like(x)
    out: dict[str, dict[str, float]] = {"numpy": {}, "scalar": {}}
    for name, fn in _NUMPY_FUNCTIONS.items():
        out["numpy"][name] = 1e9 * _best(lambda fn=fn: fn(x, o), budget=budget) / n
    if _have("numba"):
        import math

        import numba

        for name, expr in _SCALAR_SOURCE.items():
            src = f"def f(x):\n    s = 0.0\n    for v in x:\n        s += {expr}\n    return s\n"
            ns: dict[str, Any] = {"math": math}
            exec(src, ns)  # a tiny loop per function, compiled by numba
            f = numba.njit(ns["f"])
            loop = 1e9 * _best(lambda f=f: f(x), budget=budget) / n
            out["scalar"][name] = loop
        base = numba.njit(lambda x: x.sum())
        empty = 1e9 * _best(lambda: base(x), budget=budget) / n
        out["scalar"] = {k: max(v - empty, 0.0) for k, v in out["scalar"].items()}
    return out


# ---------------------------------------------------------------------------------------
# the benchmarks
# ---------------------------------------------------------------------------------------
def _bench_constitutive(quick: bool, budget: float, progress: Any) -> dict[str, Any]:
    from .backends import kernels
    from .constitutive import initial_state, step
    from .parameters import paper_parameters

    p = paper_parameters(0.25)
    out: dict[str, Any] = {}
    st = initial_state()
    out["numpy_one_plate_us"] = 1e6 * _best(lambda: step(p, st, 0.1, 1.0, 1e-3), budget=budget)
    row = [float(v) for v in kernels.constant_rows(kernels.channel_constants(p))]
    cs = [0.0, 0.0, 0.0, 0.0, 0.0]
    out["python_scalar_one_plate_us"] = 1e6 * _best(
        lambda: kernels.scalar_channel_step(row, 0, cs, 0, 0.1, 1.0, 1e-3, 1.0, 1.0), budget=budget
    )
    m = 30_000 if quick else 300_000
    out["batch_channels"] = m
    rng = np.random.default_rng(1)
    c = kernels.channel_constants(p)
    bst = initial_state((m,))
    g = rng.uniform(0.0, 0.5, m)
    gd = rng.normal(size=m)
    t = _best(lambda: kernels.fused_step(c, bst, g, gd, 1e-3), budget=budget)
    out["numpy_batch_ns_per_channel"] = 1e9 * t / m
    if _have("numba"):
        from .backends.numba_kernels import compiled

        nb = compiled()
        rows = np.asarray(kernels.constant_rows(c), dtype=float)
        st1 = np.zeros(5)
        nb["channel_step"](rows, 0, st1, 0, 0.1, 1.0, 1e-3, 1.0, 1.0)
        out["numba_one_plate_us"] = 1e6 * _best(
            lambda: nb["channel_step"](rows, 0, st1, 0, 0.1, 1.0, 1e-3, 1.0, 1.0), budget=budget
        )
        stm = np.zeros(5 * m)
        tot = np.zeros(m)
        t = _best(lambda: nb["channel_batch"](rows, stm, g, gd, 1e-3, 1.0, tot), budget=budget)
        out["numba_batch_ns_per_channel"] = 1e9 * t / m
    if _have("jax"):
        from .backends import jax as mjax

        jp = mjax.to_jax(p)
        js = mjax.initial_state()
        out["jax_one_plate_us"] = 1e6 * _best(
            lambda: mjax.step(jp, js, 0.1, 1.0, 1e-3)[1].total, budget=budget, sync=_block
        )
        jsm = mjax.initial_state((m,))
        import jax.numpy as jnp

        gj, gdj = jnp.asarray(g), jnp.asarray(gd)
        t = _best(lambda: mjax.step(jp, jsm, gj, gdj, 1e-3)[1].total, budget=budget, sync=_block)
        out["jax_batch_ns_per_channel"] = 1e9 * t / m
    _say(progress, "  constitutive step: done")
    return out


def _bench_mesh(quick: bool, budget: float, progress: Any) -> dict[str, Any]:
    import warnings

    from .feet.mesh import MeshFoot
    from .feet.meshgen import semisphere_mesh
    from .feet.surface import integrate_prepared

    out: dict[str, Any] = {}
    s = np.array([800.0, 300.0, 2000.0])

    def numpy_call(prep: Any) -> Any:
        return integrate_prepared(prep, 0.013, s, 0.4, trailing=True)

    for label, res in MESH_RESOLUTIONS.items():
        v, f = semisphere_mesh(0.045, 0.026, resolution=res)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            foot = MeshFoot(v, f, trailing=True)
        m = len(foot)
        prep = foot._prep
        t = _best(lambda prep=prep: numpy_call(prep), budget=budget)
        r: dict[str, Any] = {"facets": m, "numpy_us": 1e6 * t, "numpy_ns_per_facet": 1e9 * t / m}
        if _have("jax"):
            import jax

            from .backends import jax as mjax
            from .feet.surface import PreparedTriangles

            xp = mjax.safe_namespace()
            jprep = PreparedTriangles(*(xp.asarray(a) for a in prep))
            fn = jax.jit(
                lambda pr, d, st, h, xp=xp: integrate_prepared(pr, d, st, h, trailing=True, xp=xp)
            )
            t = _best(
                lambda jprep=jprep, fn=fn: fn(jprep, 0.013, s, 0.4), budget=budget, sync=_block
            )
            r["jax_us"] = 1e6 * t
            r["jax_ns_per_facet"] = 1e9 * t / m
        out[label] = r
        _say(progress, f"  mesh integration, {m} facets: done")
    return out


def _moving_feet(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Tip positions in the mud (1-3 cm deep) and velocities in every direction, (n, 3)."""
    rng = np.random.default_rng(seed)
    pos = np.column_stack(
        [rng.uniform(-0.01, 0.01, n), rng.uniform(-0.01, 0.01, n), -rng.uniform(0.01, 0.03, n)]
    )
    vel = rng.normal(scale=0.05, size=(n, 3))
    return pos, vel


def _batch_time(backend: str, n: int, budget: float) -> float:
    """Seconds per BatchedMud step of n flat feet (JAX: device-resident step, no copies)."""
    from .backends.batch import BatchedMud
    from .feet import Flat
    from .parameters import paper_mud

    pos, vel = _moving_feet(n)
    sim = BatchedMud(
        paper_mud(0.3), Flat(), n, position=pos + np.array([0, 0, 0.001]), backend=backend
    )
    sim.step(pos, vel, 1e-3)
    if backend != "jax":
        return _best(lambda: sim.step(pos, vel, 1e-3), budget=budget)
    import jax.numpy as jnp

    pj, vj = jnp.asarray(pos), jnp.asarray(vel)
    holder = {"st": sim._jst}

    def run() -> Any:
        holder["st"], (f, _, _) = sim._jax_step(holder["st"], pj, vj, 1e-3)
        return f

    return _best(run, budget=budget, sync=_block)


def _bench_batches(quick: bool, budget: float, progress: Any) -> dict[str, Any]:
    backends = ["numpy"] + [b for b in ("numba", "jax") if _have(b)]
    out: dict[str, Any] = {}
    for b in backends:
        res: dict[str, Any] = {}
        for n in BATCH_SIZES:
            t = _batch_time(b, n, budget)
            res[str(n)] = {"step_us": 1e6 * t, "us_per_foot": 1e6 * t / n}
        out[b] = res
        _say(progress, f"  batches of 1, 1e3, 1e5 feet, {b}: done")
    return out


def _single_foot_loop_time(k: int, budget: float) -> float:
    """Seconds per foot of a Python loop over k single-foot MudTerrain.step calls."""
    from .feet import Flat
    from .parameters import paper_mud
    from .terrains import MudTerrain

    foot = Flat()
    terrain = MudTerrain(paper_mud(0.3))
    pos, vel = _moving_feet(k)
    states = [terrain.initial_state(foot, p + np.array([0, 0, 0.001])) for p in pos]

    def loop() -> None:
        for i in range(k):
            states[i], _ = terrain.step(foot, states[i], pos[i], vel[i], 1e-3)

    return _best(loop, budget=budget, repeat=3) / k


def _bench_speedup(quick: bool, budget: float, progress: Any) -> dict[str, Any]:
    n = 10_000
    loop = _single_foot_loop_time(200 if quick else 1000, budget)
    out: dict[str, Any] = {"single_foot_loop_us_per_foot": 1e6 * loop}
    for b in ["numpy"] + [b for b in ("numba", "jax") if _have(b)]:
        t = _batch_time(b, n, budget) / n
        out[f"batch_1e4_{b}_us_per_foot"] = 1e6 * t
        out[f"speedup_{b}"] = loop / t
    _say(progress, "  batch speedup at 1e4 feet: done")
    return out


def _bench_fast(quick: bool, budget: float, progress: Any) -> dict[str, Any]:
    from .backends.fast import FastMudFoot
    from .feet import Flat
    from .parameters import paper_mud
    from .terrains import MudTerrain

    foot, mud = Flat(), paper_mud(0.3)
    terrain = MudTerrain(mud)
    pos = np.array([0.001, 0.0, -0.01])
    vel = np.array([0.02, 0.01, -0.03])
    st = terrain.initial_state(foot, np.zeros(3))
    out: dict[str, Any] = {
        "mud_terrain_us": 1e6 * _best(lambda: terrain.step(foot, st, pos, vel, 1e-3), budget=budget)
    }
    for b in ["python"] + (["numba"] if _have("numba") else []):
        ff = FastMudFoot(foot, terrain, backend=b)
        out[f"fast_{b}_us"] = 1e6 * _best(lambda ff=ff: ff.step(pos, vel, 1e-3), budget=budget)
    _say(progress, "  single-foot fast path: done")
    return out


def _mujoco_benchmark() -> tuple[Callable[..., Any] | None, str]:
    """Find a MuJoCo overhead benchmark: the integration's own, or the checkout's script."""
    names = ("mujoco_overhead_ratio", "overhead_ratio", "benchmark_overhead")
    for modname in ("mudrft.integrations.benchmark", "mudrft.integrations.mujoco"):
        try:
            mod = importlib.import_module(modname)
        except ImportError:
            continue
        for name in names:
            fn = getattr(mod, name, None)
            if callable(fn):
                return fn, f"{modname}.{name}"
    script = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_mujoco.py"
    if script.is_file():
        spec = importlib.util.spec_from_file_location("_mudrft_bench_mujoco", script)
        if spec is not None and spec.loader is not None:
            mod = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(mod)
            fn = getattr(mod, "mujoco_overhead_ratio", None)
            if callable(fn):
                return fn, f"{script}:mujoco_overhead_ratio"
    return None, "no MuJoCo overhead benchmark found (mudrft.integrations.mujoco has none)"


def _bench_mujoco(quick: bool, progress: Any) -> dict[str, Any]:
    if not _have("mujoco"):
        return {"ratio": None, "note": "mujoco is not installed"}
    fn, where = _mujoco_benchmark()
    if fn is None:
        return {"ratio": None, "note": where}
    try:
        res = fn(seconds=0.5 if quick else 2.0)
    except Exception as exc:  # a broken optional benchmark must not sink the others
        return {"ratio": None, "note": f"{where} failed: {type(exc).__name__}: {exc}"}
    res = dict(res) if isinstance(res, dict) else {"ratio": res}
    ratio = res.get("mujoco_overhead_ratio", res.get("ratio"))
    _say(progress, "  MuJoCo coupling overhead: done")
    return {"ratio": None if ratio is None else float(ratio), "source": where, "details": res}


def roofline(results: dict[str, Any]) -> dict[str, Any]:
    """Limits of the three kernels on this machine and the measured fraction of them.

    The limit time per unit is ``max(bytes / bandwidth, flops / peak)`` with the copy
    bandwidth and the matmul peak measured in the same run; the ratio is limit time over
    measured time (1 = at the machine's limit).

    Parameters
    ----------
    results : dict
        Output of :func:`run_benchmarks` (needs ``limits`` and the kernel timings).

    Returns
    -------
    dict
        Per kernel: bytes, flops, arithmetic intensity [flop/B], limit [ns], bound
        ("memory" or "compute"), and for each backend the measured time [ns] and ratio.
    """
    lim = results["limits"]
    bw = lim["copy_GBps"] * 1e9
    peak = lim["matmul_GFLOPs"] * 1e9
    measured: dict[str, dict[str, float]] = {"channel_step": {}, "facet_step": {}, "foot_step": {}}
    con = results.get("constitutive", {})
    for b in ("numpy", "numba", "jax"):
        if f"{b}_batch_ns_per_channel" in con:
            measured["channel_step"][b] = con[f"{b}_batch_ns_per_channel"]
    big = results.get("mesh", {}).get("1e5", {})
    for b in ("numpy", "jax"):
        if f"{b}_ns_per_facet" in big:
            measured["facet_step"][b] = big[f"{b}_ns_per_facet"]
    for b, res in results.get("batch", {}).items():
        measured["foot_step"][b] = 1e3 * res[str(BATCH_SIZES[-1])]["us_per_foot"]
    funcs = results.get("functions", {})
    out: dict[str, Any] = {}
    for k, w in ROOFLINE.items():
        t_mem = w["bytes"] / bw * 1e9
        t_cpu = w["flops"] / peak * 1e9
        limit = max(t_mem, t_cpu)
        row: dict[str, Any] = {
            "bytes": w["bytes"],
            "flops": w["flops"],
            "intensity": w["flops"] / w["bytes"],
            "limit_ns": limit,
            "bound": "memory" if t_mem >= t_cpu else "compute",
            "measured_ns": measured[k],
            "ratio_to_limit": {b: limit / t for b, t in measured[k].items()},
        }
        # a tighter bound for this code: the time its elementary functions alone take
        for kind in ("numpy", "scalar"):
            costs = funcs.get(kind, {})
            if costs and all(f in costs for f in FUNCTION_CALLS[k]):
                row[f"functions_{kind}_ns"] = sum(
                    n * costs[f] for f, n in FUNCTION_CALLS[k].items()
                )
        out[k] = row
    return out


def run_benchmarks(
    *, quick: bool = False, progress: Callable[[str], None] | None = None
) -> dict[str, Any]:
    """Run every benchmark and return the results (the JSON of ``mudrft bench``).

    Parameters
    ----------
    quick : bool, keyword-only
        Shorter timings, smaller bandwidth arrays and batches of channels (well under a
        minute on 2 cores); the sizes asked for (1e3/1e5 facets, 1, 1e3, 1e5 and 1e4 feet)
        are kept.
    progress : callable, keyword-only
        ``progress(message)`` after each stage (the CLI prints to stderr).

    Returns
    -------
    dict
        ``machine``, ``limits``, ``constitutive``, ``mesh``, ``batch``, ``speedup``,
        ``fast_single_foot``, ``mujoco``, ``roofline``, and the headline numbers
        ``batch_speedup_1e4`` (numpy backend) and ``mujoco_overhead_ratio`` (or None).
    """
    t_start = time.perf_counter()
    budget = 0.05 if quick else 0.4
    res: dict[str, Any] = {
        "schema": 1,
        "quick": bool(quick),
        "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    _say(progress, "mudrft bench: machine")
    res["machine"] = machine_info()
    res["jax_devices"] = res["machine"].get("jax_devices")
    res["limits"] = {
        **measure_bandwidth(n=2**25 if quick else 2**26, repeat=3 if quick else 5),
        **measure_peak_flops(n=1536 if quick else 2048, repeat=2 if quick else 3),
    }
    res["functions"] = measure_functions(n=2**16 if quick else 2**18, budget=budget / 2)
    _say(progress, "  bandwidth, peak and elementary functions: done")
    res["constitutive"] = _bench_constitutive(quick, budget, progress)
    res["mesh"] = _bench_mesh(quick, budget, progress)
    res["batch"] = _bench_batches(quick, budget, progress)
    res["speedup"] = _bench_speedup(quick, budget, progress)
    res["batch_speedup_1e4"] = res["speedup"]["speedup_numpy"]
    res["fast_single_foot"] = _bench_fast(quick, budget, progress)
    res["mujoco"] = _bench_mujoco(quick, progress)
    res["mujoco_overhead_ratio"] = res["mujoco"]["ratio"]
    res["roofline"] = roofline(res)
    res["seconds"] = time.perf_counter() - t_start
    if hasattr(os, "getloadavg"):
        res["machine"]["load_average_1min_end"] = round(os.getloadavg()[0], 2)
    return res


# ---------------------------------------------------------------------------------------
# command line
# ---------------------------------------------------------------------------------------
def summary_lines(res: dict[str, Any]) -> list[str]:
    """Human-readable summary of :func:`run_benchmarks` results."""
    m, lim = res["machine"], res["limits"]
    lines = [
        f"machine: {m.get('cpu_model', '?')}, {m.get('logical_cpus')} logical CPUs, "
        f"{m.get('memory_GiB', '?')} GiB, load average {m.get('load_average_1min', '?')}; "
        f"JAX devices: {res.get('jax_devices')}",
        f"limits: copy {lim['copy_GBps']:.1f} GB/s, triad {lim['triad_GBps']:.1f} GB/s, "
        f"matmul {lim['matmul_GFLOPs']:.1f} GFLOP/s",
        "constitutive step (one plate, per call): "
        + ", ".join(
            f"{k.replace('_one_plate_us', '')} {v:.2f} us"
            for k, v in res["constitutive"].items()
            if k.endswith("_one_plate_us")
        ),
        f"constitutive step (batch of {res['constitutive']['batch_channels']} channels): "
        + ", ".join(
            f"{k.replace('_batch_ns_per_channel', '')} {v:.1f} ns/channel"
            for k, v in res["constitutive"].items()
            if k.endswith("_ns_per_channel")
        ),
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
            f", {sp[k]:.0f} ({k[8:]})"
            for k in sp
            if k.startswith("speedup_") and k != "speedup_numpy"
        )
    )
    lines.append(
        "single foot per step: "
        + ", ".join(
            f"{k.replace('_us', '')} {v:.2f} us" for k, v in res["fast_single_foot"].items()
        )
    )
    mj = res["mujoco"]
    lines.append(
        f"mujoco_overhead_ratio: {mj['ratio']}" + (f" ({mj['note']})" if mj.get("note") else "")
    )
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
