"""Shared helpers of the backend tests (imported as `_backend_support`): random inputs, paths."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

import mudrft
from mudrft.constitutive.state import ChannelState
from mudrft.parameters.base import PARAMETER_UNITS, MudParameters

FIELDS = tuple(PARAMETER_UNITS)


@st.composite
def parameter_sets(draw: st.DrawFn) -> MudParameters:
    """A valid parameter set: a paper row with every field scaled by a factor in [1/3, 3]."""
    w = draw(st.sampled_from([0.25, 0.35, 0.45]))
    direction = draw(st.sampled_from(["vertical", "horizontal"]))
    base = mudrft.paper_parameters(w, direction)
    out = {}
    for k in FIELDS:
        f = 10.0 ** draw(st.floats(-0.48, 0.48))
        out[k] = float(getattr(base, k)) * f
    out["n"] = draw(st.floats(0.05, 1.0))
    return MudParameters(**out)


@st.composite
def channel_inputs(draw: st.DrawFn, shape: tuple[int, ...] = (4,)) -> tuple:
    """(state, gamma, gamma_dot, dt, seal) arrays of ``shape`` with valid values."""
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    gw = rng.normal(size=shape) * 0.4
    # the old displacement is at most as deep as the deepest point, same side
    g_old = gw * rng.uniform(0.0, 1.0, size=shape)
    clock = rng.uniform(0.0, 2.0, size=shape)
    state = ChannelState(
        gamma=g_old,
        gamma_w=gw,
        xi=rng.uniform(0.0, 1.0, size=shape),
        s_th=rng.normal(size=shape) * 3e3,
        sigma_s=-np.abs(rng.normal(size=shape)) * 3e3,
        clock=clock,
        clock_w=np.where(
            np.abs(g_old) < np.abs(gw), clock * rng.uniform(0.0, 1.0, size=shape), 0.0
        ),
    )
    gamma = g_old + rng.normal(size=shape) * 0.05
    gamma_dot = rng.normal(size=shape) * 2.0
    dt = float(10.0 ** rng.uniform(-4, -1))
    seal = rng.uniform(0.0, 1.0, size=shape)
    return state, gamma, gamma_dot, dt, seal


def wandering_path(n: int = 300, dt: float = 1e-3, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A 3D tip path that enters, moves in every horizontal quadrant, leaves and re-enters.

    Returns (position (n, 3) [m], velocity (n, 3) [m/s]); velocity is the exact derivative.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    a = rng.uniform(0.01, 0.03, 3)
    w = rng.uniform(10.0, 30.0, 3)
    ph = rng.uniform(0, 2 * np.pi, 3)
    pos = np.stack(
        [
            a[0] * np.sin(w[0] * t + ph[0]),
            a[1] * np.sin(w[1] * t + ph[1]),
            0.004 - a[2] * np.sin(w[2] * t + ph[2]),
        ],
        axis=1,
    )
    vel = np.stack(
        [
            a[0] * w[0] * np.cos(w[0] * t + ph[0]),
            a[1] * w[1] * np.cos(w[1] * t + ph[1]),
            -a[2] * w[2] * np.cos(w[2] * t + ph[2]),
        ],
        axis=1,
    )
    return pos, vel


def terrain_forces(terrain: mudrft.MudTerrain, foot, pos: np.ndarray, vel: np.ndarray, dt: float):
    """Reference: MudTerrain stepped along (pos, vel); returns (force, stress, depth) per step."""
    state = terrain.initial_state(foot, pos[0])
    f, s, d = [], [], []
    for k in range(1, len(pos)):
        state, out = terrain.step(foot, state, pos[k], vel[k], dt)
        f.append(out.force)
        s.append(out.stress)
        d.append(out.depth)
    return np.array(f), np.array(s), np.array(d)
