"""Rigid ground: penalty contact with regularised Coulomb friction."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft import MudrftError
from mudrft.baselines import RigidGround, run_terrain


@pytest.mark.parametrize("speed", [0.13, 0.2, 0.26])
def test_normal_force_is_the_clipped_spring_damper_and_never_pulls(box, speed):
    g = RigidGround()
    tr = mudrft.gait(speed)
    h = run_terrain(g, box, tr)
    d = tr.depth
    expected = np.where(
        d > 0, np.maximum(g.stiffness * d - g.damping * tr.velocity[:, 2], 0.0), 0.0
    )
    np.testing.assert_allclose(h.force[:, 2], expected, rtol=1e-12, atol=1e-12)
    assert np.all(h.force[:, 2] >= 0.0)  # no adhesion


def test_friction_opposes_sliding_and_obeys_coulomb(box):
    g = RigidGround(friction=0.5)
    h = run_terrain(g, box, mudrft.gait(0.2))
    ft = h.force[:, :2]
    vt = h.velocity[:, :2]
    assert np.all(np.linalg.norm(ft, axis=1) <= 0.5 * h.force[:, 2] + 1e-12)
    assert np.all((ft * vt).sum(1) <= 0.0)
    fast = np.linalg.norm(vt, axis=1) > 10 * g.slip_speed
    # beyond ten slip speeds tanh(10) = 1 - 4e-9: full Coulomb friction
    np.testing.assert_allclose(np.linalg.norm(ft[fast], axis=1), 0.5 * h.force[fast, 2], rtol=1e-8)


@pytest.mark.parametrize("mass", [0.5, 1.0, 5.0, 20.0])
def test_defaults_are_stable_at_one_millisecond(mass):
    """A mass dropped from 1 cm, semi-implicit Euler at dt = 1 ms, settles at m g / k."""
    g = RigidGround()
    dt, z, v = 1e-3, 0.01, 0.0
    zs = []
    state = g.initial_state(None, np.array([0.0, 0.0, z]))
    for _ in range(3000):
        state, out = g.step(None, state, np.array([0.0, 0.0, z]), np.array([0.0, 0.0, v]), dt)
        v += dt * (out.force[2] / mass - 9.81)
        z += dt * v
        zs.append(z)
    zs = np.array(zs)
    assert np.all(np.isfinite(zs)) and zs.min() > -0.01  # no blow-up: bounded penetration
    # after 3 s the oscillation has decayed (slowest: 20 kg, decay rate 15.8 1/s): 0.1 % of the sag
    assert -zs[-1] == pytest.approx(mass * 9.81 / g.stiffness, rel=1e-3)


def test_errors():
    with pytest.raises(MudrftError, match="stiffness"):
        RigidGround(stiffness=-1.0)
    with pytest.raises(MudrftError, match="friction"):
        RigidGround(friction=-0.1)
