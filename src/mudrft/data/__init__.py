"""Files shipped with mudrft: the synthetic calibration logs and an example foot mesh.

``foot.stl`` is the semi-spherical foot of the paper (radius 45 mm, height 26 mm) as a
closed binary STL of 288 facets in millimetres, made by
``SemiSphere().to_mesh(resolution=6)``; the calibration logs are described in
:mod:`mudrft.calibration.synthetic`.
"""

from __future__ import annotations

from pathlib import Path

from .._validation import MudrftError

__all__ = ["data_path"]


def data_path(name: str) -> Path:
    """The path of a file shipped with mudrft.

    Parameters
    ----------
    name : str
        The file's name, such as ``"foot.stl"``.

    Examples
    --------
    >>> data_path("foot.stl").name
    'foot.stl'
    """
    here = Path(__file__).parent
    shipped = sorted(p.name for p in here.iterdir() if p.suffix in (".csv", ".stl"))
    if name not in shipped:
        raise MudrftError(
            f"name must be a file shipped with mudrft, one of {shipped}, got {name!r}"
        )
    return here / name
