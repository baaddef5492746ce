"""Mud on an uneven surface (``MudField(heights=...)``, ``MudField.from_hfield``): the
surface is MuJoCo's heightfield, a foot on a slope sinks along the surface normal as on
level mud under the same load turned with it, and the surface gives a free foot no energy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudrft
from mudrft._validation import MudrftError
from mudrft.terrains.field import MudField

pytest.importorskip("mujoco")
pytest.importorskip("numba")
from mudrft.integrations.mujoco import attach, attach_batch

from .conftest import energy_rise, mujoco

MUD = mudrft.paper_mud(0.3)
MASS = 0.6  # [kg]


def _free_foot(shape: str, *, g: float = 9.81, dt: float = 1e-3) -> object:
    """A free ball (radius 30 mm) or box foot (60 x 60 x 30 mm) of isotropic inertia, so
    that MuJoCo's step alone keeps its energy and a turned problem is the same problem."""
    geom = 'type="sphere" size="0.03"' if shape == "ball" else 'type="box" size="0.03 0.03 0.015"'
    return mujoco.MjModel.from_xml_string(f"""<mujoco>
      <option timestep="{dt}" gravity="0 0 -{g}"/><worldbody><body name="foot" pos="0 0 0.1">
        <freejoint/><inertial pos="0 0 0" mass="{MASS}" diaginertia="4e-4 4e-4 4e-4"/>
        <geom {geom} mass="0"/></body></worldbody></mujoco>""")


def test_a_field_on_a_mujoco_heightfield_is_mujocos_surface():
    """``from_hfield`` takes the heightfield's samples, its size and its geom's position;
    between the samples the surface is MuJoCo's own (two planar triangles a cell): the
    height agrees with ``mj_ray`` onto the geom to round-off at random points, and the
    normal is the triangle's."""
    rng = np.random.default_rng(3)
    elevation = " ".join(f"{v:.6f}" for v in rng.random(5 * 7))
    model = mujoco.MjModel.from_xml_string(f"""<mujoco><asset>
      <hfield name="h" nrow="5" ncol="7" size="0.6 0.4 0.1 0.05" elevation="{elevation}"/>
      </asset><worldbody><geom name="ground" type="hfield" hfield="h" pos="0.2 -0.1 0.02"/>
      </worldbody></mujoco>""")
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    field = MudField.from_hfield(model, "ground", {"wet": 0.35, "dry": 0.25}, ["wet dry"], surface=0.01)  # fmt: skip
    assert field.heights.shape == (5, 7) and field.names == ("wet", "dry")
    geom = np.zeros(1, dtype=np.int32)
    errors = []
    for x, y in zip(rng.uniform(-0.4, 0.8, 200), rng.uniform(-0.5, 0.3, 200), strict=True):
        above = mujoco.mj_ray(model, data, np.array([x, y, 1.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, geom)  # fmt: skip
        h, n = field.height(x, y)
        errors.append((1.0 - above) - (0.01 + h))
        # the normal is that of the plane through three surface points around (x, y)
        e = 1e-7
        p = [np.array([x + dx, y + dy, field.height(x + dx, y + dy)[0]]) for dx, dy in ((0, 0), (e, 0), (0, e))]  # fmt: skip
        want = np.cross(p[1] - p[0], p[2] - p[0])
        if np.allclose(field.height(x + e, y + e)[1], n):  # not on a triangle's edge
            np.testing.assert_allclose(n, want / np.linalg.norm(want), atol=1e-6)
    assert np.abs(errors).max() < 1e-12
    with pytest.raises(MudrftError, match="geom must name a heightfield geom"):
        MudField.from_hfield(model, 5, {"wet": 0.35})


def _slope_and_turned(shape: str, theta: float, dt: float, start: float, seconds: float):
    """The foot on a slope of ``theta`` [deg] (the surface h = tan(theta) x), placed
    ``start`` [m] along the normal above the surface point (0, 0) and turned with the
    slope; and the same problem turned level: gravity g cos(theta) along -z and
    m g sin(theta) down x. Returns per step the depth [m], the position along the slope
    and along the normal [m] and the mud's explicit force along the normal [N], for both."""
    t, c, s = math.tan(math.radians(theta)), math.cos(math.radians(theta)), math.sin(math.radians(theta))  # fmt: skip
    slope = _free_foot(shape, dt=dt)
    d = mujoco.MjData(slope)
    normal, along = np.array([-s, 0.0, c]), np.array([c, 0.0, s])
    d.qpos[:3] = start * normal
    d.qpos[3:7] = [math.cos(math.radians(theta) / 2), 0.0, -math.sin(math.radians(theta) / 2), 0.0]  # fmt: skip
    heights = np.tile(t * np.linspace(-1.0, 1.0, 3), (3, 1))
    field = MudField({"m": MUD}, ["m"], cell_size=2.0, origin=(-1.0, -1.0), border=0.5, heights=heights)  # fmt: skip
    on_slope = attach(slope, "foot", field)
    on_slope.reset(d)
    level = _free_foot(shape, g=9.81 * c, dt=dt)
    d2 = mujoco.MjData(level)
    d2.qpos[2] = start
    turned = attach(level, "foot", MUD)
    turned.reset(d2)
    d2.qfrc_applied[0] = -MASS * 9.81 * s
    a, b = [], []
    for _ in range(round(seconds / dt)):
        mujoco.mj_step(slope, d)
        mujoco.mj_step(level, d2)
        one, two = on_slope.last, turned.last
        a.append((one.depth[0], d.qpos[:3] @ along, d.qpos[:3] @ normal, one.explicit_force[0] @ normal))  # fmt: skip
        b.append((two.depth[0], d2.qpos[0], d2.qpos[2], two.explicit_force[0, 2]))
    return np.array(a), np.array(b)


@pytest.mark.parametrize("start", [0.031, 0.026], ids=["above", "in-mud"])
@pytest.mark.parametrize("dt", [1e-3, 2e-3])
@pytest.mark.parametrize("shape", ["ball", "box"])
def test_on_a_slope_a_foot_sinks_along_the_normal_as_the_level_case_turned(shape, dt, start):
    """A free foot on a 15 degree slope of W = 30 % mud moves as the same foot on level
    mud under the load turned with the slope: starting above the surface, its depth along
    the normal and its position along the slope and the normal agree to round-off
    (1e-12 m) at every step of 1 s. The mud carries it (depth > 0.5 mm) while it creeps
    down the slope (> 10 mm), so a wrong frame, sign or moment could not pass.

    Starting 4 mm in the mud, its mud starts undisturbed at that depth along the normal
    (``reset``): the first step's depth and the mud's explicit force along the normal
    agree to round-off. Later steps drift apart by micrometres, from that first step: with
    no step before it, the coupling takes gravity for the other forces' acceleration, on
    the slope the whole of it, while the level model's push down x is not gravity."""
    in_mud = start < 0.03
    if shape == "box":
        start -= 0.015  # the box's center sits 15 mm above its sole
    on_slope, turned = _slope_and_turned(shape, 15.0, dt, start, 1.0)
    sinks, creeps = (5e-4, -0.01) if shape == "ball" else (1e-4, -1e-3)  # the box: firmer
    assert on_slope[-1, 0] > sinks and on_slope[-1, 1] < creeps
    if in_mud:  # the first step
        assert on_slope[0, 3] > 1.0  # the mud pushes from the start
        on_slope, turned = on_slope[:1, [0, 3]], turned[:1, [0, 3]]
    np.testing.assert_allclose(on_slope[:, :3], turned[:, :3], rtol=0, atol=1e-12)  # [m]
    np.testing.assert_allclose(on_slope[:, 3:], turned[:, 3:], rtol=0, atol=1e-9)  # [N]


def test_a_steeper_slope_sinks_less_along_its_normal():
    """The depth along the normal follows the normal load m g cos(theta): the ball sinks
    less on 30 degrees than on 10, and on 10 about as much as level mud does."""
    depth = [_slope_and_turned("ball", th, 1e-3, 0.031, 0.6)[0][-1, 0] for th in (0.0, 10.0, 30.0)]  # fmt: skip
    assert depth[2] < depth[1] < depth[0] and depth[1] > 0.95 * depth[0]


@pytest.mark.filterwarnings("ignore::mudrft.trajectories.BuriedFootWarning")
@settings(max_examples=4, deadline=None)
@given(angle=st.floats(-180.0, 180.0), speed=st.floats(0.2, 1.0), seed=st.integers(0, 2**16))
@pytest.mark.parametrize("dt", [1e-3, 2e-3])
@pytest.mark.parametrize("shape", ["ball", "box"])
def test_a_free_foot_on_an_uneven_field_gains_no_energy(shape, dt, angle, speed, seed):
    """A free foot thrown spinning across random bumps (10 mm standard deviation on a
    25 mm grid, so it crosses triangles whose normals jump) and a border of W = 25 % and
    35 % mud: its mechanical energy never rises above the start (also where a spinning
    box digs in past its height, which warns)."""
    rng = np.random.default_rng(seed)
    heights = 0.01 * rng.standard_normal((9, 9))
    field = MudField({"a": 0.25, "b": 0.35}, ["a b", "b a"], cell_size=0.1, origin=(-0.1, -0.1), border=0.05, heights=heights)  # fmt: skip
    model = _free_foot(shape, dt=dt)
    data = mujoco.MjData(model)
    data.qpos[:3] = [-0.05, -0.03, 0.035 + field.height(-0.05, -0.03)[0]]
    coupling = attach(model, "foot", field)
    coupling.reset(data)
    a = math.radians(angle)
    data.qvel[:] = [speed * math.cos(a), speed * math.sin(a), -0.2, *(10.0 * rng.normal(size=3))]
    rise, e0 = energy_rise(model, data, lambda: mujoco.mj_step(model, data), round(0.4 / dt))
    assert coupling.last.depth[0] > 0.0  # it ended in the mud
    assert rise <= 1e-12 * e0


def test_a_level_field_at_zero_height_steps_as_the_plane_to_the_bit():
    """Heights of zero everywhere are the plane: the same steps, bit for bit."""
    runs = []
    for heights in (None, np.zeros((3, 4))):
        model = _free_foot("box")
        data = mujoco.MjData(model)
        data.qpos[2], data.qvel[:3] = 0.02, [0.3, 0.1, -0.2]
        coupling = attach(model, "foot", MudField({"m": MUD}, ["m"], heights=heights))
        coupling.reset(data)
        for _ in range(300):
            mujoco.mj_step(model, data)
        runs.append(np.concatenate([data.qpos, data.qvel]))
    assert np.array_equal(runs[0], runs[1])


def test_heights_are_checked_and_a_draw_keeps_them():
    with pytest.raises(MudrftError, match="heights must be None or finite heights"):
        MudField({"m": MUD}, ["m"], heights=np.zeros((1, 3)))
    with pytest.raises(MudrftError, match="heights must be None or finite heights"):
        MudField({"m": MUD}, ["m"], heights=[[0.0, np.nan], [0.0, 0.0]])
    field = MudField({"a": 0.25, "b": 0.35}, ["a b"], heights=[[0.0, 0.1], [0.0, 0.1]])
    assert np.array_equal(field.randomized(1, water_content=(0.2, 0.4)).heights, field.heights)
    batch = attach_batch(_free_foot("box"), "foot", field, n=2)
    with pytest.raises(MudrftError, match=r"\(2, 2\) heights, got .* \(3, 3\) heights"):
        batch.use_field(MudField({"a": 0.25, "b": 0.35}, ["a b"], heights=np.zeros((3, 3))))
