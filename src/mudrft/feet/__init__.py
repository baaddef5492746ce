"""Feet: closed-form feet of the paper, mesh feet of any shape, and the morphing foot.

>>> from mudrft.feet import Flat, SemiCylinder, SemiSphere
>>> [f.name for f in (Flat(), SemiCylinder(), SemiSphere())]
['flat', 'semi-cylinder', 'semi-sphere']
"""

from __future__ import annotations

import importlib
import os
from typing import Any

from .._validation import MudrftError
from .base import Foot, SurfaceElements, first_quadrant
from .mesh import MeshFoot, MeshWarning
from .shapes import Flat, SemiCylinder, SemiSphere

__all__ = [
    "Flat", "Foot", "MeshFoot", "MeshWarning", "MorphingFoot", "SemiCylinder", "SemiSphere",
    "SurfaceElements", "by_name", "first_quadrant"
]  # fmt: skip

#: Names accepted by :func:`by_name` (besides mesh file paths).
NAMES = ("flat", "semi-cylinder", "semi-sphere", "morphing")


def __getattr__(name: str) -> Any:  # the morphing foot loads on first use
    if name == "MorphingFoot":
        return importlib.import_module(".morphing", __name__).MorphingFoot
    raise AttributeError(f"module 'mudrft.feet' has no attribute {name!r}")


def by_name(
    name: str | os.PathLike[str], *, unit: str | None = None, trailing: bool | None = None,
    up: str | None = None,
) -> Foot:  # fmt: skip
    """The foot called ``name`` with the paper's dimensions, or a mesh foot read from a file.

    Parameters
    ----------
    name : str or path-like
        ``"flat"``, ``"semi-cylinder"``, ``"semi-sphere"``, ``"morphing"``, or a path ending
        in ``.stl``, ``.obj`` or ``.ply``.
    unit, trailing, up : keyword-only, mesh files only
        As :meth:`MeshFoot.from_file`: the file's length unit (default ``"m"``), whether
        trailing facets resist (default ``False``) and its up axis (default ``"z"``).

    Examples
    --------
    >>> by_name("semi-sphere")
    SemiSphere(radius=0.045, height=0.026)
    """
    is_path = isinstance(name, str) and name.lower().endswith((".stl", ".obj", ".ply"))
    if isinstance(name, os.PathLike) or is_path:
        if not os.path.exists(name):  # named as the foot (CLI: --foot), not the reader's path
            raise MudrftError(f"foot (CLI: --foot) {os.fspath(name)!r}: no such mesh file")
        unit, up = ("m" if unit is None else unit), ("z" if up is None else up)
        return MeshFoot.from_file(name, unit=unit, trailing=bool(trailing), up=up)
    for option, given, why in (
        ("unit", unit, "the named feet have the paper's dimensions in metres"),
        ("trailing", trailing, "the named feet's closed forms fix which facets resist (D23)"),
        ("up", up, "the named feet stand with z up"),
    ):
        if given is not None:
            raise MudrftError(
                f"{option} (CLI: --{option}) applies to mesh files only (.stl/.obj/.ply), but "
                f"foot is {name!r}; {why}"
            )
    closed = {"flat": Flat, "semi-cylinder": SemiCylinder, "semi-sphere": SemiSphere}
    if isinstance(name, str) and name in closed:
        return closed[name]()
    if name == "morphing":
        return __getattr__("MorphingFoot")()  # type: ignore[no-any-return]
    raise MudrftError(f"foot must be one of {list(NAMES)} or a .stl/.obj/.ply file, got {name!r}")
