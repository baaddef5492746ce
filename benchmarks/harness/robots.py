"""Robot-steps per second with mud: the CPU coupling and MJX at 1, 64 and 1,024 robots.

The robot is the walker's biped (:mod:`mudrft.envs.walker`: the project's planar biped,
MuJoCo's contacts off, the bed as the coupling's penalty) standing in the paper's mud at
W = 25 %, its servos holding the pose, flat feet, dt = 2 ms. One robot-step is one physics
step of one robot. Measured in one run:

* ``cpu_mud``: :func:`mudrft.integrations.mujoco.attach_batch` (the compiled coupling,
  ``backend="numba"`` where numba is installed) over N ``MjData``;
* ``mjx_mud``: :class:`mudrft.integrations.mjx.MjxCoupling`, ``jit(vmap(scan(step)))``
  over N robots, ``steps`` physics steps per call;
* ``mjx_no_mud``: the same program with ``mjx.step`` alone (MJX's own figure);
* ``mjx_field`` (:func:`bench_fields`): MJX with mud, each robot on its own draw of a field
  of 0.5 m patches along the walk (W = 15-35 %, layout shuffled), the fields traced
  arguments: a second set of draws reuses the compilation.

MJX runs in float32 (MJX's default; the harness switches JAX's 64-bit mode off for it) on
``jax.devices()[0]`` (a CPU where the machine has no GPU). Compile times are reported
beside the rates and are not part of them.
"""

from __future__ import annotations

import time
from typing import Any

from ._timing import Progress, have, say

__all__ = ["ROBOT_COUNTS", "bench_fields", "bench_robots"]

ROBOT_COUNTS = (1, 64, 1024)


def _layout() -> Any:
    from mudrft.envs.walker import WalkerConfig, walker_layout

    return walker_layout(WalkerConfig())


def _cpu(lay: Any, n: int, seconds: float) -> dict[str, float]:
    import mujoco

    import mudrft
    from mudrft.integrations.mujoco import attach_batch

    foot = mudrft.feet.Flat()
    mud = mudrft.paper_mud(0.25)
    datas = []
    for _ in range(n):
        d = mujoco.MjData(lay.model)
        d.qpos[:] = lay.qpos0
        d.ctrl[:] = lay.ctrl0
        datas.append(d)
    batch = attach_batch(
        lay.model, list(lay.bodies), mud, n=n, feet=foot, bottom=0.15,
    )  # fmt: skip
    batch.reset(datas)
    batch.step(datas, 2)  # warm-up (compiles the numba kernel once)
    steps, t0 = 0, time.perf_counter()
    while True:
        batch.step(datas, 5)
        steps += 5
        dt = time.perf_counter() - t0
        if dt > seconds:
            break
    return {"robot_steps_per_s": n * steps / dt, "backend": batch.backend}


#: The field of :func:`bench_fields`: patches along the walk, drawn per robot.
FIELD_CELLS = ["a b a b a b a b"]
FIELD_DRAW = {"water_content": (0.15, 0.35), "layout": True}


def _field() -> Any:
    import mudrft

    return mudrft.MudField({"a": 0.25, "b": 0.35}, FIELD_CELLS, cell_size=0.5, origin=(-0.25, -5.0))  # fmt: skip


def _mjx(
    lay: Any, n: int, steps: int, repeat: int, mud: bool, field: bool = False, chunk: int = 0
) -> dict[str, Any]:
    """Robot-steps per second of ``n`` robots vmapped in one jitted call; ``chunk`` > 0
    runs them as ``n / chunk`` vmapped groups in sequence (``lax.map``), still one call."""
    import jax
    import jax.numpy as jnp
    import mujoco
    import numpy as np

    import mudrft
    from mudrft.integrations import mjx as mm
    from mudrft.integrations.mjx._lazy import _mjx as load_mjx

    mjx = load_mjx()
    ground = _field() if field else mudrft.paper_mud(0.25)
    cpl = mm.attach(lay.model, list(lay.bodies), ground, bottom=0.15)
    d = mujoco.MjData(lay.model)
    d.qpos[:] = lay.qpos0
    d.ctrl[:] = lay.ctrl0
    mujoco.mj_forward(lay.model, d)
    d0 = cpl.put_data(d)
    st0 = mm.jit(cpl.init)(d0)
    batch = jax.tree_util.tree_map(lambda a: jnp.broadcast_to(a, (n, *a.shape)), (d0, st0))
    mx = cpl.mjx_model

    def draws(first: int) -> Any:  # a field per robot, stacked
        arrays = [cpl.field_arrays(_field().randomized(first + i, **FIELD_DRAW)) for i in range(n)]  # fmt: skip
        return tuple(np.stack(a) for a in zip(*arrays, strict=True))

    def run(carry: Any, fields: Any = None) -> Any:
        def body(c: Any, _: Any) -> Any:
            dd, st = c
            if mud:
                dd, st, _o = cpl.step(dd, st, field=fields)
            else:
                dd = jax.tree_util.tree_map(
                    lambda new, old: new.astype(old.dtype), mjx.step(mx, dd), dd
                )
            return (dd, st), None

        return jax.lax.scan(body, carry, None, length=steps)[0]

    fn = jax.jit(jax.vmap(run))
    if chunk and n > chunk:  # groups of chunk robots, one after the other, in one program
        if n % chunk:
            raise ValueError(f"robots ({n}) must be a multiple of chunk ({chunk})")

        def grouped(carry: Any, fields: Any = None) -> Any:
            def split(a: Any) -> Any:
                return a.reshape(n // chunk, chunk, *a.shape[1:])

            xs = jax.tree_util.tree_map(split, (carry, fields))
            out = jax.lax.map(lambda x: jax.vmap(run)(*x) if field else jax.vmap(run)(x[0]), xs)
            return jax.tree_util.tree_map(lambda a: a.reshape(n, *a.shape[2:]), out)

        fn = jax.jit(grouped)
    args = (draws(0),) if field else ()
    t0 = time.perf_counter()
    carry = jax.block_until_ready(fn(batch, *args))
    compile_s = time.perf_counter() - t0
    times = []
    for k in range(repeat):
        if field:  # new draws each call: the same compiled program
            args = (draws(n * (k + 1)),)
        t0 = time.perf_counter()
        carry = jax.block_until_ready(fn(carry, *args))
        times.append(time.perf_counter() - t0)
    finite = bool(jnp.all(jnp.isfinite(carry[0].qpos)))
    out = {"robot_steps_per_s": n * steps / min(times), "compile_s": compile_s, "finite": finite}
    if field:
        out["compilations"] = int(fn._cache_size())  # 1: the draws reused the first
    return out


def bench_robots(quick: bool, progress: Progress) -> dict[str, Any]:
    """Robot-steps per second with mud at :data:`ROBOT_COUNTS` robots (module docstring).

    Returns
    -------
    dict
        ``cpu_mud``, ``mjx_mud``, ``mjx_no_mud`` (each ``{N: {"robot_steps_per_s", ...}}``),
        ``device``, ``dtype``; or a ``note`` when MuJoCo, JAX or MJX is missing.
    """
    if not have("mujoco"):
        return {"note": "mujoco is not installed"}
    lay = _layout()
    res: dict[str, Any] = {"robot": "walker biped, flat feet, W = 25 %, dt = 2 ms"}
    res["cpu_mud"] = {}
    for n in ROBOT_COUNTS:
        res["cpu_mud"][str(n)] = _cpu(lay, n, 0.5 if quick else 2.0)
        say(progress, f"  robots, CPU coupling with mud, N={n}: done")
    if not (have("jax") and have("mujoco.mjx")):
        res["note"] = "jax or mujoco-mjx is not installed: no MJX numbers"
        return res
    import jax

    with jax.enable_x64(False):
        res["device"] = str(jax.devices()[0])
        res["dtype"] = "float32"
        steps = 50 if quick else 200
        for key, mud in (("mjx_mud", True), ("mjx_no_mud", False)):
            res[key] = {}
            for n in ROBOT_COUNTS:
                res[key][str(n)] = _mjx(lay, n, steps, 2 if quick else 3, mud)
                say(progress, f"  robots, MJX {'with' if mud else 'without'} mud, N={n}: done")
    return res


def bench_fields(
    quick: bool, progress: Progress, robots: Any = None, chunk: int = 0
) -> dict[str, Any]:
    """MJX with mud on one mud and on a field drawn per robot, at ``robots`` (default
    :data:`ROBOT_COUNTS`) robots (module docstring): ``mjx_mud`` and ``mjx_field``,
    ``{N: {...}}``. (A run of several MJX programs in one process has stalled with no CPU
    use; one count a process avoids that.)"""
    if not (have("mujoco") and have("jax") and have("mujoco.mjx")):
        return {"note": "mujoco, jax or mujoco-mjx is not installed"}
    import jax

    lay = _layout()
    res: dict[str, Any] = {"robot": "walker biped, flat feet, dt = 2 ms", "dtype": "float32"}
    with jax.enable_x64(False):
        res["device"] = str(jax.devices()[0])
        steps = 50 if quick else 200
        for key, field in (("mjx_mud", False), ("mjx_field", True)):
            res[key] = {}
            for n in robots or ROBOT_COUNTS:
                res[key][str(n)] = _mjx(lay, n, steps, 2 if quick else 3, True, field, chunk)
                res[key][str(n)]["chunk"] = chunk if chunk and n > chunk else n
                say(progress, f"  robots, MJX {key}, N={n}: {res[key][str(n)]}")
    return res
