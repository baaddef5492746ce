"""The biped walking in mud, and ``mudrft walk``."""

from __future__ import annotations

import argparse
import json
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudrft

pytest.importorskip("mujoco")
import mudrft.integrations.walk_compare
from mudrft.cli import walk as walk_cli
from mudrft.integrations import walk as W
from mudrft.integrations.walk import walk
from mudrft.trajectories import BuriedFootWarning

from .conftest import mujoco, mujoco_at_least

MUD = mudrft.paper_mud(0.25)


@pytest.fixture(scope="module")
def flat_runs() -> dict[float, W.WalkResult]:
    """Ten seconds of walking with flat feet at dt = 1 ms and 2 ms."""
    with warnings.catch_warnings():  # the flat feet sink past their 26 mm in ten seconds
        warnings.simplefilter("ignore", BuriedFootWarning)
        return {dt: W.walk(mudrft.feet.Flat(), MUD, seconds=10.0, dt=dt) for dt in (1e-3, 2e-3)}


@pytest.mark.parametrize("dt", [1e-3, 2e-3])
def test_biped_walks_ten_seconds(flat_runs, dt):
    res = flat_runs[dt]
    s = res.summary
    assert not s["fell"]
    assert s["seconds"] == pytest.approx(10.0, abs=dt)
    for col, values in res.table.items():
        assert np.all(np.isfinite(values)), col
    # torso hip starts 0.37 m above the mud; it sinks with the feet but never below 0.25 m
    assert s["min_torso_height [m]"] > 0.25
    assert np.abs(res.table["pitch [rad]"]).max() < 0.3  # the boom's pitch spring holds the torso
    # it walks: at least half of the commanded 1 m (the feet slip backward in the mud)
    assert s["distance [m]"] > 0.5
    assert s["steps"] >= 8
    assert s["max_suction [N]"] > 0 and s["mean_sinking [m]"] > 0.02


def test_walk_converges_in_the_time_step(flat_runs):
    """Halving the step changes the gait metrics little (O(dt) coupling; measured <= 0.6 %)."""
    a, b = flat_runs[1e-3].summary, flat_runs[2e-3].summary
    for key in ("distance [m]", "energy_per_step [J]", "mean_sinking [m]"):
        assert b[key] == pytest.approx(a[key], rel=0.05), key


@pytest.mark.xfail(
    mujoco_at_least(3, 5),
    strict=True,
    reason="one-step overshoot at the stance switch at 2 ms from MuJoCo 3.5, whose "
    "implicitfast drops a torque-saturated servo's implicit damping (D62d, D152)",
)
def test_walk_max_suction_converges_in_the_time_step(flat_runs):
    """The largest suction is one sample: at 2 ms the first step after a stance switch
    overshoots (the servos' new torque reaches the mud's implicit step a step late, in the
    acceleration estimate of D62): -616 N against a plateau of -329 N (-562 N before the
    feet of a robot were solved together, D62d; at 1 ms -359 N). So the 2 ms maximum is
    that spike, 6 % above the 1 ms one (580 N); since the secant toward rest (D119) it is
    -626 N, from +83 N the step before and -271 N after, 8 % above 1 ms (577 N). Strict: it
    fails once the coupling sees the actuators' change (the estimates tried and why none is
    built: D62d). The spike comes with MuJoCo 3.5: on 3.3.6 and 3.4.0 the 2 ms maximum is
    574 and 570 N against 578 N at 1 ms, and the test passes. The cause (D152):
    from 3.5 a servo at its torque limit has no velocity derivative in implicitfast's
    implicit step, and the spike is the step after the stance switch's saturated servos;
    the largest suction on any other step is 562 N; at 1 ms there is no spike."""
    a, b = flat_runs[1e-3].summary, flat_runs[2e-3].summary
    assert b["max_suction [N]"] == pytest.approx(a["max_suction [N]"], rel=0.05)


def test_a_servo_at_its_torque_limit_is_not_damped_implicitly_from_mujoco_3_5():
    """What the spike above rests on (D152): the biped's knee servo (its kp, kv and torque
    limit) on a hinge at 2 ms, from 2 rad/s. Within its limit, implicitfast damps it
    implicitly (unlike Euler); at its limit, from MuJoCo 3.5, it does not (as Euler: the
    clamped torque has no velocity derivative), before 3.5 it did (measured 5.85 against
    18.67 rad/s after the step)."""
    biped = W.biped_model(mudrft.feet.Flat())
    knee = biped.actuator("left_knee").id
    kp, kv = biped.actuator_gainprm[knee, 0], -biped.actuator_biasprm[knee, 2]
    limit = biped.actuator_forcerange[knee, 1]
    xml = f"""<mujoco><option timestep="0.002" gravity="0 0 0"/><worldbody><body>
      <joint name="j" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.2" size="0.02" mass="0.5"/></body></worldbody>
      <actuator><position joint="j" kp="{kp}" kv="{kv}" forcerange="{-limit} {limit}"/>
      </actuator></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    after = {}
    for setpoint in (0.05, 1.0):  # within the limit; at it
        for integrator in ("Euler", "implicitfast"):
            model.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator.upper()}")
            data = mujoco.MjData(model)
            data.qvel[0], data.ctrl[0] = 2.0, setpoint
            mujoco.mj_step(model, data)
            after[setpoint, integrator] = float(data.qvel[0])
        saturated = abs(float(data.actuator_force[0])) == pytest.approx(limit)
        assert saturated == (setpoint == 1.0)
    assert after[0.05, "implicitfast"] != pytest.approx(after[0.05, "Euler"], rel=1e-3)
    clamped_as_euler = after[1.0, "implicitfast"] == pytest.approx(after[1.0, "Euler"], rel=1e-9)
    assert clamped_as_euler == mujoco_at_least(3, 5), after


def test_morphing_foot_walks_with_less_suction(flat_runs):
    """Any foot walks, including the morphing foot, and it meets less suction (paper Sec. IV)."""
    res = W.walk(mudrft.feet.MorphingFoot(), MUD, seconds=3.0, dt=2e-3)
    assert not res.summary["fell"]
    flat = flat_runs[2e-3].table
    early = flat["time [s]"] <= 3.0
    flat_suction = -min(flat["left_Fz [N]"][early].min(), flat["right_Fz [N]"][early].min())
    assert res.summary["max_suction [N]"] < 0.5 * flat_suction


def test_walk_energy_is_joint_torque_times_joint_velocity(flat_runs):
    """Per step: positive work of the joints <= absolute work; both from tau q_dot (D69)."""
    res = flat_runs[2e-3]
    st_ = res.steps
    assert np.all(st_["energy [J]"] > 0)
    assert np.all(st_["absolute_work [J]"] >= st_["energy [J]"] - 1e-12)
    # the net power's positive part is at most the joints' positive work
    t = res.table
    dt = 2e-3
    net_pos = np.cumsum(np.maximum(t["joint_power [W]"], 0.0)) * dt
    assert net_pos[-1] <= t["joint_energy [J]"][-1] + 1e-9
    s = res.summary
    assert s["absolute_work_per_step [J]"] >= s["energy_per_step [J]"]
    assert s["weight [N]"] == pytest.approx(10.0 * 9.81, rel=1e-9)
    assert s["max_suction_over_weight"] == pytest.approx(s["max_suction [N]"] / s["weight [N]"])
    assert 0.0 < s["mean_slip [m]"] < 0.05  # the stance foot slides a little in the mud
    assert set(np.unique(st_["shank_in_mud"])) <= {0.0, 1.0}


def test_walk_compare_writes_table_claims_and_figure(tmp_path):
    """``mudrft walk --compare``: every foot on the same mud, the paper's claims beside.
    The flat foot sinks past its 26 mm height there, and the walk says so."""
    with pytest.warns(BuriedFootWarning, match="walk: a foot sank .* deeper than the"):
        assert walk_cli.run(_args(tmp_path, compare=True, seconds=1.2, step_time=0.5)) == 0
    out = tmp_path / "run"
    table = np.genfromtxt(out / "compare.csv", delimiter=",", names=True, dtype=None)
    assert [r[0].decode() if isinstance(r[0], bytes) else r[0] for r in table] == list(
        mudrft.integrations.walk_compare.FEET
    )
    claims = (out / "claims.csv").read_text().splitlines()
    assert claims[0] == "claim,paper,mudrft,verdict" and len(claims) == 5
    assert (out / "compare.png").stat().st_size > 10_000
    data = json.loads((out / "compare.json").read_text())
    assert set(data["feet"]) == set(mudrft.integrations.walk_compare.FEET)


def test_a_walk_without_a_complete_step_is_undetermined_and_strict_json(tmp_path):
    """Too short a walk has no per-step energy or sinking: the claims that need them are
    'undetermined' (they read 'differs' on NaN before) and compare.json writes null, not
    the NaN that strict JSON parsers reject."""
    from mudrft.integrations.walk_compare import UNDETERMINED, compare_claims, write_compare

    def summary(suction, energy, sinking):
        return {"fell": False, "max_suction [N]": suction, "energy_per_step [J]": energy,
                "mean_sinking [m]": sinking, "steps": 0 if math.isnan(energy) else 3}  # fmt: skip

    nan = float("nan")
    short = {f: summary(s, nan, nan) for f, s in zip(mudrft.integrations.walk_compare.FEET,
                                                      (30.0, 20.0, 10.0, 5.0), strict=True)}  # fmt: skip
    rows = {r["claim"]: r["verdict"] for r in compare_claims(short)}
    assert sum(v == UNDETERMINED for v in rows.values()) == 3
    assert rows["flat foot: largest suction, semi-sphere: least (Sec. IV-B)"] == "agrees"
    full = dict(short, morphing=summary(5.0, 1.0, 0.01), flat=summary(30.0, 2.0, 0.02),
                **{"semi-cylinder": summary(20.0, 2.0, 0.02)}, **{"semi-sphere": summary(10.0, 2.0, 0.02)})  # fmt: skip
    assert UNDETERMINED not in {r["verdict"] for r in compare_claims(full)}
    write_compare(tmp_path, short)
    text = (tmp_path / "compare.json").read_text()
    data = json.loads(text, parse_constant=lambda c: pytest.fail(f"non-standard JSON: {c}"))
    assert data["feet"]["flat"]["energy_per_step [J]"] is None


@settings(max_examples=40, deadline=None)
@given(st.floats(-0.15, 0.15), st.floats(-0.36, -0.2))  # reachable: |(x, z)| < 0.4 m
def test_leg_inverse_kinematics_round_trip(x, z):
    q1, q2 = W._leg_ik(x, z)
    # forward kinematics of the hinge convention (rotation about +y)
    fx = -W.THIGH * math.sin(q1) - W.SHANK * math.sin(q1 + q2)
    fz = -W.THIGH * math.cos(q1) - W.SHANK * math.cos(q1 + q2)
    assert (fx, fz) == pytest.approx((x, z), abs=1e-12)
    assert q2 >= 0  # the knee bends forward


def test_ik_agrees_with_mujoco():
    """The controller's leg model matches the MJCF: the ankle lands where the IK says."""
    model = W.biped_model()
    data = mujoco.MjData(model)
    q1, q2 = W._leg_ik(0.07, -0.33)
    data.qpos[model.joint("left_hip").qposadr[0]] = q1
    data.qpos[model.joint("left_knee").qposadr[0]] = q2
    mujoco.mj_forward(model, data)
    rel = data.xpos[model.body("left_foot").id] - data.xpos[model.body("left_thigh").id]
    np.testing.assert_allclose(rel[[0, 2]], [0.07, -0.33], atol=1e-12)
    assert model.body_subtreemass[model.body("torso").id] == pytest.approx(10.0, rel=1e-12)


def _args(tmp_path, **kw):
    base = {
        "foot": "semi-sphere",
        "unit": None,
        "trailing": None,
        "up": None,
        "water_content": 0.3,
        "seconds": 1.2,
        "out": str(tmp_path / "run"),
        "dt": 2e-3,
        "speed": 0.1,
        "step_time": 0.5,
        "bottom": 0.15,
        "explicit": False,
        "extrapolate": False,
        "no_render": True,
        "force": False,
        "quiet": True,
        "compare": False,
        "vertical": None,
        "horizontal": None,
    }
    base.update(kw)
    return argparse.Namespace(**base)


@pytest.mark.filterwarnings(
    "ignore::mudrft.trajectories.BuriedFootWarning"
)  # the biped sinks past 26 mm
def test_cli_writes_outputs_and_refuses_to_overwrite(tmp_path):
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="command")
    walk_cli.add_parser(sub)
    ns = parser.parse_args(
        ["walk", "--foot", "flat", "--out", str(tmp_path / "x"), "--seconds", "2"]
    )
    assert ns.func is walk_cli.run and ns.water_content == 0.25 and ns.seconds == 2.0
    assert walk_cli.run(_args(tmp_path)) == 0
    out = tmp_path / "run"
    summary = json.loads((out / "summary.json").read_text())
    for key in (
        "fell",
        "distance [m]",
        "energy_per_step [J]",
        "mean_sinking [m]",
        "max_suction [N]",
    ):
        assert key in summary
    assert isinstance(summary["fell"], bool) and summary["foot"] == "semi-sphere"
    table = np.genfromtxt(out / "walk.csv", delimiter=",", names=True)
    assert (
        len(table) == 600
        and (out / "steps.csv").exists()
        and (out / "walk.png").stat().st_size > 1000
    )
    with pytest.raises(mudrft.MudrftError, match="exists; pass --force"):
        walk_cli.run(_args(tmp_path))
    assert walk_cli.run(_args(tmp_path, force=True, seconds=0.6)) == 0
    assert len(np.genfromtxt(out / "walk.csv", delimiter=",", names=True)) == 300


def test_cli_rejects_bad_input(tmp_path):
    with pytest.raises(mudrft.MudrftError, match="seconds"):
        walk_cli.run(_args(tmp_path, seconds=-1.0))
    with pytest.raises(mudrft.MudrftError):
        walk_cli.run(_args(tmp_path, foot="paddle"))
    with pytest.raises(mudrft.MudrftError, match="dt"):
        W.walk(mudrft.feet.Flat(), MUD, seconds=1.0, dt=0.05)


def test_a_walk_shorter_than_one_step_is_refused(tmp_path):
    """``mudrft walk --seconds 1e-9`` raised numpy's "zero-size array" in walk.py."""
    message = r"seconds must be at least one physics step \(dt = 0\.002 s\), got 1e-09 s"
    with pytest.raises(mudrft.MudrftError, match=message):
        walk_cli.run(_args(tmp_path, seconds=1e-9))
    assert not (tmp_path / "run").exists()  # a failed run leaves nothing
    with pytest.raises(mudrft.MudrftError, match=message):
        W.walk(mudrft.feet.Flat(), MUD, seconds=1e-9, dt=2e-3)


def test_a_step_of_a_few_physics_steps_is_refused():
    """walk(step_time=1e-6) ran and returned meaningless numbers (found by a CLI fuzz)."""
    with pytest.raises(mudrft.MudrftError, match=r"step_time must span at least 20 physics steps"):
        W.walk(mudrft.feet.Flat(), MUD, seconds=0.01, dt=1e-3, step_time=0.019)


@pytest.mark.filterwarnings(
    "ignore::mudrft.trajectories.BuriedFootWarning"
)  # the biped sinks past 26 mm
def test_walk_takes_a_calibrated_parameter_file(tmp_path):
    """``mudrft walk --vertical FIT.json`` walks on a fitted set (D111), as simulate does;
    the summary names the mud, and a softer fitted row sinks the feet deeper."""
    v45 = mudrft.paper_parameters(0.45, "vertical")
    fit = tmp_path / "fit.json"
    fit.write_text(json.dumps({"direction": "vertical", **v45.as_dict()}))
    assert walk_cli.run(_args(tmp_path, water_content=0.25)) == 0
    paper = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert walk_cli.run(_args(tmp_path, water_content=0.25, vertical=str(fit), force=True)) == 0
    fitted = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert paper["mud"] == "Chen 2026 mud, W = 25 %"
    assert fitted["mud"] == f"vertical {fit}, the rest of the paper's mud at W = 25 %"
    assert fitted["steps"] > 0 and fitted["mean_sinking [m]"] > paper["mean_sinking [m]"]


def test_a_foot_sunk_past_its_height_in_a_walk_warns_once_and_strict_refuses_it():
    """Issue 38: a walk whose feet sank deeper than they are tall said nothing. The
    semi-sphere (26 mm tall) in W = 45 % mud sinks far past it: one warning a run, and
    under ``strict=True`` an error."""
    foot, mud = mudrft.feet.SemiSphere(), mudrft.paper_mud(0.45)
    with pytest.warns(BuriedFootWarning) as record:
        walk(foot, mud, seconds=0.5)
    assert len([w for w in record if issubclass(w.category, BuriedFootWarning)]) == 1
    with pytest.raises(mudrft.MudrftError, match="strict: walk: a foot sank"):
        walk(foot, mud, seconds=0.5, strict=True)
