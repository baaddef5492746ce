"""A field of mud (:class:`~mudrft.terrains.field.MudField`): what a foot at a point
feels is the area average of the regions over the border square, continuous in position."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudrft
from mudrft._validation import MudrftError
from mudrft.terrains.field import MudField
from mudrft.terrains.rows import constant_row

with warnings.catch_warnings():  # W = 15 % lies outside the paper's table: extrapolated
    warnings.simplefilter("ignore")
    FIRM = mudrft.paper_mud(0.15, extrapolate=True)
FIELD = MudField(
    {"firm": FIRM, "soft": 0.35, "rock": "rigid", "wet": 0.45},
    ["firm soft rock", "wet firm soft"],
    cell_size=(0.4, 0.3),
    origin=(-0.5, -0.2),
    border=0.1,
)


def _sampled(x: float, y: float, n: int = 400) -> tuple[float, np.ndarray]:
    """The mud's share and constants at (x, y) by midpoint quadrature of the square (n x n
    points): each point takes its cell's region, outside the grid the nearest cell's."""
    grid, cells, rows = FIELD.arrays()
    x0, y0, hx, hy, b = grid
    t = (np.arange(n) + 0.5) / n - 0.5
    px, py = np.meshgrid(x + b * t, y + b * t)
    ix = np.clip(np.floor((px - x0) / hx).astype(int), 0, cells.shape[1] - 1)
    iy = np.clip(np.floor((py - y0) / hy).astype(int), 0, cells.shape[0] - 1)
    r = cells[iy, ix].ravel()
    mud = rows[r, -1] > 0
    share = mud.mean()
    const = rows[r[mud], :-1].mean(axis=0) if mud.any() else rows[0, :-1]
    return float(share), const


@settings(max_examples=60)
@given(st.floats(-1.0, 1.0), st.floats(-0.6, 0.8))
def test_a_tip_feels_the_area_average_of_the_regions_over_the_border_square(x, y):
    """Against quadrature of the square: 400 midpoints a side put each straight border
    within half a sample, so a share is off by at most 1/400 per border crossed (two at
    most); the mean constants by those errors times the regions' spread, over the share."""
    share, const = FIELD.blend(x, y)
    s_ref, c_ref = _sampled(x, y)
    assert share == pytest.approx(s_ref, abs=2 / 400)
    if share > 0.01:  # the mean of the mud regions, weighted as their shares
        spread = np.ptp(FIELD.arrays()[2][:, :-1], axis=0)
        assert np.all(np.abs(const - c_ref) <= 4 / 400 / share * spread + 1e-12 * np.abs(c_ref))


@settings(max_examples=60)
@given(st.floats(-1.0, 1.0), st.floats(-0.6, 0.8), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0))
def test_the_blend_is_continuous_in_position(x, y, dx, dy):
    """Lipschitz: the share moves by at most (|dx| + |dy|) / border (each axis' overlap
    moves by |d| / b), so a foot crossing a border feels no jump."""
    h = 1e-3
    a, _ = FIELD.blend(x, y)
    b, _ = FIELD.blend(x + h * dx, y + h * dy)
    assert abs(a - b) <= h * (abs(dx) + abs(dy)) / 0.1 * (1 + 1e-9) + 1e-15


def test_one_mud_is_that_mud_to_the_bit_and_rigid_ground_has_none():
    share, const = FIELD.blend(-0.3, -0.1)  # inside the firm cell
    assert share == 1.0
    assert np.array_equal(const, constant_row(*mudrft.MudTerrain(FIRM).constants))
    assert FIELD.blend(0.5, -0.1)[0] == 0.0  # the rock cell
    assert FIELD.blend(3.0, -0.1)[0] == 0.0  # beyond it: the nearest cell's
    assert FIELD.blend(0.3, -0.1)[0] == pytest.approx(0.5)  # on the soft-rock border


def test_a_toml_spec_gives_the_same_field(tmp_path):
    spec = tmp_path / "field.toml"
    spec.write_text(
        "cell_size = [0.4, 0.3]\norigin = [-0.5, -0.2]\nborder = 0.1\n"
        'cells = ["soft rock", "wet soft"]\n[regions]\nsoft = 0.35\nrock = "rigid"\nwet = 0.45\n'
    )
    f = MudField.from_toml(spec)
    assert f.names == ("soft", "rock", "wet")
    assert f.cells.tolist() == [[0, 1], [2, 0]]
    assert np.array_equal(f.grid, [-0.5, -0.2, 0.4, 0.3, 0.1])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"regions": {}}, "regions must be a non-empty mapping"),
        ({"regions": {"a": "rigid"}, "cells": ["a"]}, "at least one region must be mud"),
        ({"regions": {"a": "sand"}}, "region 'a' must be a water content"),
        ({"cells": ["a b", "a"]}, "rows of equal length"),
        ({"cells": 3}, "cells must be a non-empty grid of rows"),
        ({"cells": [1, 2]}, "cells must be a non-empty grid of rows"),
        ({"cells": ["a c"]}, "cells name regions ['c']"),
        ({"border": 0.5}, "border must be at most the cell size (0.4 m), got 0.5 m"),
        ({"border": 0.0}, "border must be > 0"),
        ({"cell_size": -1.0}, "cell_size must be > 0"),
        ({"origin": (np.nan, 0.0)}, "origin must be two finite numbers"),
        (
            {"regions": {"a": 0.3, "b": mudrft.MudTerrain(mudrft.paper_mud(0.3), xi0=0.5)}},
            "region 'b': its MudTerrain options differ",
        ),
    ],
)
def test_a_wrong_field_is_refused_naming_the_argument(kwargs, message):
    args = {"regions": {"a": 0.3, "b": 0.4}, "cells": ["a b"], "cell_size": 0.4, **kwargs}
    with pytest.raises(MudrftError) as err:
        MudField(**args)
    assert message in str(err.value)


def test_a_wrong_toml_spec_is_refused_naming_the_file(tmp_path):
    spec = tmp_path / "field.toml"
    spec.write_text('cells = ["a"]\nsize = 1\n[regions]\na = 0.3\n')
    with pytest.raises(MudrftError, match=r"field.toml: a field spec has regions and cells"):
        MudField.from_toml(spec)
    spec.write_text("cells = [")
    with pytest.raises(MudrftError, match="cannot be read as a field spec"):
        MudField.from_toml(spec)


@settings(max_examples=30)
@given(st.lists(st.tuples(st.floats(-1.0, 1.0), st.floats(-0.6, 0.8)), min_size=1, max_size=20))
def test_the_array_blend_is_the_kernels_to_round_off(points):
    """field_blend (numpy, JAX) accumulates by region, field_row (the compiled kernel) by
    cell: the same sums in another order, so equal to a few ulps; one mud, to the bit."""
    from mudrft.terrains.field import field_blend

    xy = np.array(points)
    share, const = field_blend(xy[:, 0], xy[:, 1], *FIELD.arrays())
    for (x, y), s, c in zip(xy, share, const, strict=True):
        s1, c1 = FIELD.blend(x, y)
        assert s == pytest.approx(s1, abs=1e-15)
        np.testing.assert_allclose(c, c1, rtol=1e-14)
        if s1 == 1.0 and any(np.array_equal(c1, r[:-1]) for r in FIELD.arrays()[2]):
            assert np.array_equal(c, c1)


def test_polygons_are_rasterized_on_cell_centers():
    pytest.importorskip("matplotlib")
    tri = [(0.2, 0.2), (0.8, 0.2), (0.5, 0.8)]
    f = MudField.from_polygons(
        {"firm": 0.25, "pool": 0.45, "rock": "rigid"},
        [("pool", tri), ("rock", [(0.9, 0.0), (1.0, 0.0), (1.0, 1.0), (0.9, 1.0)])],
        outside="firm", bounds=(0.0, 0.0, 1.0, 1.0), cell_size=0.1,
    )  # fmt: skip
    assert f.cells.shape == (10, 10) and np.array_equal(f.grid, [0.0, 0.0, 0.1, 0.1, 0.1])
    from matplotlib.path import Path

    for j in range(10):
        for i in range(10):
            center = (0.1 * i + 0.05, 0.1 * j + 0.05)
            want = "rock" if i == 9 else ("pool" if Path(tri).contains_point(center) else "firm")
            assert f.names[f.cells[j, i]] == want
    with pytest.raises(MudrftError, match=r"polygons\[0\] \('pool'\) must be three or more"):
        MudField.from_polygons({"a": 0.3, "pool": 0.4}, [("pool", [(0, 0), (1, 1)])],
                               outside="a", bounds=(0, 0, 1, 1), cell_size=0.5)  # fmt: skip
    with pytest.raises(MudrftError, match="bounds must be"):
        MudField.from_polygons({"a": 0.3}, [], outside="a", bounds=(0, 0, 0, 1), cell_size=0.5)


UNEVEN = MudField(
    {"a": 0.25}, ["a a", "a a"], cell_size=0.2, origin=(-0.1, 0.3),
    heights=np.random.default_rng(5).normal(0.0, 0.02, (4, 6)),
)  # fmt: skip


@settings(max_examples=50, deadline=None)
@given(x=st.floats(-0.3, 0.5), y=st.floats(0.1, 0.9), dx=st.floats(-1.0, 1.0), dy=st.floats(-1.0, 1.0))  # fmt: skip
def test_an_uneven_surface_is_continuous_and_its_slope_is_the_heights_derivative(x, y, dx, dy):
    """The surface (triangles between the 6 x 4 samples, the edge's height outside) has no
    jump anywhere: a step of 1 um changes the height by at most the steepest slope times
    it; and the slope it reports is the central difference of the height where both
    points lie on one plane (the same normal), to round-off."""
    e = 1e-6 / max(np.hypot(dx, dy), 1e-9)
    (h0, n0), (h1, n1) = UNEVEN.height(x, y), UNEVEN.height(x + e * dx, y + e * dy)
    steepest = np.abs(np.diff(UNEVEN.heights, axis=0)).max() / (0.4 / 3) + np.abs(np.diff(UNEVEN.heights, axis=1)).max() / (0.4 / 5)  # fmt: skip
    assert abs(h1 - h0) <= steepest * 1e-6 * (1 + 1e-9)
    assert np.isclose(np.linalg.norm(n0), 1.0) and n0[2] > 0
    if np.array_equal(n0, n1) and np.array_equal(UNEVEN.height(x - e * dx, y - e * dy)[1], n0):
        h2 = UNEVEN.height(x - e * dx, y - e * dy)[0]
        slope = -(n0[0] * dx * e + n0[1] * dy * e) / n0[2]  # the plane's rise over the step
        assert abs((h1 - h2) / 2 - slope) <= 1e-12


def test_heights_sit_on_the_grids_nodes_and_come_from_toml(tmp_path):
    """Sample (j, i) is the height at node i along x and j along y; outside the grid the
    edge's height holds, level; a TOML spec takes ``heights`` as rows."""
    f = MudField({"a": 0.25}, ["a a"], cell_size=0.5, origin=(1.0, 2.0), heights=[[0.0, 0.1, 0.2], [0.3, 0.4, 0.5]])  # fmt: skip
    for (i, j), want in {(0, 0): 0.0, (2, 0): 0.2, (1, 1): 0.4, (2, 1): 0.5}.items():
        assert f.height(1.0 + 0.5 * i, 2.0 + 0.5 * j)[0] == pytest.approx(want, abs=1e-15)
    h, n = f.height(5.0, 9.0)  # beyond the far corner
    assert h == pytest.approx(0.5) and np.array_equal(n, [0.0, 0.0, 1.0])
    spec = tmp_path / "field.toml"
    spec.write_text('cells = ["a a"]\ncell_size = 0.5\norigin = [1.0, 2.0]\nheights = [[0.0, 0.1, 0.2], [0.3, 0.4, 0.5]]\n[regions]\na = 0.25\n')  # fmt: skip
    assert np.array_equal(MudField.from_toml(spec).heights, f.heights)
