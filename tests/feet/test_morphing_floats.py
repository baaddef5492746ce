"""The morphing foot on floats: what the compiled coupling runs equals the array path.

The column balance on floats (:func:`balanced_deflection_on_floats`: the scan node by node,
then bisection; one foot, and the compiled coupling) and the batch path (the scan on arrays,
then SciPy's find_root) share the selection rule and must select the same root: they agree
far below the node spacing of the scan (0.37 mm), and each is balanced to the solver
tolerance. Both
stop at |R| <= 1e-10 N; 1e-8 N leaves margin (as in test_morphing.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mudrft._xp import pyfloat
from mudrft.feet import MorphingFoot
from mudrft.feet.morphing.equilibrium import (
    balanced_deflection_on_floats,
    column_residual,
    contact_on_floats,
)
from mudrft.feet.morphing.row import MorphingRow, morphing_row

FOOT = MorphingFoot()
ROW = morphing_row(FOOT)
BALANCE_TOL = 1e-8  # [N]
SAME_ROOT = 1e-9  # [m]: far below the 0.37 mm between scan nodes, far above round-off


def _cases() -> list[tuple[float, float, float]]:
    """(depth [m], sz [Pa], previous [m]): random over the whole range, the snap-through
    at 10 mm and 4.2 kPa (three roots) from both ends, both stops, out of the mud."""
    rng = np.random.default_rng(11)
    n = 300
    rand = zip(
        rng.uniform(0.0, 0.05, n),
        rng.uniform(-3e4, 6e4, n),
        rng.uniform(0.0, FOOT.stroke, n),
        strict=True,
    )
    cases = [(float(a), float(b), float(c)) for a, b, c in rand]
    cases += [(0.010, 4200.0, 0.0), (0.010, 4200.0, FOOT.stroke), (0.010, 4200.0, 0.006)]
    cases += [(0.03, 1e6, 0.0), (0.03, -1e4, FOOT.stroke), (0.0, 0.0, 0.005), (0.02, 0.0, 0.0)]
    return cases


def _balanced(depth: float, sz: float, delta: float) -> bool:
    r = column_residual(ROW, ROW.pole_top, ROW.branch, ROW, delta, depth, sz, xp=pyfloat)
    if delta <= 0.0:
        return r >= -BALANCE_TOL
    if delta >= FOOT.stroke:
        return r <= BALANCE_TOL
    return abs(r) <= BALANCE_TOL


def test_row_holds_the_foot_numbers():
    assert ROW.stroke == FOOT.stroke and ROW.pole_top == FOOT.linkage.pole_top
    assert ROW.knee_force == FOOT.spring.knee_force and ROW.lock == -1.0
    assert ROW.n_pads == float(FOOT.geometry.n_pads) and len(np.array(ROW)) == len(
        MorphingRow._fields
    )
    assert morphing_row(MorphingFoot(mode="expanded")).lock == FOOT.stroke


def test_residual_on_floats_equals_the_array_residual():
    rng = np.random.default_rng(5)
    x = rng.uniform(0.0, FOOT.stroke, 50)
    d = rng.uniform(0.0, 0.05, 50)
    s = rng.uniform(-3e4, 6e4, 50)
    want = FOOT.residual(x, d, s)
    got = [
        column_residual(ROW, ROW.pole_top, ROW.branch, ROW, *c, xp=pyfloat)
        for c in zip(x, d, s, strict=True)
    ]
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)


def test_deflection_on_floats_equals_the_array_path():
    """Same root as the batch path (the scan on arrays, find_root), and balanced."""
    cases = _cases()
    depth, sz, prev = (np.array(c) for c in zip(*cases, strict=True))
    batch = FOOT.equilibrium(depth, sz, previous=prev)  # > 16 moving elements: find_root
    snap = []
    for (d, s, p), want in zip(cases, batch, strict=True):
        got = balanced_deflection_on_floats(ROW, d, s, p)
        assert abs(got - want) <= SAME_ROOT, (d, s, p, got, want)
        assert _balanced(d, s, got), (d, s, p, got)
        if (d, s) == (0.010, 4200.0):
            snap.append(got)
    # the snap-through: loading from curled stays low, unloading from spread stays high, and
    # from between the column reaches one of those two (the middle root is unstable)
    assert snap[1] - snap[0] > 1e-3 and snap[2] in (snap[0], snap[1])


@pytest.mark.parametrize(("delay", "retraction"), [(0.0, 0.0), (0.0, 0.02), (0.05, 0.02)])
def test_contact_on_floats_equals_contact_force(delay, retraction):
    """Force, deflection, pad angle and seal memory of one step, any heading, all modes;
    with the pads held by a pad-curl delay (0.02 s into the retraction, 0.05 s delay) too."""
    rng = np.random.default_rng(7)
    for mode in ("morphing", "expanded", "retracted"):
        foot = MorphingFoot(mode=mode, curl_delay=delay)
        row = morphing_row(foot)
        assert row.curl_delay == delay
        for depth, sz, prev in _cases()[::10]:
            sx, sy = float(rng.uniform(-2e4, 2e4)), float(rng.uniform(-2e4, 2e4))
            heading = float(rng.uniform(-math.pi, math.pi))
            st0 = foot.initial_foot_state()._replace(
                deflection=np.asarray(prev), most_spread=np.asarray(0.3)
            )
            st1, f = foot.contact_force(
                st0, np.asarray(depth), np.array([sx, sy, sz]), heading, 1e-3,
                retraction=retraction,
            )  # fmt: skip
            got = contact_on_floats(row, prev, 0.3, depth, sx, sy, sz, heading, retraction)
            scale = max(float(np.abs(f).max()), 1e-9)
            np.testing.assert_allclose(got[:3], f, rtol=0, atol=1e-9 * scale)
            want_state = (st1.deflection, st1.pad_angle, st1.most_spread)
            np.testing.assert_allclose(got[3:], np.ravel(want_state), rtol=0, atol=SAME_ROOT)


def test_compiled_balance_equals_the_floats_path():
    """numba compiles the same function (mudrft._jit): the same deflections to round-off."""
    from mudrft._jit import jit

    fast = jit(balanced_deflection_on_floats)
    for depth, sz, prev in _cases()[::3]:
        want = balanced_deflection_on_floats(ROW, depth, sz, prev)
        assert fast(ROW, depth, sz, prev) == pytest.approx(want, rel=0, abs=1e-15)
