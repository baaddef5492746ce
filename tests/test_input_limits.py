"""Hostile inputs (issue 15): bounded runs, plain-number messages, checks where objects are made.

Each test fails on the behaviour before the fix: a MemoryError (or an out-of-memory kill)
instead of an error naming the numbers, a ZeroDivisionError, a silent extrapolation or a
``np.float64(1.0)`` in a message. The sizes asked for are absurd on purpose; the fix refuses
them before allocating anything, so the tests need no memory.
"""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft._validation import (
    MAX_SAMPLES,
    MudrftError,
    check_finite,
    check_increasing,
    check_samples,
    plain,
)
from mudrft.cli import main
from mudrft.simulation import LoadControl


def run_cli(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize(
    ("make", "needle"),
    [
        (lambda: mudrft.gait(speed=1e-9), "higher speed"),  # was: 969 GiB asked of numpy
        (lambda: mudrft.gait(0.2, dt=1e-12), "larger dt"),
        (lambda: mudrft.plate_intrusion(dt=1e-12), "larger dt"),
        (lambda: LoadControl(weight=10.0, duration=10.0, dt=1e-6), "larger dt"),
        (
            lambda: mudrft.simulate(
                mudrft.feet.Flat(), mudrft.paper_mud(), mudrft.gait(), dt=1e-12
            ),
            "larger dt",
        ),
    ],
)
def test_every_run_is_bounded_by_the_one_sample_limit(make, needle):
    with pytest.raises(MudrftError) as info:
        make()
    text = str(info.value)
    assert "one run may hold" in text and f"{MAX_SAMPLES:.0e}" in text and needle in text
    assert "iB" in text  # the memory it would have needed


@pytest.mark.parametrize(("speed", "dt"), [(0.2, 10.0), (0.2, 0.3), (9.0, 1e-3), (0.2, 0.0326)])
def test_a_gait_cycle_too_coarse_to_mean_anything_is_refused(speed, dt):
    """Fewer than MIN_GAIT_STEPS steps a cycle is an error naming dt and the largest dt that
    works (it used to run: dt = 10 s gave a 2-sample cycle with no suction at all)."""
    from mudrft.trajectories import MIN_GAIT_STEPS

    with pytest.raises(MudrftError, match=r"dt = .* at least 20 are needed: use dt <= "):
        mudrft.gait(speed, dt=dt)
    period = mudrft.trajectories.STRIDE_LENGTH / speed
    assert len(mudrft.gait(speed, dt=period / MIN_GAIT_STEPS).time) == MIN_GAIT_STEPS + 1


def test_simulate_cli_with_a_coarse_dt_is_a_one_line_error(tmp_path, capsys):
    code, _, err = run_cli(
        capsys, "simulate", "--foot", "flat", "--dt", "10", "--out", str(tmp_path / "a.csv")
    )
    assert code == 2 and err.count("\n") == 1 and "dt = 10 s" in err, err
    assert not (tmp_path / "a.csv").exists()


def test_the_sample_limit_reports_count_and_memory():
    with pytest.raises(MudrftError, match=r"1\.3e\+11 samples.*about 23\.6 TiB"):
        check_samples("gait", 1.3e11, hint="use a larger dt", bytes_per_sample=200)
    with pytest.raises(MudrftError, match="nan samples"):
        check_samples("t/dt", float("nan"), hint="check dt")
    assert check_samples("t/dt", 10.2, hint="") == 11


# (values too large for numpy to even try: before the fix --dt 1e-9 was killed after a minute)
@pytest.mark.parametrize(("option", "value"), [("--speed", "1e-9"), ("--dt", "1e-12")])
def test_cli_simulate_refuses_a_run_too_long_to_hold(tmp_path, capsys, option, value):
    out = tmp_path / "run.csv"
    code, _, err = run_cli(capsys, "simulate", "--foot", "flat", option, value, "--out", str(out))
    assert code == 2 and "samples" in err and "Traceback" not in err, err
    assert not out.exists()


@pytest.mark.parametrize("lam", [0, 0.0, np.array([1.0, 0.0])])
def test_zero_relaxation_time_is_an_error_naming_lam(lam):
    p = mudrft.paper_parameters(0.25)
    with pytest.raises(MudrftError, match=r"lam must be > 0 s, got 0\.0"):
        p.replace(lam=lam)


def test_messages_show_plain_numbers():
    assert plain(np.float64(1.0)) == "1.0" and plain(np.int32(2)) == "2"
    with pytest.raises(MudrftError) as info:
        check_increasing("time", np.array([0.0, 1.0, 1.0]))
    assert "np." not in str(info.value) and "time[2] = 1.0" in str(info.value)
    # a numpy repr that slips into any message still reads as a plain number
    assert str(MudrftError(f"dt = {np.float64(0.5)!r} s")) == "dt = 0.5 s"


@pytest.mark.parametrize(
    ("value", "message"),
    [
        (float("nan"), "depth must be finite, got nan"),  # was: "got nan containing nan"
        (-np.inf, "depth must be finite, got -inf"),
        # one number is asked for: a list is refused for its count before its entries
        ([0.01, np.inf], "depth must be a single number [m], got an array of shape (2,)"),
    ],
)
def test_a_non_finite_number_is_named_once(value, message):
    with pytest.raises(MudrftError) as info:
        mudrft.gait(speed=0.2, depth=value)
    assert str(info.value) == message


def test_a_non_finite_entry_of_an_array_is_named():
    with pytest.raises(MudrftError) as info:
        check_finite("depth", [0.01, np.inf])
    assert str(info.value) == "depth must be finite, got an array of shape (2,) containing inf"


def test_compare_needs_extrapolate_like_simulate_and_walk(tmp_path, capsys):
    from mudrft.baselines import default_terrains

    with pytest.raises(MudrftError, match="extrapolate=True"):
        default_terrains(0.2)
    with pytest.warns(UserWarning, match="extrapolated"):
        assert "mud" in default_terrains(0.2, extrapolate=True)
    out = tmp_path / "cmp"
    code, _, err = run_cli(
        capsys, "compare", "--water-content", "0.2", "--no-figures", "--out", str(out)
    )
    assert code == 2 and "--extrapolate" in err and not out.exists(), err
