"""Metrics on simple signals whose values are computed by hand."""

from __future__ import annotations

import numpy as np
import pytest

from mudrft import metrics
from mudrft._validation import MudrftError


def test_impulse_of_a_triangle_and_a_constant():
    t = np.linspace(0, 2, 201)
    f = np.zeros((201, 3))
    f[:, 0] = np.where(t <= 1, t, 2 - t) * 10.0  # triangle of height 10 N over 2 s: 10 N s
    f[:, 2] = -3.0  # constant -3 N for 2 s: -6 N s
    np.testing.assert_allclose(metrics.impulse(t, f), [10.0, 0.0, -6.0], rtol=1e-12)


@pytest.mark.parametrize("shape", [(7,), (7, 3), (1,), (1, 3)])
def test_the_trapezoid_rule_is_scipys(shape):
    """mudrft's own trapezoid rule (numpy.trapezoid exists from numpy 2.0 only, numpy.trapz
    is gone from 2.4) equals scipy's, on uneven samples and per column; one sample
    integrates to zero."""
    from scipy.integrate import trapezoid

    rng = np.random.default_rng(3)
    x = np.cumsum(rng.uniform(0.1, 1.0, shape[0]))
    y = rng.normal(size=shape)
    got = metrics._trapz(y, x)
    np.testing.assert_allclose(got, trapezoid(y, x, axis=0), rtol=1e-14, atol=1e-15)
    assert np.shape(got) == shape[1:]


def test_energy_of_a_spring_loop_is_zero_and_of_a_damper_is_positive():
    t = np.linspace(0, 1, 20001)
    z = 0.01 * np.sin(2 * np.pi * t)
    rate = np.diff(z) / np.diff(t)  # each sample's velocity: the step that ends there (D13b)
    v = np.r_[rate[0], rate]
    k, c = 1e4, 50.0
    spring = np.zeros((t.size, 3))
    spring[:, 2] = -k * z
    # the trapezoidal work of a spring along the sampled path telescopes to k (z_0^2 - z_N^2)/2
    assert metrics.energy(t, spring, np.column_stack([0 * t, 0 * t, v])) == pytest.approx(
        0.0, abs=1e-12
    )
    damper = np.zeros((t.size, 3))
    damper[:, 2] = -c * v
    # work against a damper over one period: c * (2 pi A)^2 / 2 * T = c * 2 pi^2 A^2 / T
    expected = c * 2 * np.pi**2 * 0.01**2
    assert metrics.energy(t, damper, np.column_stack([0 * t, 0 * t, v])) == pytest.approx(
        expected, rel=1e-6
    )


def test_max_suction_peak_support_sinking_rmse():
    fz = np.array([0.0, 5.0, 2.0, -4.0, -1.0])
    assert metrics.max_suction(fz) == 4.0
    assert metrics.peak_support(fz) == 5.0
    assert metrics.max_suction(np.abs(fz)) == 0.0
    assert metrics.sinking_depth([0.0, 0.02, 0.01]) == 0.02
    assert metrics.sinking_depth([0.0, 0.02, 0.01], final=True) == 0.01
    m = np.array([0.0, 1.0, 2.0, 1.0])
    assert metrics.relative_rmse(m, m) == 0.0
    assert metrics.relative_rmse(m + 0.2, m) == pytest.approx(0.1)


def test_metric_errors_name_the_argument():
    with pytest.raises(MudrftError, match="measured"):
        metrics.relative_rmse([1.0, 2.0], [1.0, 1.0])
    with pytest.raises(MudrftError, match="time"):
        metrics.impulse([0.0, 0.0], [1.0, 2.0])
    with pytest.raises(MudrftError, match="force"):
        metrics.energy([0.0, 1.0], np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(MudrftError, match="force_z"):
        metrics.max_suction([np.nan])


def test_relative_rmse_is_scale_free_up_to_the_largest_float():
    """The error is normalised before it is squared: forces above about 1e150 overflowed the
    squares to inf (a RuntimeWarning, an error in this suite), though the ratio is finite;
    a range beyond the largest float is refused instead of reading 0."""
    m = np.array([0.0, 1.0, 3.0])
    p = np.array([0.0, 1.0, 2.0])
    e = metrics.relative_rmse(p, m)
    assert metrics.relative_rmse(1e200 * p, 1e200 * m) == pytest.approx(e, rel=1e-15)
    assert metrics.relative_rmse(1e-200 * p, 1e-200 * m) == pytest.approx(e, rel=1e-15)
    with pytest.raises(MudrftError, match="largest float"):
        metrics.relative_rmse([0.0, 1e308], [-1e308, 1e308])


@pytest.mark.parametrize("fn", [metrics.max_suction, metrics.peak_support, metrics.sinking_depth])
def test_one_component_metrics_refuse_a_3d_history_and_an_empty_one(fn):
    """A (n, 3) force or position passed whole gave a number from the wrong component
    (max_suction([[-50, 0, 10]]) was 50 N though F_z = +10 N); an empty one failed in numpy."""
    name = "depth" if fn is metrics.sinking_depth else "force_z"
    with pytest.raises(MudrftError, match=rf"{name} must have shape \(n,\), got shape \(1, 3\)"):
        fn([[-50.0, 0.0, 10.0]])
    with pytest.raises(MudrftError, match=f"{name} must hold at least one sample"):
        fn([])


def test_cycle_metrics_name_the_deepest_depth_and_the_settled_one_apart():
    """max_depth is the deepest tip depth of any run; sinking, the final depth, only under a
    load (it was the deepest depth of a prescribed motion and the final one under a load)."""
    t = np.array([0.0, 1.0, 2.0])
    f = np.array([[0, 0, 0], [0, 0, 10.0], [0, 0, -4.0]])
    v = np.array([[0, 0, 0], [0, 0, -0.01], [0, 0, 0.005]])
    d = np.array([0.0, 0.01, 0.005])
    m = metrics.cycle_metrics(t, f, v, d, load=False)
    assert (m["peak_support"], m["max_suction"], m["max_depth"]) == (10.0, 4.0, 0.01)
    assert m["suction_ratio"] == 0.4 and "sinking" not in m
    assert m["impulse_z"] == pytest.approx(8.0)  # (0 + 10) / 2 + (10 - 4) / 2
    loaded = metrics.cycle_metrics(t, f, v, d, load=True)
    assert loaded["sinking"] == 0.005 and loaded["max_depth"] == 0.01
    with pytest.raises(KeyError):
        m["depth"]
