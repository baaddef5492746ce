"""Shared test fixtures and the hypothesis profiles.

Hypothesis profiles
-------------------
``dev`` (the default)
    Random search with hypothesis' defaults and its example database, so repeated local
    runs explore new inputs and replay the failures they found.
``ci``
    Derandomized (the examples depend only on the test, not on the run), no example
    database, at most 50 examples a test, so a CI run is reproducible; a failure prints
    its ``@reproduce_failure`` blob. Tests that set ``max_examples`` themselves keep their
    own count.

Neither profile has a deadline: speed is measured by the benchmarks, not asserted in
tests, and a deadline fails a correct test on a loaded machine (a reference quadrature's
first call in a process took 0.26 s, over hypothesis' default 0.2 s, in the README's test
command on a fresh clone).

``HYPOTHESIS_PROFILE=<name>`` picks a profile explicitly; otherwise ``ci`` is loaded
when the environment variable ``CI`` is set (as CI services do, e.g. ``CI=true``;
empty, ``0``, ``false`` or ``no`` count as unset), and ``dev`` when it is not.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

os.environ.setdefault("MPLBACKEND", "Agg")
# the MJX coupling's programs compile with XLA's cheap CPU pipeline in the tests: half the
# compile time, slower batched steps (mudrft.integrations.mjx.jit, decision D81)
os.environ.setdefault("MUDRFT_FAST_COMPILE", "1")
# the tests compare numba's compilation of the physics with its other paths: no run goes
# through the interpreted warm-up here (its own test runs it in a fresh process)
import mudrft._jit

mudrft._jit.WARM_UP_STEPS = 0
try:  # matplotlib is an optional extra; where it is installed, it draws off screen
    import matplotlib
except ImportError:
    pass
else:
    matplotlib.use("Agg")

# hypothesis' built-in profiles: "default" (random) and "ci", which hypothesis itself loads
# whenever CI is set; both are extended here so that the choice below is explicit.
settings.register_profile("dev", parent=settings.get_profile("default"), deadline=None)
settings.register_profile(
    "ci",
    parent=settings.get_profile("ci"),
    derandomize=True,
    database=None,
    deadline=None,
    max_examples=50,
)


def _profile() -> str:
    """The profile named by HYPOTHESIS_PROFILE, else ``ci`` under CI, else ``dev``."""
    if os.environ.get("HYPOTHESIS_PROFILE"):
        return os.environ["HYPOTHESIS_PROFILE"]
    ci = os.environ.get("CI", "").strip().lower()
    return "ci" if ci not in ("", "0", "false", "no") else "dev"


settings.load_profile(_profile())

REPO = Path(__file__).resolve().parents[1]
PAPER = REPO.parent / "shared" / "paper" / "foot-mud-resistive-force-model.tex"


@pytest.fixture
def paper_tex() -> str:
    """The paper's LaTeX source (CI has shared/ beside the clone); skip if absent."""
    if not PAPER.exists():
        pytest.skip("the paper source ../shared/paper is not available")
    return PAPER.read_text()
