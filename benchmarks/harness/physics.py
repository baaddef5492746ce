"""Benchmarks of the physics kernels: the constitutive step and the mesh integration.

The constitutive step is timed on every path that runs the one definition,
:func:`mudrft.constitutive.kernel.channel_update`:

* ``numpy_one_plate_us``: :func:`mudrft.constitutive.step` (validated) on one channel;
* ``numpy_batch_ns_per_channel``: ``channel_update`` on numpy arrays of ``batch_channels``
  channels (no validation, as the batched terrain calls it);
  ``numpy_step_batch_ns_per_channel``: the validated ``step`` on the same batch;
* ``python_float_one_plate_us``: ``channel_update(..., xp=pyfloat)`` on Python floats (the
  path of the single-foot :class:`mudrft.MudTerrain`);
* ``jax_one_plate_us`` / ``jax_batch_ns_per_channel``: :func:`mudrft.backends.jax.step`.

The mesh integration times :func:`mudrft.feet.surface.integrate_prepared` (numpy, and under
``jax.jit``) on semi-sphere meshes of about 1e3 and 1e5 facets.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ._timing import Progress, best, block, have, say

__all__ = ["BATCH_CHANNELS", "MESH_RESOLUTIONS", "bench_constitutive", "bench_mesh"]

#: Channels in the batched constitutive step.
BATCH_CHANNELS = 300_000
#: Semi-sphere mesh resolutions giving 968 and 100,352 facets (8 r^2).
MESH_RESOLUTIONS = {"1e3": 11, "1e5": 112}


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
    from mudrft._xp import pyfloat
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
    out["python_float_one_plate_us"] = 1e6 * best(
        lambda: kernel.channel_update(cf, sf, 0.1, 1.0, 1e-3, 1.0, 1.0, pyfloat), budget=budget
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
