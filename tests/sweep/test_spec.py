"""The sweep spec: designs, chunks, and a clear error naming the key for every mistake.

Nothing here runs the physics.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from mudrft._validation import MudrftError
from mudrft.sweep import load_spec
from mudrft.sweep.spec import Axis
from mudrft.sweep.spec import SweepSpec as Design

REPO = Path(__file__).resolve().parents[2]


def spec(**sections):
    base = {"foot": {"kind": "flat"}}
    base.update(sections)
    return load_spec(base)


def test_grid_has_one_dimension_per_swept_parameter_in_spec_order():
    s = spec(
        foot={"kind": "semi-cylinder", "radius": [0.03, 0.045], "width": 0.065},
        mud={"water_content": {"low": 0.25, "high": 0.45, "num": 5}},
        motion={"speed": [0.13, 0.2, 0.26]},
    )
    assert s.dims == ("radius", "water_content", "speed")
    assert s.shape == (2, 5, 3) and s.n_points == 30
    assert s.fixed == {"foot": "semi-cylinder", "width": 0.065}
    assert np.allclose(s.axes[1].values, [0.25, 0.3, 0.35, 0.4, 0.45])
    assert s.metrics[0] == "peak_support" and "energy" in s.metrics  # all by default


def test_log_range_is_geometric():
    s = spec(motion={"speed": {"low": 0.01, "high": 1.0, "num": 3, "log": True}})
    assert np.allclose(s.axes[0].values, [0.01, 0.1, 1.0])


@given(
    shape=st.lists(st.integers(1, 6), min_size=1, max_size=4),
    per_task=st.integers(1, 40),
)
def test_chunks_cover_every_grid_point_exactly_once(shape, per_task):
    axes = tuple(Axis(f"p{i}", "float", values=np.arange(float(n))) for i, n in enumerate(shape))
    d = Design("grid", axes, points_per_task=per_task)
    seen = np.zeros(shape, dtype=int)
    for i in range(d.n_chunks):
        sl = d.chunk_slices(i)
        seen[sl] += 1
        points = d.chunk_points(i)
        assert len(points) == int(np.prod(d.chunk_shape(i))) <= max(per_task, 1)
        # the points list the block in C order, with the values of the axes
        first = {f"p{k}": float(s.start) for k, s in enumerate(sl)}
        assert points[0] == first
    assert np.all(seen == 1)


def test_sample_designs_are_seeded_and_inside_their_ranges():
    def sample(design, seed, n=16):
        return spec(
            sweep={"design": design, "n": n, "seed": seed},
            mud={"sigma_y_scale": {"low": 0.5, "high": 2.0, "log": True}},
            motion={"speed": {"low": 0.1, "high": 0.3}},
        )

    for design in ("lhs", "sobol"):
        a, b, c = sample(design, 1), sample(design, 1), sample(design, 2)
        assert a.dims == ("point",) and a.shape == (16,)
        assert np.array_equal(a.sample["speed"], b.sample["speed"])
        assert not np.array_equal(a.sample["speed"], c.sample["speed"])
        assert a.identity() == b.identity() != c.identity()
        assert 0.1 <= a.sample["speed"].min() and a.sample["speed"].max() <= 0.3
        s = a.sample["sigma_y_scale"]
        assert 0.5 <= s.min() and s.max() <= 2.0
    lhs = sample("lhs", 0, n=10).sample["speed"]
    # a Latin hypercube puts one point in each tenth of the range
    assert sorted(np.floor((lhs - 0.1) / 0.02).astype(int)) == list(range(10))


def test_sample_chunks_and_integer_parameters():
    s = spec(
        sweep={"design": "lhs", "n": 10, "points_per_task": 4},
        foot={"kind": "morphing", "n_pads": {"low": 4, "high": 8}},
    )
    assert s.chunks == (4,) and s.n_chunks == 3 and len(s.chunk_points(2)) == 2
    pads = s.sample["n_pads"]
    assert pads.dtype.kind == "i" and pads.min() >= 4 and pads.max() <= 8
    assert isinstance(s.chunk_points(0)[0]["n_pads"], int)


def test_points_per_task_default_depends_on_the_spec_only():
    s = spec(motion={"speed": {"low": 0.1, "high": 0.3, "num": 200}})
    assert s.chunk_size == 7 and s.n_chunks == 29  # ceil(200 / 32), the same on any machine
    walk = spec(motion={"kind": "walk", "seconds": [1.0, 2.0]})
    assert walk.chunk_size == 1 and walk.metrics[0] == "fell"


def test_identity_changes_with_what_decides_the_values_only():
    a = spec(motion={"speed": [0.1, 0.2]}, plot={"x": "speed"})
    assert a.identity() == spec(motion={"speed": [0.1, 0.2]}).identity()
    assert a.identity() != spec(motion={"speed": [0.1, 0.25]}).identity()
    assert a.identity() != spec(motion={"speed": [0.1, 0.2]}, sweep={"points_per_task": 1}).identity()  # fmt: skip


def test_example_spec_file_loads():
    s = load_spec(REPO / "examples" / "sweep_example.toml")
    assert s.where.endswith("sweep_example.toml") and "[foot]" in s.text
    assert s.n_points >= 27 and len(s.dims) >= 3


def test_mud_sets_are_read_relative_to_the_spec(tmp_path):
    import mudrft

    mud = mudrft.paper_mud(0.35)
    for d in ("vertical", "horizontal"):
        p = getattr(mud, d).as_dict()
        (tmp_path / f"{d}.json").write_text(json.dumps(p))
    (tmp_path / "s.toml").write_text(
        '[foot]\nkind = "flat"\n[mud]\nmud_set = ["site"]\n'
        '[mud.sets.site]\nvertical = "vertical.json"\nhorizontal = "horizontal.json"\n'
    )
    s = load_spec(tmp_path / "s.toml")
    assert s.dims == ("mud_set",)
    assert s.mud_sets["site"]["vertical"]["sigma_y"] == mud.vertical.sigma_y


def test_mud_sets_refuse_a_set_fitted_to_the_other_direction(tmp_path):
    """A horizontal fit named as the vertical set is an error naming the key (it used to run
    the sweep on swapped sets without a word)."""
    import mudrft

    mud = mudrft.paper_mud(0.35)
    for d in ("vertical", "horizontal"):
        p = dict(getattr(mud, d).as_dict(), direction=d)
        (tmp_path / f"{d}.json").write_text(json.dumps(p))
    (tmp_path / "s.toml").write_text(
        '[foot]\nkind = "flat"\n[mud]\nmud_set = ["site"]\n'
        '[mud.sets.site]\nvertical = "horizontal.json"\nhorizontal = "vertical.json"\n'
    )
    with pytest.raises(MudrftError, match=r"\[mud.sets.site\] vertical: .* holds a horizontal"):
        load_spec(tmp_path / "s.toml")


BAD = [
    ({"foo": {}}, r"unknown section \[foo\]"),
    ({"sweep": {"desing": "grid"}}, r"\[sweep\] desing: unknown key \(did you mean 'design'\?\)"),
    ({"sweep": {"design": "random"}}, r"\[sweep\] design must be one of grid, lhs, sobol"),
    ({"sweep": {"metrics": ["suction"]}}, r"\[sweep\] metrics: unknown metric 'suction'"),
    ({"sweep": {"metrics": []}}, r"\[sweep\] metrics must be a non-empty list"),
    ({"sweep": {"points_per_task": 0}}, r"\[sweep\] points_per_task must be an integer >= 1"),
    ({"sweep": {"n": 8}}, r"\[sweep\] n is for sample designs"),
    (
        {"sweep": {"design": "lhs"}, "motion": {"speed": {"low": 0.1, "high": 0.2}}},
        r"\[sweep\] n \(the number of points\) is required",
    ),
    (
        {"sweep": {"design": "sobol", "n": 100}, "motion": {"speed": {"low": 0.1, "high": 0.2}}},
        r"power of 2.*got 100; use 128",
    ),
    ({"sweep": {"design": "lhs", "n": 8}}, r"needs at least one range"),
    ({"foot": {}}, r"\[foot\] kind is required"),
    ({"foot": {"kind": "square"}}, r"\[foot\] kind must be one of flat, semi-cylinder"),
    (
        {"foot": {"kind": "flat", "radius": 0.04}},
        r"\[foot\] radius: not a parameter of the flat foot; expected one of height, length, width",
    ),
    (
        {"foot": {"kind": "flat", "width": "wide"}},
        r"\[foot\] width must be a number \[m\].*got 'wide'",
    ),
    ({"foot": {"kind": "flat", "width": True}}, r"\[foot\] width must be a number"),
    ({"foot": {"kind": "flat", "width": float("nan")}}, r"\[foot\] width must be finite"),
    ({"foot": {"kind": "flat", "width": []}}, r"\[foot\] width: empty list"),
    ({"foot": {"kind": "flat", "width": [0.05, 0.05]}}, r"\[foot\] width lists a value twice"),
    (
        {"foot": {"kind": "flat", "width": {"low": 0.06, "high": 0.05, "num": 3}}},
        r"\[foot\] width: empty range, high \(0.05\) must be > low \(0.06\)",
    ),
    (
        {"foot": {"kind": "flat", "width": {"low": 0.05, "high": 0.06}}},
        r"\[foot\] width: a grid range needs num",
    ),
    (
        {"foot": {"kind": "flat", "width": {"low": 0.05, "high": 0.06, "num": 1}}},
        r"\[foot\] width num must be an integer >= 2",
    ),
    (
        {"foot": {"kind": "flat", "width": {"low": 0.05, "hi": 0.06}}},
        r"\[foot\] width hi: unknown key \(did you mean 'high'\?\)",
    ),
    (
        {"motion": {"lift": {"low": 0.0, "high": 0.02, "num": 2, "log": True}}},
        r"\[motion\] lift: a log range needs low > 0",
    ),
    ({"sweep": {"points_per_task": True}}, r"\[sweep\] points_per_task must be an integer >= 1"),
    (
        {"sweep": {"design": "lhs", "n": 4, "sed": 1}},
        r"\[sweep\] sed: unknown key \(did you mean 'seed'\?\)",
    ),
    (
        {"foot": {"kind": "flat", "width": {"low": 0.05}}},
        r"\[foot\] width needs high, it is missing",
    ),
    (
        {"foot": {"kind": "flat", "width": {"low": 0.05, "high": 0.06, "num": 3, "log": "yes"}}},
        r"\[foot\] width log must be true or false",
    ),
    ({"mud": {"sets": {"a": {"vertical": "v.json"}}}}, r"\[mud.sets.a\] needs horizontal"),
    (
        {"mud": {"sets": {"a": {"vertical": 1, "horizontal": "h.json"}}}},
        r"\[mud.sets.a\] vertical must be a string, got 1",
    ),
    (
        {"plot": {"metrics": ["energy"]}, "sweep": {"metrics": ["max_depth"]}},
        r"\[plot\] metrics must name measured metrics \(max_depth\)",
    ),
    ({"foot": {"kind": "flat", "unit": "mm"}}, r"\[foot\] unit applies to mesh files only"),
    ({"foot": {"kind": "flat", "up": "y"}}, r"\[foot\] up applies to mesh files only"),
    (
        {"foot": {"kind": "morphing", "mode": "open"}},
        r"\[foot\] mode must be one of morphing, expanded, retracted",
    ),
    ({"foot": {"kind": "morphing", "n_pads": 7.5}}, r"\[foot\] n_pads must be an integer"),
    ({"foot": {"kind": ["flat", "flat"]}}, r"\[foot\] kind lists a foot twice"),
    (
        {"mud": {"watercontent": 0.3}},
        r"\[mud\] watercontent: unknown key \(did you mean 'water_content'\?\)",
    ),
    ({"mud": {"extrapolate": [True, False]}}, r"\[mud\] extrapolate cannot be swept"),
    (
        {"mud": {"water_content": 0.3, "mud_set": "a"}},
        r"water_content .* or mud_set .* not both",
    ),
    ({"mud": {"mud_set": "a"}}, r"\[mud\] mud_set: no set 'a' in \[mud.sets\]"),
    (
        {"mud": {"thixotropy": ["ode", "fast"]}},
        r"\[mud\] thixotropy must be one of ode, quasi-static, got 'fast'",
    ),
    ({"motion": {"kind": "run"}}, r"\[motion\] kind must be one of gait, load, walk"),
    ({"motion": {"weight": 10.0}}, r"\[motion\] \(gait\) weight: unknown key"),
    ({"motion": {"kind": "load"}}, r"\[motion\] weight is required for kind = 'load'"),
    (
        {"motion": {"speed": 0.2}, "plot": {"x": "speed"}},
        r"\[plot\] x must be a swept parameter \(none\)",
    ),
    (
        {"motion": {"speed": [0.1, 0.2]}, "plot": {"colour": "speed"}},
        r"\[plot\] colour: unknown key",
    ),
    (
        {"sweep": {"design": "lhs", "n": 4}, "motion": {"speed": [0.1, 0.2]}},
        r"\[motion\] speed: a list of values is for grids",
    ),
    (
        {
            "sweep": {"design": "lhs", "n": 4},
            "motion": {"speed": {"low": 0.1, "high": 0.2, "num": 3}},
        },
        r"\[motion\] speed: num is for grids",
    ),
]


@pytest.mark.parametrize(("sections", "message"), BAD)
def test_bad_spec_is_a_clear_error_naming_the_key(sections, message):
    data = {"foot": {"kind": "flat"}, **sections}
    with pytest.raises(MudrftError, match=message):
        load_spec(data)


def test_a_mesh_foot_takes_its_files_up_axis(tmp_path):
    # a y-up export (Blender's OBJ default) could be stood up on the command line (--up)
    # and in Python (up=), not in a sweep spec: [foot] up takes the file's up axis
    import trimesh

    from mudrft.feet import MeshFoot, SemiSphere
    from mudrft.feet.mesh import UP_AXES

    dome = SemiSphere().to_mesh(resolution=6)
    lying = trimesh.Trimesh(
        dome.vertices @ np.array(UP_AXES["y"], float), dome.faces, process=False
    )
    lying.export(tmp_path / "y.stl", file_type="stl_ascii")
    toml = tmp_path / "spec.toml"
    toml.write_text('[foot]\nkind = "y.stl"\nup = "y"\n[motion]\nspeed = [0.1, 0.2]\n')
    stood = load_spec(toml).mesh
    upright = MeshFoot.from_file(tmp_path / "y.stl", up="y")
    np.testing.assert_allclose(stood.vertices, upright.vertices, atol=1e-15)
    assert stood.height == pytest.approx(dome.height, abs=1e-12)
    lying = load_spec({"foot": {"kind": str(tmp_path / "y.stl")}}).mesh
    assert lying.height > 2 * dome.height  # the dome on its side
    for up, shown in (("Y", "'Y'"), (1, "1")):
        with pytest.raises(
            MudrftError,
            match=r"\[foot\] up must be the mesh file's up axis, a string, one of \"z\", "
            rf"\"-z\", .*\(y for a y-up export\), got {shown}",
        ):
            load_spec({"foot": {"kind": str(tmp_path / "y.stl"), "up": up}})
    with pytest.raises(MudrftError, match=r"\[foot\] radius: a mesh foot has no parameters \(only unit and up\)"):  # fmt: skip
        load_spec({"foot": {"kind": str(tmp_path / "y.stl"), "up": "y", "radius": 0.04}})


def test_bad_files_are_clear_errors(tmp_path):
    with pytest.raises(MudrftError, match="no such file"):
        load_spec(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[foot\nkind = 1\n")
    with pytest.raises(MudrftError, match="is not valid TOML"):
        load_spec(bad)
    with pytest.raises(MudrftError, match="spec must be a TOML file path, a dict"):
        load_spec(42)  # type: ignore[arg-type]


# Ranges: a value the library refuses at every point is refused with the spec (it ran, and
# every point failed); each bound is the catalog entry's, named with the key and the value.
RANGE = [
    ({"motion": {"dt": 0}}, r"\[motion\] dt must be > 0 \[s\], got 0"),
    ({"motion": {"speed": 0}}, r"\[motion\] speed must be > 0 \[m/s\], got 0"),
    ({"foot": {"kind": "flat", "width": -0.05}}, r"\[foot\] width must be > 0 \[m\], got -0.05"),
    (
        {"foot": {"kind": "flat", "width": [0.05, -0.01]}},
        r"\[foot\] width must be > 0 \[m\], got -0.01",
    ),
    (
        {"foot": {"kind": "flat", "width": {"low": -0.01, "high": 0.05, "num": 3}}},
        r"\[foot\] width low must be > 0 \[m\], got -0.01",
    ),
    (
        {"mud": {"water_content": [0.25, 0.6]}},
        r"\[mud\] water_content must be <= 0.5 \[-\], got 0.6",
    ),
    ({"mud": {"sigma_y_scale": 0.0}}, r"\[mud\] sigma_y_scale must be > 0 "),
    ({"mud": {"xi0": 1.5}}, r"\[mud\] xi0 must be <= 1"),
    ({"motion": {"slip": -0.1}}, r"\[motion\] slip must be >= 0"),
    (
        {"foot": {"kind": "morphing", "n_pads": [0, 4]}},
        r"\[foot\] n_pads must be >= 1 \[-\], got 0",
    ),
    ({"motion": {"kind": "load", "weight": -1.0}}, r"\[motion\] weight must be > 0 \[N\]"),
]


@pytest.mark.parametrize(("sections", "message"), RANGE)
def test_a_value_out_of_range_is_refused_naming_the_key_and_value(sections, message):
    with pytest.raises(MudrftError, match=message):
        load_spec({"foot": {"kind": "flat"}, **sections})


def test_a_walk_may_stand_still_where_a_gait_may_not():
    # speed > 0 for a gait, >= 0 for the walk's command: the motion's own entry decides
    assert load_spec({"foot": {"kind": "flat"}, "motion": {"kind": "walk", "speed": 0.0}}).fixed["speed"] == 0.0  # fmt: skip
    with pytest.raises(MudrftError, match=r"\[motion\] speed must be > 0"):
        load_spec({"foot": {"kind": "flat"}, "motion": {"speed": 0.0}})


def _outside(p):
    if p.gt is not None:
        return p.gt
    if p.ge is not None:
        return p.ge - (1 if p.kind == "int" else 1e-3)
    return None


def test_every_catalog_bound_is_one_the_library_enforces():
    """A value just outside a catalog bound fails where the library builds the point too, so
    the spec refuses nothing the library would run (walk: tests/integrations)."""
    import mudrft
    from mudrft.sweep.catalog import FOOT_KINDS, MOTIONS, PARAMETERS
    from mudrft.sweep.evaluate import build_foot, build_mud

    checked = 0
    for p in PARAMETERS.values():
        for bad in (_outside(p), None if p.le is None else p.le + 0.1):
            if bad is None or p.section == "motion":
                continue
            with pytest.raises(MudrftError):
                if p.section == "foot":
                    kind = next(k for k, names in FOOT_KINDS.items() if p.name in names)
                    build_foot({"foot": kind, p.name: bad})
                else:
                    build_mud({"water_content": 0.25, "extrapolate": True, p.name: bad})
            checked += 1
    for kind, make in (("gait", mudrft.gait), ("load", lambda **kw: mudrft.LoadControl(**{"weight": 10.0, **kw}))):  # fmt: skip
        for p in MOTIONS[kind].values():
            for bad in (_outside(p), None if p.le is None else p.le + 0.1):
                if bad is not None:
                    with pytest.raises(MudrftError):
                        make(**{p.name: bad})
                    checked += 1
    assert checked >= 45
