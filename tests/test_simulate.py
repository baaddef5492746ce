"""simulate(): energy, load control, convergence, output files, bad input.

A minimal horizontal plate foot is defined here so these tests exercise the
simulation layer alone; the feet have their own tests.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
from hypothesis import given, settings
from hypothesis import strategies as st

import mudrft
from mudrft._validation import MudrftError, PlausibilityWarning
from mudrft.feet.base import Foot
from mudrft.simulation import CSV_COLUMNS, LoadControl, simulate, static_sinking


class PlateFoot(Foot):
    """A square plate of side 60 mm and height 50 mm (tall enough for every motion here to
    leave it unburied): Fz = A sz, Fx = z W (cos^2 sx + ...)."""

    name = "plate"
    side = 0.06

    @property
    def characteristic_length(self) -> float:
        return self.side

    @property
    def height(self) -> float:
        return 0.05

    def resultant(self, depth, stress, heading):
        s = np.asarray(stress, dtype=float)
        d = np.minimum(np.asarray(depth, dtype=float), self.height)
        c2, s2 = np.cos(heading) ** 2, np.sin(heading) ** 2
        h = d * self.side * (s[..., 0] + s[..., 1])
        return np.stack([c2 * h, s2 * h, self.side**2 * s[..., 2]], axis=-1)

    def projected_areas(self, depth):
        d = np.minimum(np.asarray(depth, dtype=float), self.height)
        a = d * self.side
        return np.stack([a, a, np.where(np.asarray(depth) > 0, self.side**2, 0.0)], axis=-1)


FOOT = PlateFoot()


@settings(max_examples=15, deadline=None)
@given(w=st.floats(0.25, 0.45), speed=st.floats(0.1, 0.3), depth=st.floats(0.005, 0.04))
def test_energy_of_a_closed_cycle_is_nonnegative(w, speed, depth):
    res = simulate(FOOT, mudrft.paper_mud(w), mudrft.gait(speed, depth=depth, dt=2e-3))
    assert res.metrics()["energy"] >= 0.0


def test_plate_cycle_energy_equals_loop_area():
    """Work = closed integral of Fz d(depth), the loop area, computed independently. The two
    trapezoid rules differ only at the three velocity corners of the protocol, by O(dt):
    halving dt must halve the gap, and at dt = 0.5 ms it is below 0.1 %."""
    gaps = []
    for dt in (1e-3, 5e-4):
        tr = mudrft.plate_intrusion(depth=0.02, speed=0.02, hold=0.5, rest=0.0, dt=dt)
        res = simulate(FOOT, mudrft.paper_mud(0.25), tr)
        loop = scipy.integrate.trapezoid(res.force[:, 2], res.depth)
        assert loop > 0
        gaps.append(abs(res.metrics()["energy"] - loop) / loop)
    assert gaps[1] < 0.6 * gaps[0] and gaps[1] < 1e-3


def test_load_controlled_sinking_matches_static_balance():
    """A slowly applied weight creeps to the static depth where alpha (d/Lc)^n A = W. The creep
    time constant is a few seconds (structural viscosity over the elastic stiffness); after 35 s
    the remaining gap is below 1e-3 (measured 2e-6 after 60 s)."""
    mud = mudrft.paper_mud(0.25)
    W = 40.0
    res = simulate(FOOT, mud, LoadControl(weight=W, duration=35.0, dt=5e-3, ramp=2.0))
    d_static = static_sinking(FOOT, mud, W)
    assert res.metrics()["sinking"] == pytest.approx(d_static, rel=1e-3)
    assert res.force[-1, 2] == pytest.approx(W, rel=1e-4)
    # a load applied at once overshoots and compacts the mud: it rests a little above the static depth
    sudden = simulate(FOOT, mud, LoadControl(weight=W, duration=35.0, dt=5e-3))
    assert 0.98 * d_static < sudden.depth[-1] < d_static


def test_a_ramped_load_creeps_to_the_static_depth_in_the_quasi_static_evaluation_too():
    """Decision D13: the static depth is the limit of a ramped load whatever the evaluation.
    In the quasi-static one (D15) eq. (9) is a lag-free damper (eta_inf + eta_m) A / L_c, so the
    explicit coupling needs dt near 1 ms (simulate checks it); the creep time constant is a few
    seconds, 30 s leave a gap below 1e-3. A load applied at once meets no damping at contact
    (1 - e^{-t/lambda} = 0), overshoots and stays deep: the bed-contact factor (D2) removes the
    elastic push as the foot rebounds."""
    mud = mudrft.paper_mud(0.25)
    terrain = mudrft.MudTerrain(mud, thixotropy="quasi-static")
    W = 40.0
    d_static = static_sinking(FOOT, mud, W)
    with pytest.raises(MudrftError, match="dt"):
        simulate(FOOT, terrain, LoadControl(weight=W, duration=1.0, dt=5e-3, ramp=2.0))
    res = simulate(FOOT, terrain, LoadControl(weight=W, duration=30.0, dt=1e-3, ramp=2.0))
    assert res.metrics()["sinking"] == pytest.approx(d_static, rel=1e-3)
    sudden = simulate(FOOT, terrain, LoadControl(weight=W, duration=4.0, dt=1e-3))
    assert sudden.depth[-1] > 1.4 * d_static


def test_spring_leg_settles_to_the_same_depth():
    mud = mudrft.paper_mud(0.25)
    load = LoadControl(
        weight=40.0,
        leg_stiffness=2e4,
        leg_damping=200.0,
        foot_mass=2.0,
        duration=35.0,
        dt=2e-3,
        ramp=2.0,
    )
    res = simulate(FOOT, mud, load)
    assert res.depth[-1] == pytest.approx(static_sinking(FOOT, mud, 40.0), rel=1e-3)


def test_unstable_explicit_coupling_is_refused():
    with pytest.raises(MudrftError, match="dt"):
        simulate(
            FOOT, mudrft.paper_mud(0.25), LoadControl(weight=40.0, leg_stiffness=2e4, foot_mass=0.1)
        )


def test_results_converge_as_dt_is_halved():
    """Metrics converge as dt is refined. (The force itself jumps when a flat foot with suction
    leaves the mud, so a max-norm of the force history cannot converge; its metrics do. Where
    the exit falls between two samples makes the impulse error oscillate at first order as dt
    is halved (at the 20 mm gait: 0.05 % at 1 ms, 0.3 % at 0.5 ms), so the error is compared
    over a factor 4 in dt, not 2.)"""
    mud = mudrft.paper_mud(0.25)
    tr = mudrft.gait(0.2, dt=1e-4)
    ref = simulate(FOOT, mud, tr).metrics()
    keys = ("peak_support", "max_suction", "impulse_z", "energy")
    errs = []
    for dt in (4e-3, 2e-3, 1e-3, 5e-4):
        m = simulate(FOOT, mud, tr, dt=dt).metrics()
        errs.append(max(abs(m[k] - ref[k]) / abs(ref[k]) for k in keys))
    assert errs[2] < errs[0] and errs[3] < errs[1], errs
    assert errs[-1] < 0.01


def test_forces_oppose_motion_in_every_quadrant():
    mud = mudrft.paper_mud(0.25)
    for ang in np.deg2rad([0, 60, 135, 200, 300]):
        t = np.linspace(0, 0.5, 501)
        pos = np.column_stack(
            [0.05 * t * np.cos(ang), 0.05 * t * np.sin(ang), -0.02 * np.ones_like(t)]
        )
        pos[:, 2][t < 0.1] = -0.2 * t[t < 0.1]
        res = simulate(FOOT, mud, mudrft.Trajectory.from_positions(t, pos))
        late = res.time > 0.2
        fh = res.force[late][:, :2]
        u = np.array([np.cos(ang), np.sin(ang)])
        assert np.all(fh @ u < 0)


def test_csv_round_trip_and_no_overwrite(tmp_path):
    res = simulate(FOOT, mudrft.paper_mud(0.25), mudrft.gait(0.2, dt=2e-3))
    p = res.to_csv(tmp_path / "run.csv")
    head = p.read_text().splitlines()[0]
    assert head == ",".join(CSV_COLUMNS)
    data = np.loadtxt(p, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 4:], res.force, rtol=1e-8, atol=1e-9)
    before = p.read_bytes()
    with pytest.raises(MudrftError, match="overwrite"):
        res.to_csv(p)
    assert p.read_bytes() == before
    with pytest.raises(MudrftError, match="directory"):
        res.to_csv(tmp_path / "missing" / "run.csv")
    pytest.importorskip("pandas")
    df = res.to_pandas()
    assert list(df.columns[:7]) == list(CSV_COLUMNS) and len(df) == len(res)


def test_bad_input():
    mud = mudrft.paper_mud(0.25)
    with pytest.raises(MudrftError, match="foot"):
        simulate("flat", mud, mudrft.gait())
    with pytest.raises(MudrftError, match="mud"):
        simulate(FOOT, {"alpha": 1}, mudrft.gait())
    with pytest.raises(MudrftError, match="trajectory"):
        simulate(FOOT, mud, [0, 1, 2])
    with pytest.raises(MudrftError, match="speed"):
        mudrft.gait(speed=0)
    with pytest.raises(MudrftError, match="weight"):
        LoadControl(weight=-1)
    with pytest.raises(MudrftError, match="position"):
        mudrft.Trajectory(time=np.arange(3.0), position=np.zeros((2, 3)), velocity=np.zeros((3, 3)))


def test_plate_protocol_geometry():
    tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0, rest=0.5)
    assert tr.duration == pytest.approx(2 * 1.5 + 1.0 + 0.5)
    assert tr.depth.max() == pytest.approx(0.03)
    h = mudrft.plate_intrusion(direction="horizontal", angle=np.pi / 4)
    assert h.position[:, 0].max() == pytest.approx(0.03) and np.all(h.position[:, 2] == 0)
    r = mudrft.plate_response(h, mudrft.paper_mud(0.25))
    np.testing.assert_allclose(r.normal, 0.5 * r.stress)
    np.testing.assert_allclose(r.normal + r.tangential, r.stress)
    with pytest.raises(MudrftError, match="angle"):
        mudrft.plate_intrusion(angle=2.0)


def test_default_gait_keeps_the_paper_feet_unburied():
    """Decision D10: the closed forms (12)-(14) assume a foot that is not buried, and the
    paper's three fixed feet are h_F = 26 mm tall (Sec. IV-A), so the default stance stays
    within that height."""
    from mudrft.trajectories import FOOT_HEIGHT, STANCE_DEPTH

    for speed in mudrft.GAIT_SPEEDS.values():
        assert mudrft.gait(speed).depth.max() == pytest.approx(STANCE_DEPTH, abs=1e-12)
    assert STANCE_DEPTH < FOOT_HEIGHT
    for name in ("flat", "semi-cylinder", "semi-sphere"):
        assert mudrft.feet.by_name(name).height == pytest.approx(FOOT_HEIGHT, abs=1e-12)


def test_light_loads_sink_to_the_closed_form_depth():
    """The flat foot's static support is alpha (d/L)^n L W: a 1 N load balances at
    d = L (W_load / (alpha A))^(1/n), 5e-11 m at W = 35 % (n = 0.60). The bracket used to
    start at 1e-9 m and scipy raised 'f(a) and f(b) must have different signs'."""
    foot, mud = mudrft.feet.Flat(), mudrft.paper_mud(0.35)
    p, lc = mud.vertical, foot.characteristic_length
    area = foot.length * foot.width
    for load in (1.0, 1e-3, 49.0):
        want = lc * (load / (p.alpha * area)) ** (1.0 / p.n)
        assert static_sinking(foot, mud, load) == pytest.approx(want, rel=1e-9)
    for other in (mudrft.feet.SemiCylinder(), mudrft.feet.SemiSphere()):  # grow with the load
        depths = [static_sinking(other, mud, w) for w in (1e-6, 1e-3, 1.0)]
        assert 0 < depths[0] < depths[1] < depths[2]


def test_positions_sampled_around_a_rest_give_the_rest_its_own_rate():
    """A foot rests 1 s in the mud (no samples inside the rest), then slides. The velocity
    of the sample that ends the rest is the rest's (0), not the slide's: simulate applies
    it over the whole step, and a central difference gave a 173 N drag at the end of a
    rest where the mud had relaxed. Same force and energy as a path sampled every 1 ms."""

    def path(t):
        x = np.interp(t, [0, 1.5, 1.52], [0, 0, 0.02])
        z = np.interp(t, [0, 0.5, 1.52, 2.02], [0, -0.01, -0.01, 0])
        return np.c_[x, 0 * x, z]

    sparse = np.r_[
        np.linspace(0, 0.5, 501), np.linspace(1.5, 1.52, 201), np.linspace(1.521, 2.02, 500)
    ]
    dense = np.unique(np.r_[np.arange(0, 2.02, 1e-3), sparse])
    runs = {}
    for name, t in (("sparse", sparse), ("dense", dense)):
        tr = mudrft.Trajectory.from_positions(t, path(t))
        np.testing.assert_allclose(
            tr.velocity[1:], np.diff(tr.position, axis=0) / np.diff(t)[:, None]
        )
        runs[name] = simulate(FOOT, mudrft.paper_mud(0.25), tr)
    end_of_rest = [float(r.force[np.searchsorted(r.time, 1.5), 0]) for r in runs.values()]
    assert abs(end_of_rest[0] - end_of_rest[1]) < 0.05 * abs(end_of_rest[1]) + 1.0  # N
    energy = [r.metrics()["energy"] for r in runs.values()]
    assert energy[0] == pytest.approx(energy[1], rel=0.05)  # was 91.8 J against 3.5 J


def test_the_deepest_plate_sample_is_still_intruding():
    """Each corner of plate_intrusion carries the rate of the step that ends there: the
    deepest sample's force is the intrusion's peak, not the retraction's (it read 50 N
    after 90 N one sample before, whatever dt)."""
    for hold in (0.0, 1.0):
        tr = mudrft.plate_intrusion(depth=0.02, speed=0.02, hold=hold, dt=1e-3)
        k = int(np.argmax(tr.depth))
        assert tr.velocity[k, 2] == pytest.approx(-0.02)
        res = simulate(FOOT, mudrft.paper_mud(0.25), tr)
        assert int(np.argmax(res.force[:, 2])) == k


def test_a_load_too_light_for_the_time_step_warns_that_the_foot_will_chatter():
    """1 N on the flat foot at W = 35 % balances 5e-11 m deep, where the elastic law is a
    4e9 N/m spring: at dt = 0.1 ms the explicit step threw the foot into the air 81 % of the
    time without a word. The damping check alone passed it."""
    from mudrft._validation import PlausibilityWarning

    light = LoadControl(1.0, duration=0.05, dt=1e-4)
    with pytest.warns(PlausibilityWarning, match=r"chatter at the surface; use dt <= 5.\de-06 s"):
        res = simulate(mudrft.feet.Flat(), mudrft.paper_mud(0.35), light)
    assert (res.depth[len(res.depth) // 2 :] == 0).mean() > 0.5  # it does chatter
    # the paper's 49 N settles at 1 ms without a warning (warnings are errors in the suite)
    simulate(mudrft.feet.Flat(), mudrft.paper_mud(0.35), LoadControl(49.0, duration=0.05, dt=1e-3))


def test_resampling_holds_each_samples_velocity_over_its_step():
    """simulate(..., dt=) interpolated the velocity: next to a rest the mud met half the
    slide's rate (D13b: velocity[k] holds over the step that ends at k)."""
    from mudrft.simulation import _resample

    tr = mudrft.Trajectory.from_positions(
        [0.0, 1.0, 2.0], [[0, 0, -0.01], [0, 0, -0.01], [0.1, 0, -0.01]]
    )
    fine = _resample(tr, 0.01)
    moving = fine.time > 1.0 + 1e-12
    np.testing.assert_allclose(fine.velocity[moving, 0], 0.1)
    np.testing.assert_allclose(fine.velocity[~moving, 0], 0.0)
    assert mudrft.metrics.energy([0.0, 1.0], np.zeros((2, 3)), np.zeros((2, 3))) == 0.0
    assert str(mudrft.metrics.energy([0.0, 1.0], np.zeros((2, 3)), np.ones((2, 3)))) == "0.0"


def test_a_weight_beyond_the_buried_foot_names_the_support_and_the_depth_searched():
    """Before: "weight=200.0 N exceeds the static support of flat at depth 0.104 m" gave no
    support to compare with and no reason for that depth (4 heights of a 26 mm foot), and
    read as "no balance", though a LoadControl run settles deeper."""
    foot, mud = mudrft.feet.Flat(), mudrft.paper_mud(0.25)
    at = float(foot.resultant(0.104, [0.0, 0.0, mud.vertical.alpha * (0.104 / foot.characteristic_length) ** mud.vertical.n], 0.0)[2])  # fmt: skip
    with pytest.raises(mudrft.MudrftError) as err:
        static_sinking(foot, mud, 200.0)
    assert str(err.value) == (
        f"weight=200.0 N exceeds the static support of the flat foot buried 4 times its "
        f"height ({at:.4g} N at a tip depth of 0.104 m): the balance lies deeper still, where "
        "the mud on the leg, which the model does not count (decision D26), would carry part "
        "of the load. Is the weight in newtons (a mass of m kg weighs 9.81 m N)?"
    )
    assert 150.0 < at < 200.0


def test_results_and_trajectories_print_as_a_summary_not_their_arrays():
    """``print(result)`` in a notebook shows what the run was, in one line with units;
    the dataclass default printed every array (18,741 characters for one gait cycle)."""
    mud = mudrft.paper_mud(0.25)
    gait = mudrft.gait(0.2)
    res = simulate(mudrft.feet.Flat(), mud, gait)
    plate = mudrft.plate_response(mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0), mud)
    for obj, needed in (
        (gait, ("Trajectory(", "samples=651", "duration=0.65 s", "lowest_z=-0.02 m")),
        (res, ("Result(foot='flat'", "samples=651", "max_depth=0.02 m")),
        (plate, ("PlateResult(", "samples=4501", "max_displacement=0.03 m", "Pa")),
    ):
        text = repr(obj)
        assert "\n" not in text and len(text) < 160, text
        for part in needed:
            assert part in text, (part, text)


def test_a_load_that_buries_the_foot_deeper_than_static_sinking_looks_warns():
    """5,000 N on the flat foot sinks it metres deep; static_sinking refuses it and
    the dynamic run says the foot is buried (D26) and asks for the unit of the weight."""
    mud, foot = mudrft.paper_mud(0.25), mudrft.feet.Flat()
    with pytest.warns(PlausibilityWarning, match=r"deeper than the flat foot is tall.*in N") as w:
        res = simulate(foot, mud, LoadControl(weight=5000.0, duration=2.0, ramp=0.5))
    assert len(w) == 1  # once a run
    assert res.depth.max() > 4 * foot.height
    # 49 N, the paper's load, stays shallow and quiet (warnings are errors in the suite)
    simulate(foot, mud, LoadControl(weight=49.0, duration=2.0, ramp=0.5))


@pytest.mark.parametrize("dt", [1e-3, 2e-3])
def test_a_spring_terrain_gives_back_its_work_over_a_gait_cycle(dt):
    """D133: the gait's velocities are the rates of its steps (D13b), so an elastic terrain's
    cycle work is 0 but for the step that crosses the surface (measured 2.3e-5 of the stored
    work at 1 ms, 7e-5 at 2 ms). With the path's analytic velocity, half a step off the step
    rate, it was -1.1 % of it (-0.0129 J of 1.13 J for the flat foot)."""
    res = simulate(mudrft.feet.Flat(), mudrft.terrains.LinearStiffness(), mudrft.gait(0.2, dt=dt))
    k = int(np.argmax(res.depth))
    stored = float(
        np.sum(0.5 * (res.force[1 : k + 1, 2] + res.force[:k, 2]) * np.diff(res.depth[: k + 1]))
    )
    assert stored > 1.0
    assert abs(res.metrics()["energy"]) < 1e-4 * stored


def test_gait_velocities_are_the_rates_of_its_steps():
    tr = mudrft.gait(0.2)
    np.testing.assert_allclose(
        tr.velocity[1:], np.diff(tr.position, axis=0) / np.diff(tr.time)[:, None]
    )


# ---------------------------------------------------------------------------------------
# a foot pushed deeper than its height (D26): one warning a run, an error under strict
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "motion",
    [
        mudrft.gait(0.2, depth=0.03),
        mudrft.plate_intrusion(),  # 30 mm
        LoadControl(weight=400.0, duration=1.0, ramp=0.5),
    ],
    ids=["gait", "plate", "load"],
)
def test_a_foot_deeper_than_its_height_warns_once_and_strict_refuses_it(motion):
    from mudrft.trajectories import BuriedFootWarning

    mud, foot = mudrft.paper_mud(0.25), mudrft.feet.Flat()
    with pytest.warns(BuriedFootWarning) as caught:
        res = simulate(foot, mud, motion)
    assert len(caught) == 1
    assert res.depth.max() > foot.height
    message = str(caught[0].message)
    assert f"{res.depth.max():.3g} m deep" in message and "(0.026 m)" in message
    with pytest.raises(MudrftError, match=r"strict: .*deeper than the flat foot is tall"):
        simulate(foot, mud, motion, strict=True)


def test_a_foot_within_its_height_does_not_warn_under_strict():
    """The default gait keeps the paper's 26 mm feet unburied; at 26 mm exactly too."""
    mud = mudrft.paper_mud(0.25)
    for depth in (None, 0.026):
        gait = mudrft.gait(0.2) if depth is None else mudrft.gait(0.2, depth=depth)
        simulate(mudrft.feet.Flat(), mud, gait, strict=True)  # warnings are errors here
    with pytest.raises(MudrftError, match="strict must be True or False, got 'yes'"):
        simulate(mudrft.feet.Flat(), mud, mudrft.gait(0.2), strict="yes")


def test_a_gaits_metric_is_its_depth_and_sinking_is_the_settled_depth_under_a_load():
    """max_depth is the deepest tip depth (a gait's prescribed stance depth); sinking is
    only the settled depth under a load. Reading a gait's 'sinking' still gives its
    deepest depth, with a DeprecationWarning (mudrft 0.1 named it so)."""
    from mudrft.trajectories import STANCE_DEPTH

    mud, foot = mudrft.paper_mud(0.25), mudrft.feet.Flat()
    m = simulate(foot, mud, mudrft.gait(0.2)).metrics()
    assert m["max_depth"] == pytest.approx(STANCE_DEPTH, abs=1e-12)
    assert "sinking" not in m and "sinking" not in list(m)
    with pytest.warns(DeprecationWarning, match=r"\['max_depth'\]"):
        assert m["sinking"] == m["max_depth"]
    with pytest.raises(KeyError):
        m["depth"]
    # a load at once on a spring overshoots and settles shallower
    res = simulate(foot, mudrft.terrains.LinearStiffness(), LoadControl(weight=10.0, duration=2.0))
    m = res.metrics()
    assert m["sinking"] == res.depth[-1] and m["max_depth"] == res.depth.max()
    assert m["max_depth"] > m["sinking"]
