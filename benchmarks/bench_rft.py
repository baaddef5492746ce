"""Benchmark: the granular RFTs along a gait, against a plain vectorised numpy RFT.

``python benchmarks/bench_rft.py [--rounds 3] [--budget 3]`` times, on the paper's gait at
0.2 m/s (650 steps, the direction of motion changes at every step),

* ``terrain``: ``mudrft.simulate(foot, terrain, gait)`` with :class:`GranularRFT` and
  :class:`GranularRFT3D` (the terrain step, the stresses on projected areas included);
* ``plain``: the same facets' forces, step by step, in plain numpy: the facets under the
  surface, their depths and the public ``rft_forces`` / ``rft3d_forces`` (forces only);

for a mesh foot (a semi-sphere mesh of 512 facets, tilted: every facet its own normal)
and the meshes of two closed-form feet (``SemiSphere``: 18,432 facets, 9,217 normals;
``Flat``: 27,648 facets, 6 normals). Times are ms per step, the best of ``--rounds``
rounds (the harness's timer). To compare two trees, run it with each tree's ``src``
first on ``PYTHONPATH``, alternating, and keep the best of each.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

import numpy as np
from harness._timing import best
from scipy.spatial.transform import Rotation

import mudrft
from mudrft.feet.meshgen import semisphere_mesh
from mudrft.terrains import GranularRFT, GranularRFT3D
from mudrft.terrains.granular_rft import rft_forces
from mudrft.terrains.granular_rft3d import rft3d_forces


def feet() -> dict[str, mudrft.feet.Foot]:
    """The three feet of the benchmark, by label."""
    tilt = Rotation.from_rotvec([0.1, 0.2, 0.3])
    return {
        "mesh (512 facets)": mudrft.feet.MeshFoot(
            *semisphere_mesh(0.045, 0.045, resolution=8)
        ).posed(tilt),
        "SemiSphere": mudrft.feet.SemiSphere(),
        "Flat": mudrft.feet.Flat(),
    }


def plain(foot: mudrft.feet.Foot, terrain: GranularRFT | GranularRFT3D) -> Callable[[], None]:
    """The plain numpy RFT of ``foot``'s facets along the gait: submerged facets only."""
    g = mudrft.gait(speed=0.2)
    el = foot.elements()
    n, h, a = el.normals, el.centroids[:, 2], el.areas

    def force(d: np.ndarray, v: np.ndarray) -> np.ndarray:
        if isinstance(terrain, GranularRFT):
            return rft_forces(n[d > 0], d[d > 0], a[d > 0], v, zeta=terrain.zeta)
        return rft3d_forces(
            n[d > 0], d[d > 0], a[d > 0], v, xi_n=terrain.xi_n, mu_surf=terrain.mu_surf
        )

    def run() -> None:
        v = np.array([0.0, 0.0, -1.0])
        for k in range(1, len(g)):
            if np.linalg.norm(g.velocity[k]) > terrain.rest_speed:
                v = g.velocity[k]
            d = -(g.position[k, 2] + h)
            if np.any(d > 0):
                force(d, v)

    return run


def run(rounds: int, budget: float) -> dict[str, dict[str, float]]:
    """ms per step of ``terrain`` and ``plain`` for each foot and RFT."""
    g = mudrft.gait(speed=0.2)
    steps = len(g) - 1
    out = {}
    for label, foot in feet().items():
        for terrain in (GranularRFT(), GranularRFT3D()):
            kw = {"budget": budget, "repeat": rounds}
            sim = best(lambda: mudrft.simulate(foot, terrain, g), **kw)  # noqa: B023
            ref = best(plain(foot, terrain), **kw)
            out[f"{label}, {terrain.name}"] = {
                "terrain": 1e3 * sim / steps,
                "plain": 1e3 * ref / steps,
            }
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3, help="rounds per case (best is kept)")
    ap.add_argument("--budget", type=float, default=3.0, help="seconds per case")
    args = ap.parse_args(argv)
    print(f"{'foot, terrain':34s} {'terrain':>9s} {'plain':>9s}  ratio   [ms per step]")
    for case, t in run(args.rounds, args.budget).items():
        ratio = t["terrain"] / t["plain"]
        print(f"{case:34s} {t['terrain']:9.3f} {t['plain']:9.3f}  {ratio:5.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
