"""A mesh of separate closed parts that overlap (a sole and cleats exported unmerged) warns
(decision D136); the winding number behind the check against values known by hand."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from mudrft.feet import MeshFoot, MeshWarning
from mudrft.feet.meshgen import box_mesh, semisphere_mesh
from mudrft.feet.meshparts import overlapping_parts, winding_numbers


def sole() -> tuple[np.ndarray, np.ndarray]:
    return box_mesh(0.06, 0.04, 0.01)  # x in +-0.02, y in +-0.03, z in [0, 0.01] m


def cleat(z0: float, z1: float, dx: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    v, f = box_mesh(0.01, 0.01, z1 - z0)
    return v + np.array([dx, 0.0, z0]), f


def joined(*parts: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
    return (
        np.vstack([v for v, _ in parts]),
        np.vstack([f + o for (_, f), o in zip(parts, offsets, strict=True)]),
    )


def test_winding_number_is_one_inside_half_on_a_face_and_zero_outside():
    v, f = sole()
    points = np.array(
        [
            [0.0, 0.0, 0.005],  # centre
            [0.019, 0.029, 0.009],  # near a corner, inside
            [0.005, -0.01, 0.0],  # on the bottom face
            [0.0, 0.0, 0.0],  # on the bottom face's diagonal, an edge of two facets
            [0.02, 0.0, 0.005],  # on a side face
            [0.0, 0.0, -0.001],  # just below
            [0.5, 0.3, 0.2],  # far away
        ]
    )
    np.testing.assert_allclose(
        winding_numbers(points, v[f]), [1.0, 1.0, 0.5, 0.5, 0.5, 0.0, 0.0], atol=1e-12
    )
    # wound inward, the number is negative: the check takes its magnitude
    np.testing.assert_allclose(winding_numbers(points[:1], v[f[:, ::-1]]), [-1.0], atol=1e-12)


@pytest.mark.parametrize(
    ("z0", "z1", "why"),
    [
        (-0.008, 0.002, "pushed 2 mm into the sole"),
        (-0.008, 0.0, "standing on the sole's bottom"),
        (0.002, 0.008, "a copy inside the sole"),
    ],
)
def test_a_cleat_that_overlaps_or_touches_the_sole_warns_and_names_a_vertex(z0, z1, why):
    v, f = joined(sole(), cleat(z0, z1))
    hit = overlapping_parts(v, f)
    assert hit is not None, why
    assert (hit.parts, hit.inner, hit.outer) == (2, 2, 1)
    with pytest.warns(MeshWarning, match=r"2 separate closed parts.*part 2 lies inside or on"):
        MeshFoot(v, f, name="cleated")


def test_parts_apart_and_one_part_meshes_stay_quiet():
    for v, f in (
        sole(),
        joined(sole(), cleat(0.0, 0.01, dx=0.04)),  # beside the sole, 15 mm away
        semisphere_mesh(0.045, 0.026, resolution=16),
    ):
        assert overlapping_parts(v, f) is None
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            MeshFoot(v, f)


def test_the_facets_inside_another_part_change_the_force():
    """Why it warns: a copy of a box inside the sole is invisible to mud, but its facets
    are integrated as if mud reached them (the element rule cannot tell)."""
    stress = np.array([1e3, 0.0, 1e4])
    with pytest.warns(MeshWarning):
        doubled = MeshFoot(*joined(sole(), cleat(0.002, 0.008)))
    alone = MeshFoot(*sole())
    a, b = alone.resultant(0.009, stress, 0.0), doubled.resultant(0.009, stress, 0.0)
    assert not np.allclose(a, b, rtol=1e-3)
