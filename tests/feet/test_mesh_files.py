"""Mesh files against a fuzz: truncated and malformed STL, inward open meshes, units, memory.

Each test fails on the behaviour before the fix: a half ASCII STL read as half a foot, quad
facets split into wrong triangles, a foot with no bottom that crashed later with a
ZeroDivisionError, ``unit=1`` an AttributeError, an ASCII STL parsed whole before its memory
was checked, and messages that did not name the file.
"""

from __future__ import annotations

import numpy as np
import pytest

from mudrft._validation import MudrftError
from mudrft.feet import Flat, MeshFoot, MeshWarning
from mudrft.feet.stl import write_stl
from mudrft.sweep.spec import load_spec
from mudrft.units import parse_unit

#: A downward-facing sole (80 x 65 mm): faces [0, 2, 1], [0, 3, 2] point down.
SOLE = [[0, 0, 0], [0.065, 0, 0], [0.065, 0.08, 0], [0, 0.08, 0]]


def facet_text(tri, *, vertices: int = 3) -> str:
    """One ASCII STL facet with its first ``vertices`` corners (cycling for more than 3)."""
    corners = [np.asarray(tri).tolist()[k % 3] for k in range(vertices)]
    rows = "".join(f"vertex {x!r} {y!r} {z!r}\n" for x, y, z in corners)
    return f"facet normal 0 0 0\nouter loop\n{rows}endloop\nendfacet\n"


@pytest.fixture
def box_text() -> str:
    """The paper's flat foot (12 facets) as ASCII STL text."""
    tri = Flat().to_mesh(resolution=1).triangles
    return "solid box\n" + "".join(facet_text(t) for t in tri) + "endsolid box\n"


def boundary(path, match: str) -> None:
    with pytest.raises(MudrftError, match=match) as info:
        MeshFoot.from_file(path)
    assert str(path) in str(info.value), f"the message does not name the file: {info.value}"


# -- 2. an open mesh whose normals point inward ----------------------------------------------
def test_a_mesh_with_no_downward_facing_area_is_refused():
    with pytest.raises(MudrftError, match=r"plan area is 0 m\^2.*normals may point inward"):
        MeshFoot(SOLE, [[0, 1, 2], [0, 2, 3]])  # the sole wound upward: no bottom
    with pytest.warns(MeshWarning, match="open"):
        plate = MeshFoot(SOLE, [[0, 2, 1], [0, 3, 2]])  # wound downward: a valid plate
    assert plate.characteristic_length == pytest.approx(np.sqrt(0.065 * 0.08))
    with pytest.raises(MudrftError, match="no facet facing down"):
        plate.posed([[1, 0, 0], [0, 0, -1], [0, 1, 0]])  # turned on edge: no bottom left


# -- 3. units and paths that are not strings -------------------------------------------------
@pytest.mark.parametrize("unit", [None, 1e-3, 1, True])
def test_a_unit_that_is_not_a_string_is_named(tmp_path, unit):
    path = tmp_path / "foot.stl"
    write_stl(path, Flat().to_mesh(resolution=1).triangles)
    with pytest.raises(MudrftError, match=r"unit must be .* such as 'm' or 'mm'"):
        MeshFoot.from_file(path, unit=unit)
    with pytest.raises(MudrftError, match=r"unit for length must be a unit string"):
        parse_unit("length", unit)
    with pytest.raises(MudrftError, match=r'\[foot\] unit must be .* such as "m" or "mm"'):
        load_spec({"foot": {"kind": str(path), "unit": unit}})


@pytest.mark.parametrize("path", [None, 3, b"foot.stl"])
def test_a_path_that_is_not_a_path_is_named(path):
    with pytest.raises(MudrftError, match="path must be the path of a mesh file"):
        MeshFoot.from_file(path)
