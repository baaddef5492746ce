"""The float specialization of the one source (mudrft._specialize) computes what it rewrites.

``on_floats(f)`` is ``f`` rewritten for one element on Python floats: ``xp.where`` as a
conditional, straight-line callees inlined. Its result must be the generic ``f(...,
xp=pyfloat)`` bit for bit (the same operations on the same doubles), so these tests compare
with ``==``, not a tolerance. The toy functions show what may and may not be inlined.
"""

from __future__ import annotations

import ast
from typing import NamedTuple

import numpy as np
import pytest
from _backend_support import channel_inputs, parameter_sets
from hypothesis import given, settings
from hypothesis import strategies as st

import mudrft
from mudrft._specialize import on_floats
from mudrft._xp import pyfloat
from mudrft.constitutive import channel_constants, kernel
from mudrft.constitutive.state import ChannelState
from mudrft.feet.closed_form import closed_form_force
from mudrft.feet.morphing.equilibrium import balanced_deflection_on_floats
from mudrft.feet.morphing.row import linkage_row
from mudrft.terrains.mud import mud_step


def _floats(tree):
    """A pytree of 1-element arrays (or floats) as Python floats."""
    return type(tree)(*(float(np.ravel(v)[0]) for v in tree))


@settings(max_examples=60)
@given(parameter_sets(), channel_inputs(shape=(1,)), st.sampled_from([0.0, 1.0]))
def test_the_float_channel_step_is_the_generic_one_bit_for_bit(p, inputs, kappa):
    state, gamma, gamma_dot, dt, seal = inputs
    c = _floats(channel_constants(p))
    s = _floats(state)
    g, gd, sl = float(gamma[0]), float(gamma_dot[0]), float(seal[0])
    for qs, restart in ((False, False), (True, False), (True, True)):
        args = (c, s, g, gd, dt, sl, kappa, qs, restart)
        assert on_floats(kernel.channel_step)(*args) == kernel.channel_step(*args, xp=pyfloat)


@settings(max_examples=40)
@given(
    st.sampled_from([0.25, 0.35, 0.45]),
    st.integers(0, 2**31 - 1),
    st.booleans(),
    st.booleans(),
)
def test_the_float_terrain_step_and_closed_forms_are_the_generic_ones_bit_for_bit(
    w, seed, reset, quasi_static
):
    rng = np.random.default_rng(seed)
    terrain = mudrft.MudTerrain(
        mudrft.paper_mud(w), thixotropy="quasi-static" if quasi_static else "ode"
    )
    for foot in (mudrft.feet.Flat(), mudrft.feet.SemiCylinder(), mudrft.feet.SemiSphere()):
        ch = terrain.initial_state(foot, np.zeros(3)).channels
        lc = terrain.length(foot)
        for _ in range(20):  # a short random walk in and out of the mud
            p = (*rng.normal(0.0, 0.01, 2), float(rng.uniform(-0.03, 0.005)))
            v = tuple(rng.normal(0.0, 0.1, 3))
            args = (terrain.constants, ch, *p, *v, 1e-3, lc, 1.0, 1.0, reset, 1e-3, 1.0)
            out = on_floats(mud_step)(*args, quasi_static, False)
            assert out == mud_step(*args, quasi_static, False, xp=pyfloat)
            ch, sx, sy, sz, depth = out
            geom = foot.kernel_geometry
            f = on_floats(closed_form_force)(*geom, depth, sx, sy, sz, ch.heading)
            assert f == closed_form_force(*geom, depth, sx, sy, sz, ch.heading, xp=pyfloat)


@settings(max_examples=40)
@given(st.floats(0.0, 0.03), st.floats(-4e4, 6e4), st.floats(0.0, 0.012))
def test_the_float_column_balance_is_the_generic_one_bit_for_bit(depth, sz, previous):
    foot = mudrft.feet.MorphingFoot()
    row = linkage_row(foot.linkage, foot.spring)
    got = on_floats(balanced_deflection_on_floats)(row, depth, sz, previous)
    assert got == balanced_deflection_on_floats(row, depth, sz, previous, xp=pyfloat)


# -- what is inlined --------------------------------------------------------------------


def _half(x, *, xp=np):
    y = 0.5 * x
    return y


def _recip(x, *, xp=np):
    return 1.0 / x


def _toy(x, *, xp=np):
    a = _half(x, xp=xp) + _half(2.0 * x, xp=xp)  # inlined twice, its names kept apart
    b = xp.where(x > 0.0, _recip(x, xp=xp), 0.0)  # a branch: called only when taken
    n = 0
    while _half(float(n), xp=xp) < 1.0:  # a while test: called at every test
        n += 1
    return a + b + n


def _branches(x, *, xp=np):
    # one-return callees in branches: inlined where their arguments are names or constants
    return xp.where(x > 0.0, _recip(x, xp=xp), xp.where(x < 0.0, _recip(x - 1.0, xp=xp), 0.0))


def _walrus(x, *, xp=np):
    y = (x := x + 1.0) + _half(x, xp=xp)  # _half must see the new x: not moved before
    return y


def _walrus_i(x, *, xp=np):
    y = (_idx := x + 1.0) + _half(_idx, xp=xp)  # a name like the rewrite's own temporaries
    return y


@pytest.fixture
def toys(monkeypatch):
    """The toy functions as mudrft functions (the specializer rewrites only those)."""
    for f in (_half, _recip, _toy, _branches, _walrus, _walrus_i, _extrema, _tanh):
        monkeypatch.setattr(f, "__module__", "mudrft._toy")
    on_floats.cache_clear()
    yield
    on_floats.cache_clear()


def test_straight_line_callees_are_inlined_where_always_evaluated(toys):
    fdef, _env = on_floats(_toy).__specialized__
    calls = [
        n.func.id
        for n in ast.walk(fdef)
        if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)
    ]
    # the two halves of `a` inlined, and `_recip` (one return, a name for argument) as an
    # expression in the branch of the where; the while test still calls `_half`
    assert sorted(c for c in calls if c.startswith("_k_")) == ["_k_mudrft__toy__half"]
    assert on_floats(_toy)(2.0) == _toy(2.0, xp=pyfloat) == 3.0 + 0.5 + 2


def test_one_return_callees_are_inlined_in_branches_where_their_arguments_are_names(toys):
    fdef, _env = on_floats(_branches).__specialized__
    calls = [n.func.id for n in ast.walk(fdef) if isinstance(n, ast.Call)]
    assert calls == ["_k_mudrft__toy__recip"], ast.unparse(fdef)  # only the x - 1.0 one
    for x in (2.0, -3.0):
        assert on_floats(_branches)(x) == _branches(x, xp=pyfloat)
    assert on_floats(_branches)(0.0) == 0.0  # neither branch evaluated (1/0 on floats)


def _extrema(x, *, xp=np):
    # a name, a constant, an expression, and a name the other operand reassigns
    return xp.maximum(x, 0.0) + xp.minimum(2.0 * x, 1.0) + xp.maximum(x, (x := 2.0 * x) - 5.0)


def test_maximum_and_minimum_store_only_what_they_must_evaluate_once(toys):
    fdef, _env = on_floats(_extrema).__specialized__
    stored = sorted(n.target.id for n in ast.walk(fdef) if isinstance(n, ast.NamedExpr))
    # 2.0 * x, and the x read before (x := ...) reassigns it; the rest read as they are
    assert [s for s in stored if s != "x"] == ["_xp_t0", "_xp_t1", "_xp_t2"], stored
    for x in (-1.0, 0.25, 1.0, 4.0):
        assert on_floats(_extrema)(x) == _extrema(x, xp=pyfloat), x


def _tanh(x, *, xp=np):
    return xp.tanh(x)


def test_tanh_is_not_called_at_zero_and_keeps_its_sign(toys):
    import math

    f = on_floats(_tanh)
    _fdef, env = f.__specialized__
    calls = []
    env["_xp_tanh"] = lambda x: calls.append(x) or math.tanh(x)  # the function's globals
    for x in (0.0, -0.0, 0, 1e-300, -2.0, 30.0, float("inf"), float("nan")):
        got, want = f(x), _tanh(x, xp=pyfloat)
        assert type(got) is float and math.copysign(1.0, got) == math.copysign(1.0, want), x
        assert got == want or (math.isnan(got) and math.isnan(want)), x
    assert len(calls) == 5  # all but the three zeros


def test_a_branch_not_taken_is_not_evaluated_on_floats(toys):
    with pytest.raises(ZeroDivisionError):  # the generic float path evaluates both branches
        _toy(0.0, xp=pyfloat)
    assert on_floats(_toy)(0.0) == 2.0  # a = b = 0; the loop ran twice


def test_without_source_the_float_path_runs_the_generic_code(monkeypatch):
    def no_source(obj):
        raise OSError("could not get source code")

    monkeypatch.setattr("mudrft._specialize.inspect.getsource", no_source)
    on_floats.cache_clear()
    try:
        c = channel_constants(mudrft.paper_parameters(0.25))
        s = ChannelState(*[0.0] * len(ChannelState._fields))
        args = (kernel.ChannelConstants(*map(float, c)), s, 0.1, 1.0, 1e-3)
        step = on_floats(kernel.channel_update)
        assert not hasattr(step, "__specialized__")  # nothing rewritten
        assert step(*args) == kernel.channel_update(*args, xp=pyfloat)
        terrain = mudrft.MudTerrain(mudrft.paper_mud(0.25))  # the whole float path still runs
        foot = mudrft.feet.Flat()
        st = terrain.initial_state(foot, np.zeros(3))
        out = terrain.step(foot, st, [0.0, 0.0, -0.01], [0.0, 0.0, -0.02], 1e-3)[1]
        assert out.force[2] > 0.0
    finally:
        monkeypatch.undo()
        on_floats.cache_clear()


def test_a_statement_with_an_assignment_expression_keeps_its_calls_in_place(toys):
    assert on_floats(_walrus)(1.0) == _walrus(1.0, xp=pyfloat) == 2.0 + 1.0
    assert on_floats(_walrus_i)(1.0) == _walrus_i(1.0, xp=pyfloat) == 2.0 + 1.0


# -- named tuples on floats ---------------------------------------------------------------
class _Pair(NamedTuple):
    a: float
    b: float


class _Checked(_Pair):
    """A named tuple whose own __new__ checks its input (must not be bypassed)."""

    def __new__(cls, a: float, b: float) -> _Checked:
        if a < 0:
            raise ValueError("a must be >= 0")
        return super().__new__(cls, a, b)


def _pair(x, *, xp=np):
    return _Pair(b=2.0 * x, a=x)


def _pair_positional(x, *, xp=np):
    return _Pair(x, 2.0 * x)


def _checked(x, *, xp=np):
    return _Checked(x, 2.0 * x)


@pytest.fixture
def tuple_toys(monkeypatch):
    for f in (_pair, _pair_positional, _checked):
        monkeypatch.setattr(f, "__module__", "mudrft._toy")
    on_floats.cache_clear()
    yield
    on_floats.cache_clear()


def test_named_tuples_are_made_without_their_python_new_unless_it_is_their_own(tuple_toys):
    for fn in (_pair, _pair_positional):
        fdef, _env = on_floats(fn).__specialized__
        made = [n.func.id for n in ast.walk(fdef) if isinstance(n, ast.Call)]
        assert made == ["_xp_tuple_new"], ast.unparse(fdef)
        out = on_floats(fn)(3.0)
        assert type(out) is _Pair and out == fn(3.0, xp=pyfloat) == (3.0, 6.0)
        assert out.b == 6.0
    # a subclass with its own __new__ keeps it: its check still runs
    fdef, _env = on_floats(_checked).__specialized__
    assert "_xp_tuple_new" not in ast.unparse(fdef)
    with pytest.raises(ValueError, match="a must be >= 0"):
        on_floats(_checked)(-1.0)


def test_the_float_exp_overflows_to_inf_as_numpy_does():
    edge = 709.782712893384  # log of the largest double: the last argument math.exp takes
    with np.errstate(over="ignore"):
        for x in (edge, np.nextafter(edge, np.inf), 1e308, np.inf, -np.inf, -800.0, 0.0):
            assert pyfloat.exp(float(x)) == float(np.exp(x)), x
    assert np.isnan(pyfloat.exp(float("nan")))


# -- named-tuple arguments read once ------------------------------------------------------
class _Three(NamedTuple):
    a: float
    b: float
    c: float


class _Sub(_Three):
    @property
    def a(self) -> float:  # a subclass that reads a field its own way
        return -1.0


class _Duck:
    a, b, c = 1.0, 2.0, 3.0


def _sum3(t: _Three, x, *, xp=np):
    return t.a * x + t.b + t.c * t.a


@pytest.fixture
def field_toys(monkeypatch):
    monkeypatch.setattr(_sum3, "__module__", "mudrft._toy")
    on_floats.cache_clear()
    yield
    on_floats.cache_clear()


def test_a_named_tuple_argument_is_unpacked_once_for_its_own_class_only(field_toys):
    f = on_floats(_sum3)
    names = f.__code__.co_names
    assert "_xp_plain" in names and "a" not in names, names  # unpacked: no attribute read
    for t in (_Three(1.0, 2.0, 3.0), _Sub(1.0, 2.0, 3.0), _Duck()):
        assert f(t, 0.5) == _sum3(t, 0.5, xp=pyfloat), t  # others: the reads as written
    assert f(_Sub(1.0, 2.0, 3.0), 0.5) == -0.5 + 2.0 - 3.0
    fdef, _env = f.__specialized__  # callers inline the function without the entry check
    assert "_xp_plain" not in ast.unparse(fdef)


def _refresh(t: _Three, fresh, *, xp=np):
    return _Three(
        a=xp.where(fresh, 0.0, t.a), b=xp.where(fresh, 0.0, t.b), c=xp.where(fresh, 1.0, t.c)
    )


def test_a_tuple_of_conditionals_on_one_test_is_one_conditional_of_tuples(field_toys, monkeypatch):
    monkeypatch.setattr(_refresh, "__module__", "mudrft._toy")
    f = on_floats(_refresh)
    kept = _Three(1.0, 2.0, 3.0)
    assert f(kept, False) is kept  # its own fields, of its own class: not copied
    assert f(kept, True) == _refresh(kept, True, xp=pyfloat) == (0.0, 0.0, 1.0)
    for t in (_Sub(1.0, 2.0, 3.0), _Duck()):  # others are read field by field, as written
        got = f(t, False)
        assert type(got) is _Three and got == _refresh(t, False, xp=pyfloat), t
    assert f(_Sub(1.0, 2.0, 3.0), False) == (-1.0, 2.0, 3.0)


# -- control flow: if statements of assignments, an early return, fields read -------------
def _scaled(x, flag, *, xp=np):
    y = 2.0 * x
    if flag:  # an if statement that only assigns: inlined as it is
        y = y + 1.0
    return _Pair(y, 3.0 * x)


def _dispatch(x, flag, *, xp=np):
    if flag:  # an early return: the branch calls this function again, the rest is inlined
        return _Pair(-x, 0.0)
    p = _scaled(x, flag, xp=xp)
    return _Pair(p.a + 1.0, p.b)


def _uses_a(x, flag, *, xp=np):
    u = _dispatch(x, flag, xp=xp)  # only u.a is read: u is not made where it is built
    v = _dispatch(2.0 * x, flag, xp=xp)
    return u.a * v.a + v.b


@pytest.fixture
def flow_toys(monkeypatch):
    for f in (_scaled, _dispatch, _uses_a):
        monkeypatch.setattr(f, "__module__", "mudrft._toy")
    on_floats.cache_clear()
    yield
    on_floats.cache_clear()


def _calls(fdef):
    return sorted(n.func.id for n in ast.walk(fdef) if isinstance(n, ast.Call))


def test_callees_with_if_statements_of_assignments_are_inlined(flow_toys):
    fdef, _env = on_floats(_dispatch).__specialized__
    assert not [c for c in _calls(fdef) if "_scaled" in c], ast.unparse(fdef)  # inlined
    for x, flag in ((1.5, False), (1.5, True), (-2.0, False)):
        assert on_floats(_dispatch)(x, flag) == _dispatch(x, flag, xp=pyfloat)


def test_a_callee_with_an_early_return_is_inlined_as_an_if_statement(flow_toys):
    fdef, _env = on_floats(_uses_a).__specialized__
    # both calls of _dispatch inlined: each an if statement whose early branch calls the
    # specialization of _dispatch, the rest (and _scaled in it) in place
    calls = _calls(fdef)
    assert not [c for c in calls if "_dispatch" in c or "_scaled" in c], ast.unparse(fdef)
    assert sum(c.endswith("_g__xp_self") for c in calls) == 2, ast.unparse(fdef)
    assert sum(isinstance(n, ast.If) for n in ast.walk(fdef)) >= 2
    for x, flag in ((1.5, False), (1.5, True), (-2.0, False), (0.0, True)):
        assert on_floats(_uses_a)(x, flag) == _uses_a(x, flag, xp=pyfloat), (x, flag)


def test_a_local_named_tuple_read_by_field_is_its_fields(flow_toys):
    fdef, _env = on_floats(_uses_a).__specialized__
    text = ast.unparse(fdef)
    # u is never made where _dispatch is inlined (only u.a is read, its other element a
    # name or a constant); after the early branch's call, u.a is read right away
    assert "_xp_field_u_a" in text and "_xp_field_v_b" in text, text
    made = [n for n in ast.walk(fdef) if isinstance(n, ast.Call) and "tuple_new" in n.func.id]
    assert not made, text
    assert [n.attr for n in ast.walk(fdef) if isinstance(n, ast.Attribute)] == ["a", "a", "b"]
    assert on_floats(_uses_a)(1.0, False) == _uses_a(1.0, False, xp=pyfloat) == 3.0 * 5.0 + 6.0


def _copies(x, *, xp=np):
    p = _Pair(x, 2.0 * x)  # returned, so made; p.a read back is x itself
    y = _half(p.a, xp=xp)  # the inlined parameter: a copy of x
    k = 3.0  # a constant, assigned once
    return p, y * k


def test_copies_are_read_from_their_source(monkeypatch):
    for f in (_half, _copies):
        monkeypatch.setattr(f, "__module__", "mudrft._toy")
    on_floats.cache_clear()
    try:
        f = on_floats(_copies)
        fdef, _env = f.__specialized__
        text = ast.unparse(fdef)
        # no field read back, no copy of x or of the constant: only p and the half stored
        assert not [n for n in ast.walk(fdef) if isinstance(n, ast.Attribute)], text
        stored = {n.id for n in ast.walk(fdef) if isinstance(n, ast.Name) and n.ctx == ast.Store()}
        assert "k" not in stored and not [s for s in stored if s.endswith("_x")], text
        assert "_i" in text and "0.5 * x" in text and "* 3.0" in text, text
        assert f(2.0) == _copies(2.0, xp=pyfloat) == ((2.0, 4.0), 3.0)
        assert f.__code__.co_nlocals == 3  # x, p and the half
    finally:
        on_floats.cache_clear()


def _pair_sum(pair: tuple[_Three, _Three], x, *, xp=np):
    y = 2.0 * x
    u, v = pair  # each read field by field: unpacked after this line, for their own class
    return u.a * y + u.b + u.c * u.a + v.a * v.b + v.c


def test_a_pair_of_named_tuples_is_unpacked_once_for_its_own_classes_only(monkeypatch):
    monkeypatch.setattr(_pair_sum, "__module__", "mudrft._toy")
    on_floats.cache_clear()
    try:
        f = on_floats(_pair_sum)
        names = f.__code__.co_names
        assert "_xp_plain" in names and not {"a", "b", "c"} & set(names), names
        t, s = _Three(1.0, 2.0, 3.0), _Sub(1.0, 2.0, 3.0)
        for pair in ((t, t), (t, s), (s, t), (_Duck(), t), (t, _Duck())):
            assert f(pair, 0.5) == _pair_sum(pair, 0.5, xp=pyfloat), pair
        assert f((t, s), 0.5) == 1.0 + 2.0 + 3.0 - 2.0 + 3.0
    finally:
        on_floats.cache_clear()
