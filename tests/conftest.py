"""Shared test fixtures."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")

REPO = Path(__file__).resolve().parents[1]
PAPER = REPO.parent / "shared" / "paper" / "foot-mud-resistive-force-model.tex"


@pytest.fixture
def paper_tex() -> str:
    """The paper's LaTeX source (CI has shared/ beside the clone); skip if absent."""
    if not PAPER.exists():
        pytest.skip("the paper source ../shared/paper is not available")
    return PAPER.read_text()
