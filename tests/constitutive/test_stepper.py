"""The time stepper: exactness, convergence order, stability, steady states, batches."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import mudrft
from mudrft._validation import MudrftError
from mudrft.constitutive import initial_state, run, step, thixotropic_exact

P25V = mudrft.paper_parameters(0.25, "vertical")


def _smooth_cycle(A=0.6, T=2.0):
    """gamma(t) = A (1 - cos(2 pi t / T)) / 2 over one period: intrude then retract, smooth."""
    w = 2 * np.pi / T
    g = lambda t: 0.5 * A * (1 - np.cos(w * t))  # noqa: E731
    gd = lambda t: 0.5 * A * w * np.sin(w * t)  # noqa: E731
    gdd = lambda t: 0.5 * A * w * w * np.cos(w * t)  # noqa: E731
    gw = lambda t: np.where(t <= T / 2, g(t), A)  # noqa: E731  deepest point so far
    return g, gd, gdd, gw, T


def _reference(p, t_eval):
    """The model written with the ORIGINAL eq. (3a) (explicit gamma-ddot term), for a smooth input."""
    g, gd, gdd, gw, T = _smooth_cycle()

    def rhs(t, y):
        xi, sth, ss = y
        r = max(float(gw(t) - g(t)), 0.0)
        phi = np.tanh(r / p.epsilon)
        dxi = p.k_a * (1 - xi) - p.k_r * abs(gd(t)) * xi
        dsth = ((p.eta_inf + xi * p.eta_m) * gd(t) + p.lam * p.eta_inf * gdd(t) - sth) / p.lam
        dss = -(phi / p.tau_build) * (ss + p.sigma_y) - ((1 - phi) / p.tau_leak) * ss
        return [dxi, dsth, dss]

    # sigma_th(0) = eta_inf * gamma_dot(0) = 0 because the cycle starts at rest
    sol = solve_ivp(
        rhs,
        (0, t_eval[-1]),
        [0.0, 0.0, 0.0],
        t_eval=t_eval,
        rtol=1e-11,
        atol=1e-12,
        method="Radau",
        max_step=T / 400,
    )
    assert sol.success
    return sol.y


def _stepper_states(p, n):
    g, gd, _gdd, _gw, T = _smooth_cycle()
    t = np.linspace(0, T, n + 1)
    s = initial_state()
    xs, sths, sss = [0.0], [0.0], [0.0]
    for k in range(1, n + 1):
        dt = t[k] - t[k - 1]
        s, out = step(p, s, g(t[k]), (g(t[k]) - g(t[k - 1])) / dt, dt)
        xs.append(float(s.xi))
        sths.append(
            float(out.thixotropic - p.eta_inf * (g(t[k]) - g(t[k - 1])) / dt + p.eta_inf * gd(t[k]))
        )
        sss.append(float(s.sigma_s))
    return t, np.array(xs), np.array(sths), np.array(sss)


def test_stepper_matches_original_ode_and_converges_with_order_two():
    """The Jeffreys form (D6) plus exact exponentials reproduce eq. (3) with its gamma-ddot term,
    and the state error falls like dt^2 (inputs piecewise linear, sealing at mid-step)."""
    p = P25V
    errs = []
    for n in (100, 200, 400):
        t, xi, sth, ss = _stepper_states(p, n)
        xi_r, sth_r, ss_r = _reference(p, t)
        e = max(
            np.max(np.abs(xi - xi_r)),
            np.max(np.abs(sth - sth_r)) / p.eta_m,
            np.max(np.abs(ss - ss_r)) / p.sigma_y,
        )
        errs.append(e)
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    # second order expected; 1.7 leaves room for the kink of the sealing at the turning point
    assert np.all(orders > 1.7), (errs, orders)
    assert errs[-1] < 1e-3


def test_stepper_is_exact_for_constant_rate_at_any_step():
    p = P25V
    rate = 0.8
    for dt in (1e-4, 1e-3, 1e-2, 0.5):
        n = round(2.0 / dt)
        s = initial_state()
        for k in range(1, n + 1):
            s, out = step(p, s, rate * k * dt, rate, dt, acceleration=False)
        exact = thixotropic_exact(n * dt, rate, p)
        assert float(out.thixotropic) == pytest.approx(float(exact), rel=1e-10)


def _plate(dt):
    tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0, dt=dt)
    return mudrft.plate_response(tr, P25V), tr


def test_stable_and_accurate_at_10_ms():
    fine, _ = _plate(1e-4)
    coarse, _ = _plate(1e-2)
    assert np.all(np.isfinite(coarse.stress))
    ref = np.interp(coarse.time, fine.time, fine.stress)
    # 10 ms is 1/30 of tau_build and 1/190 of lambda; stay within 5 % of the peak
    assert np.max(np.abs(coarse.stress - ref)) < 0.05 * fine.stress.max()
    # no step-to-step oscillation: the stress has no spurious sign flips while held
    hold = (coarse.time > 1.6) & (coarse.time < 2.4)
    assert np.all(np.diff(coarse.stress[hold]) <= 1e-9)


@pytest.mark.parametrize("dt", [1e-4, 1e-3, 1e-2])
def test_stiff_parameters_stay_bounded(dt):
    # the stiffest constants in the tables: tau_leak 0.022 s (H45), epsilon 0.016 (V25); fast motion
    for p in (mudrft.paper_parameters(0.45, "horizontal"), P25V):
        t = np.arange(0, 1.0 + dt / 2, dt)
        g = 0.8 * np.abs(np.sin(2 * np.pi * 2 * t))
        h = run(p, t, g)
        bound = p.alpha * 2 + (p.eta_inf + p.eta_m) * 0.8 * 4 * np.pi + p.sigma_y
        assert np.all(np.isfinite(h.total)) and np.max(np.abs(h.total)) < bound


def test_relaxation_time_constant_is_lambda_while_held():
    res, tr = _plate(1e-3)
    t_hold = tr.meta["t_retract"] - tr.meta["hold"]
    sel = (res.time > t_hold + 0.05) & (res.time < tr.meta["t_retract"] - 0.05)
    y = res.thixotropic[sel]
    slope = np.polyfit(res.time[sel], np.log(y), 1)[0]
    assert -1 / slope == pytest.approx(P25V.lam, rel=1e-6)


def test_plate_test_shape_claims_of_the_paper():
    """Rising resistance, relaxation while held, suction comparable to the intrusion peak."""
    res, tr = _plate(1e-3)
    t_in = tr.meta["t_retract"] - tr.meta["hold"]
    intr = res.time <= t_in
    assert np.all(np.diff(res.stress[intr][5:]) > 0)
    held = (res.time > t_in) & (res.time < tr.meta["t_retract"])
    assert np.all(np.diff(res.stress[held]) < 0) and res.stress[held][-1] > 0
    peak, suction = res.stress.max(), -res.stress.min()
    assert suction > 0.3 * peak  # comparable: same order as the peak
    assert suction < 2.0 * peak


def test_suction_tends_to_minus_sigma_y_when_sealed_and_zero_when_leaking():
    p = P25V
    s = initial_state()
    # intrude, then retract slowly for a long time with the cavity sealed
    s, _ = step(p, s, 0.5, 0.5, 1.0)
    for _ in range(1000):  # 10 s = 31 tau_build: the transient is e^-31
        s, _out = step(p, s, float(s.gamma) - 4e-4, -4e-2, 0.01)  # retract 0.4 >> epsilon
    assert float(s.sigma_s) == pytest.approx(-p.sigma_y, rel=1e-6)
    # seal broken by the foot (seal factor 0): suction leaks away
    for _ in range(400):  # 4 s = 23 tau_leak
        s, _out = step(p, s, float(s.gamma) - 1e-5, -1e-3, 0.01, seal=0.0)
    assert abs(float(s.sigma_s)) < 1e-6 * p.sigma_y


def test_scalar_and_array_inputs_agree():
    sets = [
        mudrft.paper_parameters(w, d)
        for w in (0.25, 0.35, 0.45)
        for d in ("vertical", "horizontal")
    ]
    batch = mudrft.MudParameters.stack(sets)
    t = np.linspace(0, 3, 301)
    g = 0.5 * np.sin(np.pi * t / 3)
    hb = run(batch, t, np.repeat(g[:, None], len(sets), 1))
    for i, p in enumerate(sets):
        hs = run(p, t, g)
        np.testing.assert_allclose(hb.total[:, i], hs.total, rtol=1e-12, atol=1e-9)


def test_horizontal_channel_is_odd():
    p = mudrft.paper_parameters(0.25, "horizontal")
    t = np.linspace(0, 2, 201)
    g = 0.4 * np.sin(np.pi * t / 2)
    np.testing.assert_allclose(run(p, t, -g).total, -run(p, t, g).total, rtol=1e-12, atol=1e-9)


def test_bad_input_is_rejected_with_the_argument_name():
    with pytest.raises(MudrftError, match="dt"):
        step(P25V, initial_state(), 0.1, 1.0, 0.0)
    with pytest.raises(MudrftError, match="gamma"):
        step(P25V, initial_state(), np.nan, 1.0, 0.01)
    with pytest.raises(MudrftError, match="time"):
        run(P25V, [0.0, 0.2, 0.1], [0.0, 0.1, 0.2])
    with pytest.raises(MudrftError, match="gamma"):
        run(P25V, [0.0, 0.1, 0.2], [0.0, 0.1])
    with pytest.raises(MudrftError, match="xi0"):
        initial_state(xi0=1.5)


params_strategy = st.builds(
    lambda w, d, scale: mudrft.paper_parameters(w, d).replace(
        alpha=mudrft.paper_parameters(w, d).alpha * scale
    ),
    st.floats(0.25, 0.45),
    st.sampled_from(["vertical", "horizontal"]),
    st.floats(0.1, 10.0),
)


@settings(max_examples=40, deadline=None)
@given(
    p=params_strategy,
    amps=st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=12),
    dt=st.sampled_from([1e-4, 1e-3, 1e-2]),
)
def test_no_nan_or_inf_for_any_valid_input(p, amps, dt):
    t = np.arange(0, len(amps)) * 0.05
    tt = np.arange(0, t[-1] + dt / 2, dt)
    g = np.interp(tt, t, amps)
    if tt.size < 2:
        return
    h = run(p, tt, g)
    for arr in (h.total, h.elastic, h.thixotropic, h.suction, h.xi):
        assert np.all(np.isfinite(arr))
    assert np.all((h.xi >= 0) & (h.xi <= 1))
    assert np.all(h.suction * np.sign(g + 1e-300) <= p.sigma_y * (1 + 1e-9))


@settings(max_examples=40)
@given(
    st.sampled_from([0.25, 0.35, 0.45]),
    st.integers(0, 2**31 - 1),
    st.sampled_from(
        [("ode", "contact"), ("quasi-static", "contact"), ("quasi-static", "retraction")]
    ),
)
def test_one_channel_on_floats_is_the_array_step(w, seed, evaluation):
    """A step of one channel (numbers, 0-d state) takes the float path; a 1-element batch
    takes numpy: the same step, to the rounding of libm against numpy (an ulp or so of
    each term), and float64 numbers out."""
    thixotropy, clock = evaluation
    rng = np.random.default_rng(seed)
    p = mudrft.paper_parameters(w)
    one, batch = initial_state(), initial_state((1,))
    for _ in range(30):  # a random walk in and out, both directions
        g = float(rng.uniform(-0.3, 0.3))
        gd, dt, seal = float(rng.normal(0.0, 2.0)), float(10 ** rng.uniform(-4, -2)), 1.0
        kw = {"seal": seal, "thixotropy": thixotropy, "clock": clock}
        one, s1 = step(p, one, g, gd, dt, **kw)
        batch, sb = step(p, batch, np.array([g]), np.array([gd]), dt, **kw)
        assert all(type(v) is np.float64 for v in (*one, *s1))
        scale = abs(s1.elastic) + abs(s1.thixotropic) + abs(s1.suction) + 1.0
        for a, b in zip((*one, *s1), (*batch, *sb), strict=True):
            assert abs(a - float(np.ravel(b)[0])) <= 1e-12 * max(scale, abs(a))


def test_one_channel_refuses_bad_input_as_the_array_step_does():
    p = mudrft.paper_parameters(0.25)
    for args, match in (((0.1, 1.0, -1e-3), "dt must be > 0 s"), ((np.nan, 1.0, 1e-3), "gamma")):
        with pytest.raises(MudrftError, match=match):
            step(p, initial_state(), *args)
        with pytest.raises(MudrftError, match=match):
            step(p, initial_state((1,)), *(np.array([a]) for a in args[:2]), args[2])


@pytest.mark.parametrize("lam", [1e-6, 1e-4, 1e-2])
@pytest.mark.parametrize("dt", [1e-3, 0.05])
def test_relaxation_much_faster_than_the_step_stays_exact(lam, dt):
    """lambda << dt < tau_xi (k_a set apart from 1/lambda): the exact update's factor
    e^{-dt/lambda} (e^x - 1)/x overflowed to 0 * inf once x = dt (1/lambda - 1/tau) > 709 (NaN
    on arrays, OverflowError on floats). Both paths against a stiff solver of eqs. (3a)-(3b)."""
    p = P25V.replace(lam=lam, k_a=0.5)
    gd, xi0 = 2.0, 1.0
    tau = 1.0 / (p.k_a + p.k_r * gd)

    def rhs(t, y):
        xi, s = y
        return [(p.k_a * tau - xi) / tau, (p.eta_m * gd * xi - s) / lam]  # kappa = 1: A = 0

    ref = solve_ivp(rhs, (0.0, dt), [xi0, 0.0], method="Radau", rtol=1e-11, atol=[1e-14, 1e-6])
    xi_ref, s_ref = ref.y[:, -1]
    one, _ = step(p, initial_state(xi0=xi0), gd * dt, gd, dt)
    arr, _ = step(p, initial_state((2,), xi0=xi0), np.full(2, gd * dt), np.full(2, gd), dt)
    for s_th, xi in ((one.s_th, one.xi), (arr.s_th[1], arr.xi[1])):
        assert xi == pytest.approx(xi_ref, rel=1e-9)
        # the solver's own tolerance: rtol 1e-11 of a stress of about 1e5 Pa
        assert s_th == pytest.approx(s_ref, rel=1e-8)


def test_both_evaluations_take_the_steady_suction_from_the_one_eq_11(monkeypatch):
    """Eq. (11) is written once (laws.suction_steady_at_rate, which laws.suction_steady calls):
    the ODE step's exponential target and the quasi-static plateau both read it with the rate
    they computed, so doubling it changes both suctions."""
    from mudrft.constitutive import laws

    t = np.linspace(0.0, 2.0, 201)
    g = np.concatenate([np.linspace(0.0, 0.6, 100), np.linspace(0.6, 0.2, 101)])
    before = {th: run(P25V, t, g, thixotropy=th).suction for th in ("ode", "quasi-static")}
    original = laws.suction_steady_at_rate
    monkeypatch.setattr(laws, "suction_steady_at_rate", lambda *a: 2.0 * original(*a))
    for th, s0 in before.items():
        s1 = run(P25V, t, g, thixotropy=th).suction
        assert np.any(s0 != 0.0)
        np.testing.assert_allclose(s1, 2.0 * s0, rtol=1e-12, atol=1e-9)
