"""Every closed-form solution of the paper against a numerical ODE solution (solve_ivp).

Tolerances: solve_ivp runs at rtol=1e-10, atol tiny, so agreement to 1e-7 relative
is limited by the reference, not by the closed form.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mudrft
from mudrft.constitutive import (
    laws,
    suction_closed_form,
    thixotropic_approx,
    thixotropic_exact,
    xi_exact,
)

P25V = mudrft.paper_parameters(0.25, "vertical")
P35H = mudrft.paper_parameters(0.35, "horizontal")


def _ivp(rhs, y0, t_end, t_eval):
    sol = solve_ivp(rhs, (0.0, t_end), y0, t_eval=t_eval, rtol=1e-10, atol=1e-12, method="LSODA")
    assert sol.success
    return sol.y


@pytest.mark.parametrize("p", [P25V, P35H], ids=["V25", "H35"])
@pytest.mark.parametrize("rate", [0.05, 0.4, 3.0])
@pytest.mark.parametrize("xi0", [0.0, 1.0])
def test_xi_and_thixotropic_exact_match_ode(p, rate, xi0):
    t = np.linspace(0, 3 * p.lam, 61)

    def rhs(_t, y):
        xi, s = y
        dxi = p.k_a * (1 - xi) - p.k_r * abs(rate) * xi
        ds = ((p.eta_inf + xi * p.eta_m) * rate - s) / p.lam
        return [dxi, ds]

    xi_ref, s_ref = _ivp(rhs, [xi0, 0.0], t[-1], t)
    np.testing.assert_allclose(xi_exact(t, rate, p, xi0=xi0), xi_ref, rtol=1e-7, atol=1e-10)
    scale = (p.eta_inf + p.eta_m) * rate
    np.testing.assert_allclose(
        thixotropic_exact(t, rate, p, xi0=xi0), s_ref, rtol=0, atol=1e-7 * scale
    )


def test_thixotropic_exact_with_tau_equal_lambda_is_the_limit():
    # k_a chosen so that tau_xi == lambda exactly at this rate: the formula must stay finite
    rate = 0.5
    p = P25V
    k_a = 1.0 / p.lam / (1 + rate / p.gamma_dot_c)  # tau = 1/(k_a (1 + |rate|/gc))
    q = p.replace(k_a=k_a)
    assert np.isclose(1 / (q.k_a + q.k_r * rate), q.lam)
    t = np.linspace(0, 5, 41)

    def rhs(_t, y):
        xi, s = y
        return [
            q.k_a * (1 - xi) - q.k_r * rate * xi,
            ((q.eta_inf + xi * q.eta_m) * rate - s) / q.lam,
        ]

    _, s_ref = _ivp(rhs, [0.0, 0.0], t[-1], t)
    np.testing.assert_allclose(thixotropic_exact(t, rate, q), s_ref, atol=1e-7 * q.eta_m * rate)


def test_erratum_E5_second_term_does_not_vanish_when_tau_equals_lambda():
    """The supplementary drops the second term of (S2) for tau_xi ~ lambda; it tends to
    -(t/lam) exp(-t/lam) xi_ss eta_m gamma_dot, whose largest magnitude is xi_ss eta_m gamma_dot / e."""
    rate = 0.5
    p = P25V
    k_a = 1.0 / p.lam / (1 + rate / p.gamma_dot_c)
    q = p.replace(k_a=k_a)
    t = np.linspace(0, 10 * q.lam, 4001)
    err = thixotropic_approx(t, rate, q) - thixotropic_exact(t, rate, q)
    xi_ss = laws.xi_steady(rate, q.gamma_dot_c)
    expected_max = xi_ss * q.eta_m * rate / np.e
    # the grid resolves the maximum of (t/lam) e^{-t/lam} at t = lam to 1e-5 relative
    assert np.max(np.abs(err)) == pytest.approx(expected_max, rel=1e-4)
    assert np.max(np.abs(err)) > 0.05 * laws.thixotropic_steady(
        rate, q.eta_inf, q.eta_m, q.gamma_dot_c
    )


def test_paper_approximation_holds_when_structure_starts_at_steady_state():
    # eq. (9) is exact if xi(0) = xi_ss: then only the Maxwell lag remains
    rate = 1.0
    xi_ss = float(laws.xi_steady(rate, P25V.gamma_dot_c))
    t = np.linspace(0, 8, 50)
    np.testing.assert_allclose(
        thixotropic_exact(t, rate, P25V, xi0=xi_ss),
        thixotropic_approx(t, rate, P25V),
        rtol=1e-12,
        atol=1e-9,
    )


@pytest.mark.parametrize("phi", [0.0, 0.3, 0.8, 1.0])
def test_suction_closed_form_matches_ode(phi):
    p = P25V
    t = np.linspace(0, 2.0, 41)

    def rhs(_t, y):
        return [-(phi / p.tau_build) * (y[0] + p.sigma_y) - ((1 - phi) / p.tau_leak) * y[0]]

    for s0 in (0.0, -0.5 * p.sigma_y):
        (ref,) = _ivp(rhs, [s0], t[-1], t)
        np.testing.assert_allclose(
            suction_closed_form(t, phi, p, sigma_s0=s0), ref, atol=1e-8 * p.sigma_y
        )


def test_suction_steady_states():
    p = P25V
    assert laws.suction_steady(1.0, p.tau_build, p.tau_leak, p.sigma_y) == pytest.approx(-p.sigma_y)
    assert laws.suction_steady(0.0, p.tau_build, p.tau_leak, p.sigma_y) == 0.0
    # the closed form reaches them: after 20 time constants the transient is e^-20
    assert suction_closed_form(20 * p.tau_build, 1.0, p) == pytest.approx(-p.sigma_y, rel=1e-8)
    assert suction_closed_form(20 * p.tau_leak, 0.0, p, sigma_s0=-p.sigma_y) == pytest.approx(
        0, abs=1e-8 * p.sigma_y
    )


def test_steady_structure_and_thixotropic_stress_eq4():
    p = P25V
    rate = 2.0
    xi_ss = laws.xi_steady(rate, p.gamma_dot_c)
    assert xi_ss == pytest.approx(p.gamma_dot_c / (p.gamma_dot_c + rate))
    # k_a/(k_a + k_r |rate|) is the same number (paper, below eq. 3)
    assert xi_ss == pytest.approx(p.k_a / (p.k_a + p.k_r * rate))
    long = xi_exact(50 * p.lam, rate, p)
    assert long == pytest.approx(xi_ss, rel=1e-10)
    sth = thixotropic_exact(50 * p.lam, rate, p)
    assert sth == pytest.approx((p.eta_inf + xi_ss * p.eta_m) * rate, rel=1e-10)


def test_erratum_E3_printed_xi_solution_has_sign_slip():
    """Printed: xi(t) = (1 - e^{+t/tau}) xi_ss -- negative and unbounded; the ODE gives e^{-t/tau}."""
    p, rate = P25V, 0.5
    tau = float(laws.tau_xi(rate, p.k_a, p.k_r))
    xi_ss = float(laws.xi_steady(rate, p.gamma_dot_c))
    t = np.array([0.5, 1.0, 2.0]) * tau
    printed = (1 - np.exp(t / tau)) * xi_ss
    exact = xi_exact(t, rate, p)
    assert np.all(printed < 0) and np.all((exact > 0) & (exact < xi_ss))
    np.testing.assert_allclose(exact, (1 - np.exp(-t / tau)) * xi_ss, rtol=1e-12)
