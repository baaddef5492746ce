r"""The roofline estimate: work per unit of the three kernels against the machine's limits.

Work per unit (decision D78; the count is in docs/performance.md): ``bytes`` is the
minimal DRAM traffic of a one-pass kernel (state read and written, inputs and outputs,
per-foot constants not cached); ``flops`` the arithmetic operations, with every
transcendental function (exp, expm1, tanh, pow, acos, atan2, sqrt, sin, cos) counted as
``TRANSCENDENTAL_FLOPS`` operations, about what a vectorized libm spends on one. These are
properties of the model's equations, not of an implementation: the one-physics rewrite
did not change them.

>>> ROOFLINE["channel_step"]["flops"] > 0
True
"""

from __future__ import annotations

from typing import Any

__all__ = ["FUNCTION_CALLS", "ROOFLINE", "TRANSCENDENTAL_FLOPS", "roofline"]

TRANSCENDENTAL_FLOPS = 15
ROOFLINE: dict[str, dict[str, float]] = {
    # state 5 doubles in and out, gamma and rate in, stress out, 12 constants per channel
    # (the fields of ChannelConstants; the fused kernel before the rewrite carried 13)
    "channel_step": {"bytes": (5 + 5 + 2 + 1 + 12) * 8, "basic": 52, "transcendental": 9},
    # z of three vertices, normal (3), area in; 3 force components accumulated in registers
    "facet_step": {"bytes": (3 + 3 + 1) * 8, "basic": 62, "transcendental": 1},
    # 24 constants (horizontal and vertical channels, the numba backend's constants row),
    # 19-double foot state in/out, position and velocity in, 7 outputs
    "foot_step": {
        "bytes": 2 * 12 * 8 + (19 + 19 + 6 + 7) * 8,
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


def roofline(results: dict[str, Any]) -> dict[str, Any]:
    """Limits of the three kernels on this machine and the measured fraction of them.

    The limit time per unit is ``max(bytes / bandwidth, flops / peak)`` with the copy
    bandwidth and the matmul peak measured in the same run; the ratio is limit time over
    measured time (1 = at the machine's limit).

    Parameters
    ----------
    results : dict
        Output of ``run_benchmarks`` (needs ``limits`` and the kernel timings; ``limits``
        has ``copy_GBps`` [GB/s] and ``matmul_GFLOPs`` [GFLOP/s]).

    Returns
    -------
    dict
        Per kernel: ``bytes``, ``flops``, ``intensity`` [flop/B], ``limit_ns`` [ns],
        ``bound`` ("memory" or "compute"), ``measured_ns`` and ``ratio_to_limit`` per
        backend, and ``functions_{numpy,scalar}_ns`` (the elementary functions alone) when
        ``results["functions"]`` has them.
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
        largest = max(res, key=int)
        measured["foot_step"][b] = 1e3 * res[largest]["us_per_foot"]
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
