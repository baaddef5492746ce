"""User mistakes in the library's API: each gets a MudrftError that names the argument.

Found by a fuzz of the public API with wrong shapes, types and signs. Before the fix each
case either failed inside numpy (``operands could not be broadcast``, ``zero-size array``,
``could not convert string to float``, an AttributeError on None) or, worse, returned a
number without a word: the test fails on that behaviour.
"""

from __future__ import annotations

import csv
import warnings
from pathlib import Path

import numpy as np
import pytest

import mudrft
from mudrft import baselines as B
from mudrft import calibration as C
from mudrft._validation import (
    MudrftError,
    PlausibilityWarning,
    nonnegative_number,
    number_in_range,
    positive_number,
)
from mudrft.feet import first_quadrant

FLAT = mudrft.feet.Flat()
MUD = mudrft.paper_mud(0.25)
PLATE = mudrft.plate_intrusion(depth=0.02)  # within the 26 mm foot
TWO, THREE_BY_3, FOUR = np.array([0.01, 0.02]), np.ones((3, 3)), np.zeros(4)


CASES = [
    # simulate resampled a 0.65 s gait at 0.3 s: 3 samples, no suction, no warning
    (
        lambda: mudrft.simulate(FLAT, MUD, mudrft.gait(), dt=0.3),
        r"dt = 0.3 s cuts the 0.65 s trajectory into fewer than 20 steps; use dt <= 0.0325 s",
    ),
    # one number each: a list of speeds failed in plain arithmetic
    (
        lambda: mudrft.gait(speed=[0.1, 0.2]),
        r"speed must be a single number \[m/s\], got an array of shape \(2,\)",
    ),
    (lambda: mudrft.gait(slip=[0.1, 0.2]), r"slip must be a single number"),
    (lambda: mudrft.static_sinking(None, MUD, 10.0), r"foot must be a Foot"),
    (
        lambda: mudrft.static_sinking(FLAT, MUD, [10.0, 20.0]),
        r"weight must be a single number \[N\]",
    ),
    # shapes that do not broadcast: three feet, three kinds
    (
        lambda: FLAT.resultant(TWO, THREE_BY_3, FOUR),
        r"the shapes must broadcast together, got depth \(2,\), stress \(its last axis, 3, aside\) \(3,\), heading \(4,\)",
    ),
    (
        lambda: mudrft.feet.SemiSphere().force(TWO, THREE_BY_3, FOUR),
        r"must broadcast together",
    ),
    (lambda: FLAT.to_mesh().resultant(TWO, THREE_BY_3, FOUR), r"must broadcast together"),
    (lambda: first_quadrant((1.0, 1.0, 1.0), np.nan), r"heading must be finite"),
    (
        lambda: first_quadrant(np.ones((2, 3)), np.ones(3)),
        r"the shapes must broadcast together, got stress \(its last axis, 3, aside\) \(2,\), heading \(3,\)",
    ),
    (
        lambda: first_quadrant(np.ones((2, 3)), np.ones((4, 1))),
        r"heading \(shape \(4, 1\)\) must broadcast to stress's batch shape \(2,\)",
    ),
    # a trial whose depth was logged negative converged at the bounds with "converged"
    (
        lambda: C.Trial([0.0, 1.0, 2.0], [0.0, -0.01, -0.02], [0.0, 1e3, 2e3]),
        r"depth is never positive .* flip its sign",
    ),
    (
        lambda: C.OnlineEstimator().update("x", 0.01, 1.0),
        r"update: time must be a number, got 'x'",
    ),
    (
        lambda: C.StreamClassifier([mudrft.paper_parameters(0.25, "vertical")]).update(
            0.0, None, 1.0
        ),
        r"update: depth must be a number, got None",
    ),
    (
        lambda: C.OnlineEstimator().update_many([0.0, 1.0], [[0.01, 0.02]], [1.0, 2.0]),
        r"depth must have shape \(n,\), got shape \(1, 2\)",
    ),
    (
        lambda: C.load_dataset(None),
        r"path must be a file path or a sequence of file paths, got NoneType",
    ),
    (
        lambda: C.synthetic_dataset(mudrft.paper_parameters(0.25, "vertical"), seed="x"),
        r"seed must be an integer or None, got 'x'",
    ),
    # area and characteristic_length were ignored for a loaded dataset
    (
        lambda: C.calibrate(
            C.synthetic_dataset(mudrft.paper_parameters(0.25, "vertical"), speeds=(0.02,)),
            area=-1.0,
        ),
        r"area apply to a log read from a path",
    ),
    # baselines
    (lambda: B.compare(None, PLATE), r"foot must be a Foot"),
    (lambda: B.compare(FLAT, "x"), r"trajectory must be a Trajectory"),
    (lambda: B.run_terrain(B.RigidGround(), None, PLATE), r"foot must be a Foot"),
    (lambda: B.summarize("x"), r"histories must be a mapping"),
    (lambda: B.normalized_loop("x"), r"history must be a History"),
    (lambda: B.write_csv("x", "never.csv"), r"runs must be a non-empty mapping"),
    (
        lambda: B.write_csv({}, "never.csv"),
        r"runs must be a non-empty mapping .* got an empty mapping",
    ),
    (
        lambda: B.fit_stiffness(-np.linspace(0, 0.01, 5), np.linspace(0, 100, 5)),
        r"depth must be >= 0 m",
    ),
    (lambda: B.rft_forces([[0, 0, -1]], [0.01], [-1e-4], (0, 0, -1)), r"areas must be >= 0 m\^2"),
    (
        lambda: B.rft_forces([[0, 0, 0]], [0.01], [1e-4], (0, 0, -1)),
        r"normals must be nonzero vectors, got normals\[0\]",
    ),
    (lambda: B.treers_weights(np.nan, 0.0), r"v1 must be finite"),
    (
        lambda: B.li2013_alpha(np.ones(3), np.ones(4)),
        r"the shapes must broadcast together, got beta \(3,\), gamma \(4,\)",
    ),
]


@pytest.mark.parametrize(("call", "message"), CASES)
def test_a_user_mistake_is_named(call, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(MudrftError, match=message):
        call()
    assert list(tmp_path.iterdir()) == []  # and nothing was written


def test_batched_mud_takes_one_step_for_all_feet():
    from mudrft.backends import BatchedMud

    b = BatchedMud(MUD, FLAT, 4, backend="numpy")
    with pytest.raises(MudrftError, match=r"dt must be a single number \[s\]"):
        b.step(np.zeros((4, 3)), np.zeros((4, 3)), np.full(4, 1e-3))


def test_mud_options_given_twice_or_unknown_are_named():
    """BatchedMud ignored options given beside a MudTerrain, and an unknown one failed as a
    TypeError of MudTerrain.__init__."""
    from mudrft.backends import BatchedMud

    with pytest.raises(MudrftError, match=r"unknown mud option\(s\) \['bogus'\]; the options are \['characteristic_length'"):  # fmt: skip
        BatchedMud(MUD, FLAT, 4, backend="numpy", bogus=1)
    terrain = mudrft.MudTerrain(MUD)
    with pytest.raises(MudrftError, match=r"\['acceleration'\] cannot be set here: mud is a MudTerrain"):  # fmt: skip
        BatchedMud(terrain, FLAT, 1, backend="numba", acceleration=False)
    assert BatchedMud(terrain, FLAT, 1, backend="numba").terrain.mud is terrain.mud


def test_a_stance_depth_in_millimetres_warns():
    """gait(depth=20) meant 20 mm: a 20 m stance runs, but with a warning naming the unit."""
    with pytest.warns(PlausibilityWarning, match=r"stance depth of 20 m, more than 1 m .* metres"):
        mudrft.gait(depth=20.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mudrft.gait(depth=0.3)  # deep mud, plausible


@pytest.mark.parametrize(
    ("option", "value", "dt", "message"),
    [
        ("lift", 10.0, 1e-3, r"lift of 10 m, more than 1 m .*\(10 mm = 0.01\)"),
        ("stride", 130.0, 0.05, r"stride of 130 m, more than 5 m .*\(130 mm = 0.13\)"),
        ("speed", 200.0, 1e-6, r"speed of 200 m/s, more than 10 m/s .*\(200 mm/s = 0.2\)"),
    ],
)
def test_gait_lengths_in_mm_and_a_speed_in_mm_per_s_warn(option, value, dt, message):
    """A lift, stride or speed in mm (mm/s) ran silently (found by a fuzz of the API)."""
    with pytest.warns(PlausibilityWarning, match=message):
        mudrft.gait(**{option: value, "dt": dt})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mudrft.gait(lift=0.05, stride=0.5, speed=2.0)  # high and fast, plausible


def _fail_midway(monkeypatch, module, name):
    real = getattr(module, name)

    def broken(fname, *args, **kw):
        Path(fname).write_text("partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(module, name, broken)
    return real


def test_result_to_csv_is_atomic(tmp_path, monkeypatch):
    """A write that fails halfway keeps the old file under overwrite=True and leaves no
    temporary file (it used to truncate the old file first)."""
    res = mudrft.simulate(FLAT, MUD, mudrft.gait(dt=4e-3))
    p = tmp_path / "run.csv"
    p.write_text("old results")
    _fail_midway(monkeypatch, np, "savetxt")
    with pytest.raises(MudrftError, match="cannot be written"):
        res.to_csv(p, overwrite=True)
    assert p.read_text() == "old results"
    assert sorted(q.name for q in tmp_path.iterdir()) == ["run.csv"]
    monkeypatch.undo()
    res.to_csv(p, overwrite=True)
    assert p.read_text().splitlines()[0] == "time [s],x [m],y [m],z [m],Fx [N],Fy [N],Fz [N]"


def test_baselines_write_csv_is_atomic(tmp_path, monkeypatch):
    out = B.compare(FLAT, PLATE, [B.RigidGround()])
    p = tmp_path / "compare.csv"
    p.write_text("old results")

    class Broken:
        def __init__(self, fh):
            fh.write("partial")

        def writerow(self, row):
            raise OSError(28, "No space left on device")

    monkeypatch.setattr(csv, "writer", Broken)
    with pytest.raises(MudrftError, match="cannot be written"):
        B.write_csv(out, p, overwrite=True)
    assert p.read_text() == "old results"
    assert sorted(q.name for q in tmp_path.iterdir()) == ["compare.csv"]


def test_a_velocity_that_is_not_the_rate_of_the_position_warns():
    """A flipped sign or mm/s: the force answered a motion the position never made (a tip
    going down at +5 m/s met 5 kN of suction). The built-in paths stay quiet."""
    t = np.linspace(0.0, 1.0, 101)
    p = np.zeros((101, 3))
    p[:, 2] = -0.02 * t  # 20 mm down in 1 s
    for vz, drift in ((+0.02, "0.04 m"), (-20.0, "20 m")):  # flipped; mm/s
        v = np.zeros((101, 3))
        v[:, 2] = vz
        with pytest.warns(PlausibilityWarning, match=rf"along z they disagree by {drift} over a path that spans 0.02 m"):  # fmt: skip
            mudrft.Trajectory(t, p, v)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        v = np.zeros((101, 3))
        v[:, 2] = -0.02
        mudrft.Trajectory(t, p, v)
        mudrft.Trajectory.from_positions(t, p)
        for speed in mudrft.GAIT_SPEEDS.values():
            mudrft.gait(speed)
        mudrft.plate_intrusion(dt=0.5)  # corners kept exactly, velocity steps at them
        mudrft.plate_intrusion(direction="horizontal")
        two = mudrft.gait(0.2)  # two strokes end to end: the foot jumps back in the air
        mudrft.Trajectory(
            np.concatenate([two.time, two.time[-1] + 1e-3 + two.time]),
            np.concatenate([two.position, two.position]),
            np.concatenate([two.velocity, two.velocity]),
        )


@pytest.mark.parametrize(
    "check, args, message",
    [
        (positive_number, ("dt", -1e-3), r"dt must be > 0 s, got -0\.001"),
        (
            positive_number,
            ("dt", [1e-3, 2e-3]),
            r"dt must be a single number \[s\], got an array of shape \(2,\)",
        ),
        (positive_number, ("dt", None), r"dt .*None"),
        (nonnegative_number, ("dt", -1.0), r"dt must be >= 0 s, got -1\.0"),
        (nonnegative_number, ("dt", np.ones(2)), r"dt must be a single number \[s\]"),
        (
            positive_number,
            ("dt", [-1.0, 2.0]),
            r"dt must be a single number \[s\], got an array of shape \(2,\)",
        ),
        (number_in_range, ("dt", 2.0, 0.0, 1.0), r"dt must lie in \[0\.0, 1\.0\] s, got 2\.0 s"),
        (number_in_range, ("dt", (0.5, 0.5), 0.0, 1.0), r"dt must be a single number \[s\]"),
    ],
)
def test_one_number_checks_count_then_range(check, args, message):
    """positive_number and its siblings: one number first (a list of two is refused as such, not for its sign), then
    the range, both messages naming the argument and its unit."""
    with pytest.raises(MudrftError, match=message):
        check(*args, unit="s")


def test_one_number_checks_return_a_float():
    values = (
        positive_number("a", 2),
        nonnegative_number("b", np.float32(0)),
        number_in_range("c", np.array(0.25), 0.0, 1.0),
    )
    assert values == (2.0, 0.0, 0.25)
    assert all(type(v) is float for v in values)


def test_the_last_silent_core_inputs_are_refused():
    """Issue 43: each of these was accepted silently, returned NaN, or failed deep inside
    (AttributeError, numpy's MemoryError for 21.8 TiB)."""
    from mudrft import constitutive
    from mudrft.backends import BatchedMud

    p = mudrft.paper_parameters(0.25)
    st = constitutive.initial_state()
    with pytest.raises(MudrftError, match=r"progress must be True, False or a callable"):
        mudrft.simulate(FLAT, MUD, mudrft.gait(0.2), progress="yes")
    for seal in (2.0, -0.5):
        with pytest.raises(MudrftError, match=r"seal must lie in \[0.0, 1.0\]"):
            constitutive.step(p, st, 0.1, 1.0, 0.01, seal=seal)
    with pytest.raises(MudrftError, match="seal must be finite"):
        constitutive.step(p, st, 0.1, 1.0, 0.01, seal=float("nan"))
    with pytest.raises(MudrftError, match=r"state must be a ChannelState.*got NoneType"):
        constitutive.step(p, None, 0.1, 1.0, 0.01)
    terrain = mudrft.MudTerrain(MUD)
    state = terrain.initial_state(FLAT, [0.0, 0.0, 0.0])
    with pytest.raises(MudrftError, match=r"foot must be a mudrft foot.*got NoneType"):
        terrain.step(None, state, [0.0, 0.0, -0.01], [0.0, 0.0, -0.1], 1e-3)
    with pytest.raises(MudrftError, match=r"a batch of n = 1000000000000 feet would need about"):
        BatchedMud(MUD, FLAT, 10**12)


def test_the_jax_step_checks_concrete_inputs():
    """Issue 43: ``backends.jax.step`` took dt = -1 and a NaN gamma and returned numbers."""
    pytest.importorskip("jax")
    from mudrft.backends import jax as mjax

    jp = mjax.to_jax(mudrft.paper_parameters(0.25))
    st = mjax.initial_state()
    with pytest.raises(MudrftError, match="dt must be > 0"):
        mjax.step(jp, st, 0.1, 1.0, -1.0)
    with pytest.raises(MudrftError, match="gamma must be finite"):
        mjax.step(jp, st, float("nan"), 1.0, 0.01)
    with pytest.raises(MudrftError, match=r"seal must lie in \[0.0, 1.0\]"):
        mjax.step(jp, st, 0.1, 1.0, 0.01, seal=2.0)
