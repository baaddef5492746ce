"""World forces from the first-quadrant closed forms (decision D9): continuity and signs."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft.feet.base import unfold_forces

FEET = [
    mudrft.feet.Flat(),
    mudrft.feet.SemiCylinder(),
    mudrft.feet.SemiSphere(),
    mudrft.feet.MorphingFoot(),
]


@pytest.mark.parametrize("foot", FEET, ids=lambda f: f.name)
def test_force_is_continuous_when_one_motion_component_reverses(foot):
    """The lateral sway of a gait reverses y while x keeps going: Fx must not jump."""
    stress = np.array([8e3, 3e3, 20e3])  # x and y both still resisting their last motion
    eps = 1e-6
    for base in (0.0, np.pi / 2, np.pi):  # reversal of y (around 0 and pi) or of x (around pi/2)
        f_plus = foot.force(0.02, stress, base + eps)
        f_minus = foot.force(0.02, stress, base - eps)
        assert np.allclose(f_plus, f_minus, rtol=1e-4, atol=1e-6 * np.abs(f_plus).max())


@pytest.mark.parametrize("foot", FEET[:3], ids=lambda f: f.name)
def test_forces_resist_the_motion_in_every_quadrant(foot):
    for heading in np.deg2rad([10, 80, 100, 170, 190, 260, 280, 350]):
        u = np.array([np.cos(heading), np.sin(heading)])
        stress = np.array([5e3, 5e3, 0.0])  # the mud's one horizontal stress, resisting
        f = foot.force(0.02, stress, heading)
        assert f[:2] @ u < 0
        assert f[0] * u[0] <= 1e-12 and f[1] * u[1] <= 1e-12


def test_first_quadrant_matches_the_paper_form():
    """In the first quadrant with resisting stresses the world force is minus the paper's resultant."""
    foot = mudrft.feet.Flat()
    stress = np.array([4e3, 2e3, 10e3])
    phi = 0.6
    f = foot.force(0.02, stress, phi)
    m = foot.resultant(0.02, stress, phi)
    np.testing.assert_allclose(f, [-m[0], -m[1], m[2]], rtol=1e-12)


def test_unfold_uses_the_linearity_of_the_closed_form():
    calls = []

    def linear(su, ph):
        calls.append(su.shape)
        out = np.zeros(su.shape)
        out[..., 0] = 2.0 * su[..., 0] + 0.5 * su[..., 1]
        out[..., 1] = 0.25 * su[..., 0] + 3.0 * su[..., 1]
        out[..., 2] = 7.0 * su[..., 2]
        return out

    f = unfold_forces(linear, np.array([1.0, -2.0, 1.0]), np.pi + 0.3)  # moving -x, -y
    assert calls == [(2, 3)]
    # Fx = -sgn(ux) (2 sx + 0.5 sy) = +(2 - 1); Fy = -sgn(uy) (3 sy + 0.25 sx) = +(-6 + 0.25)
    np.testing.assert_allclose(f, [1.0, -5.75, 7.0])
