"""Linear-stiffness mud (Godon et al. 2022; Liu et al. 2023)."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft import MudrftError
from mudrft.baselines import DEFAULT_STIFFNESS, LinearStiffness, fit_stiffness, run_terrain


def test_force_is_k_depth_area_on_the_plate_test(box):
    tr = mudrft.plate_intrusion(dt=2e-3)
    h = run_terrain(LinearStiffness(), box, tr)
    expected = DEFAULT_STIFFNESS * tr.depth * box.length * box.width
    np.testing.assert_allclose(h.force[:, 2], expected, rtol=1e-12, atol=1e-12)  # rounding only
    assert np.all(h.force[:, :2] == 0.0)  # 1D vertical model


def test_no_hysteresis_loading_and_unloading_agree(box):
    tr = mudrft.plate_intrusion(dt=1e-3)
    h = run_terrain(LinearStiffness(), box, tr)
    load = tr.velocity[:, 2] < 0
    unload = tr.velocity[:, 2] > 0
    d_up, f_up = h.depth[unload][::-1], h.force[unload, 2][::-1]  # increasing depth for interp
    inside = load & (h.depth >= d_up[0]) & (h.depth <= d_up[-1])  # no extrapolation
    assert inside.sum() > 1000
    f_up_at_load = np.interp(h.depth[inside], d_up, f_up)
    # F = k d A is linear in d, so linear interpolation between unloading samples is exact
    np.testing.assert_allclose(f_up_at_load, h.force[inside, 2], rtol=1e-9, atol=1e-9)


def test_default_stiffness_is_the_fit_to_the_mud_intrusion_curve():
    tr = mudrft.plate_intrusion()  # the reference test: 30 mm at 20 mm/s, L_c = 50 mm (D1)
    res = mudrft.plate_response(tr, mudrft.paper_mud(0.25))
    load = tr.velocity[:, 2] < 0
    k = fit_stiffness(res.displacement[load], res.stress[load])
    # the default is this fit rounded to 4 significant digits (<= 0.05 %)
    assert k == pytest.approx(DEFAULT_STIFFNESS, rel=5e-4)


def test_zero_unloading_option(box):
    tr = mudrft.plate_intrusion(dt=2e-3)
    h = run_terrain(LinearStiffness(unloading="zero"), box, tr)
    up = tr.velocity[:, 2] > 0
    assert np.all(h.force[up, 2] == 0.0)
    assert np.all(
        h.force[~up, 2] == pytest.approx(DEFAULT_STIFFNESS * tr.depth[~up] * box.length * box.width)
    )


def test_errors():
    with pytest.raises(MudrftError, match="stiffness"):
        LinearStiffness(stiffness=0.0)
    with pytest.raises(MudrftError, match="unloading"):
        LinearStiffness(unloading="plastic")
    with pytest.raises(MudrftError, match="depth"):
        fit_stiffness([0.0, 0.0], [1.0, 2.0])


def test_a_stiffness_in_the_units_papers_print_warns():
    """For the linear model: 1.09 (N/cm^3 or kPa/mm read as N/m^3) is a million times
    too soft and ran silently; the paper's mud (1.09e6) and stiff soils stay quiet."""
    from mudrft._validation import PlausibilityWarning

    with pytest.warns(PlausibilityWarning, match=r"1 N/cm\^3 = 1 kPa/mm = 1e6 N/m\^3"):
        LinearStiffness(stiffness=1.09)
    LinearStiffness(stiffness=DEFAULT_STIFFNESS)  # warnings are errors in the suite
    LinearStiffness(stiffness=1e8)
