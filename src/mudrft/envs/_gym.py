"""Gymnasium, imported by the environments (optional extra ``rl``)."""

from __future__ import annotations

try:
    import gymnasium
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise ImportError("the mudrft environments need gymnasium: pip install 'mudrft[rl]'") from exc

__all__ = ["gymnasium"]
