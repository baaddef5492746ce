"""
Training PPO on the mud walker (Gymnasium)
==========================================

Train PPO (Stable-Baselines3) on the mud walker for a few thousand steps: the wiring.

``mudrft/MudWalker-v0`` is the project's planar biped in the paper's mud (W = 25 %, flat
feet; :mod:`mudrft.envs.walker`). This script trains Stable-Baselines3's PPO on it for
``--steps`` control steps (default 4096, about 80 s of simulated walking), then runs the
policy for one deterministic episode of 200 steps and prints the return, the distance and
the mean sinking. It shows that the environment plugs into a standard RL library; it does
not train long enough to reach a gait.

Run: ``pip install 'mudrft[rl-train]'`` (gymnasium, Stable-Baselines3, torch), then
``python examples/train_mud_walker.py [--steps 4096] [--foot flat] [--water-content 0.25]``.
About 30 s on 2 CPU cores (the first step compiles the numba coupling).
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description="Train PPO (Stable-Baselines3) on the mud walker for a few thousand steps."
    )
    ap.add_argument("--steps", type=int, default=4096, help="control steps of training")
    ap.add_argument("--foot", default="flat", help="flat, semi-cylinder or semi-sphere")
    ap.add_argument("--water-content", type=float, default=0.25)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)

    import gymnasium
    import torch
    from stable_baselines3 import PPO

    import mudrft.envs  # noqa: F401  (registers mudrft/MudWalker-v0)

    torch.set_num_threads(1)  # small networks: threads cost more than they give
    t0 = time.perf_counter()
    env = gymnasium.make(
        "mudrft/MudWalker-v0", foot=args.foot, water_content=args.water_content,
        max_episode_steps=200,
    )  # fmt: skip
    model = PPO(
        "MlpPolicy", env, n_steps=1024, batch_size=128, n_epochs=5, learning_rate=3e-4,
        policy_kwargs={"net_arch": [64, 64]}, seed=args.seed, verbose=0, device="cpu",
    )  # fmt: skip
    model.learn(total_timesteps=args.steps)
    t_train = time.perf_counter() - t0

    obs, info = env.reset(seed=args.seed + 1)
    x0, ret, sink = info["x_position"], 0.0, []
    for _ in range(200):
        action, _ = model.predict(obs, deterministic=True)
        obs, reward, terminated, truncated, info = env.step(action)
        ret += float(reward)
        sink.append(float(np.mean(info["sinking [m]"])))
        if terminated or truncated:
            break
    print(
        f"trained {args.steps} steps in {t_train:.1f} s; one episode: return {ret:.1f}, "
        f"distance {info['x_position'] - x0:+.3f} m, mean sinking {1e3 * np.mean(sink):.1f} mm",
        file=sys.stderr,
    )
    env.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
