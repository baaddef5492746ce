"""Feet and meshes against hostile inputs (issue 15): sizes, units, memory.

Each test fails on the behaviour before the fix (sizes of 1e30 m and ``True`` accepted, a
mm STL read silently as an 80 m foot, no ``--unit``, memory growing with samples x facets).
"""

from __future__ import annotations

import dataclasses
import tracemalloc
import warnings

import numpy as np
import pytest

from mudrft._validation import MudrftError, PlausibilityWarning
from mudrft.cli import main
from mudrft.feet import Flat, MeshFoot, SemiCylinder, SemiSphere, by_name
from mudrft.feet.base import Foot


def write_stl(path, triangles) -> None:
    """Triangles (m, 3, 3) as a binary STL file, written by trimesh."""
    import trimesh

    tri = np.asarray(triangles, dtype=float)
    faces = np.arange(3 * len(tri)).reshape(-1, 3)
    trimesh.Trimesh(tri.reshape(-1, 3), faces, process=False).export(path, file_type="stl")


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: Flat(length=True), "length must be a number, got the boolean True"),
        (lambda: SemiSphere(radius=np.True_), "radius must be a number, got the boolean"),
        (lambda: Flat(width=1e30), r"width must lie in \[1e-06, 100\] m"),
        (lambda: SemiCylinder(radius=float("inf")), "radius must be finite"),
        (lambda: Flat(height=1e-9), r"height must lie in \[1e-06, 100\] m"),
    ],
)
def test_absurd_foot_sizes_are_errors(make, match):
    with pytest.raises(MudrftError, match=match):
        make()


@pytest.mark.parametrize(
    ("cls", "name"),
    [(cls, f.name) for cls in (Flat, SemiCylinder, SemiSphere) for f in dataclasses.fields(cls)],
)
def test_every_dimension_of_a_closed_form_foot_is_checked_and_kept_as_a_float(cls, name):
    """One __post_init__ (the closed-form feet's base) checks each dataclass field [m]."""
    with pytest.raises(MudrftError, match=rf"^{name} must be > 0 m, got -0.01"):
        cls(**{name: -0.01})
    foot = cls(**{name: np.float32(getattr(cls(), name))})
    assert type(getattr(foot, name)) is float


def test_a_foot_larger_than_a_metre_warns_but_works():
    with pytest.warns(PlausibilityWarning, match=r"largest dimension, radius, is 2 m"):
        foot = SemiSphere(radius=2.0, height=0.026)
    assert foot.radius == 2.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        Flat(), SemiCylinder(), SemiSphere()  # the paper's feet are plausible


@pytest.fixture
def mm_stl(tmp_path):
    """The paper's flat foot written in millimetres, as CAD tools export it."""
    path = tmp_path / "foot.stl"
    write_stl(path, Flat().to_mesh(resolution=2).triangles * 1000.0)
    return path


def test_a_millimetre_stl_read_as_metres_warns_and_unit_fixes_it(mm_stl, tmp_path):
    with pytest.warns(PlausibilityWarning, match=r"80 m across.*unit='mm'"):
        MeshFoot.from_file(mm_stl)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        foot = MeshFoot.from_file(mm_stl, unit="mm")
        inches = tmp_path / "foot_in.stl"
        write_stl(inches, foot.triangles / 0.0254)
        assert MeshFoot.from_file(inches, unit="in").height == pytest.approx(0.026)
    assert foot.height == pytest.approx(0.026)
    with pytest.warns(PlausibilityWarning, match="less than 0.001"):
        MeshFoot(foot.vertices * 1e-3, foot.faces)


# the CLI shows the warning as a line: this test asks for it (pyproject makes it an error)
@pytest.mark.filterwarnings("default::mudrft._validation.PlausibilityWarning")
def test_cli_simulate_takes_the_unit_of_a_mesh_file(mm_stl, tmp_path, capsys):
    out = tmp_path / "run.csv"
    code = main(["simulate", "--foot", str(mm_stl), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 0 and "mudrft simulate: warning: MeshFoot" in err and "80 m across" in err
    code = main(["simulate", "--foot", str(mm_stl), "--unit", "mm", "--out", str(out), "--force"])
    err = capsys.readouterr().err
    assert code == 0 and "warning" not in err
    fz = np.loadtxt(out, delimiter=",", skiprows=1)[:, 6]
    assert 0 < fz.max() < 1e3  # an 80 mm foot, not an 80 m one
    with pytest.raises(MudrftError, match="mesh files only"):
        by_name("flat", unit="mm")


def test_a_mesh_beyond_the_memory_limit_is_refused_with_the_numbers(monkeypatch):
    v, f = Flat().to_mesh(resolution=2).vertices, Flat().to_mesh(resolution=2).faces
    monkeypatch.setenv("MUDRFT_MEMORY_LIMIT", "1000")
    with pytest.raises(MudrftError, match=r"48 facets would need about 24 KiB.*limit of 1e\+03 B"):
        MeshFoot(v, f)
    monkeypatch.setenv("MUDRFT_MEMORY_LIMIT", "lots")
    with pytest.raises(MudrftError, match="MUDRFT_MEMORY_LIMIT must be a number of bytes"):
        MeshFoot(v, f)


def test_mesh_feet_evaluate_many_samples_in_bounded_memory():
    """Samples x facets (512 x 1000 here; 18k x 6501 in the report) never sit in memory."""
    mesh = SemiSphere().to_mesh(resolution=8)
    depth = np.linspace(0.0, 0.03, 1000)
    stress = np.array([1e3, 2e3, 5e3])
    tracemalloc.start()
    try:
        areas = mesh.projected_areas(depth)
        wrench = mesh.wrench(depth, stress, 0.3)
        force = mesh.force(depth, stress, 0.3)
        generic = Foot.projected_areas(mesh, depth)  # the elements-based default
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 25e6, f"peak {peak / 1e6:.0f} MB grows with samples x facets"
    assert areas.shape == wrench.force.shape == generic.shape == (1000, 3)
    for k in (0, 777, 999):  # chunked batches equal one sample at a time
        np.testing.assert_allclose(areas[k], mesh.projected_areas(depth[k]), atol=1e-15)
        one = mesh.wrench(depth[k], stress, 0.3)
        np.testing.assert_allclose(wrench.moment[k], one.moment, atol=1e-12)
        np.testing.assert_allclose(force[k], wrench.force[k], atol=1e-9)


@pytest.mark.parametrize("name", ["flat", "semi-cylinder", "semi-sphere", "morphing", "mesh"])
def test_a_depth_in_millimetres_warns_on_every_foot(name):
    """foot.resultant(20, ...) meant 20 mm: the 26 mm foot buried under 20 m of mud gave a
    force without a word (D103). 1 m, and ten heights of a foot, do not warn."""
    foot = Flat().to_mesh(resolution=4) if name == "mesh" else by_name(name)
    stress = np.array([1e3, 1e3, 1e3])
    with pytest.warns(PlausibilityWarning, match=r"tip depth of 20 m, more than 1 m .*0\.02"):
        foot.resultant(20.0, stress, 0.3)
    with pytest.warns(PlausibilityWarning, match=r"tip depth of 20 m"):
        foot.force(np.array([0.01, 20.0]), stress, 0.3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        foot.resultant(np.array([0.0, 0.02, 1.0]), stress, 0.3)
        tall = Flat(length=0.3, width=0.3, height=0.3)  # 3 m is ten of its heights
        assert tall.resultant(3.0, stress, 0.0)[2] > 0
