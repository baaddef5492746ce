"""Reading OBJ and PLY mesh files through the optional ``trimesh`` (STL needs nothing
extra: :mod:`mudrft.feet.stl`). :meth:`mudrft.feet.mesh.MeshFoot.from_file` calls it after
the memory the parse takes is bounded (decision D102)."""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import numpy as np

from .._validation import MudrftError

if TYPE_CHECKING:
    import trimesh

__all__ = ["read_with_trimesh"]


def read_with_trimesh(path: str, ext: str) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) [file units] and faces (m, k) of the mesh file ``path`` (suffix
    ``ext``, ``.obj`` or ``.ply``), read with the optional trimesh; any failure is a
    :class:`~mudrft._validation.MudrftError` that names the file and, for PLY, what it needs.
    The caller bounds the memory first (:mod:`mudrft.feet.meshbound`)."""
    try:
        import trimesh
    except ImportError as exc:
        raise MudrftError(
            f"reading {ext} files needs the optional dependency trimesh; install it with "
            "`pip install 'mudrft[mesh]'` (or convert the mesh to STL, which needs nothing extra)"
        ) from exc
    try:
        # force="mesh": one Trimesh (a scene is concatenated), not a Scene
        mesh = cast("trimesh.Trimesh", trimesh.load(path, force="mesh", process=False))
        v = np.asarray(mesh.vertices, dtype=np.float64)
        f = np.asarray(mesh.faces)
    except Exception as exc:  # trimesh raises many exception types on bad files
        need = _PLY_NEEDS if ext == ".ply" else ""
        if isinstance(exc, KeyError) and exc.args:  # a property looked up by name: str(exc) is 'x'
            raise MudrftError(
                f"could not read the mesh file {path!r}: it lacks the property or element "
                f"{exc.args[0]!r}{need}"
            ) from exc
        raise MudrftError(
            f"could not read the mesh file {path!r}: {type(exc).__name__}: {exc}{need}"
        ) from exc
    if v.ndim != 2 or v.shape[0] == 0 or f.ndim != 2 or f.shape[0] == 0:
        raise MudrftError(f"the mesh file {path!r} contains no triangles")
    if not np.all(np.isfinite(v)):
        i = int(np.argmax(~np.isfinite(v).all(axis=1)))
        raise MudrftError(
            f"the mesh file {path!r} has NaN or infinite vertex coordinates (vertex {i}: "
            f"{v[i].tolist()})"
        )
    return v, f


_PLY_NEEDS = (
    " (a PLY mesh needs an element 'vertex' with the properties x, y and z, and an element "
    "'face' with the list property vertex_indices)"
)
