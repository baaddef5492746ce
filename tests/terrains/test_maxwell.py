"""Maxwell-type mud: reconstruction of Chen et al. (AIM 2024), 1D vertical."""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest
from scipy.linalg import expm

import mudrft
from mudrft import MudrftError
from mudrft.baselines import MaxwellMud, fit_maxwell, run_terrain
from mudrft.terrains.maxwell import MaxwellState, _zoh

FIELDS = ("modulus", "relaxation", "sigma_y", "omega", "release")


def zero_state():
    return MaxwellState(*(np.zeros(()) for _ in range(4)), in_mud=np.asarray(False))


@pytest.mark.parametrize("damping", [0.2, 1 / math.sqrt(2), 1.0, 1.0 + 1e-10, 3.0])
def test_filter_discretisation_is_the_matrix_exponential(damping):
    om, dt = 37.0, 2.3e-3
    m = np.zeros((3, 3))
    m[0, 1], m[1, 0], m[1, 1], m[1, 2] = 1.0, -om * om, -2 * damping * om, om * om
    e = expm(m * dt)
    ref = [e[0, 0], e[0, 1], e[1, 0], e[1, 1], e[0, 2], e[1, 2]]
    # closed-form 2x2 exponential (all damping regimes) vs scipy's Pade: rounding only
    np.testing.assert_allclose(_zoh(dt, om, damping), ref, rtol=1e-11, atol=1e-14)


def test_fast_history_equals_the_step_function():
    m = MaxwellMud()
    tr = mudrft.plate_intrusion()
    fast = m.response(tr)
    state, out = zero_state(), []
    for i in range(len(tr)):
        dt = tr.time[i] - tr.time[i - 1] if i else tr.time[1] - tr.time[0]
        g = tr.depth[i] / 0.05
        gd = -tr.velocity[i, 2] / 0.05 if (g > 0 or state.in_mud) else 0.0
        state, s = m.advance(state, g, gd, dt)
        out.append(float(s))
    np.testing.assert_allclose(fast, out, rtol=1e-10, atol=1e-7)  # same arithmetic, Pa


def test_maxwell_element_relaxes_exponentially_at_rest():
    m = MaxwellMud()
    g, gd, dt = 0.4, 0.4, 1e-3
    state = zero_state()
    for _ in range(1500):  # intrusion at constant rate
        state, _ = m.advance(state, g, gd, dt)
    s0 = float(state.sigma_m)
    assert s0 == pytest.approx(
        m.viscosity * gd, rel=1e-3
    )  # steady Maxwell stress eta * rate (1500 ms >> 200 ms)
    for k in range(1, 501):  # hold: no rate, no suction input
        state, s = m.advance(state, g, 0.0, dt)
        expected = m.alpha * g**m.n + s0 * math.exp(-k * dt / m.relaxation)
        assert float(s) == pytest.approx(expected, rel=1e-12)


def test_suction_is_the_second_order_step_response():
    m = MaxwellMud(damping=1 / math.sqrt(2))
    state = zero_state()._replace(gamma_max=np.asarray(0.5), in_mud=np.asarray(True))
    zeta, om, dt = m.damping, m.omega, 1e-3
    wd = om * math.sqrt(1 - zeta**2)
    for k in range(1, 201):  # retraction starts; gamma held at its maximum so u = -sigma_Y
        state, _ = m.advance(state, 0.5, -1e-9, dt)
        t = k * dt
        step = 1 - math.exp(-zeta * om * t) * (
            math.cos(wd * t) + zeta / math.sqrt(1 - zeta**2) * math.sin(wd * t)
        )
        assert float(state.suction) == pytest.approx(-m.sigma_y * step, abs=1e-6 * m.sigma_y)


def test_one_dimensional_and_fresh_mud_after_exit(box):
    m = MaxwellMud()
    one = mudrft.gait(0.2)
    h = run_terrain(m, box, one)
    assert np.all(h.force[:, :2] == 0.0)
    lc = box.characteristic_length
    np.testing.assert_allclose(
        h.force[:, 2],
        m.response(one, characteristic_length=lc) * box.length * box.width,
        rtol=1e-10,
        atol=1e-8,
    )
    # two strokes in a row: the foot leaves the mud in between, so the second sees fresh mud
    t2 = np.concatenate([one.time, one.time[-1] + 1e-3 + one.time])
    p2 = np.concatenate([one.position, one.position])
    v2 = np.concatenate([one.velocity, one.velocity])
    h2 = run_terrain(m, box, mudrft.Trajectory(t2, p2, v2))
    np.testing.assert_allclose(h2.force[len(one) :], h2.force[: len(one)], atol=1e-9)


def test_defaults_are_the_fit_to_the_mud_plate_test():
    tr = mudrft.plate_intrusion()
    ref = mudrft.plate_response(tr, mudrft.paper_mud(0.25)).stress
    start = MaxwellMud().replace(**{f: 1.3 * getattr(MaxwellMud(), f) for f in FIELDS})
    fit = fit_maxwell(tr, ref, initial=start)
    assert fit.success
    for f in FIELDS:
        # defaults are the fit rounded to 4 digits; the optimum is flat to ~0.1 %
        assert getattr(fit.model, f) == pytest.approx(getattr(MaxwellMud(), f), rel=5e-3), f


def test_fit_recovers_known_constants(caplog, capsys):
    tr = mudrft.plate_intrusion(dt=4e-3)
    truth = MaxwellMud(modulus=5e4, relaxation=0.5, sigma_y=1e4, omega=20.0, release=0.5)
    data = truth.response(tr)
    with caplog.at_level(logging.INFO, logger="mudrft"):
        fit = fit_maxwell(
            tr,
            data,
            initial=MaxwellMud(modulus=8e4, relaxation=0.3, sigma_y=1.5e4, omega=30.0, release=1.0),
            progress=True,
        )
    # progress goes through the mudrft logger, one line per 20 evaluations, never print
    notes = [r.getMessage() for r in caplog.records if r.name == "mudrft.progress"]
    assert notes[0] == "fit_maxwell: evaluation 20"
    assert capsys.readouterr().out == ""
    for f in FIELDS:
        # noise-free synthetic data: the optimiser's tolerance (ftol 1e-8) bounds the error
        assert getattr(fit.model, f) == pytest.approx(getattr(truth, f), rel=1e-3), f
    assert fit.rmse < 1e-3 * np.abs(data).max()


def test_errors():
    with pytest.raises(MudrftError, match="n must lie"):
        MaxwellMud(n=1.5)
    with pytest.raises(MudrftError, match="relaxation"):
        MaxwellMud(relaxation=0.0)
    with pytest.raises(MudrftError, match="stress must have shape"):
        fit_maxwell(mudrft.plate_intrusion(), np.zeros(3))
