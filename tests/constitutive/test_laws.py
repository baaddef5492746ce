"""Pure laws: values, limits and symmetry."""

from __future__ import annotations

import numpy as np
import pytest

from mudrft.constitutive import laws


def test_elastic_stress_power_law_and_odd():
    assert laws.elastic_stress(0.25, 24e3, 0.5) == pytest.approx(12e3)
    g = np.linspace(-1, 1, 11)
    np.testing.assert_allclose(laws.elastic_stress(-g, 1.0, 0.3), -laws.elastic_stress(g, 1.0, 0.3))
    assert laws.elastic_stress(0.0, 1.0, 0.3) == 0.0


def test_switch_limits():
    assert laws.switch(10.0, 0.01) == pytest.approx(0.0, abs=1e-12)
    assert laws.switch(-10.0, 0.01) == pytest.approx(1.0)
    assert laws.switch(0.0, 0.01) == 0.5


def test_sealing_and_contact_are_complementary_and_monotone():
    r = np.linspace(-0.1, 0.2, 31)
    phi = laws.sealing(r, 0.016)
    np.testing.assert_allclose(phi + laws.bed_contact(r, 0.016), 1.0)
    assert np.all(np.diff(phi) >= 0) and phi[0] == 0 and phi[-1] > 0.999


def test_sealing_relates_to_printed_form():
    """D4: our sealing equals 2*phi_printed - 1 with gamma_0 the retraction point and r >= 0."""
    gw, eps = 0.6, 0.02
    g = np.linspace(0.3, 0.6, 20)
    printed = laws.sealing_printed(g, gw, eps)
    np.testing.assert_allclose(laws.sealing(gw - g, eps), 2 * printed - 1, atol=1e-12)


def test_scaling_factors_sum_to_one_and_extensions_agree_on_first_quadrant():
    psi = np.linspace(0, np.pi / 2, 9)
    np.testing.assert_allclose(laws.f_n(psi) + laws.f_t(psi), 1.0)
    np.testing.assert_allclose(laws.f_n_extended(psi), laws.f_n(psi), atol=1e-15)
    np.testing.assert_allclose(laws.f_t_extended(psi), laws.f_t(psi), atol=1e-15)
    # supplementary's piecewise extension: f_n negative beyond pi/2, f_t odd
    assert laws.f_n_extended(0.75 * np.pi) == pytest.approx(-0.5 * (1 + np.cos(1.5 * np.pi)))
    assert laws.f_t_extended(-0.3) == pytest.approx(-0.5 * (1 - np.cos(-0.6)))
