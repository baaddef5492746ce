"""Cost of the mud coupling in MuJoCo: the biped with and without mud, in one run.

``python benchmarks/bench_mujoco.py [--seconds S] [--json FILE]`` prints steps per second of
the biped (``mudrft.integrations.walk``) walking

* on rigid ground (a floor at the mud surface, plain ``mj_step``): the physics step;
* in mud (``MudCoupling.step``: ``mj_step1``, the mud, ``mj_step2``) with the flat foot
  and the compiled coupling (``backend="numba"``, D68a), with a 512-facet mesh foot
  (compiled) and with the morphing foot (numpy coupling);

and the same for batches of robots (:class:`~mudrft.integrations.mujoco.MudBatch`: one
compiled call per step for all robots). :func:`mujoco_overhead_ratio` is what
``mudrft bench`` calls. Results and discussion: docs/performance.md.
Timings are the best of several repeats, with and without mud in alternation, so other
load on the machine inflates them less and lands on both sides of the ratio.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

import mudrft

if TYPE_CHECKING:
    import mujoco

    from mudrft.feet.base import Foot
    from mudrft.feet.mesh import MeshFoot
    from mudrft.integrations.mujoco import MudBatch
    from mudrft.integrations.walk import GaitController


def _best_time(fn: Callable[[], object], repeats: int = 3) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def _robots(
    n: int, *, mud: bool, dt: float, foot: Foot | None = None, backend: str = "numba"
) -> tuple[mujoco.MjModel, list[mujoco.MjData], GaitController, MudBatch | None]:
    import mujoco

    from mudrft.integrations.mujoco import attach, attach_batch
    from mudrft.integrations.walk import BIPED_FEET, GaitController, biped_model

    foot = mudrft.feet.Flat() if foot is None else foot
    # without mud the biped walks on a rigid floor 1 mm under the mud surface
    model = biped_model(foot, bottom=0.15 if mud else 1e-3, timestep=dt)
    datas = [mujoco.MjData(model) for _ in range(n)]
    ctrl = GaitController(model)
    for d in datas:
        ctrl.initial_pose(d)
    coupling = None
    if mud:
        kw = {"feet": foot, "backend": backend}
        coupling = (
            attach(model, list(BIPED_FEET), mudrft.paper_mud(0.25), **kw)
            if n == 1
            else attach_batch(model, list(BIPED_FEET), mudrft.paper_mud(0.25), n=n, **kw)
        )
        coupling.reset(datas[0] if n == 1 else datas)
    return model, datas, ctrl, coupling


def _runner(
    n: int,
    *,
    mud: bool,
    steps: int,
    dt: float,
    foot: Foot | None = None,
    backend: str = "numba",
    contact: bool = False,
) -> Callable[[], None]:
    """A function that runs ``steps`` physics steps of ``n`` robots (controller included):
    ``advance`` (the contact built only when read), or ``step`` (a :class:`MudContact`
    returned every step) where ``contact``."""
    import mujoco

    model, datas, ctrl, coupling = _robots(n, mud=mud, dt=dt, foot=foot, backend=backend)
    arg = datas[0] if n == 1 else datas
    go = None if coupling is None else (coupling.step if contact else coupling.advance)

    def run() -> None:
        for _ in range(steps):
            for d in datas:
                ctrl(d)
            if go is None:
                for d in datas:
                    mujoco.mj_step(model, d)
            else:
                go(arg)

    run()  # warm up (and walk into the gait; compiles the numba kernel once)
    return run


def _alternated(fns: Sequence[Callable[[], object]], steps: int, repeats: int) -> list[float]:
    """Best wall time per step [s] of each runner, the runners timed in turn ``repeats``
    times: a change of load on a shared machine then lands on every side of a ratio."""
    best = [np.inf] * len(fns)
    for _ in range(repeats):
        for i, fn in enumerate(fns):
            best[i] = min(best[i], _best_time(fn, 1))
    return [b / steps for b in best]


def _pair(
    n: int,
    *,
    steps: int,
    dt: float,
    repeats: int = 3,
    foot: Foot | None = None,
    backend: str = "numba",
) -> tuple[float, float]:
    """Best wall time per step without and with mud (``advance``) [s], in alternation."""
    phys = _runner(n, mud=False, steps=steps, dt=dt, foot=foot)
    mud = _runner(n, mud=True, steps=steps, dt=dt, foot=foot, backend=backend)
    tp, tm = _alternated([phys, mud], steps, repeats)
    return tp, tm


def _triple(
    n: int, *, steps: int, dt: float, repeats: int, backend: str = "numba"
) -> tuple[float, ...]:
    """As :func:`_pair`, with a third run: ``step`` returning the contact every step."""
    phys = _runner(n, mud=False, steps=steps, dt=dt)
    runs = [
        _runner(n, mud=True, steps=steps, dt=dt, contact=c, backend=backend) for c in (False, True)
    ]
    return tuple(_alternated([phys, *runs], steps, repeats))


def _mesh_foot() -> MeshFoot:
    """A mesh foot of 512 facets (the semi-sphere's mesh at resolution 8)."""
    return mudrft.feet.SemiSphere().to_mesh(resolution=8)


def mujoco_overhead_ratio(
    seconds: float = 2.0,
    *,
    batch: tuple[int, ...] = (64,),
    dt: float = 1e-3,
    feet: tuple[str, ...] = ("mesh", "morphing"),
) -> dict:
    """Wall time per biped step with mud over without: the cost of the coupling.

    The headline ``mujoco_overhead_ratio`` is the biped with the paper's flat foot and the
    compiled coupling (D68a), stepped with
    ``advance`` (the wrench written, the contact built only when read);
    ``ratio_with_contact`` steps it with ``step``, which returns a :class:`MudContact`
    every step. ``feet``
    reports the same for a 512-facet mesh foot and the morphing foot; ``batch`` the ratio per robot for batches of robots (one compiled call for
    all of them).

    Parameters
    ----------
    seconds : float
        Simulated time per measurement [s] (each is repeated three times; the other feet's
        runs use a tenth of it).
    batch : tuple of int, keyword-only
        Robot counts for the batched measurement (:class:`MudBatch`); empty to skip.
    dt : float, keyword-only
        Physics time step [s].
    feet : tuple of str, keyword-only
        Other feet to report: ``"mesh"``, ``"morphing"``.

    Returns
    -------
    dict
        ``ratio`` (= ``mujoco_overhead_ratio``): wall time per step with mud / without;
        ``ratio_with_contact``: the same with the contact returned every step;
        ``mud_cost_over_physics``: (with - without) / without, the cost of the mud
        relative to the physics step (the aim is < 1); ``backend``;
        ``steps_per_second_physics``, ``steps_per_second_mud``; ``feet``: per foot the
        same; ``batch``: per robot count the same numbers per robot; ``machine``.
    """
    steps = max(round(seconds / dt), 10)
    backend = "numba"
    t_phys, t_mud, t_contact = _triple(1, steps=steps, dt=dt, repeats=5, backend=backend)
    out: dict[str, Any] = {
        "seconds": float(seconds),
        "dt [s]": dt,
        "backend": backend,
        "steps_per_second_physics": 1.0 / t_phys,
        "steps_per_second_mud": 1.0 / t_mud,
        "ratio": t_mud / t_phys,
        "mujoco_overhead_ratio": t_mud / t_phys,
        "mud_cost_over_physics": (t_mud - t_phys) / t_phys,
        "ratio_with_contact": t_contact / t_phys,
        "feet": {},
        "batch": {},
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "python": platform.python_version(),
        },
    }
    others = {
        "mesh": (_mesh_foot, "numba"),
        "morphing": (mudrft.feet.MorphingFoot, "numba"),
    }
    for name in feet:
        make, be = others[name]
        foot = make()
        fsteps = max(steps // 10, 10)
        tp, tm = _pair(1, steps=fsteps, dt=dt, repeats=2, foot=foot, backend=be)
        out["feet"][name] = {
            "backend": be,
            "facets": len(foot.triangles) if hasattr(foot, "triangles") else None,
            "ratio": tm / tp,
            "mud_us_per_step": 1e6 * (tm - tp),
            "mud_cost_over_physics": (tm - tp) / tp,
        }
    for n in batch:
        bsteps = max(steps // 10, 10)
        tp, tm = _pair(n, steps=bsteps, dt=dt, backend=backend)
        out["batch"][str(n)] = {
            "robots": n,
            "backend": backend,
            "robot_steps_per_second_physics": n / tp,
            "robot_steps_per_second_mud": n / tm,
            "ratio": tm / tp,
            "mud_cost_over_physics": (tm - tp) / tp,
        }
    return out


def _table(res: dict) -> str:
    rows = [
        "| robots | physics [robot-steps/s] | with mud [robot-steps/s] | with / without | mud cost / physics |",
        "|---:|---:|---:|---:|---:|",
        f"| 1 | {res['steps_per_second_physics']:,.0f} | {res['steps_per_second_mud']:,.0f} | "
        f"{res['ratio']:.2f} | {res['mud_cost_over_physics']:.2f} |",
    ]
    if "ratio_with_contact" in res:
        rows.append(
            f"| 1 (`step`: the contact every step) | | | {res['ratio_with_contact']:.2f} | |"
        )
    for name, f in res.get("feet", {}).items():
        rows.append(
            f"| 1 ({name}, {f['backend']}) | | | {f['ratio']:.1f} | {f['mud_cost_over_physics']:.1f} |"
        )
    for b in res["batch"].values():
        rows.append(
            f"| {b['robots']} | {b['robot_steps_per_second_physics']:,.0f} | "
            f"{b['robot_steps_per_second_mud']:,.0f} | {b['ratio']:.2f} | {b['mud_cost_over_physics']:.2f} |"
        )
    return "\n".join(rows)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--seconds", type=float, default=2.0, help="simulated seconds per measurement"
    )
    parser.add_argument("--batch", type=int, nargs="*", default=[16, 64, 256], help="robot counts")
    parser.add_argument("--json", help="also write the results to this JSON file")
    args = parser.parse_args(argv)
    res = mujoco_overhead_ratio(args.seconds, batch=tuple(args.batch))
    print(_table(res))
    print(f"\n{res['machine']['cpus']} CPUs, {res['machine']['platform']}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
