r"""numba backend: the compiled loop over feet (:func:`mudrft.terrains.rows.run`, compiled by
:func:`mudrft._jit.jit`), multi-threaded from :data:`PARALLEL_MIN` feet on. Every foot of
:mod:`mudrft.feet` runs here.
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np

from .._jit import jit
from .._typing import FloatArray
from ..terrains.rows import N_FOOT, N_STATE, foot_step, run

__all__ = ["PARALLEL_MIN", "available", "feet_loop"]

#: Batches at least this large use the multi-threaded loop (smaller ones: one thread).
PARALLEL_MIN = 4096


def available() -> bool:
    """Whether numba can be imported (it is a core dependency of mudrft)."""
    return True


def _run_parallel(
    c: FloatArray, st: FloatArray, fst: FloatArray, pos: FloatArray, vel: FloatArray,
    dts: FloatArray, cfg: FloatArray, geom: FloatArray, up: FloatArray, mrow: FloatArray,
    out: FloatArray,
) -> None:  # fmt: skip
    """:func:`~mudrft.terrains.rows.run` with the feet spread over threads."""
    n = pos.shape[1]
    stride = 0 if c.shape[0] == 1 else 1
    for t in range(pos.shape[0]):
        bad = 0
        for i in numba.prange(n):
            row, frow = np.empty(N_STATE), np.empty(N_FOOT)
            o = out[t, i]
            fx, fy, fz, sx, sy, sz, depth = foot_step(
                c, i * stride, st[i], pos[t, i, 0], pos[t, i, 1], pos[t, i, 2], vel[t, i, 0],
                vel[t, i, 1], vel[t, i, 2], dts[t], cfg, geom, up, mrow, fst[i], row, frow,
            )  # fmt: skip
            o[0], o[1], o[2], o[3], o[4], o[5], o[6] = fx, fy, fz, sx, sy, sz, depth
            if np.isfinite(fx + fy + fz):
                for q in range(N_STATE):  # as in rows.run: no slice assignment
                    st[i, q] = row[q]
                fst[i, 0], fst[i, 1], fst[i, 2] = frow[0], frow[1], frow[2]
            else:
                bad += 1
        if bad:
            return


def feet_loop(n: int) -> Any:
    """The compiled loop for ``n`` feet: :func:`~mudrft.terrains.rows.run`, or its
    multi-threaded variant from :data:`PARALLEL_MIN` feet on."""
    return jit(_run_parallel, parallel=True) if n >= PARALLEL_MIN else jit(run)
