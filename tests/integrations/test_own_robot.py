"""A robot-learning user's own robot: the mistakes and models the demo biped never shows.

Found by a walkthrough with a quadruped of one's own (sphere feet on the calf bodies, a
visual mesh, geoms of every type). Before the fixes a geom name given for a body was
answered with the list of bodies only, a body whose only geom was an ellipsoid "had no
geom", a vertical capsule was "geom 0" without the body or its name, and a visual-only mesh
below the collision sphere became the foot.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError

pytest.importorskip("mujoco")
from mudrft.integrations.mujoco import attach, body_foot

from .conftest import mujoco

MUD = mudrft.paper_mud(0.25)


def _leg(geoms: str) -> object:
    """A free body 'calf' carrying ``geoms`` (MJCF), 5 cm above the mud."""
    xml = f"""<mujoco><worldbody><body name="calf" pos="0 0 0.05"><freejoint/>
      {geoms}</body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def test_a_geom_name_names_its_body_with_that_geom_as_the_foot():
    model = _leg(
        """<geom name="FL_foot" type="sphere" size="0.025" mass="0.3"/>
           <geom name="shin" type="box" size="0.02 0.02 0.02" pos="0 0 -0.03"/>"""
    )
    (placed,) = attach(model, ["FL_foot"], MUD).bodies
    assert placed.body == "calf" and model.geom(placed.geom).name == "FL_foot"
    assert isinstance(placed.foot, mudrft.feet.SemiSphere)  # not the lower box


def test_a_body_without_a_geom_of_a_supported_type_names_its_geoms():
    model = _leg('<geom name="sole" type="ellipsoid" size="0.03 0.02 0.01" mass="0.3"/>')
    with pytest.raises(
        MudrftError,
        match=r"body 'calf' has no geom mudrft can turn into a foot: 'sole' \(ellipsoid\); "
        r"use a box, sphere, capsule, cylinder or mesh, or pass the foot explicitly \(feet=",
    ):
        attach(model, "calf", MUD)


def test_a_body_without_any_geom_still_asks_for_the_foot():
    model = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody><body name="calf"><freejoint/><inertial pos="0 0 0" mass="1"
        diaginertia="1e-3 1e-3 1e-3"/></body></worldbody></mujoco>"""
    )
    with pytest.raises(MudrftError, match=r"body 'calf' has no geom to derive a foot from"):
        attach(model, "calf", MUD)


@pytest.mark.parametrize("named", [True, False])
def test_a_vertical_capsule_is_its_meshed_hull_and_says_so(named):
    name = 'name="shin_col" ' if named else ""
    model = _leg(f'<geom {name}type="capsule" fromto="0 0 0 0 0 -0.05" size="0.02" mass="0.3"/>')
    label = "geom 'shin_col'" if named else "geom 0"
    coupling = attach(model, "calf", MUD)
    (placed,) = coupling.bodies
    assert isinstance(placed.foot, mudrft.feet.MeshFoot)
    assert placed.foot.height == pytest.approx(0.09, abs=1e-9)  # 50 mm and two 20 mm caps
    assert f"{label} (capsule) -> its convex hull, meshed (it stands)" in coupling.feet[0]
    # its round end: the 16-gon's area at the equator, less at half the cap's height
    disk = 0.02**2 * 8 * np.sin(2 * np.pi / 16)
    assert placed.foot.projected_areas(0.02)[2] == pytest.approx(disk, rel=1e-9)
    assert placed.foot.projected_areas(0.01)[2] < 0.9 * disk


def test_a_visual_only_geom_below_the_collision_geom_is_not_the_foot():
    model = _leg(
        """<geom name="shoe" type="box" size="0.05 0.03 0.02" pos="0 0 -0.02"
             contype="0" conaffinity="0" group="2" mass="0"/>
           <geom name="foot_col" type="sphere" size="0.025" mass="0.3"/>"""
    )
    placed = body_foot(model, "calf")
    assert isinstance(placed.foot, mudrft.feet.SemiSphere)
    assert placed.kind == "sphere"
    assert placed.tip[2] == pytest.approx(-0.025)


def test_a_body_of_visual_geoms_only_still_derives_its_foot_from_them():
    model = _leg('<geom type="box" size="0.03 0.04 0.01" contype="0" conaffinity="0" mass="0.3"/>')
    assert isinstance(body_foot(model, "calf").foot, mudrft.feet.Flat)


def test_a_body_welded_to_the_world_warns_that_the_mud_moves_nothing():
    # the mud's force on a body with no joint to the world does nothing: most likely the
    # wrong body or a joint missing; a body that can move (free or hinged) does not warn
    import warnings

    from mudrft._validation import PlausibilityWarning

    xml = """<mujoco><worldbody>
      <body name="fixed" pos="0 0 0.05"><geom type="sphere" size="0.02" mass="0.3"/>
        <body name="fixed_child" pos="0 0.1 0"><geom type="box" size="0.02 0.02 0.01"/></body>
        <body name="hinged" pos="0.1 0 0"><joint type="hinge" axis="0 1 0"/>
          <geom type="sphere" size="0.02" mass="0.3"/></body></body>
      <body name="free" pos="1 0 0.05"><freejoint/><geom type="sphere" size="0.02"/></body>
    </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    for body in ("fixed", "fixed_child"):
        with pytest.warns(PlausibilityWarning, match=rf"body '{body}' is welded to the world"):
            attach(model, body, MUD)
    if importlib.util.find_spec("mujoco.mjx") is not None:  # the MJX coupling places alike
        from mudrft.integrations import mjx

        with pytest.warns(PlausibilityWarning, match=r"body 'fixed' is welded to the world"):
            mjx.attach(model, "fixed", MUD)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        attach(model, ["hinged", "free"], MUD)
        body_foot(model, "fixed")  # placing a foot to inspect it is no coupling


def test_a_timestep_far_above_the_checked_range_warns_once_at_attach_and_reset():
    # a model of one's own at 20 ms: a 1.5 kg box foot settles 2.8 times too deep there
    # with a force alternating step by step; the couplings were checked at 0.5-5 ms
    # and the biped walks at up to 10 ms, which stay quiet (D123)
    import warnings

    from mudrft._validation import PlausibilityWarning
    from mudrft.integrations import walk
    from mudrft.integrations.mujoco.options import LARGEST_TIMESTEP

    from .conftest import box_foot_model

    assert walk.MAX_DT <= LARGEST_TIMESTEP  # mudrft walk never warns
    for dt in (5e-4, 2e-3, 5e-3, LARGEST_TIMESTEP):
        model = box_foot_model(dt=dt)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            attach(model, "foot", MUD).reset(mujoco.MjData(model))
    model = box_foot_model(dt=0.02)
    advice = r"timestep is 0\.02 s, far above .* \(0\.5-5 ms.*use a timestep of 5 ms or less"
    with pytest.warns(PlausibilityWarning, match=advice) as record:
        coupling = attach(model, "foot", MUD)
    assert len(record) == 1
    data = mujoco.MjData(model)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coupling.reset(data)  # the step it warned about: once is enough
    model.opt.timestep = 0.05
    with pytest.warns(PlausibilityWarning, match=r"timestep is 0\.05 s") as record:
        coupling.reset(data)
    assert len(record) == 1
    if importlib.util.find_spec("mujoco.mjx") is not None:  # the MJX coupling alike
        from mudrft.integrations import mjx

        with pytest.warns(PlausibilityWarning, match=r"timestep is 0\.05 s") as record:
            mjx.attach(model, "foot", MUD)
        assert len(record) == 1


def _two_soles(toe_z: float = 0.0) -> object:
    """A free body 'calf' with two colliding box soles, 'heel' and 'toe' (its bottom
    ``toe_z`` [m] above the heel's), a capsule 'shin' above them and an ellipsoid."""
    return _leg(
        f"""<geom name="heel" type="box" size="0.02 0.03 0.01" pos="-0.03 0 0" mass="0.2"/>
           <geom name="toe" type="box" size="0.02 0.03 0.01" pos="0.03 0 {toe_z}" mass="0.2"/>
           <geom name="shin" type="capsule" fromto="0 0 0.02 0 0 0.1" size="0.01" mass="0.1"/>
           <geom name="knob" type="ellipsoid" size="0.01 0.01 0.02" pos="0 0 0.03"/>"""
    )


def test_foot_geoms_names_the_geom_that_is_the_foot_on_both_couplings():
    # a body with several colliding geoms: the lowest is the foot unless foot_geoms names
    # another (D124); body_foot takes the same choice as geom=
    import warnings

    model = _leg(
        """<geom name="shin" type="capsule" fromto="-0.03 0 -0.03 0.03 0 -0.03" size="0.01"/>
           <geom name="toe" type="sphere" size="0.02" mass="0.3"/>"""
    )
    toe = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "toe")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        derived = attach(model, "calf", MUD).bodies[0]
        named = attach(model, "calf", MUD, foot_geoms={"calf": "toe"}).bodies[0]
        by_id = body_foot(model, "calf", geom=toe)
    assert isinstance(derived.foot, mudrft.feet.SemiCylinder) and derived.tip[2] == pytest.approx(
        -0.04
    )
    for placed in (named, by_id):
        assert isinstance(placed.foot, mudrft.feet.SemiSphere) and placed.geom == toe
        assert placed.kind == "sphere" and placed.tip[2] == pytest.approx(-0.02)
    if importlib.util.find_spec("mujoco.mjx") is not None:
        from mudrft.integrations import mjx

        placed = mjx.attach(model, "calf", MUD, foot_geoms={"calf": "toe"}).bodies[0]
        assert isinstance(placed.foot, mudrft.feet.SemiSphere) and placed.geom == toe


def test_colliding_geoms_as_low_as_the_foot_are_one_foot_with_it():
    # D124 warned and asked for foot_geoms; the foot is now their union (its hull)
    import warnings

    for toe_z in (0.0, 0.0009):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            (placed,) = attach(_two_soles(toe_z), "calf", MUD).bodies
        assert [_two_soles().geom(g).name for g in placed.geoms] == ["heel", "toe"]
        assert isinstance(placed.foot, mudrft.feet.MeshFoot)
    (placed,) = attach(_two_soles(), "calf", MUD, foot_geoms={"calf": "toe"}).bodies
    assert isinstance(placed.foot, mudrft.feet.Flat)  # the user chose
    (placed,) = attach(_two_soles(0.0011), "calf", MUD).bodies
    assert isinstance(placed.foot, mudrft.feet.Flat)  # the heel is the lowest, clearly
    if importlib.util.find_spec("mujoco.mjx") is not None:
        from mudrft.integrations import mjx

        (placed,) = mjx.attach(_two_soles(), "calf", MUD).bodies
        assert isinstance(placed.foot, mudrft.feet.MeshFoot) and len(placed.geoms) == 2


@pytest.mark.parametrize(
    ("foot_geoms", "message"),
    [
        ("toe", r"foot_geoms must be a mapping \{body: geom name\}, e.g. foot_geoms=\{'calf': "),
        (
            {"thigh": "toe"},
            r"foot_geoms names body 'thigh', which is not coupled; the bodies are \['calf'\]",
        ),
        ({"calf": True}, r"foot_geoms\['calf'\] must be a geom's name \(or id\), or a list"),
        (
            {"calf": "sole"},
            r"geom 'sole', named as the foot of body 'calf', is not in the model; the body's "
            r"geoms are \['heel', 'toe', 'shin', 'knob'\]",
        ),
        (
            {"calf": "floor"},
            r"geom 'floor' of body 'world', named as the foot of body 'calf', is not one of its geoms",
        ),
        ({"calf": "knob"}, r"geom 'knob' of body 'calf', named as the foot, has type ellipsoid"),
    ],
)
def test_foot_geoms_mistakes_name_the_option_the_body_and_its_geoms(foot_geoms, message):
    model = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody><geom name="floor" type="plane" size="1 1 0.1" pos="0 0 -1"/>
        <body name="calf" pos="0 0 0.05"><freejoint/>
        <geom name="heel" type="box" size="0.02 0.03 0.01" pos="-0.03 0 0" mass="0.2"/>
        <geom name="toe" type="box" size="0.02 0.03 0.01" pos="0.03 0 0" mass="0.2"/>
        <geom name="shin" type="capsule" fromto="0 0 0.02 0 0 0.1" size="0.01" mass="0.1"/>
        <geom name="knob" type="ellipsoid" size="0.01 0.01 0.02" pos="0 0 0.03"/>
        </body></worldbody></mujoco>"""
    )
    with pytest.raises(MudrftError, match=message):
        attach(model, "calf", MUD, foot_geoms=foot_geoms)
