"""The morphing foot's surface elements, and its mechanism checked against independent solves.

Surface elements (D159): granular RFT integrates ``foot.elements()`` and loads only the
faces that lead the motion, so each pad, a thin plate, needs both faces. Before D159 every
pad had only its upper face: pushed into sand, the spread foot met the force of its base
disk alone, the same as the curled foot.

Independent checks (D159): the pad angle, the spring law, the vertical area and the column
balance recomputed here from the dataclass fields with SciPy (a root of the coupler length,
a root of the series compliance, quadrature over the pad, brentq on a fine grid), not with
mudrft's formulas. Tolerances: double-precision roots to 1e-12 of their scale.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from mudrft.feet import MorphingFoot
from mudrft.feet.morphing import pads
from mudrft.terrains import GranularRFT, GranularRFT3D

FOOT = MorphingFoot()
G = FOOT.geometry


# -- surface elements ---------------------------------------------------------------------------
@pytest.mark.parametrize("deflection", [0.0, 0.5 * FOOT.stroke, FOOT.stroke])
def test_elements_face_down_with_the_footprint_and_up_with_the_pads(deflection):
    el = FOOT.elements(deflection)
    theta = float(FOOT.pad_angle(deflection))
    down = el.areas @ np.clip(-el.normals[:, 2], 0.0, None)  # projection of the lower faces
    up = el.areas @ np.clip(el.normals[:, 2], 0.0, None)
    # downward: the base disk and the pads' lower faces, the footprint of the whole foot
    np.testing.assert_allclose(down, float(FOOT.footprint_area(deflection)), rtol=1e-12)
    # upward: the pads' upper faces only (the base's top is under the column and the pads)
    np.testing.assert_allclose(
        up, float(FOOT.footprint_area(deflection)) - math.pi * G.base_radius**2, rtol=1e-12
    )
    assert 0 < theta < math.pi / 2


@pytest.mark.parametrize("heading", [0.0, 0.3, 0.5 * math.pi])
def test_elements_project_sideways_as_the_mud_models_horizontal_area(heading):
    theta = float(FOOT.pad_angle(FOOT.stroke))
    el = FOOT.elements(FOOT.stroke, strips=8)
    h = np.array([math.cos(heading), math.sin(heading), 0.0])
    side = el.areas @ np.clip(el.normals @ h, 0.0, None)
    expected = float(pads.horizontal_area(G, G.height, theta, heading))
    # the walls are 16-sided polygons: their projection is 0.65 % above a circle's
    np.testing.assert_allclose(side, expected, rtol=1e-2)


@pytest.mark.parametrize("terrain", [GranularRFT(), GranularRFT3D()], ids=["rft", "rft3d"])
def test_spread_pads_resist_intrusion_into_sand(terrain):
    """Before D159 the pads had no lower face: expanded and retracted feet met the same force."""
    tip = np.array([0.0, 0.0, -0.02])
    down = np.array([0.0, 0.0, -0.02])
    fz = {}
    for mode in ("expanded", "retracted"):
        foot = MorphingFoot(mode=mode)
        state = terrain.initial_state(foot, tip)
        _, out = terrain.step(foot, state, tip, down, 1e-3)
        fz[mode] = float(out.force[2])
    assert fz["retracted"] > 0
    assert fz["expanded"] > 2.0 * fz["retracted"]


# -- the mechanism against independent solves -----------------------------------------------------
def _angle_independent(deflection: float, guess: float) -> float:
    """Pad angle [rad] at which the coupler spans the pole, by a root of its length."""
    b_pt = np.array([G.pole_radius, FOOT.linkage.pole_top - deflection])
    a_pt = np.array([G.base_radius, G.pivot_height])

    def gap(th: float) -> float:
        c = a_pt + G.crank_length * np.array(
            [math.cos(th + G.crank_offset), math.sin(th + G.crank_offset)]
        )
        return float(np.linalg.norm(c - b_pt)) - G.coupler_length

    return brentq(gap, guess - 0.2, guess + 0.2, xtol=1e-15)


def _spring_independent(deflection: float) -> float:
    """Force [N] of two springs in series whose soft stage stops after soft_travel."""
    s = FOOT.spring

    def excess(f: float) -> float:
        return min(f / s.soft_stiffness, s.soft_travel) + f / s.hard_stiffness - deflection

    return brentq(excess, 0.0, 1e5, xtol=1e-14) if deflection > 0 else 0.0


def _vertical_area_independent(depth: float, theta: float) -> float:
    """Base disk plus the plate rule (f_n cos + f_t sin) integrated over the wetted pads."""
    width = lambda s: G.pad_inner_width + (G.pad_outer_width - G.pad_inner_width) * s / G.pad_length  # noqa: E731
    wet = min(max((depth - G.pivot_height) / math.sin(theta), 0.0), G.pad_length)
    fn, ft = math.cos(theta) ** 2, math.sin(theta) ** 2
    plate = (fn * math.cos(theta) + ft * math.sin(theta)) * quad(width, 0.0, wet)[0]
    return (math.pi * G.base_radius**2 if depth > 0 else 0.0) + G.n_pads * plate


def test_pad_angle_spring_and_area_match_independent_solves():
    guess = G.retracted_angle
    for d in np.linspace(0.0, FOOT.stroke, 13):
        th = _angle_independent(float(d), guess)
        guess = th
        assert float(FOOT.pad_angle(d)) == pytest.approx(th, abs=1e-12)
        assert float(FOOT.spring_force(d)) == pytest.approx(_spring_independent(float(d)), abs=1e-9)
        for depth in (0.002, 0.008, 0.02, 0.05):
            assert float(FOOT.effective_area(depth, d)) == pytest.approx(
                _vertical_area_independent(depth, th), rel=1e-12
            )


@pytest.mark.parametrize(
    ("depth", "sz"), [(0.02, 2e3), (0.03, 5e3), (0.002, 1e4), (0.02, 200.0), (0.05, 1e3)]
)
def test_balance_matches_an_independent_root(depth, sz):
    """Where the independent residual has one root on a 400-point grid, it is the balance."""

    def resid(d: float) -> float:
        th = _angle_independent(d, float(FOOT.pad_angle(d)))
        return _spring_independent(d) - sz * _vertical_area_independent(depth, th)

    xs = np.linspace(0.0, FOOT.stroke, 400)
    rs = np.array([resid(float(x)) for x in xs])
    roots = [
        brentq(resid, xs[i], xs[i + 1], xtol=1e-15) for i in range(399) if rs[i] * rs[i + 1] < 0
    ]
    if rs[-1] <= 0:
        roots.append(FOOT.stroke)
    assert len(roots) == 1
    assert float(FOOT.equilibrium(depth, sz)) == pytest.approx(roots[0], abs=1e-12)


# -- two properties of the reconstruction that docs/model.md states (D160) -------------------------
def test_curled_pads_overlap_past_the_documented_angle():
    """Neighbouring rims touch at 49.2 deg; the defaults curl to 75 deg, where they overlap."""
    room = lambda s, th: 2 * (G.base_radius + s * math.cos(th)) * math.tan(math.pi / G.n_pads)  # noqa: E731
    touch = brentq(lambda th: G.pad_outer_width - room(G.pad_length, th), 0.01, 1.5)
    assert math.degrees(touch) == pytest.approx(49.2, abs=0.05)
    assert G.pad_outer_width > room(G.pad_length, G.retracted_angle)  # overlap when curled
    assert G.pad_inner_width < room(0.0, G.retracted_angle)  # not at the pivots
    assert G.pad_outer_width < room(G.pad_length, G.expanded_angle)  # nor when spread


def test_virtual_work_feedback_of_the_pads_is_as_documented():
    """x_p cos(theta) |dtheta/ddelta|: 0.66 curled, 2.53 spread (D32's rejected balance)."""
    width = lambda s: G.pad_inner_width + (G.pad_outer_width - G.pad_inner_width) * s / G.pad_length  # noqa: E731
    x_p = quad(lambda s: s * width(s), 0.0, G.pad_length)[0] / quad(width, 0.0, G.pad_length)[0]
    h = 1e-7
    factors = []
    for d in (h, FOOT.stroke - h):
        slope = (float(FOOT.pad_angle(d + h)) - float(FOOT.pad_angle(d - h))) / (2 * h)
        factors.append(x_p * math.cos(float(FOOT.pad_angle(d))) * abs(slope))
    assert x_p == pytest.approx(0.0198, abs=5e-5)
    assert factors[0] == pytest.approx(0.66, abs=0.005)
    assert factors[1] == pytest.approx(2.53, abs=0.005)
