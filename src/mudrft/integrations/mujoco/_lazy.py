"""MuJoCo, imported on first use: importing mudrft never needs the ``mujoco`` extra."""

from __future__ import annotations

from types import ModuleType


def _mujoco() -> ModuleType:
    """Import MuJoCo lazily with a helpful message."""
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError("the MuJoCo coupling needs mujoco: pip install 'mudrft[mujoco]'") from exc
    return mujoco
