"""Copies left by inlining, read from their source (:mod:`mudrft._specialize`).

Inlining binds a callee's parameters to the caller's values (``_i12_k_a = c.k_a``), returns
tuples that the caller unpacks into its own names (``gw_new, direction = (_i10_gw_new,
_i10_direction)``), and reads back fields of the named tuple it has just made
(``new_state.gamma``). Each copy costs a load and a store, and each name a slot of the frame
that every call clears (about a nanosecond each). :func:`propagate_copies` reads the source
instead: a name ``a`` assigned only once, from a name ``b`` that is a parameter never
assigned or a local assigned only once, or from a constant, is ``b`` wherever it is read;
and ``x.field`` of a local ``x`` assigned only once, a named tuple made by the rewrite
(:func:`mudrft._specialize_tuples.new_tuple`), is that field's element where the element is
such a name or a constant. Every read of ``a`` comes after its one assignment, which read
``b`` after its one assignment: the same value, the same floats bit for bit (docs/model.md,
D80). Functions with loops, nested scopes or ``del`` are left as they are.
"""

from __future__ import annotations

import ast
from typing import Any

from ._specialize_tuples import fields_of, plain_fields

__all__ = ["propagate_copies"]


def propagate_copies(fdef: ast.FunctionDef, env: dict[str, Any]) -> bool:
    """Rewrite ``fdef`` so that copies are read from their source (see the module
    docstring); the copies themselves are dropped. Returns whether anything changed."""
    nodes = [n for st in fdef.body for n in ast.walk(st)]
    if any(
        isinstance(n, (ast.For, ast.While, ast.AsyncFor, ast.Lambda, ast.FunctionDef))
        or isinstance(n, (ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp))
        or isinstance(n, (ast.ClassDef, ast.Global, ast.Nonlocal, ast.Try, ast.Delete))
        for n in nodes
    ):
        return False
    a = fdef.args
    params = {x.arg for x in (*a.posonlyargs, *a.args, *a.kwonlyargs, a.vararg, a.kwarg) if x}
    stores: dict[str, int] = {}
    for n in nodes:
        if isinstance(n, ast.Name) and not isinstance(n.ctx, ast.Load):
            stores[n.id] = stores.get(n.id, 0) + 1

    def once(name: str) -> bool:  # one value in the whole call
        return stores.get(name, 0) == (0 if name in params else 1)

    def source(value: ast.expr) -> bool:
        return (isinstance(value, ast.Name) and once(value.id)) or (
            isinstance(value, ast.Constant) and isinstance(value.value, (int, float, bool))
        )

    copies: dict[str, ast.expr] = {}  # a -> its source
    made: dict[str, tuple[tuple[str, ...], list[ast.expr]]] = {}  # x -> fields, elements
    pairs: list[tuple[ast.Name, ast.expr]] = []  # every name assigned once, and its value
    for n in nodes:
        if not (isinstance(n, ast.Assign) and len(n.targets) == 1):
            continue
        t = n.targets[0]
        if isinstance(t, ast.Tuple) and isinstance(n.value, ast.Tuple):
            if len(t.elts) != len(n.value.elts):
                continue
            sources = {v.id for v in n.value.elts if isinstance(v, ast.Name)}
            these = list(zip(t.elts, n.value.elts, strict=True))
        else:
            sources, these = set(), [(t, n.value)]
        pairs += [
            (x, v)
            for x, v in these
            if isinstance(x, ast.Name) and once(x.id) and x.id not in sources
        ]
    for x, v in pairs:
        if (m := fields_of(v, env)) is not None:
            made[x.id] = (plain_fields(m[0]) or (), m[1])

    def field(e: ast.expr) -> ast.expr | None:
        """The element that ``x.field`` of a made tuple ``x`` reads, if a source."""
        if isinstance(e, ast.Attribute) and isinstance(e.value, ast.Name) and e.value.id in made:
            fields, elements = made[e.value.id]
            if e.attr in fields and source(elements[fields.index(e.attr)]):
                return elements[fields.index(e.attr)]
        return None

    for x, v in pairs:
        if source(v) or (v := field(v)) is not None:  # type: ignore[assignment]
            copies[x.id] = v
    if not copies and not made:
        return False

    def resolve(e: ast.expr) -> ast.expr:
        while isinstance(e, ast.Name) and e.id in copies:
            e = copies[e.id]
        return ast.Name(e.id, ast.Load()) if isinstance(e, ast.Name) else ast.Constant(e.value)  # type: ignore[attr-defined]

    class Reads(ast.NodeTransformer):
        def visit_Name(self, n: ast.Name) -> ast.AST:
            if isinstance(n.ctx, ast.Load) and n.id in copies:
                return ast.copy_location(resolve(n), n)
            return n

        def visit_Attribute(self, n: ast.Attribute) -> ast.AST:
            e = field(n) if isinstance(n.ctx, ast.Load) else None
            if e is not None:
                return ast.copy_location(resolve(e), n)
            self.generic_visit(n)
            return n

    def drop(block: list[ast.stmt]) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        for st in block:
            for field in ("body", "orelse"):
                inner = getattr(st, field, None)
                if isinstance(inner, list) and inner and isinstance(inner[0], ast.stmt):
                    setattr(st, field, drop(inner) or [ast.Pass()])
            if isinstance(st, ast.Assign) and len(st.targets) == 1:
                t = st.targets[0]
                if isinstance(t, ast.Name) and t.id in copies:
                    continue
                if isinstance(t, ast.Tuple) and isinstance(st.value, ast.Tuple):
                    kept = [
                        (x, v)
                        for x, v in zip(t.elts, st.value.elts, strict=True)
                        if not (isinstance(x, ast.Name) and x.id in copies)
                    ]
                    if not kept:
                        continue
                    if len(kept) == 1:
                        st.targets, st.value = [kept[0][0]], kept[0][1]
                    else:
                        t.elts = [x for x, _ in kept]
                        st.value.elts = [v for _, v in kept]
            out.append(Reads().visit(st))
        return out

    fdef.body = drop(fdef.body) or [ast.Pass()]
    return True
