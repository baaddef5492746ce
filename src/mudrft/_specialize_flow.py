"""Callees with an early return: inlined as an ``if`` statement (:mod:`mudrft._specialize`).

The inliner of :func:`mudrft._specialize.on_floats` inlines straight-line callees
(assignments, then one return). A callee that first dispatches on a name, as
:func:`mudrft.constitutive.kernel.channel_step` does on its static ``quasi_static``::

    def f(c, state, ..., quasi_static):
        if quasi_static:
            return ...
        <straight-line statements>
        return B

called as the whole value of an assignment to names (``cx, sx = f(...)``), is inlined as::

    if quasi_static':
        cx, sx = f_specialized(c', state', ..., quasi_static')
    else:
        <the statements'>
        cx, sx = B'

(primes: the callee's names renamed apart, its parameters bound to the arguments, each
argument evaluated once before the ``if``). The early branch calls the callee's own
specialization, which tests the same name again and takes its early return; the rest is
inlined (the other evaluation, taken when the name is false, is not copied in: its locals
would cost every call, taken or not, about a nanosecond each). The names are assigned last
in each branch, as the assignment did after the call returned. The same floats bit for bit
(docs/model.md, D80).

The inliner's order of evaluation lives here too: which calls evaluating an expression
always evaluates (:func:`always_evaluated`), which parts of a statement run once before it
does anything else (:func:`evaluated_parts`), and the location inlined statements take
(:func:`located_at`, so that a traceback names the call's line).
"""

from __future__ import annotations

import ast
import copy
from collections.abc import Callable

__all__ = [
    "always_evaluated",
    "as_branches",
    "assign_in_branches",
    "evaluated_parts",
    "located_at",
]

#: The placeholder the branches assign (renamed apart by the inliner, then replaced).
RESULT = "_xp_result"
#: The name of a specialization in its own environment (its early branch calls it).
SELF = "_xp_self"


def _names_target(st: ast.stmt, call: ast.Call) -> bool:
    """Whether ``st`` is ``<names> = call`` (one target: a name or a tuple of names)."""
    if not (isinstance(st, ast.Assign) and len(st.targets) == 1 and st.value is call):
        return False
    t = st.targets[0]
    names = t.elts if isinstance(t, ast.Tuple) else [t]
    return all(isinstance(n, ast.Name) for n in names)


def as_branches(
    fdef: ast.FunctionDef, st: ast.stmt, call: ast.Call,
    straight_line: Callable[[ast.FunctionDef], bool], body: list[ast.stmt],
) -> ast.FunctionDef | None:  # fmt: skip
    """``fdef`` (whose statements without docstring are ``body``) as a straight-line
    definition ``if test: _xp_result = _xp_self(<its parameters>)`` ``else: ...;
    _xp_result = B``, ``return _xp_result``, when it has the early-return form above (the
    test a name or a constant) and ``st`` is ``<names> = call``; else None."""
    if not _names_target(st, call) or len(body) < 2:
        return None
    first, rest = body[0], body[1:]
    if not (
        isinstance(first, ast.If)
        and isinstance(first.test, (ast.Name, ast.Constant))
        and not first.orelse
        and isinstance(first.body[-1], ast.Return)
    ):
        return None
    tail = copy.copy(fdef)
    tail.body = rest
    if not straight_line(tail):
        return None
    ret = rest[-1]
    assert isinstance(ret, ast.Return) and ret.value is not None
    a = fdef.args
    again = ast.Call(  # the early branch: the specialization itself, as the call was
        func=ast.Name(SELF, ast.Load()),
        args=[ast.Name(x.arg, ast.Load()) for x in a.args],
        keywords=[ast.keyword(x.arg, ast.Name(x.arg, ast.Load())) for x in a.kwonlyargs],
    )

    def result(value: ast.expr) -> ast.Assign:
        return ast.Assign(targets=[ast.Name(RESULT, ast.Store())], value=value)

    branch = ast.If(test=first.test, body=[result(again)], orelse=[*rest[:-1], result(ret.value)])
    out = copy.copy(fdef)
    out.body = [branch, ast.Return(ast.Name(RESULT, ast.Load()))]
    return out


def assign_in_branches(pre: list[ast.stmt], value: ast.expr, st: ast.Assign) -> None:
    """Make the branches in ``pre`` (the inlined :func:`as_branches`, whose result is the
    name ``value``) assign ``st``'s target instead of the placeholder."""
    assert isinstance(value, ast.Name)
    for n in ast.walk(pre[-1]):
        if isinstance(n, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == value.id for t in n.targets
        ):
            n.targets = [copy.deepcopy(st.targets[0])]


def always_evaluated(node: ast.AST) -> list[ast.Call]:
    """Calls in ``node`` that evaluating it always evaluates, outermost first."""
    found: list[ast.Call] = []

    def walk(n: ast.AST) -> None:
        if isinstance(n, ast.Call):
            found.append(n)
            for c in (n.func, *n.args, *n.keywords):
                walk(c)
            return
        if isinstance(n, ast.IfExp):
            walk(n.test)
            return
        if isinstance(n, ast.BoolOp):
            walk(n.values[0])
            return
        if isinstance(n, ast.Compare) and len(n.ops) > 1:
            walk(n.left)
            walk(n.comparators[0])
            return
        if isinstance(n, (ast.Lambda, ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp)):
            return
        for c in ast.iter_child_nodes(n):
            walk(c)

    walk(node)
    return found


def evaluated_parts(st: ast.stmt) -> list[ast.AST]:
    """The parts of a statement evaluated once, before anything else it does."""
    if isinstance(st, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.Return, ast.Expr)):
        return [st.value] if st.value is not None else []
    if isinstance(st, ast.If):
        return [st.test]
    if isinstance(st, ast.For):
        return [st.iter]
    return []  # while (its test is evaluated again), with, try, ...: left as they are


def located_at(nodes: list[ast.stmt], where: ast.AST) -> list[ast.stmt]:
    """``nodes`` with every location set to ``where``'s (tracebacks name the call's line)."""
    for st in nodes:
        for n in ast.walk(st):
            if "lineno" in n._attributes:
                n.lineno = where.lineno  # type: ignore[attr-defined]
                n.end_lineno = where.end_lineno  # type: ignore[attr-defined]
                n.col_offset = where.col_offset  # type: ignore[attr-defined]
                n.end_col_offset = where.end_col_offset  # type: ignore[attr-defined]
    return nodes
