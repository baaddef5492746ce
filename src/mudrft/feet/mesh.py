r"""A foot of any shape, given as a triangle mesh: the element rule of
:mod:`mudrft.feet.surface` integrated over it, each facet clipped exactly by the mud surface.
"""

from __future__ import annotations

import functools
import math
import os
import warnings

import numpy as np

from .._typing import ArrayLike, FloatArray, RotationLike
from .._validation import (
    PLAUSIBLE_FOOT_SIZE,
    MudrftError,
    check_finite,
    check_memory,
    check_nonnegative,
    warn_implausible,
)
from ..units import SCALE, parse_unit
from .base import (  # fmt: skip
    CHUNK,
    Foot,
    SurfaceElements,
    batch_shape,
    check_depth_stress,
    check_resultant_inputs,
    in_chunks,
    projection_weights,
)
from .meshfile import FORMATS, SIMPLIFY, read_mesh, weld
from .meshparts import overlapping_parts
from .surface import (
    PreparedTriangles,
    Wrench,
    integrate_prepared,
    integrate_wrench,
    prepare_triangles,
    submerged_area,
)

__all__ = ["CHUNK", "MeshFoot", "MeshWarning"]

#: Memory a mesh foot takes while it is built, per facet [bytes].
BYTES_PER_FACET = 512

#: Rotations that turn a file's up axis to +z (proper rotations; ``from_file(up=)``).
UP_AXES = {
    "z": ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
    "-z": ((1, 0, 0), (0, -1, 0), (0, 0, -1)),
    "y": ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    "-y": ((1, 0, 0), (0, 0, 1), (0, -1, 0)),
    "x": ((0, 0, -1), (0, 1, 0), (1, 0, 0)),
    "-x": ((0, 0, 1), (0, 1, 0), (-1, 0, 0)),
}


class MeshWarning(UserWarning):
    """A mesh was accepted with a change or a caveat (dropped facets, open surface)."""


def _rotation_matrix(rotation: RotationLike) -> FloatArray:
    """A (3, 3) rotation matrix from a scipy Rotation or a proper orthonormal matrix."""
    if hasattr(rotation, "as_matrix") and callable(rotation.as_matrix):
        m = np.asarray(rotation.as_matrix(), dtype=float)
        if m.shape != (3, 3):
            raise MudrftError(f"rotation must be a single rotation, got a stack of shape {m.shape}")
        return m
    m = check_finite("rotation", rotation)
    if m.shape != (3, 3):
        raise MudrftError(f"rotation must be a 3x3 matrix or a scipy Rotation, got shape {m.shape}")
    err = float(np.abs(m @ m.T - np.eye(3)).max())
    if err > 1e-6 or np.linalg.det(m) < 0:
        raise MudrftError(
            "rotation must be a proper rotation (orthonormal, determinant +1), got a matrix with "
            f"|R R^T - I| = {err:.2g} and determinant {np.linalg.det(m):.3g}"
        )
    return m


def _check_faces(faces: ArrayLike, n_vertices: int) -> np.ndarray:
    if isinstance(faces, str):
        raise MudrftError(
            f"faces must be an integer array of shape (m, 3), got the string {faces!r}"
        )
    try:
        f = np.asarray(faces)
    except (TypeError, ValueError) as exc:
        raise MudrftError(
            f"faces must be an integer array of shape (m, 3), got {type(faces).__name__}"
        ) from exc
    if f.ndim != 2 or f.shape[1] != 3:
        hint = " (quads or polygons: triangulate them first)" if f.ndim == 2 else ""
        raise MudrftError(f"faces must have shape (m, 3){hint}, got shape {f.shape}")
    if f.shape[0] == 0:
        raise MudrftError("faces must contain at least one triangle, got an empty array")
    if not np.issubdtype(f.dtype, np.integer):
        ok = np.issubdtype(f.dtype, np.floating) and np.all(np.isfinite(f))
        if not (ok and np.all(f == np.round(f))):
            raise MudrftError(f"faces must hold integer vertex indices, got dtype {f.dtype}")
        f = f.astype(np.int64)
    bad = (f < 0) | (f >= n_vertices)
    if np.any(bad):
        i = int(np.argmax(bad.any(axis=1)))
        raise MudrftError(
            f"faces must index vertices in [0, {n_vertices - 1}], but face {i} is {f[i].tolist()}"
        )
    return f.astype(np.int64)


def _topology(vertices: np.ndarray, faces: np.ndarray) -> tuple[bool, int, np.ndarray]:
    """``(closed, n_inconsistent, weld)``: whether the mesh is a closed 2-manifold, the
    count of mis-wound edges, and each vertex's index among the distinct coordinates."""
    welded = weld(vertices)[1]
    f = welded[faces]
    # facets with a repeated vertex are no surface (dropped later); leave them out here
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])]
    start = np.concatenate([f[:, 0], f[:, 1], f[:, 2]]).astype(np.int64)
    end = np.concatenate([f[:, 1], f[:, 2], f[:, 0]]).astype(np.int64)
    n = int(welded.max(initial=0)) + 1  # an edge as one integer key: sorted 10x faster
    dcount = np.unique(start * n + end, return_counts=True)[1]
    ucount = np.unique(np.minimum(start, end) * n + np.maximum(start, end), return_counts=True)[1]
    closed = bool(ucount.size > 0 and np.all(ucount == 2))
    return closed, int(np.sum(dcount > 1)), welded


class MeshFoot(Foot):
    r"""A foot given by a triangle mesh (decision D25): zero-area facets are dropped and an open
    mesh is accepted (a :class:`MeshWarning` each), a closed mesh wound inward is flipped.

    Parameters
    ----------
    vertices : array_like, shape (n, 3)
        Vertex coordinates [m] (z up), translated to put the lowest point at the origin.
    faces : array_like, shape (m, 3)
        Vertex indices of each triangle, wound outward (right-hand rule).
    trailing : bool, optional
        Let facets that trail the horizontal motion resist too (as the semi-sphere's closed
        form does; D23).
    name : str, optional
        Name used in reports.

    Attributes
    ----------
    vertices, faces, triangles : ndarray
        Vertices in the foot frame [m]; faces after dropping zero-area facets and flipping;
        their triangles, shape (m, 3, 3) [m].
    shift : ndarray (3,)
        Translation added to the given vertices [m].
    closed, flipped, dropped : bool, bool, int
        Whether the mesh is a closed 2-manifold, whether its winding was reversed, and the
        number of zero-area facets dropped.

    Examples
    --------
    >>> import warnings
    >>> v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     plate = MeshFoot(v, [[0, 2, 1], [0, 3, 2]])
    >>> plate.resultant(0.01, [0.0, 0.0, 2.0], 0.0).tolist()
    [0.0, 0.0, 2.0]
    """

    def __init__(
        self, vertices: ArrayLike, faces: ArrayLike, *, trailing: bool = False, name: str = "mesh"
    ) -> None:
        if np.iscomplexobj(vertices):
            raise MudrftError(
                "vertices must be real coordinates [m], got complex numbers (dtype "
                f"{np.asarray(vertices).dtype})"
            )
        v = check_finite("vertices", vertices)
        if v.ndim != 2 or v.shape[1] != 3 or v.shape[0] < 3:
            raise MudrftError(f"vertices must have shape (n, 3) with n >= 3, got shape {v.shape}")
        f = _check_faces(faces, v.shape[0])
        check_memory(
            f"a mesh foot of {f.shape[0]} facets", f.shape[0] * BYTES_PER_FACET, hint=SIMPLIFY
        )
        if not isinstance(trailing, bool | np.bool_):
            raise MudrftError(f"trailing must be True or False, got {trailing!r}")
        self.name, self.trailing = str(name), bool(trailing)
        vu = v[np.unique(f)]
        extent = vu.max(0) - vu.min(0)
        diag = float(np.linalg.norm(extent))
        if diag == 0.0:
            raise MudrftError("vertices must not all coincide: the mesh is degenerate (zero size)")
        hint = (
            "if its coordinates are not in metres, state their unit: MeshFoot.from_file(path, "
            "unit='mm') (CLI: --unit {m,mm,cm,in}), or scale the vertices to metres"
        )
        what = f"MeshFoot {self.name!r}: the mesh is"
        warn_implausible(what, float(extent.max()), PLAUSIBLE_FOOT_SIZE, unit="m across", hint=hint)
        closed, wrong, weld = _topology(v, f)
        if wrong:
            raise MudrftError(
                f"faces must be consistently wound, but {wrong} edge(s) are traversed twice in the "
                "same direction; fix the mesh (e.g. trimesh.repair.fix_normals) and retry"
            )
        tri = v[f]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        zero = area <= 1e-14 * diag**2
        if np.all(zero):
            raise MudrftError("the mesh has no non-degenerate facet: every facet has zero area")
        self.dropped = int(zero.sum())
        if self.dropped:
            warnings.warn(
                f"MeshFoot: dropped {self.dropped} zero-area facet(s)", MeshWarning, stacklevel=2
            )
            f = f[~zero]
        self.closed, self.flipped = closed, False
        if closed:  # wound inward when the signed volume is negative
            tri = v[f]
            self.flipped = bool(np.sum(tri[:, 0] * np.cross(tri[:, 1], tri[:, 2])) < 0)
            if self.flipped:
                f = f[:, ::-1].copy()
            hit = overlapping_parts(v, f, weld=weld)
            if hit is not None:
                warnings.warn(
                    f"MeshFoot {self.name!r}: the mesh is {hit.parts} separate closed parts, and "
                    f"the vertex ({', '.join(f'{c:.4g}' for c in hit.point)}) m of part "
                    f"{hit.inner} lies inside or on part {hit.outer}: the facets where parts "
                    "overlap or touch count as if mud reached them, so the forces come out too "
                    "large. Merge the parts into one surface (a boolean union in CAD, or "
                    "trimesh.boolean.union) before loading",
                    MeshWarning,
                    stacklevel=2,
                )
        self._set_geometry(v, f)
        self._check_plan_area(
            "If the mesh is open, its normals may point inward (the winding of an open mesh "
            "is taken as given): reverse it (faces[:, ::-1]) or close the mesh"
        )
        if not closed:
            warnings.warn(
                "MeshFoot: the mesh is open (or non-manifold); its winding is taken as given, so "
                "make sure the normals of the surface in contact point outward",
                MeshWarning,
                stacklevel=2,
            )

    def _check_plan_area(self, hint: str) -> None:
        total = float(np.sum(self._prep.area))
        if not (self._plan_area > 1e-12 * total and self.characteristic_length > 0):
            raise MudrftError(
                f"MeshFoot {self.name!r}: the mesh must have a bottom, an area that faces "
                f"down and meets the mud as the foot goes in, but its downward-facing plan "
                f"area is {self._plan_area:.3g} m^2 (of {total:.3g} m^2 in all), so its "
                f"characteristic length is {self.characteristic_length:.3g} m. {hint}"
            )

    def _set_geometry(self, v: np.ndarray, f: np.ndarray) -> None:
        used = np.unique(f)
        vu = v[used]
        diag = float(np.linalg.norm(vu.max(0) - vu.min(0)))
        zmin = float(vu[:, 2].min())
        low = vu[vu[:, 2] <= zmin + 1e-9 * diag]
        tip = np.array([low[:, 0].mean(), low[:, 1].mean(), zmin])
        self.shift = -tip
        self.vertices = v + self.shift
        self.faces = f
        self.triangles = self.vertices[f]
        self._prep: PreparedTriangles = prepare_triangles(self.triangles)
        self._height = float(self.vertices[used, 2].max())
        n, a = self._prep.normal, self._prep.area
        self._plan_area = float(np.sum(a * np.clip(-n[:, 2], 0.0, None)))

    @classmethod
    def from_file(
        cls, path: str | os.PathLike[str], *, unit: str = "m", trailing: bool = False,
        name: str | None = None, up: str = "z",
    ) -> MeshFoot:  # fmt: skip
        """Read a mesh file: STL (ASCII or binary), OBJ or PLY, through trimesh.

        Parameters
        ----------
        path : str or path-like
            File to read (never modified).
        unit : str, optional
            Length unit of the file's coordinates (``"m"``, ``"cm"``, ``"mm"``, ``"um"``,
            ``"in"``); a mesh more than 1 m or less than 1 mm across warns.
        trailing : bool, optional
            See :class:`MeshFoot`.
        name : str, optional
            Name (default: the file name without extension).
        up : {"z", "y", "x", "-z", "-y", "-x"}, optional
            The file's axis that points up, turned to +z (a Y-up export: ``"y"``).

        Examples
        --------
        >>> import mudrft
        >>> foot = MeshFoot.from_file(mudrft.data_path("foot.stl"), unit="mm")
        >>> foot.name, round(foot.height, 3)
        ('foot', 0.026)
        """
        if not isinstance(path, str | os.PathLike):
            raise MudrftError(
                f"path must be the path of a mesh file (a str or path-like ending in "
                f"{'/'.join(FORMATS)}), got {path!r}"
            )
        if not isinstance(unit, str):
            raise MudrftError(
                "unit must be the length unit of the file's coordinates as a string such as "
                f"'m' or 'mm' (one of {sorted(SCALE['length'])}), got {unit!r} "
                f"({type(unit).__name__})"
            )
        scale = parse_unit("length", unit)
        if not isinstance(trailing, bool | np.bool_):  # before reading a file that may be large
            raise MudrftError(f"trailing must be True or False, got {trailing!r}")
        if not isinstance(up, str) or up not in UP_AXES:
            raise MudrftError(f"up must be the file's up axis, one of {list(UP_AXES)}, got {up!r}")
        p = os.fspath(path)
        if os.path.splitext(p)[1].lower() not in FORMATS:
            raise MudrftError(f"path must end in one of {list(FORMATS)}, got {p!r}")
        if os.path.isdir(p):
            raise MudrftError(f"path must be a mesh file, got {p!r}, which is a directory")
        if not os.path.isfile(p):
            raise MudrftError(f"path must be an existing mesh file, got {p!r} (no such file)")
        v, f = read_mesh(p)
        nm = name if name is not None else os.path.splitext(os.path.basename(p))[0]
        try:
            if v.shape[0] < 3:
                raise MudrftError(
                    f"the mesh has no non-degenerate facet: its {f.shape[0]} facet(s) have "
                    f"{v.shape[0]} distinct vertex position(s) in all, so every facet has zero "
                    "area"
                )
            v = v * scale if up == "z" else (v * scale) @ np.array(UP_AXES[up], float).T
            return cls(v, f, trailing=trailing, name=nm)
        except MudrftError as exc:
            raise MudrftError(f"the mesh file {p!r}: {exc}") from exc

    def posed(self, rotation: RotationLike) -> MeshFoot:
        """A copy rotated by ``rotation`` (3x3 matrix or scipy Rotation), tip at its lowest point.

        >>> from mudrft.feet import Flat
        >>> tilted = Flat().to_mesh(resolution=2).posed([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
        >>> round(tilted.height, 3)  # the 80 mm length now stands vertical
        0.08
        """
        r = _rotation_matrix(rotation)
        new = object.__new__(type(self))
        new.__dict__.update({k: v for k, v in self.__dict__.items() if not k.startswith("_")})
        new._set_geometry(self.vertices @ r.T, self.faces)
        new._check_plan_area(
            "The rotation leaves no facet facing down (an open or flat mesh turned on edge "
            "or upside down)"
        )
        return new

    @property
    def height(self) -> float:
        """Height of the mesh above its tip [m]."""
        return self._height

    @property
    def characteristic_length(self) -> float:
        """:math:`L_c=\\sqrt{A_z}` [m], :math:`A_z` the downward-facing plan area (D27)."""
        return math.sqrt(self._plan_area)

    def __len__(self) -> int:
        return int(self.faces.shape[0])

    def elements(self) -> SurfaceElements:
        """Centroid, outward unit normal and area of every facet in the foot frame."""
        t = self.triangles
        return SurfaceElements(t.mean(axis=1), self._prep.normal.copy(), self._prep.area.copy())

    def force_unchecked(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> FloatArray:
        """:meth:`Foot.force` without validation [N]; any heading, no folding; in chunks of
        about :data:`CHUNK` facet evaluations."""
        d, s, h = np.asarray(depth), np.asarray(stress), np.asarray(heading)
        block = functools.partial(integrate_prepared, self._prep, trailing=self.trailing)
        shape = np.broadcast_shapes(d.shape, s.shape[:-1], h.shape)
        if math.prod(shape) <= max(1, CHUNK // len(self)):
            return block(d, s, h)
        return in_chunks(block, len(self), *_flat_rows(shape, d, s, h)).reshape((*shape, 3))

    def resultant(self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike) -> FloatArray:
        """Paper-style magnitudes ``(-Fx, -Fy, Fz)`` [N] of the integrated force, heading in
        [0, pi/2] (an asymmetric foot may give a negative one)."""
        d, s, h = check_resultant_inputs(depth, stress, heading, height=self.height)
        f = self.force_unchecked(d, s, h)
        return f * np.array([-1.0, -1.0, 1.0]) + 0.0  # + 0.0 turns -0.0 into 0.0

    def wrench(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike, *,
        point: ArrayLike | None = None,
    ) -> Wrench:  # fmt: skip
        """Force [N], moment about ``point`` [m] (default the tip) [N m] and center of pressure
        [m], foot frame (:func:`mudrft.feet.surface.integrate_wrench`)."""
        d, s = check_depth_stress(depth, stress, height=self.height)
        h = check_finite("heading", heading)
        pt = np.zeros(3) if point is None else check_finite("point", point)
        if pt.shape[-1:] != (3,):
            raise MudrftError(f"point must have shape (..., 3) [m], got shape {pt.shape}")
        shape = batch_shape(d, s, h, point=pt.shape[:-1])

        def block(dd: np.ndarray, ss: np.ndarray, hh: np.ndarray, pp: np.ndarray) -> Wrench:
            return integrate_wrench(
                None, dd, ss, hh, point=pp, trailing=self.trailing, prepared=self._prep
            )

        if not shape:
            return block(d, s, h, pt)
        w = in_chunks(block, len(self), *_flat_rows(shape, d, s, h, pt))
        return type(w)(*(np.asarray(a).reshape((*shape, 3)) for a in w))

    def center_of_pressure(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> FloatArray:
        """Center of pressure in the foot frame [m], shape (..., 3) (decision D24), for any
        heading [rad]; the stresses [Pa] as in :meth:`force`."""
        return np.asarray(self.wrench(depth, stress, heading).center_of_pressure)

    def projected_areas(self, depth: ArrayLike) -> FloatArray:
        r"""Submerged areas projected along x, y and z [m^2] (..., 3): :math:`\tfrac12\sum|n_x|dS`,
        :math:`\tfrac12\sum|n_y|dS` and :math:`\sum\max(-n_z,0)dS` over the clipped facets."""
        d = check_nonnegative("depth", depth, unit="m")
        p, weights = self._prep, projection_weights(self._prep.normal)
        wetted = in_chunks(lambda dd: submerged_area(p, dd) @ weights, len(self), d.reshape(-1))
        return np.asarray(wetted).reshape((*d.shape, 3))

    def __repr__(self) -> str:
        return (
            f"MeshFoot(name={self.name!r}, facets={len(self)}, height={self.height:.4g} m, "
            f"closed={self.closed}, trailing={self.trailing})"
        )


def _flat_rows(shape: tuple[int, ...], *arrays: np.ndarray) -> list[np.ndarray]:
    """``depth, stress, heading[, point]`` broadcast to the batch ``shape`` and flattened to
    rows: depth and heading of shape (n,), stress and point of shape (n, 3)."""
    vector = (False, True, False, True)
    return [
        np.broadcast_to(a, (*shape, 3) if vec else shape).reshape((-1, 3) if vec else (-1,))
        for a, vec in zip(arrays, vector, strict=False)
    ]
