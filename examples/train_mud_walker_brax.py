"""
Training Brax's PPO on the MJX mud walker across fields of mud
==============================================================

Train the MJX walker (the vector form of ``mudrft/MudWalker-v0``) with Brax's PPO, the
whole loop (thousands of robots in mud, the policy and its updates) compiled by JAX in one
program: on a GPU that is where training pays off. The walker's field is the one of
``examples/train_mud_walker.py`` (eight 0.5 m patches, W = 15-35 %, the same reward): a
bank of :data:`BANK` draws is made from ``--seed``, and each environment starts on one of
them, chosen from its own key. Brax's auto-reset starts an environment again from its first
state, so an environment keeps its draw for the whole training; the draws differ between
environments.

The script writes ``DIR/curves.csv`` (Brax's evaluation return and forward speed against
training steps) and ``DIR/run.json`` (the command, wall time, machine, JAX's device and
versions); it refuses an existing ``DIR`` file without ``--force``.

Run: ``pip install 'mudrft[mjx]' brax``, then ``python examples/train_mud_walker_brax.py
--out DIR [--steps 20000000] [--num-envs 2048]`` where a GPU is present. ``--steps 640
--num-envs 8 --episode-steps 20 --evals 2`` is the smoke setting the slow tests run on a
CPU (it compiles for minutes there and learns nothing: it shows the wiring).
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

#: The field and its draws, as in ``examples/train_mud_walker.py``.
PATCHES = {"a": 0.25, "b": 0.35}
CELLS = ["a b a b a b a b"]
DRAW = {"water_content": (0.15, 0.35), "layout": True}
#: The reward's weight of forward speed, as in ``examples/train_mud_walker.py``.
FORWARD_REWARD_WEIGHT = 5.0
#: Draws of the field made before training; each environment starts on one of them.
BANK = 64


def make_env(seed: int) -> Any:
    """The MJX walker on fields of mud, as a Brax environment."""
    import jax
    import jax.numpy as jnp
    from brax.envs.base import Env, State

    import mudrft
    from mudrft.envs import MudWalkerVectorEnv
    from mudrft.envs.vector import robot_functions

    field = mudrft.MudField(PATCHES, CELLS, cell_size=0.5, origin=(-0.25, -5.0))
    walker = MudWalkerVectorEnv(
        1, field=field, randomize=DRAW, observe="proprioceptive",
        forward_reward_weight=FORWARD_REWARD_WEIGHT,
    )  # fmt: skip
    reset_one, step_one, _ = robot_functions(walker)
    rng = np.random.default_rng(seed)
    draws = [walker.coupling.field_arrays(field.randomized(rng, **DRAW)) for _ in range(BANK)]
    bank = tuple(jnp.stack([d[i] for d in draws]) for i in range(len(draws[0])))
    constants = jax.tree_util.tree_map(lambda c: jnp.asarray(c[0]), walker.constants)

    class BraxMudWalker(Env):  # type: ignore[misc]
        def reset(self, rng: jax.Array) -> State:
            pick, key = jax.random.split(rng)
            k = jax.random.randint(pick, (), 0, BANK)
            fld = tuple(a[k] for a in bank)
            d, st, obs = reset_one(key, fld)
            zero = jnp.zeros((), obs.dtype)
            return State((d, st), obs, zero, zero, {"x_velocity": zero}, {"field": fld})

        def step(self, state: State, action: jax.Array) -> State:
            d, st = state.pipeline_state
            d, st, obs, r, term, info = step_one(d, st, action, constants, state.info["field"])
            metrics = {**state.metrics, "x_velocity": info["x_velocity"].astype(obs.dtype)}
            return state.replace(
                pipeline_state=(d, st), obs=obs, reward=r.astype(obs.dtype),
                done=term.astype(obs.dtype), metrics=metrics,
            )  # fmt: skip

        @property
        def observation_size(self) -> int:
            return int(walker.single_observation_space.shape[0])

        @property
        def action_size(self) -> int:
            return int(walker.single_action_space.shape[0])

        @property
        def backend(self) -> str:
            return "mjx"

    return BraxMudWalker()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--out", required=True, help="output directory DIR")
    ap.add_argument("--steps", type=int, default=20_000_000, help="control steps of training")
    ap.add_argument("--num-envs", type=int, default=2048, help="environments stepped together")
    ap.add_argument("--episode-steps", type=int, default=500, help="control steps of an episode (50 a second)")  # fmt: skip
    ap.add_argument("--evals", type=int, default=20, help="evaluations during training")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--force", action="store_true", help="replace existing results in DIR")
    args = ap.parse_args(argv)
    for name in ("steps", "num_envs", "episode_steps", "evals"):
        if getattr(args, name) < 1:
            ap.error(f"--{name.replace('_', '-')} must be >= 1, got {getattr(args, name)}")
    if args.num_envs % 8:
        ap.error(f"--num-envs must be a multiple of 8 (Brax's batches), got {args.num_envs}")
    out = Path(args.out)
    names = ("curves.csv", "run.json")
    taken = [n for n in names if (out / n).exists()]
    if taken and not args.force:
        ap.error(f"{out}: {', '.join(taken)} exist; pass --force to replace them")

    import jax
    import jax.numpy as jnp
    from brax.training.agents.ppo import train as ppo

    try:  # Brax 0.14.2 calls it; JAX 0.10 removed it (a copy on each device, stacked)
        jax.device_put_replicated  # noqa: B018
    except AttributeError:
        jax.device_put_replicated = lambda x, devices: jax.tree_util.tree_map(
            lambda a: jax.device_put(jnp.stack([jnp.asarray(a)] * len(devices))), x
        )

    import mudrft
    from mudrft.io.atomic import atomic_write

    t0 = time.perf_counter()
    rows: list[tuple[int, float, float]] = []

    def progress(step: int, metrics: dict[str, Any]) -> None:
        ret = float(metrics["eval/episode_reward"])
        # the speed summed over an episode's control steps, over their number
        length = float(metrics.get("eval/avg_episode_length", np.nan))
        speed = float(metrics.get("eval/episode_x_velocity", np.nan)) / length
        rows.append((int(step), ret, speed))
        print(f"{step} steps, evaluation return {ret:.1f}, {time.perf_counter() - t0:.0f} s",
              file=sys.stderr)  # fmt: skip

    ppo.train(
        environment=make_env(args.seed), num_timesteps=args.steps, episode_length=args.episode_steps,
        num_envs=args.num_envs, num_eval_envs=args.num_envs, batch_size=args.num_envs // 8,
        num_minibatches=8, unroll_length=20, num_updates_per_batch=4, learning_rate=3e-4,
        entropy_cost=1e-3, discounting=0.99, normalize_observations=True, reward_scaling=0.1,
        num_evals=args.evals, seed=args.seed, progress_fn=progress,
    )  # fmt: skip
    wall = time.perf_counter() - t0
    out.mkdir(parents=True, exist_ok=True)
    text = io.StringIO()
    w = csv.writer(text, lineterminator="\n")
    w.writerow(("steps", "eval_return", "eval_forward_speed [m/s]"))
    w.writerows(rows)
    run = {
        "command": "python examples/train_mud_walker_brax.py " + " ".join(sys.argv[1:] if argv is None else argv),
        "wall_time [s]": round(wall, 1), "machine": f"{platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} CPUs, {platform.system()}", "device": str(jax.devices()[0]),
        "python": platform.python_version(), "mudrft": mudrft.__version__, "jax": jax.__version__,
    }  # fmt: skip
    atomic_write(out / "curves.csv", text.getvalue(), overwrite=args.force, option="--force")
    atomic_write(out / "run.json", json.dumps(run, indent=2) + "\n", overwrite=args.force, option="--force")  # fmt: skip
    print(f"{wall:.0f} s; results in {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
