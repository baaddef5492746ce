"""
Training PPO on the mud walker across fields of mud
===================================================

Train the mud walker (``mudrft/MudWalker-v0``, the project's planar biped) with
Stable-Baselines3's PPO twice: once on fields of mud patches from W = 15 % to 35 %, drawn
anew each episode, and once on rigid ground. Then compare the two policies on the same
held-out fields (drawn from seeds no training episode used): success rate (1 m forward
without falling in 10 s), forward speed, cost of transport, sinking and suction per step.

Both policies see only the robot's own state (``observe="proprioceptive"``) and earn the
same reward, so they differ only in the ground they trained on. The reward weighs forward
speed five times the walker's default (:data:`FORWARD_REWARD_WEIGHT`): at its 0.2-0.3 m/s
the default makes standing still worth nearly as much as walking, and PPO learned to stand.
Each policy trains on :data:`N_ENVS` copies of its environment, its observations and rewards
normalized as it goes (Stable-Baselines3's ``VecNormalize``, the usual recipe for MuJoCo
locomotion); the evaluations use the statistics of that moment. The script writes ``DIR/results.csv`` and
``DIR/results.md`` (the comparison), ``DIR/curves.csv`` and ``DIR/curves.png`` (the
held-out return against training steps) and ``DIR/run.json`` (the command, wall time,
machine and versions); it refuses an existing ``DIR`` file without ``--force``.

Run: ``pip install 'mudrft[rl-train]'`` (gymnasium, Stable-Baselines3, torch), then
``python examples/train_mud_walker.py --out DIR [--steps 500000] [--jobs 2]`` (``--jobs 2``:
the two policies train side by side, one process each). ``--steps 256 --eval-every 128
--eval-episodes 1 --episode-steps 20`` is the smoke setting the tests run.
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

#: The training field: eight 0.5 m patches along the walk, each drawn at W = 15-35 % (and
#: the layout shuffled) every episode; beyond the grid the nearest patch holds.
PATCHES = {"a": 0.25, "b": 0.35}
CELLS = ["a b a b a b a b"]
DRAW = {"water_content": (0.15, 0.35), "layout": True}
#: Held-out fields come from these seeds on; training draws from the episodes' own seeds.
HELD_OUT_SEED = 10_000
#: Success: this far forward [m] without falling within an evaluation episode.
SUCCESS_DISTANCE = 1.0
#: The reward's weight of forward speed [1/(m/s)], the same for both policies (the walker's
#: default is 1.0, with 1.0 a control step for staying up).
FORWARD_REWARD_WEIGHT = 5.0
#: Environments each policy trains on at once (Stable-Baselines3's ``DummyVecEnv``).
N_ENVS = 4
COLUMNS = (
    "trained_on", "episodes", "success_rate", "forward_speed [m/s]", "cost_of_transport [-]",
    "sinking_per_step [mm]", "suction_per_step [N]", "max_suction [N]", "return",
)  # fmt: skip


def make_env(ground: str, episode_steps: int) -> Any:
    import warnings

    import gymnasium

    import mudrft
    from mudrft.envs import MudWalkerEnv
    from mudrft.trajectories import BuriedFootWarning

    # known, and in the guide: in the wettest patches the 26 mm flat foot sinks deeper than
    # it is tall, where the model gives the foot's force alone (D26); once an environment
    # would say so again for every one the evaluations make
    warnings.filterwarnings("ignore", category=BuriedFootWarning)
    same = {"observe": "proprioceptive", "forward_reward_weight": FORWARD_REWARD_WEIGHT}
    if ground == "rigid":
        env = MudWalkerEnv(ground="rigid", **same)
    else:
        field = mudrft.MudField(PATCHES, CELLS, cell_size=0.5, origin=(-0.25, -5.0))
        env = MudWalkerEnv(field=field, randomize=DRAW, **same)
    return gymnasium.wrappers.TimeLimit(env, max_episode_steps=episode_steps)


def evaluate(model: Any, norm: Any, episodes: int, episode_steps: int) -> dict[str, float]:
    """The policy, deterministic, on ``episodes`` held-out fields of mud; ``norm`` (a
    ``VecNormalize``) normalizes its observations as in training."""
    env = make_env("mud", episode_steps)
    walker = env.unwrapped
    lay, cfg = walker.layout, walker.config
    period = cfg.dt * cfg.frame_skip
    rows = []
    for k in range(episodes):
        obs, info = env.reset(seed=HELD_OUT_SEED + k)
        x0, ret, work, sink, suction, n = info["x_position"], 0.0, 0.0, [], [], 0
        fell = False
        for n in range(1, episode_steps + 1):  # noqa: B007 (n: the steps walked)
            action, _ = model.predict(norm.normalize_obs(obs), deterministic=True)
            obs, reward, terminated, truncated, info = env.step(action)
            d = walker.data
            power = d.actuator_force * d.qvel[lay.joint_dadr]  # sampled once a control step
            work += float(np.maximum(power, 0.0).sum()) * period
            sink.append(1e3 * float(np.mean(info["sinking [m]"])))
            suction.append(float(np.maximum(-info["mud_force [N]"][:, 2], 0.0).max()))
            ret += float(reward)
            if terminated or truncated:
                fell = terminated
                break
        dist = info["x_position"] - x0
        cot = work / (lay.weight * dist) if dist > 0.05 else float("nan")
        rows.append((not fell and dist >= SUCCESS_DISTANCE, dist / (n * period), cot,
                     np.mean(sink), np.mean(suction), np.max(suction), ret))  # fmt: skip
    env.close()
    a = np.array(rows, dtype=float)
    with np.errstate(invalid="ignore"):
        cot = float(np.nanmean(a[:, 2])) if np.isfinite(a[:, 2]).any() else float("nan")
    return {
        "episodes": episodes, "success_rate": a[:, 0].mean(), "forward_speed [m/s]": a[:, 1].mean(),
        "cost_of_transport [-]": cot, "sinking_per_step [mm]": a[:, 3].mean(),
        "suction_per_step [N]": a[:, 4].mean(), "max_suction [N]": a[:, 5].max(),
        "return": a[:, 6].mean(),
    }  # fmt: skip


def train(
    ground: str, args: argparse.Namespace
) -> tuple[dict[str, float], list[tuple[int, float]]]:
    """Train on ``ground`` (``"mud"`` or ``"rigid"``); the held-out results and the curve."""
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.logger import Logger
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    torch.set_num_threads(1)  # small networks: threads cost more than they give
    env = VecNormalize(DummyVecEnv([lambda: make_env(ground, args.episode_steps)] * N_ENVS))
    # a rollout of at most eval_every steps (all environments), so evaluations fall on time
    n_steps = max(min(512, args.eval_every // N_ENVS), 16)
    model = PPO(
        "MlpPolicy", env, n_steps=n_steps, batch_size=64, n_epochs=10, learning_rate=3e-4,
        policy_kwargs={"net_arch": [64, 64]}, seed=args.seed, verbose=0, device="cpu",
    )  # fmt: skip
    model.set_logger(Logger(None, []))  # SB3's own would leave a folder in the temp directory
    curve = []
    while model.num_timesteps < args.steps:
        model.learn(args.eval_every, reset_num_timesteps=False)
        held = evaluate(model, env, args.eval_episodes, args.episode_steps)
        curve.append((int(model.num_timesteps), held["return"]))
        print(f"{ground}: {model.num_timesteps} steps, held-out return {held['return']:.1f}",
              file=sys.stderr)  # fmt: skip
    env.close()
    return {"trained_on": ground, **held}, curve


def _csv(rows: list[dict[str, Any]] | list[tuple[Any, ...]], header: tuple[str, ...]) -> str:
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    w.writerow(header)
    for r in rows:
        w.writerow([r[c] for c in header] if isinstance(r, dict) else r)
    return out.getvalue()


def _table(results: list[dict[str, Any]]) -> str:
    def cell(v: Any) -> str:
        return f"{v:.3g}" if isinstance(v, float) else str(v)

    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(cell(r[c]) for c in COLUMNS) + " |" for r in results]
    return "\n".join(lines) + "\n"


def _curves(curves: dict[str, list[tuple[int, float]]]) -> bytes:
    """The held-out return against training steps, as PNG bytes."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.0, 3.2))
    for ground, c in curves.items():
        a = np.array(c, dtype=float)
        ax.plot(a[:, 0], a[:, 1], marker="o", label=f"trained on {ground}")
    ax.set_xlabel("training steps (control steps)")
    ax.set_ylabel("return on held-out mud fields")
    ax.legend()
    fig.tight_layout()
    png = io.BytesIO()
    fig.savefig(png, format="png", dpi=120)
    plt.close(fig)
    return png.getvalue()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--out", required=True, help="output directory DIR")
    ap.add_argument("--steps", type=int, default=500_000, help="control steps of training, each")
    ap.add_argument("--eval-every", type=int, default=25_000, help="control steps between evaluations")  # fmt: skip
    ap.add_argument("--eval-episodes", type=int, default=10, help="held-out fields per evaluation")
    ap.add_argument("--episode-steps", type=int, default=500, help="control steps of an episode (50 a second)")  # fmt: skip
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--jobs", type=int, default=1, help="policies trained at once (1 or 2), a process each"
    )
    ap.add_argument("--force", action="store_true", help="replace existing results in DIR")
    args = ap.parse_args(argv)
    for name in ("steps", "eval_every", "eval_episodes", "episode_steps", "jobs"):
        if getattr(args, name) < 1:
            ap.error(f"--{name.replace('_', '-')} must be >= 1, got {getattr(args, name)}")
    out = Path(args.out)
    names = ("results.csv", "results.md", "curves.csv", "curves.png", "run.json")
    taken = [n for n in names if (out / n).exists()]
    if taken and not args.force:
        ap.error(f"{out}: {', '.join(taken)} exist; pass --force to replace them")

    import matplotlib  # before training: every output is made before any is written
    import stable_baselines3
    import torch

    import mudrft
    from mudrft.io.atomic import atomic_write

    matplotlib.use("Agg")
    t0 = time.perf_counter()
    grounds = ("mud", "rigid")
    if args.jobs > 1:  # a process each: PPO's loop is single-threaded
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        spawn = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(min(args.jobs, len(grounds)), mp_context=spawn) as pool:
            trained = list(pool.map(train, grounds, [args] * len(grounds)))
    else:
        trained = [train(ground, args) for ground in grounds]
    results = [r for r, _ in trained]
    curves = {g: c for g, (_, c) in zip(grounds, trained, strict=True)}
    wall = time.perf_counter() - t0
    png = _curves(curves)
    out.mkdir(parents=True, exist_ok=True)
    rows = [(g, s, v) for g, c in curves.items() for s, v in c]
    run = {
        "command": "python examples/train_mud_walker.py " + " ".join(sys.argv[1:] if argv is None else argv),
        "wall_time [s]": round(wall, 1), "machine": f"{platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} CPUs, {platform.system()}", "python": platform.python_version(),
        "mudrft": mudrft.__version__, "stable_baselines3": stable_baselines3.__version__,
        "torch": torch.__version__,
    }  # fmt: skip
    force = "--force"
    atomic_write(out / "results.csv", _csv(results, COLUMNS), overwrite=args.force, option=force)
    atomic_write(out / "results.md", _table(results), overwrite=args.force, option=force)
    atomic_write(out / "curves.csv", _csv(rows, ("trained_on", "steps", "held_out_return")),
                 overwrite=args.force, option=force)  # fmt: skip
    atomic_write(out / "curves.png", png, overwrite=args.force, option=force)
    atomic_write(out / "run.json", json.dumps(run, indent=2) + "\n", overwrite=args.force, option=force)  # fmt: skip
    print(_table(results), end="")
    print(f"{wall:.0f} s; results in {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
