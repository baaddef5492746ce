"""The paper's quasi-static evaluation (decision D15) equals eqs. (9)-(11) evaluated by hand.

The hand values below use the printed numbers of Table S1, W = 25 % (in SI: eta_inf = 14000
Pa s, eta_m = 67000 Pa s, gamma_dot_c = 0.14 1/s, lambda = 1.9 s, alpha = 24000 Pa, n = 0.53,
tau_build = 0.32 s, tau_leak = 0.17 s, epsilon = 0.016, sigma_Y = 7100 Pa), written out, not
taken from mudrft's laws. The model evaluates the same closed forms, so they agree to
rounding: rtol 1e-12, or 1e-9 where the model's clock is a sum of thousands of steps.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mudrft
from mudrft import MudrftError
from mudrft.constitutive import run, thixotropic_approx
from mudrft.terrains import MudTerrain

P = mudrft.paper_parameters(0.25, "vertical")
RTOL = 1e-12


def _sigma_th_by_hand(t, rate):
    """Eq. (9) with eq. (4), the printed W = 25 % vertical row [Pa]."""
    xi_ss = 0.14 / (0.14 + abs(rate))
    return (1.0 - math.exp(-t / 1.9)) * (14000.0 + xi_ss * 67000.0) * rate


def _plate(speed=0.02, hold=0.0, depth=0.03, dt=1e-3):
    """A vertical plate test on a 50 mm plate: (time [s], gamma [-], t_retract [s])."""
    tr = mudrft.plate_intrusion(depth=depth, speed=speed, hold=hold, dt=dt, rest=0.0)
    return tr.time, tr.depth / 0.05, tr.meta["t_retract"]


@pytest.mark.parametrize("t_check", [0.1, 0.5, 1.2])
def test_intrusion_equals_eq9_and_eq2_by_hand(t_check):
    t, g, _ = _plate()
    h = run(P, t, g, thixotropy="quasi-static")
    k = int(np.argmin(np.abs(t - t_check)))
    rate = 0.02 / 0.05  # [1/s]
    assert h.thixotropic[k] == pytest.approx(_sigma_th_by_hand(t[k], rate), rel=RTOL)
    elastic = 24000.0 * g[k] ** 0.53  # eq. (2): still on the bed, no retraction
    assert h.elastic[k] == pytest.approx(elastic, rel=RTOL)
    assert h.suction[k] == 0.0  # the retraction clock has not started: eq. (10) gives 0
    assert h.total[k] == pytest.approx(elastic + _sigma_th_by_hand(t[k], rate), rel=RTOL)
    # and the library's own eq. (9) (constitutive.exact) says the same
    assert h.thixotropic[k] == pytest.approx(float(thixotropic_approx(t[k], rate, P)), rel=RTOL)


@pytest.mark.parametrize("clock", ["contact", "retraction"])
@pytest.mark.parametrize("dt_after", [0.05, 0.2, 0.6])
def test_retraction_equals_eqs_9_to_11_by_hand(clock, dt_after):
    t, g, t_w = _plate(hold=0.3)
    h = run(P, t, g, thixotropy="quasi-static", clock=clock)
    k = int(np.argmin(np.abs(t - (t_w + dt_after))))
    delta = t[k] - t_w  # Delta t of eq. (10): the retraction started at t_w
    rate = -0.02 / 0.05
    # eq. (9): the clock runs from first contact, or restarts at t_w
    t9 = t[k] if clock == "contact" else delta
    assert h.thixotropic[k] == pytest.approx(_sigma_th_by_hand(t9, rate), rel=1e-9)  # clock sums
    # eqs. (10)-(11) with the sealing state of decision D4 at the current retraction
    r = g.max() - g[k]
    phi = math.tanh(r / 0.016)
    a = phi / 0.32 + (1.0 - phi) / 0.17
    steady = -phi * 7100.0 / (a * 0.32)
    switch = 0.5 * (1.0 - math.tanh(rate / 0.01))  # H_nu of eq. (1), about 1
    suction = switch * (1.0 - math.exp(-a * delta)) * steady
    assert h.suction[k] == pytest.approx(suction, rel=1e-9)
    assert h.suction[k] < -0.1 * 7100.0  # a real suction, not a vanishing term
    # the bed-contact factor (decision D2) removes sigma_b once the plate has left the bed
    elastic = 24000.0 * g[k] ** 0.53 * (1.0 - phi)
    assert h.total[k] == pytest.approx(elastic + h.thixotropic[k] + suction, rel=1e-9)


def test_quasi_static_equals_the_ode_where_eq9_is_exact():
    """Eq. (9) solves eq. (3) exactly when the structure starts at its steady value and the
    rate is constant (supplementary Sec. I): there the two evaluations must agree."""
    t, g, t_w = _plate()
    rate = 0.02 / 0.05
    xi_ss = P.gamma_dot_c / (P.gamma_dot_c + rate)
    qs = run(P, t, g, thixotropy="quasi-static")
    ode = run(P, t, g, acceleration=False, xi0=xi_ss)
    intruding = (t > 0) & (t < t_w)
    scale = np.abs(ode.thixotropic[intruding]).max()
    assert np.all(np.abs(qs.thixotropic[intruding] - ode.thixotropic[intruding]) <= 1e-9 * scale)


def test_speed_barely_changes_the_quasi_static_stress_at_the_same_depth():
    """Sec. III-A's point: (1 - e^{-t/lambda}) ~ t/lambda scales as 1/speed while the rate
    scales as speed, so at a given depth eq. (9) hardly depends on the speed; a stress
    proportional to the rate (the viscous term kept by the ODE with its acceleration term)
    would change by the speed ratio, 4 here."""
    out = []
    for speed in (0.01, 0.02, 0.04):
        t, g, t_w = _plate(speed=speed, depth=0.02, dt=1e-4)
        h = run(P, t, g, thixotropy="quasi-static")
        k = np.argmin(np.abs(t - t_w)) - 1  # at 20 mm, just before the retraction
        out.append(h.thixotropic[k])
        # the clock is a sum of ~20000 steps: its rounding, not the formula, sets 1e-9
        assert h.thixotropic[k] == pytest.approx(_sigma_th_by_hand(t[k], speed / 0.05), rel=1e-9)
    assert max(out) / min(out) < 1.25  # 1.22: a factor 4 in speed, a 22 % change


def test_terrain_flat_foot_force_is_the_area_times_the_closed_form_stress():
    """MudTerrain in the quasi-static evaluation: F_z = L W sigma_z (eq. 12) with sigma_z
    from eqs. (2) and (9) by hand, at a few points of a constant-speed intrusion."""
    foot = mudrft.feet.Flat()
    lc = foot.characteristic_length
    terrain = MudTerrain(mudrft.paper_mud(0.25), thixotropy="quasi-static")
    speed, dt = 0.05, 1e-3
    state = terrain.initial_state(foot, np.zeros(3))
    for k in range(1, 301):
        z = -speed * k * dt
        state, out = terrain.step(foot, state, [0.0, 0.0, z], [0.0, 0.0, -speed], dt)
        if k in (50, 150, 300):
            gamma, rate = -z / lc, speed / lc
            sigma = 24000.0 * gamma**0.53 + _sigma_th_by_hand(k * dt, rate)
            assert out.force[2] == pytest.approx(0.08 * 0.065 * sigma, rel=RTOL)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"thixotropy": "closed-form"}, "thixotropy"),
        ({"clock": "retraction"}, "clock"),
        ({"clock": "now", "thixotropy": "quasi-static"}, "clock"),
        ({"thixotropy": "quasi-static", "acceleration": True}, "acceleration"),
    ],
)
def test_evaluation_options_are_checked_where_the_terrain_is_made(options, message):
    with pytest.raises(MudrftError, match=message):
        MudTerrain(mudrft.paper_mud(0.25), **options)


def test_quasi_static_terrain_resolves_its_flags():
    t = MudTerrain(mudrft.paper_mud(0.25), thixotropy="quasi-static", clock="retraction")
    assert (t.quasi_static, t.restart, t.acceleration, t.kappa) == (True, True, False, 0.0)
    assert MudTerrain(mudrft.paper_mud(0.25)).acceleration is True
