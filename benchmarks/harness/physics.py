"""Benchmarks of the physics kernels: the constitutive step and the mesh integration.

The constitutive step is timed on every path that runs the one definition,
:func:`mudrft.constitutive.kernel.channel_update`:

* ``numpy_one_plate_us``: :func:`mudrft.constitutive.step` (validated) on one channel;
* ``numpy_batch_ns_per_channel``: ``channel_update`` on numpy arrays of ``batch_channels``
  channels (no validation, as the batched terrain calls it);
  ``numpy_step_batch_ns_per_channel``: the validated ``step`` on the same batch;
* ``python_float_one_plate_us``: ``channel_update(..., xp=pyfloat)`` on Python floats (the
  path of the single-foot :class:`mudrft.MudTerrain`);
* ``numba_one_plate_us``: ``compile_scalar(channel_update)`` called from Python with
  named tuples of floats (numba boxes and unboxes 17 floats in, 9 out);
  ``numba_array_one_plate_us``: the same compiled update inside a small ``njit`` wrapper
  that reads constants and state from float arrays and writes the state back (the
  interface of a compiled caller); ``numba_batch_ns_per_channel``: a ``prange`` loop over
  the batch calling the compiled update;
* ``jax_one_plate_us`` / ``jax_batch_ns_per_channel``: :func:`mudrft.backends.jax.step`.

The mesh integration times :func:`mudrft.feet.surface.integrate_prepared` (numpy, and under
``jax.jit``) on semi-sphere meshes of about 1e3 and 1e5 facets.
"""

from __future__ import annotations

import functools
import warnings
from typing import Any

import numpy as np

from ._timing import Progress, best, block, have, say

#: Floats in a channel's state: the drivers below unpack ChannelState field by field (numba
#: cannot splat a row), and check this count when they are built.
N_FIELDS = 7

__all__ = ["BATCH_CHANNELS", "MESH_RESOLUTIONS", "bench_constitutive", "bench_mesh"]

#: Channels in the batched constitutive step.
BATCH_CHANNELS = 300_000
#: Semi-sphere mesh resolutions giving 968 and 100,352 facets (8 r^2).
MESH_RESOLUTIONS = {"1e3": 11, "1e5": 112}


@functools.cache
def _numba_drivers() -> tuple[Any, Any, Any]:
    """The compiled update, an array-interface wrapper of it, and a prange loop over channels."""
    import numba

    from mudrft.backends.numba import compile_scalar
    from mudrft.constitutive.kernel import ChannelConstants, channel_update
    from mudrft.constitutive.state import ChannelState

    if len(ChannelState._fields) != N_FIELDS:
        raise RuntimeError(f"ChannelState has {len(ChannelState._fields)} fields; update N_FIELDS")
    upd = compile_scalar(channel_update)

    @numba.njit(inline="always")
    def constants(r: Any) -> Any:
        return ChannelConstants(
            r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11]
        )

    @numba.njit(error_model="numpy")
    def one(r: Any, s: Any, g: float, gd: float, dt: float) -> float:
        new, out = upd(
            constants(r), ChannelState(s[0], s[1], s[2], s[3], s[4], s[5], s[6]), g, gd, dt,
            1.0, 1.0,
        )  # fmt: skip
        s[0], s[1], s[2], s[3], s[4], s[5], s[6] = new
        return out.total

    @numba.njit(error_model="numpy", parallel=True)
    def batch(r: Any, s: Any, g: Any, gd: Any, dt: float, tot: Any) -> None:
        c = constants(r)
        for i in numba.prange(g.shape[0]):
            si = s[i]
            st = ChannelState(si[0], si[1], si[2], si[3], si[4], si[5], si[6])
            new, out = upd(c, st, g[i], gd[i], dt, 1.0, 1.0)
            si[0], si[1], si[2], si[3], si[4], si[5], si[6] = new
            tot[i] = out.total

    return upd, one, batch


def bench_constitutive(quick: bool, budget: float, progress: Progress) -> dict[str, Any]:
    """Time the constitutive step per call and per channel of a batch (see module docstring).

    Parameters
    ----------
    quick : bool
        Unused (the batch keeps its size, so that quick and full runs compare).
    budget : float
        Timing budget per measurement [s].
    progress : callable or None
        Receives one line when done.

    Returns
    -------
    dict
        Times per call [us] and per channel [ns], keyed as in the module docstring.
    """
    from mudrft._specialize import on_floats
    from mudrft.constitutive import initial_state, kernel, step
    from mudrft.constitutive.state import ChannelState
    from mudrft.parameters import paper_parameters

    p = paper_parameters(0.25)
    c = kernel.channel_constants(p)
    out: dict[str, Any] = {}
    st = initial_state()
    out["numpy_one_plate_us"] = 1e6 * best(lambda: step(p, st, 0.1, 1.0, 1e-3), budget=budget)
    cf = kernel.ChannelConstants(*(float(v) for v in c))
    sf = ChannelState(*[0.0] * len(ChannelState._fields))
    update = on_floats(kernel.channel_update)  # what one foot on floats runs
    out["python_float_one_plate_us"] = 1e6 * best(
        lambda: update(cf, sf, 0.1, 1.0, 1e-3), budget=budget
    )
    m = BATCH_CHANNELS
    out["batch_channels"] = m
    rng = np.random.default_rng(1)
    bst = initial_state((m,))
    g = rng.uniform(0.0, 0.5, m)
    gd = rng.normal(size=m)
    t = best(lambda: kernel.channel_update(c, bst, g, gd, 1e-3), budget=budget)
    out["numpy_batch_ns_per_channel"] = 1e9 * t / m
    t = best(lambda: step(p, bst, g, gd, 1e-3), budget=budget)
    out["numpy_step_batch_ns_per_channel"] = 1e9 * t / m
    if have("numba"):
        upd, one, batch = _numba_drivers()
        out["numba_one_plate_us"] = 1e6 * best(
            lambda: upd(cf, sf, 0.1, 1.0, 1e-3, 1.0, 1.0), budget=budget
        )
        row = np.array(cf, dtype=float)
        s1 = np.zeros(N_FIELDS)
        out["numba_array_one_plate_us"] = 1e6 * best(
            lambda: one(row, s1, 0.1, 1.0, 1e-3), budget=budget
        )
        sm = np.zeros((m, N_FIELDS))
        tot = np.zeros(m)
        t = best(lambda: batch(row, sm, g, gd, 1e-3, tot), budget=budget)
        out["numba_batch_ns_per_channel"] = 1e9 * t / m
    if have("jax"):
        import jax.numpy as jnp

        from mudrft.backends import jax as mjax

        jp = mjax.to_jax(p)
        js = mjax.initial_state()
        out["jax_one_plate_us"] = 1e6 * best(
            lambda: mjax.step(jp, js, 0.1, 1.0, 1e-3)[1].total, budget=budget, sync=block
        )
        jsm = mjax.initial_state((m,))
        gj, gdj = jnp.asarray(g), jnp.asarray(gd)
        t = best(lambda: mjax.step(jp, jsm, gj, gdj, 1e-3)[1].total, budget=budget, sync=block)
        out["jax_batch_ns_per_channel"] = 1e9 * t / m
    say(progress, "  constitutive step: done")
    return out


def bench_mesh(quick: bool, budget: float, progress: Progress) -> dict[str, Any]:
    """Time the surface integration of semi-sphere meshes of about 1e3 and 1e5 facets.

    Parameters
    ----------
    quick : bool
        Unused (the mesh sizes are kept).
    budget : float
        Timing budget per measurement [s].
    progress : callable or None
        Receives one line per mesh.

    Returns
    -------
    dict
        Per mesh label: ``facets``, ``numpy_us``, ``numpy_ns_per_facet`` and, with JAX,
        ``jax_us``, ``jax_ns_per_facet`` (jit, one state).
    """
    from mudrft.feet.mesh import MeshFoot
    from mudrft.feet.meshgen import semisphere_mesh
    from mudrft.feet.surface import PreparedTriangles, integrate_prepared

    out: dict[str, Any] = {}
    s = np.array([800.0, 300.0, 2000.0])
    for label, res in MESH_RESOLUTIONS.items():
        v, f = semisphere_mesh(0.045, 0.026, resolution=res)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            foot = MeshFoot(v, f, trailing=True)
        m = len(foot)
        prep = foot._prep
        t = best(
            lambda prep=prep: integrate_prepared(prep, 0.013, s, 0.4, trailing=True), budget=budget
        )
        r: dict[str, Any] = {"facets": m, "numpy_us": 1e6 * t, "numpy_ns_per_facet": 1e9 * t / m}
        if have("jax"):
            import jax

            from mudrft.backends import jax as mjax

            xp = mjax.safe_namespace()
            jprep = PreparedTriangles(*(xp.asarray(a) for a in prep))
            fn = jax.jit(
                lambda pr, d, st, h, xp=xp: integrate_prepared(pr, d, st, h, trailing=True, xp=xp)
            )
            t = best(lambda jprep=jprep, fn=fn: fn(jprep, 0.013, s, 0.4), budget=budget, sync=block)
            r["jax_us"] = 1e6 * t
            r["jax_ns_per_facet"] = 1e9 * t / m
        out[label] = r
        say(progress, f"  mesh integration, {m} facets: done")
    return out
