"""The MuJoCo coupling: same forces as MudTerrain, settling, energy, stability, batches."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

pytest.importorskip("mujoco")
from mudrft.integrations.mujoco import MudBatch, attach, attach_batch, body_foot, stability_limits
from mudrft.simulation import LoadControl, simulate, static_sinking

from .conftest import G, box_foot_model, kinematic_foot_model, mechanical_energy, mujoco

MUD = mudrft.paper_mud(0.25)


# ---------------------------------------------------------------------------------------
# Forces: the coupling writes exactly what MudTerrain gives for the same motion
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("yaw", [0.0, 0.7, -2.5])
def test_forces_equal_mudterrain_along_gait(yaw):
    """Kinematic foot driven along mudrft.gait: the explicit force equals MudTerrain.step
    (D61, D65).

    The yawed runs drive the foot along the gait rotated by ``yaw``; the force must be the
    rotated force of the unrotated foot (the foot frame turns with the body's yaw).
    """
    tr = mudrft.gait(speed=0.2)
    dt = float(tr.time[1] - tr.time[0])
    model = kinematic_foot_model(yaw=yaw, dt=dt)
    data = mujoco.MjData(model)
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    coupling = attach(model, "foot", MUD)
    assert (
        coupling.bodies[0].foot == mudrft.feet.Flat()
    )  # 65 x 80 x 26 mm box -> the paper's flat foot
    terrain = mudrft.MudTerrain(MUD)
    foot = mudrft.feet.Flat()
    state = terrain.initial_state(foot, tr.position[0])
    data.qpos[:] = rot @ tr.position[0]
    coupling.reset(data)
    got, want = [], []
    for k in range(1, len(tr)):
        data.qpos[:] = rot @ tr.position[k]
        data.qvel[:] = rot @ tr.velocity[k]
        mujoco.mj_forward(model, data)
        contact = coupling.apply(data)
        state, out = terrain.step(foot, state, tr.position[k], tr.velocity[k], dt)
        got.append(contact.explicit_force[0])
        want.append(rot @ out.force)
    got, want = np.array(got), np.array(want)
    assert np.abs(want[:, 2]).max() > 50 and want[:, 2].min() < -5  # support and suction both occur
    # same arithmetic up to the rotation into and out of the foot frame: round-off only
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())


def test_explicit_force_reported_when_stabilised():
    """With the implicit treatment on, ``explicit_force`` is still MudTerrain's force."""
    tr = mudrft.gait(speed=0.13)
    dt = float(tr.time[1] - tr.time[0])
    model = kinematic_foot_model(dt=dt)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", MUD)
    terrain, foot = mudrft.MudTerrain(MUD), mudrft.feet.Flat()
    state = terrain.initial_state(foot, tr.position[0])
    coupling.reset(data)
    diff = 0.0
    for k in range(1, len(tr)):
        data.qpos[:], data.qvel[:] = tr.position[k], tr.velocity[k]
        mujoco.mj_forward(model, data)
        out_c = coupling.apply(data)
        state, out = terrain.step(foot, state, tr.position[k], tr.velocity[k], dt)
        np.testing.assert_allclose(out_c.explicit_force[0], out.force, rtol=1e-9, atol=1e-9)
        diff = max(diff, float(np.abs(out_c.force[0] - out.force).max()))
    assert (
        diff > 1.0
    )  # the applied force differs: the body has mass, so the damper is treated implicitly


def test_mud_advances_once_per_step():
    """One terrain call per physics step in the numpy reference, even with the implicit
    treatment (D61): the derivative's four evaluations go in one call."""
    from ._reference import attach as reference

    class Counting(mudrft.MudTerrain):
        calls = 0

        def step(self, foot, state, position, velocity, dt):
            self.calls += 1
            return super().step(foot, state, position, velocity, dt)

    terrain = Counting(MUD)
    model = box_foot_model()
    data = mujoco.MjData(model)
    coupling = reference(model, "foot", terrain, backend="numpy")
    coupling.reset(data)
    coupling.step(data, 37)
    assert terrain.calls == 37


def test_torque_is_moment_about_center_of_mass():
    """xfrc_applied holds the force at the center of mass and the moment about it (D66).

    Applying the force at the reported point of application, plus the couple left over,
    with mj_applyFT gives the same accelerations (the body origin is off the center of
    mass here, so a moment taken about the origin would not).
    """
    xml = """<mujoco><worldbody><body name="foot" pos="0.2 0.1 0.005" euler="0 0 23"><freejoint/>
      <geom type="box" size="0.0325 0.04 0.013" pos="0.01 0 0.008" mass="0.8"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[:3] = [0.05, -0.02, -0.05]
    coupling = attach(model, "foot", MUD)
    coupling.reset(data)
    coupling.step(data, 20)
    mujoco.mj_forward(model, data)
    out = coupling.apply(data)
    assert (
        out.depth[0] > 0 and np.linalg.norm(out.force[0, :2]) > 0.1
    )  # horizontal force -> a lever arm
    assert abs(out.point[0, 2] - out.tip[0, 2]) > 1e-5  # applied above the lowest point
    mujoco.mj_forward(model, data)
    qacc_xfrc = data.qacc.copy()
    couple = out.torque[0] - np.cross(out.point[0] - data.xipos[1], out.force[0])
    qfrc = np.zeros(model.nv)
    mujoco.mj_applyFT(model, data, out.force[0], couple, out.point[0], 1, qfrc)
    data.xfrc_applied[:] = 0.0
    data.qfrc_applied[:] = qfrc
    ours = mujoco.get_mjcb_passive()  # the coupling writes xfrc_applied in mj_forward too
    mujoco.set_mjcb_passive(None)
    try:
        mujoco.mj_forward(model, data)
    finally:
        mujoco.set_mjcb_passive(ours)
    np.testing.assert_allclose(qacc_xfrc, data.qacc, rtol=1e-9, atol=1e-9)


def test_yawing_foot_in_mud_feels_no_spurious_drag():
    """Odometry in the foot frame (D65): a sphere spinning about the vertical axis through its
    tip, far from the world origin, has no horizontal displacement, so no horizontal force."""
    xml = """<mujoco><option timestep="0.001" gravity="0 0 0"/><worldbody>
      <body name="foot" pos="3 -2 0.02"><joint name="yaw" type="hinge" axis="0 0 1"/>
        <geom type="sphere" size="0.03" mass="0.3"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", MUD)
    coupling.reset(data)
    fz = []
    for k in range(400):
        data.qpos[0] = 2.0 * k * 1e-3
        data.qvel[0] = 2.0
        mujoco.mj_forward(model, data)
        out = coupling.apply(data)
        fz.append(out.force[0, 2])
        # 1 cm deep: support, but zero horizontal motion of the tip; round-off only
        assert np.abs(out.force[0, :2]).max() < 1e-9
    assert min(fz[1:]) > 0


# ---------------------------------------------------------------------------------------
# A dropped foot settles where load-controlled simulate (and the static balance) put it
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("dt", [1e-3, 2e-3])
def test_dropped_foot_settles_like_load_control(dt):
    mass, duration = 1.5, 3.0
    model = box_foot_model(mass=mass, dt=dt)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", MUD)
    coupling.reset(data)
    n = round(duration / dt)
    z = np.empty(n)
    for k in range(n):
        coupling.step(data)
        z[k] = data.qpos[2] - 0.013
    foot = coupling.bodies[0].foot
    ref = simulate(foot, MUD, LoadControl(weight=mass * G, duration=duration, dt=2.5e-4))
    z_ref = np.interp(dt * np.arange(1, n + 1), ref.time, ref.position[:, 2])
    final = -z_ref[-1]
    assert 1e-3 < final < 2e-3  # it sank about a millimetre
    # the same dynamics at a 4-8x larger step: O(dt) differences of the explicit coupling
    # during the first steps, measured 0.5 % (1 ms) and 2.7 % (2 ms) of the final depth
    assert np.abs(z - z_ref).max() < 0.05 * final
    # once settled they agree far better (measured 0.01 % and 0.03 %)
    assert abs(z[-1] - z_ref[-1]) < 0.002 * final
    # and that is the static balance F_z(d) = m g, up to the creep left after 3 s (0.9 %)
    assert abs(-z[-1] - static_sinking(foot, MUD, mass * G)) < 0.02 * final


# ---------------------------------------------------------------------------------------
# Stability: the analysis predicts the explicit limit; the coupling stays inside it
# ---------------------------------------------------------------------------------------
def _drop_energy_rise(dt: float, mass: float = 0.3, duration: float = 0.4) -> float:
    model = box_foot_model(mass=mass, dt=dt)
    data = mujoco.MjData(model)
    data.qvel[2] = -0.1
    coupling = attach(model, "foot", MUD)
    coupling.reset(data)
    e0 = mechanical_energy(model, data)
    rise = -np.inf
    for _ in range(int(duration / dt)):
        try:
            coupling.step(data)
        except mudrft.MudrftError:  # the coupling refuses to return a non-finite force
            return np.inf
        rise = max(rise, mechanical_energy(model, data) - e0)
    return float(rise)


def test_the_implicit_step_is_passive_above_the_explicit_limit():
    """The coupling gains no energy at time steps above the explicit limit 2 m / c (D62)."""
    foot = mudrft.feet.Flat()
    lim = stability_limits(foot, MUD, mass=0.3, depth=1e-3)
    assert lim["dt_viscous"] < lim["dt_elastic"]  # the damper, not the spring, sets the limit
    for factor in (0.8, 1.3, 3.0):
        assert _drop_energy_rise(factor * lim["dt_viscous"]) <= 1e-9  # round-off


@pytest.mark.parametrize("dt", [1e-3, 2e-3])
def test_no_energy_injected_through_intrusion_and_suction(dt):
    """A light foot on a spring is shot into the mud and pulled out against suction.

    Total mechanical energy (kinetic + gravity + spring, MuJoCo's own) never rises above its
    start, at time steps 2-3x above the explicit limit of this 0.3 kg foot (0.6 ms).
    """
    k, mass = 300.0, 0.3
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody><body name="foot" pos="0 0 0.013">
      <joint name="z" type="slide" axis="0 0 1" stiffness="{k}" springref="0.06"/>
      <geom type="box" size="0.0325 0.04 0.013" mass="{mass}"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[0] = -0.3
    coupling = attach(model, "foot", MUD)
    coupling.reset(data)
    e0 = mechanical_energy(model, data)
    rise, fz_min = -np.inf, 0.0
    for _ in range(int(1.2 / dt)):
        out = coupling.step(data)
        fz_min = min(fz_min, float(out.force[0, 2]))
        rise = max(rise, mechanical_energy(model, data) - e0)
    assert fz_min < -5.0  # the retraction met suction
    # semi-implicit Euler alone lets a spring-mass's energy swing by (omega dt)^2 / 4 of it
    omega = np.sqrt(k / mass)
    tol = 0.25 * (omega * dt) ** 2 * e0
    assert rise <= tol


def test_stability_limits_scale_as_derived():
    """dt_viscous ~ m, dt_elastic ~ sqrt(m) (properties of the linearisation)."""
    foot = mudrft.feet.SemiSphere()
    a = stability_limits(foot, MUD, mass=0.5, depth=0.01)
    b = stability_limits(foot, MUD, mass=2.0, depth=0.01)
    assert b["dt_viscous"] == pytest.approx(4 * a["dt_viscous"], rel=1e-12)
    assert b["dt_elastic"] == pytest.approx(2 * a["dt_elastic"], rel=1e-12)
    shallow = stability_limits(foot, MUD, mass=0.5, depth=1e-4)
    # elastic stiffness alpha n gamma^(n-1) A/Lc: with n < 1 it grows as the foot touches down
    assert shallow["stiffness"] / shallow["damping"] > a["stiffness"] / a["damping"]


# ---------------------------------------------------------------------------------------
# Rigid bottom, batches, geometry, errors
# ---------------------------------------------------------------------------------------
def test_rigid_bottom_carries_what_the_mud_cannot():
    mud = mudrft.paper_mud(0.45)  # 12 kg on the flat foot sinks without end in this mud
    mass, bottom = 12.0, 0.02
    model = box_foot_model(mass=mass, dt=1e-3)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", mud, bottom=bottom)
    coupling.reset(data)
    out = coupling.step(data, 2000)
    pen = out.depth[0] - bottom
    assert 0 < pen < mass * G / coupling.bottom_stiffness  # on the bed, which carries part of it
    # at rest the mud plus bed force balances the weight (1 % for the residual creep)
    assert out.force[0, 2] == pytest.approx(mass * G, rel=0.01)


def test_batch_equals_single_robots():
    """MudBatch with one vectorized terrain call per step = separate couplings (D68)."""
    v0 = [-0.05, -0.2, 0.0]
    model = box_foot_model(mass=1.0, dt=1e-3)
    datas = [mujoco.MjData(model) for _ in v0]
    for d, v in zip(datas, v0, strict=True):
        d.qvel[:3] = [0.02, -0.01, v]
    batch = attach_batch(model, "foot", MUD, n=len(v0))
    assert isinstance(batch, MudBatch)
    batch.reset(datas)
    batch.step(datas, 300)
    for d_b, v in zip(datas, v0, strict=True):
        d = mujoco.MjData(model)
        d.qvel[:3] = [0.02, -0.01, v]
        single = attach(model, "foot", MUD)
        single.reset(d)
        single.step(d, 300)
        # identical arithmetic up to the batch layout: round-off
        np.testing.assert_allclose(d_b.qpos, d.qpos, rtol=1e-9, atol=1e-12)
    assert batch.last.force.shape == (3, 1, 3)


def test_feet_derived_from_geoms():
    feet = mudrft.feet
    xml = """<mujoco><asset><mesh name="m" vertex="-0.03 -0.02 0  0.03 -0.02 0  0.03 0.02 0  -0.03 0.02 0
               -0.03 -0.02 0.01  0.03 -0.02 0.01  0.03 0.02 0.01  -0.03 0.02 0.01"/></asset><worldbody>
      <body name="sphere" pos="0 0 0.5"><geom type="sphere" size="0.03"/></body>
      <body name="cap_x" pos="1 0 0.5"><geom type="capsule" fromto="-0.02 0 0 0.02 0 0" size="0.015"/></body>
      <body name="cyl_y" pos="2 0 0.5"><geom type="cylinder" fromto="0 -0.025 0 0 0.025 0" size="0.02"/></body>
      <body name="box" pos="3 0 0.5" euler="0 0 90"><geom type="box" size="0.04 0.03 0.01"/></body>
      <body name="mesh" pos="4 0 0.5"><geom type="mesh" mesh="m"/></body>
      <body name="upright" pos="5 0 0.5"><geom type="cylinder" size="0.02 0.03"/></body>
      <body name="nothing" pos="6 0 0.5"/>
    </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    sph = body_foot(model, "sphere")
    assert sph.foot == feet.SemiSphere(radius=0.03, height=0.03)
    np.testing.assert_allclose(sph.tip, [0, 0, -0.03], atol=1e-12)
    cap = body_foot(model, "cap_x")
    assert cap.foot == feet.SemiCylinder(radius=0.015, width=0.04, height=0.015)
    np.testing.assert_allclose(
        abs(cap.forward[0]), 1.0, atol=1e-12
    )  # the axis is the foot's x (D20)
    np.testing.assert_allclose(cap.tip, [0, 0, -0.015], atol=1e-12)
    cyl = body_foot(model, "cyl_y")
    assert cyl.foot == feet.SemiCylinder(radius=0.02, width=0.05, height=0.02)
    np.testing.assert_allclose(abs(cyl.forward[1]), 1.0, atol=1e-12)
    box = body_foot(model, "box")  # the body is yawed 90 deg: its 0.08 m side lies along world y
    assert box.foot == feet.Flat(length=0.08, width=0.06, height=0.02)
    mesh = body_foot(model, "mesh")
    assert isinstance(mesh.foot, feet.MeshFoot)
    assert mesh.foot.height == pytest.approx(0.01, abs=1e-9)
    assert mesh.foot.projected_areas(0.005)[2] == pytest.approx(0.06 * 0.04, rel=1e-6)
    # a standing cylinder (r 20 mm, 60 mm long) is its meshed convex hull, tip at its base
    up = body_foot(model, "upright")
    assert isinstance(up.foot, feet.MeshFoot) and up.kind == "points"
    assert up.foot.height == pytest.approx(0.06, abs=1e-9)
    np.testing.assert_allclose(up.tip, [0, 0, -0.03], atol=1e-12)
    disk = np.pi * 0.02**2 * 16 / (2 * np.pi) * np.sin(2 * np.pi / 16)  # its 16-gon
    assert up.foot.projected_areas(0.01)[2] == pytest.approx(disk, rel=1e-9)
    with pytest.raises(mudrft.MudrftError, match="no geom"):
        body_foot(model, "nothing")
    explicit = body_foot(model, "nothing", feet.SemiSphere())
    np.testing.assert_allclose(explicit.tip, 0.0)


def test_bad_arguments_are_named():
    model = box_foot_model()
    with pytest.raises(
        mudrft.MudrftError, match="'heel' is neither a body nor a geom of the model"
    ):
        attach(model, "heel", MUD)
    with pytest.raises(mudrft.MudrftError, match=r"model must be a mujoco\.MjModel"):
        attach("model.xml", "foot", MUD)
    with pytest.raises(mudrft.MudrftError, match="bottom must be > 0"):
        attach(model, "foot", MUD, bottom=-0.1)
    for name, value in (("implicit", False), ("mobility", "body"), ("lookahead", True)):
        with pytest.raises(mudrft.MudrftError, match=f"option {name}= was removed in mudrft 0.3"):
            attach(model, "foot", MUD, **{name: value})
    with pytest.raises(mudrft.MudrftError, match="unexpected keyword argument 'surfase'"):
        attach(model, "foot", MUD, surfase=0.1)
    coupling = attach(model, "foot", MUD)
    with pytest.raises(mudrft.MudrftError, match="reset"):
        coupling.step(mujoco.MjData(model))
    batch = attach_batch(model, "foot", MUD, n=2)
    with pytest.raises(mudrft.MudrftError, match="expected 2 MjData"):
        batch.reset([mujoco.MjData(model)])


def test_rk4_integrator_is_refused():
    """The coupling runs one scheme, under Euler, implicitfast or implicit: RK4 is refused
    at attach, and at reset if the model was switched to it after attach."""
    model = box_foot_model(mass=1.5, dt=1e-3)
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    with pytest.raises(mudrft.MudrftError, match=r"'implicitfast' or 'implicit'.*mjINT_RK4"):
        attach(model, "foot", MUD)
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICIT
    coupling = attach(model, "foot", MUD)
    data = mujoco.MjData(model)
    coupling.reset(data)
    assert coupling.step(data, 300).depth[0] > 5e-4  # implicit runs the same scheme
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    with pytest.raises(mudrft.MudrftError, match=r"set model\.opt\.integrator"):
        coupling.reset(data)


def test_quasi_static_mud_damps_with_eta_inf_plus_eta_m():
    """Eq. (9) from rest acts as an (eta_inf + xi_ss eta_m) damper at once, xi_ss -> 1 at
    rest: its explicit limit is that much shorter (D15)."""
    foot = mudrft.feet.Flat()
    qs = mudrft.MudTerrain(MUD, thixotropy="quasi-static", acceleration=False)
    ode = stability_limits(foot, MUD, mass=0.3, depth=0.01)
    fast = stability_limits(foot, qs, mass=0.3, depth=0.01)
    p = MUD.vertical
    ratio = (float(p.eta_inf) + float(p.eta_m)) / float(p.eta_inf)
    assert fast["damping"] == pytest.approx(ode["damping"] * ratio, rel=1e-12)
    assert fast["dt_viscous"] == pytest.approx(ode["dt_viscous"] / ratio, rel=1e-12)
