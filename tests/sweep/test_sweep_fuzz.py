"""User mistakes in sweep specs, in ``mudrft.sweep``'s options and in the maps' arguments:
each is a MudrftError naming the key or argument, raised before anything is allocated or run
(a fuzz of the sweeps; every case here failed differently before).
"""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError
from mudrft.sweep import load_spec

xr = pytest.importorskip("xarray")
pytest.importorskip("zarr")

FLAT = {"kind": "flat"}

BAD = [
    # num = 1e12 allocated 7 TiB in numpy.linspace (MemoryError) before the point limit
    (
        {"foot": {**FLAT, "width": {"low": 0.05, "high": 0.06, "num": 10**12}}},
        r"\[foot\] width num = 1e\+12 values, more than a sweep's limit of 1e\+07 points",
    ),
    # an integer beyond int64: OverflowError from numpy (list), or -2**63 drawn (range)
    (
        {"foot": {"kind": "morphing", "n_pads": [3, 10**30]}},
        r"\[foot\] n_pads must be an integer of magnitude at most 2\*\*53, got 10{30}",
    ),
    (
        {
            "sweep": {"design": "lhs", "n": 4},
            "foot": {"kind": "morphing", "n_pads": {"low": 1, "high": 10**30}},
        },
        r"\[foot\] n_pads high must be an integer of magnitude at most 2\*\*53",
    ),
    # log = true was ignored: the integers were drawn uniformly
    (
        {
            "sweep": {"design": "lhs", "n": 4},
            "foot": {"kind": "morphing", "n_pads": {"low": 1, "high": 8, "log": True}},
        },
        r"\[foot\] n_pads: log applies to real ranges; an integer range is drawn uniformly",
    ),
    # high - low overflows: every point drawn was inf, a grid's middle value NaN
    (
        {
            "sweep": {"design": "lhs", "n": 4},
            "foot": {"kind": "morphing", "crank_offset": {"low": -1e308, "high": 1e308}},
        },
        r"\[foot\] crank_offset: the range is too wide, high - low .* is not a finite number",
    ),
    # the maps of x = y failed with xarray's "axes don't match array" after the whole sweep
    (
        {"foot": {**FLAT, "width": [0.05, 0.06]}, "plot": {"x": "width", "y": "width"}},
        r"\[plot\] x and y are both 'width'; a map needs a different parameter for each",
    ),
    (
        {
            "foot": {**FLAT, "width": [0.05, 0.06]},
            "motion": {"speed": [0.1, 0.2]},
            "plot": {"x": "width", "panels": "width"},
        },
        r"\[plot\] x and panels are both 'width'",
    ),
]


@pytest.mark.parametrize(("sections", "message"), BAD)
def test_bad_spec_is_refused_before_anything_is_made(sections, message):
    with pytest.raises(MudrftError, match=message):
        load_spec({"foot": FLAT, **sections})


SMALL = {"foot": {**FLAT, "width": [0.05, 0.06]}}


@pytest.mark.parametrize(
    ("options", "message"),
    [
        # zarr's TypeError "Unsupported type for store_like"
        (
            {"store": 42},
            r"store must be the path of a \.zarr directory, a zarr store or None, got int",
        ),
        # Path("") is ".": "store '.' exists"
        ({"store": ""}, r"store must be the path of a \.zarr directory, got an empty string"),
        # a truthy string resumed; "no" asked for a store to resume
        ({"resume": "no"}, r"resume must be True or False, got 'no'"),
        ({"overwrite": "no"}, r"overwrite must be True or False, got 'no'"),
        # silently no progress
        (
            {"progress": "yes"},
            r"progress must be True, False or a callable f\(fraction\), got 'yes'",
        ),
        # AttributeError: 'str' object has no attribute 'scheduler_info', from inside the run
        ({"client": "tcp://host:8786"}, r"client must be a distributed\.Client, got str"),
    ],
)
def test_bad_options_of_a_sweep_are_named(tmp_path, options, message):
    with pytest.raises(MudrftError, match=message):
        mudrft.sweep(SMALL, **options)
    assert list(tmp_path.iterdir()) == []


def _fake_result():
    """A grid result's shape (no physics): four swept parameters, one metric."""
    coords = {"width": [0.05, 0.06], "length": [0.07, 0.08], "speed": [0.1, 0.2], "depth": [0.01, 0.02]}  # fmt: skip
    data = np.arange(16.0).reshape(2, 2, 2, 2)
    return xr.Dataset(
        {"energy": (tuple(coords), data), "error": (tuple(coords), np.full(data.shape, ""))},
        coords=coords,
    )


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"x": "width", "y": "width"}, r"x and y are both 'width'"),
        ({"x": "width", "y": "length", "select": [1]}, r"select must be a dict"),
        # ignored silently: the maps showed another slice than the one asked for
        (
            {"x": "width", "y": "length", "select": {"nope": 1}},
            r"select 'nope': not a parameter these maps hold at one value; expected one of depth",
        ),
        (
            {"x": "width", "y": "length", "select": {"width": 0.05}},
            r"select 'width': not a parameter",
        ),
        # xarray's KeyError from .sel
        (
            {"x": "width", "y": "length", "select": {"depth": 0.015}},
            r"select 'depth': 0\.015 is not one of its values \(0\.01, 0\.02\)",
        ),
    ],
)
def test_bad_map_arguments_are_named(options, message):
    pytest.importorskip("matplotlib")
    with pytest.raises(MudrftError, match=message):
        mudrft.sweep.plot_maps(_fake_result(), "energy", **options)


def test_a_held_parameter_is_selected_by_one_of_its_values():
    plt = pytest.importorskip("matplotlib.pyplot")
    fig = mudrft.sweep.plot_maps(_fake_result(), "energy", x="width", y="length", select={"depth": 0.02})  # fmt: skip
    plt.close(fig)


def test_resume_with_another_spec_says_so_before_asking_for_force(tmp_path, capsys):
    # it said "points.csv exists; pass --force", and --force then named the other spec
    from mudrft.cli import main
    from mudrft.sweep.store import create_store

    out = tmp_path / "out"
    out.mkdir()
    create_store(out / "sweep.zarr", load_spec(SMALL))  # a store of SMALL (no points run)
    (out / "points.csv").write_text("width [m]\n")
    other = tmp_path / "other.toml"
    other.write_text('[foot]\nkind = "flat"\nwidth = [0.05, 0.07]\n')
    code = main(["sweep", str(other), "--out", str(out), "--resume", "--scheduler", "serial"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "sweep.zarr' was made from another spec" in err
    assert (out / "points.csv").read_text() == "width [m]\n"
