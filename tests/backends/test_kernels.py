"""The optimized kernels compute the reference constitutive step (dynamics.step)."""

from __future__ import annotations

import numpy as np
import pytest
from _backend_support import channel_inputs, parameter_sets
from hypothesis import given, settings
from hypothesis import strategies as st

from mudrft.backends import kernels
from mudrft.constitutive import step
from mudrft.constitutive.state import ChannelState

# Tolerance of the kernel-vs-reference comparisons. The kernels reorder a few operations
# (multiply by a precomputed reciprocal instead of dividing, k_a/(1/tau) instead of k_a*tau),
# which changes results by a few ulp per operation; about 40 operations, and the total
# stress is a sum of terms that may cancel, so the error is bounded relative to the sum of
# the magnitudes of the terms: 1e-12 of that scale is ~10^4 ulp, far above rounding noise
# and far below any modelling error (a wrong sign or factor gives O(1) of the scale).
RTOL_SCALE = 1e-12


def _scale(out) -> np.ndarray:
    return np.abs(out.elastic) + np.abs(out.thixotropic) + np.abs(out.suction) + 1.0


def _state_close(a: ChannelState, b: ChannelState) -> None:
    for name, x, y in zip(ChannelState._fields, a, b, strict=True):
        sc = np.abs(np.asarray(y)) + (1.0 if name in ("gamma", "gamma_w", "xi") else 1e3)
        assert np.all(np.abs(np.asarray(x) - np.asarray(y)) <= RTOL_SCALE * sc), name


@settings(max_examples=40, deadline=None)
@given(parameter_sets(), channel_inputs(shape=(6,)), st.booleans())
def test_fused_step_matches_reference_step(p, inputs, acceleration):
    state, gamma, gdot, dt, seal = inputs
    ref_state, ref = step(p, state, gamma, gdot, dt, seal=seal, acceleration=acceleration)
    c = kernels.channel_constants(p)
    new, total = kernels.fused_step(c, state, gamma, gdot, dt, seal, 1.0 if acceleration else 0.0)
    assert np.all(np.abs(total - ref.total) <= RTOL_SCALE * _scale(ref))
    _state_close(new, ref_state)


@settings(max_examples=40, deadline=None)
@given(parameter_sets(), channel_inputs(shape=(6,)), st.booleans())
def test_scalar_channel_step_matches_reference_step(p, inputs, acceleration):
    state, gamma, gdot, dt, seal = inputs
    ref_state, ref = step(p, state, gamma, gdot, dt, seal=seal, acceleration=acceleration)
    row = [float(v) for v in kernels.constant_rows(kernels.channel_constants(p))]
    kappa = 1.0 if acceleration else 0.0
    for i in range(gamma.size):
        cs = [float(a[i]) for a in state]
        total = kernels.scalar_channel_step(
            row, 0, cs, 0, float(gamma[i]), float(gdot[i]), dt, float(seal[i]), kappa
        )
        assert abs(total - ref.total[i]) <= RTOL_SCALE * _scale(ref)[i]
        _state_close(ChannelState(*cs), ChannelState(*(np.asarray(a)[i] for a in ref_state)))


def test_fused_step_handles_sign_flip_and_rest():
    """Edge cases the random inputs rarely hit: a displacement that changes side, rest."""
    import mudrft

    p = mudrft.paper_parameters(0.35, "horizontal")
    state = ChannelState(
        gamma=np.array([0.2, 0.0, 0.0]),
        gamma_w=np.array([0.3, 0.0, 0.0]),
        xi=np.array([0.5, 0.0, 1.0]),
        s_th=np.array([10.0, 0.0, 0.0]),
        sigma_s=np.array([-5.0, 0.0, 0.0]),
    )
    gamma = np.array([-0.1, 0.0, 0.0])
    gdot = np.array([-3.0, 0.0, 0.0])
    ref_state, ref = step(p, state, gamma, gdot, 1e-2)
    new, total = kernels.fused_step(kernels.channel_constants(p), state, gamma, gdot, 1e-2)
    assert np.all(np.abs(total - ref.total) <= RTOL_SCALE * _scale(ref))
    _state_close(new, ref_state)
    assert new.gamma_w[0] == pytest.approx(-0.1)  # the deepest point restarts on the new side
