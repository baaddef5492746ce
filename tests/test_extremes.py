"""Valid but extreme inputs: each case a numerical-robustness search found (CHANGELOG)."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft import feet
from mudrft._validation import MudrftError
from mudrft.simulation import LoadControl


def test_a_spring_leg_too_stiff_for_the_step_is_refused_naming_the_leg():
    """A 1 kg body on a 5000 N s/m leg over a 10 g foot: dt = 5 us satisfies the mud's
    damper (limit 20 us) but not the leg's, so the explicit step diverged to NaN and the
    terrain refused its own input ("position must be finite"), an argument the user never
    passed. The leg is now checked with the mud, before the run."""
    load = LoadControl(
        weight=10.0,
        duration=0.05,
        mass=1.0,
        leg_stiffness=1e3,
        leg_damping=5000.0,
        foot_mass=0.01,
        dt=5e-6,
    )
    with pytest.raises(MudrftError, match=r"LoadControl\.dt=5e-06 s .*leg_damping=5000\.0"):
        mudrft.simulate(feet.SemiSphere(), mudrft.paper_mud(0.25), load)
    # at the step it names, the same leg runs and stays finite
    ok = LoadControl(**{**load.__dict__, "dt": 1.6e-6, "duration": 0.005})
    res = mudrft.simulate(feet.SemiSphere(), mudrft.paper_mud(0.25), ok)
    assert np.all(np.isfinite(res.force)) and np.all(np.isfinite(res.position))


def test_a_diverging_load_control_on_any_terrain_says_so():
    """Terrains other than the mud have no stability check; a diverged run names
    LoadControl.dt instead of the terrain's position argument."""
    load = LoadControl(weight=10.0, duration=0.05, mass=1.0, leg_stiffness=1e3,
                       leg_damping=5000.0, foot_mass=0.01, dt=5e-6)  # fmt: skip
    with pytest.raises(MudrftError, match=r"diverged; reduce LoadControl\.dt"):
        mudrft.simulate(feet.SemiSphere(), mudrft.terrains.LinearStiffness(), load)
