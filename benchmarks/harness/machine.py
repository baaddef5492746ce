"""The machine the benchmarks ran on, and its limits: bandwidth, peak rate, libm costs."""

from __future__ import annotations

import importlib
import math
import os
import platform
from collections.abc import Callable
from typing import Any

import numpy as np

from ._timing import best, have, timed

__all__ = ["machine_info", "measure_bandwidth", "measure_functions", "measure_peak_flops"]


def machine_info() -> dict[str, Any]:
    """CPU model, logical CPUs, memory [GiB], load average, library versions, JAX devices."""
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
        # other processes share the cores: multi-threaded timings depend on it
        info["load_average_1min"] = round(os.getloadavg()[0], 2)
    for mod in ("numba", "jax"):
        if have(mod):
            info[mod] = importlib.import_module(mod).__version__
    if have("jax"):
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
        convention, for ``a = b + s c`` done by numpy in two passes) [GB/s];
        ``array_MiB`` [MiB].
    """
    a = np.ones(n)
    b = np.empty(n)
    c = np.full(n, 2.0)
    np.copyto(b, a)
    t_copy = min(timed(lambda: np.copyto(b, a)) for _ in range(repeat))

    def triad() -> None:
        np.multiply(c, 3.0, out=b)
        np.add(b, a, out=b)

    triad()
    t_triad = min(timed(triad) for _ in range(repeat))
    return {
        "copy_GBps": 2 * n * 8 / t_copy / 1e9,
        "triad_GBps": 3 * n * 8 / t_triad / 1e9,
        "array_MiB": n * 8 / 2**20,
    }


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
    t = min(timed(lambda: a @ b) for _ in range(repeat))
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
    """Cost of the elementary functions the physics calls [ns per evaluation].

    Parameters
    ----------
    n : int, keyword-only
        Values per measurement, uniform in (0.01, 2).
    budget : float, keyword-only
        Timing budget per function [s].

    Returns
    -------
    dict
        ``numpy``: vectorized throughput (SIMD where numpy has it); ``scalar``: one value at
        a time in a numba loop (the libm the compiled scalar physics uses), minus the cost of
        the empty loop; empty when numba is not installed.
    """
    x = np.random.default_rng(0).uniform(0.01, 2.0, n)
    o = np.empty_like(x)
    out: dict[str, dict[str, float]] = {"numpy": {}, "scalar": {}}
    for name, fn in _NUMPY_FUNCTIONS.items():
        out["numpy"][name] = 1e9 * best(lambda fn=fn: fn(x, o), budget=budget) / n
    if have("numba"):
        import numba

        for name, expr in _SCALAR_SOURCE.items():
            src = f"def f(x):\n    s = 0.0\n    for v in x:\n        s += {expr}\n    return s\n"
            ns: dict[str, Any] = {"math": math}
            exec(src, ns)  # a tiny loop per function, compiled by numba
            f = numba.njit(ns["f"])
            out["scalar"][name] = 1e9 * best(lambda f=f: f(x), budget=budget) / n
        base = numba.njit(lambda x: x.sum())
        empty = 1e9 * best(lambda: base(x), budget=budget) / n
        out["scalar"] = {k: max(v - empty, 0.0) for k, v in out["scalar"].items()}
    return out
