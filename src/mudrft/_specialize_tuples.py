"""Named tuples on floats: passes of the float specialization (:mod:`mudrft._specialize`).

The physics reads the constants and the state of a step by name (``c.k_a``, ``state.xi``)
and returns named tuples. On one foot's Python floats (:func:`mudrft._specialize.on_floats`)
each read goes through the field's descriptor, and each tuple made costs more than the
arithmetic around it. Three rewrites, each the same floats bit for bit (docs/model.md, D80):

* :func:`unpack_fields`: a parameter annotated with a named-tuple class, whose fields the
  function reads often enough, is unpacked once at entry into locals (a third of the cost
  of a read per field), guarded by the exact type of the argument: anything else (a
  subclass, another object with those attributes) goes to the function as it was; so are
  the elements of a ``tuple[X, Y]`` parameter unpacked by name (``hor, ver = ch``);
* :func:`drop_fields`: a local named tuple of which only fields are read is those fields
  (``sx.total`` when the terrain step reads only the total stress);
* :func:`shared_test` and :func:`new_tuple`: a named tuple whose every field is a
  conditional on one test (``xp.where(fresh, 0.0, ch.gamma)``, ...) is made as one
  conditional of two tuples, and a tuple of the fields of an argument ``x`` of that exact
  class, in order, is ``x`` itself (a channel state that stays as it was is not copied).
"""

from __future__ import annotations

import ast
import copy
import inspect
import types
import typing
from typing import Any

__all__ = ["drop_fields", "fields_of", "new_tuple", "plain_fields", "shared_test", "unpack_fields"]


def shared_test(elements: list[ast.expr]) -> ast.Name | None:
    """The name that every element tests (``a if t else b``), not assigned in any."""
    tests = {
        e.test.id for e in elements if isinstance(e, ast.IfExp) and isinstance(e.test, ast.Name)
    }
    if len(tests) != 1 or not all(isinstance(e, ast.IfExp) for e in elements):
        return None
    test = next(iter(tests))
    if any(
        isinstance(n, ast.NamedExpr) and n.target.id == test for e in elements for n in ast.walk(e)
    ):
        return None
    return ast.Name(test, ast.Load())


def new_tuple(name: str, elements: list[ast.expr], fields: tuple[str, ...] | None) -> ast.expr:
    """``tuple.__new__`` of the named tuple ``name`` (in the environment) from ``elements``;
    when they are ``x.<field>`` of one name ``x`` in the order of the fields, ``x`` itself
    if it is of that exact class (the same floats; its own fields are the elements)."""
    new = ast.Call(
        func=ast.Name("_xp_tuple_new", ast.Load()),
        args=[ast.Name(name, ast.Load()), ast.Tuple(elts=elements, ctx=ast.Load())],
        keywords=[],
    )
    x = {
        e.value.id
        for e in elements
        if isinstance(e, ast.Attribute) and isinstance(e.value, ast.Name)
    }
    if len(x) != 1 or [getattr(e, "attr", None) for e in elements] != list(fields or ()):
        return new
    name_x = next(iter(x))
    same = ast.Compare(
        left=ast.Call(ast.Name("_xp_type", ast.Load()), [ast.Name(name_x, ast.Load())], []),
        ops=[ast.Is()],
        comparators=[ast.Name(name, ast.Load())],
    )
    return ast.IfExp(test=same, body=ast.Name(name_x, ast.Load()), orelse=new)


def plain_fields(cls: object) -> tuple[str, ...] | None:
    """The fields of ``cls`` if it is a named tuple whose fields are the tuple's elements
    and whose iteration is the tuple's (no field redefined, no ``__iter__`` of its own)."""
    fields = getattr(cls, "_fields", None)
    if not (isinstance(cls, type) and issubclass(cls, tuple) and isinstance(fields, tuple)):
        return None
    owner = next((k for k in cls.__mro__ if "_fields" in vars(k)), None)
    if owner is None or cls.__iter__ is not tuple.__iter__:
        return None
    getter = type(vars(owner).get(fields[0])) if fields else None
    if not fields or any(
        type(inspect.getattr_static(cls, f)) is not getter
        or inspect.getattr_static(cls, f) is not vars(owner).get(f)
        for f in fields
    ):
        return None
    return fields


def _annotated_tuples(fn: types.FunctionType) -> dict[str, tuple[type, tuple[str, ...]]]:
    """Parameters of ``fn`` annotated with a plain named-tuple class: name -> (class, fields)."""
    out = {}
    for name, ann in getattr(fn, "__annotations__", {}).items():
        try:
            cls = eval(ann, fn.__globals__) if isinstance(ann, str) else ann
        except Exception:  # a name only imported for type checking, a generic alias...
            continue
        fields = plain_fields(cls)
        if fields is not None and name != "return":
            out[name] = (cls, fields)
    return out


def unpack_fields(
    fn: types.FunctionType, fdef: ast.FunctionDef, env: dict[str, Any], plain: str
) -> bool:
    """Rewrite ``fdef`` (the specialization of ``fn``) to unpack its named-tuple parameters.

    A parameter qualifies if it is annotated with a plain named tuple, never assigned, and
    its fields are read (``p.field``) at least half as many times as it has fields: then
    ``_xp_p_<field>, ... = p`` once at entry is cheaper than the reads. The entry checks
    ``type(p) is`` the annotated class for every such parameter and otherwise returns
    ``plain(...)`` with the same arguments, ``plain`` being the name in ``env`` of the
    function before this pass. A parameter annotated with a tuple of plain named tuples
    (``ch: tuple[ChannelConstants, ChannelConstants]``) and read only as ``hor, ver = ch``
    gives locals of known classes: their fields are unpacked right after that statement,
    behind the same check (the function, free of side effects and with no parameter
    assigned, then starts again from its entry). Returns whether anything was rewritten.
    """
    if any(
        isinstance(n, (ast.Lambda, ast.FunctionDef, ast.ClassDef, ast.ListComp, ast.SetComp))
        or isinstance(n, (ast.DictComp, ast.GeneratorExp, ast.Global, ast.Nonlocal))
        for st in fdef.body
        for n in ast.walk(st)
    ):  # a nested scope would read the locals as cells: left as it is
        return False
    a = fdef.args
    if a.vararg or a.kwarg or a.posonlyargs:
        return False
    stored = {
        n.id
        for st in fdef.body
        for n in ast.walk(st)
        if isinstance(n, ast.Name) and not isinstance(n.ctx, ast.Load)
    }
    reads: dict[str, int] = {}
    for st in fdef.body:
        for n in ast.walk(st):
            if isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name):
                reads[n.value.id] = reads.get(n.value.id, 0) + 1
    chosen = {
        name: (cls, fields)
        for name, (cls, fields) in _annotated_tuples(fn).items()
        if name in {x.arg for x in (*a.args, *a.kwonlyargs)}
        and name not in stored
        and reads.get(name, 0) >= max(2, len(fields) / 2)
    }
    derived = _unpacked_pairs(fn, fdef, reads)  # local -> (class, fields, statement)
    if not chosen and not derived:
        return False
    every = {name: fields for name, (_, fields) in chosen.items()}
    every.update({name: fields for name, (_, fields, _) in derived.items()})

    class Fields(ast.NodeTransformer):
        def visit_Attribute(self, n: ast.Attribute) -> ast.AST:
            self.generic_visit(n)
            v = n.value
            if isinstance(v, ast.Name) and v.id in every and n.attr in every[v.id]:
                if isinstance(n.ctx, ast.Load):
                    return ast.copy_location(ast.Name(f"_xp_{v.id}_{n.attr}", ast.Load()), n)
            return n

    body = [Fields().visit(st) for st in fdef.body]
    env["_xp_type"] = type
    call = ast.Call(
        func=ast.Name(plain, ast.Load()),
        args=[ast.Name(x.arg, ast.Load()) for x in a.args],
        keywords=[ast.keyword(x.arg, ast.Name(x.arg, ast.Load())) for x in a.kwonlyargs],
    )
    after: dict[int, dict[str, tuple[type, tuple[str, ...]]]] = {-1: chosen}
    for name, (cls, fields, i) in derived.items():
        after.setdefault(i, {})[name] = (cls, fields)
    for i in sorted(after, reverse=True):  # the checks and unpacking after statement i
        where = fdef if i < 0 else fdef.body[i]
        if after[i]:
            body[i + 1 : i + 1] = _located(_checked_unpack(after[i], env, call), where)
    fdef.body = body
    return True


def _checked_unpack(
    names: dict[str, tuple[type, tuple[str, ...]]], env: dict[str, Any], call: ast.Call
) -> list[ast.stmt]:
    """``if type(x) is not X or ...: return call`` then ``_xp_x_<field>, ... = x``."""
    checks: list[ast.expr] = []
    for name, (cls, _) in names.items():
        env[cls_name := f"_xp_cls_{cls.__name__}_{id(cls)}"] = cls
        checks.append(
            ast.Compare(
                left=ast.Call(ast.Name("_xp_type", ast.Load()), [ast.Name(name, ast.Load())], []),
                ops=[ast.IsNot()],
                comparators=[ast.Name(cls_name, ast.Load())],
            )
        )
    test = checks[0] if len(checks) == 1 else ast.BoolOp(op=ast.Or(), values=checks)
    out: list[ast.stmt] = [ast.If(test=test, body=[ast.Return(copy.deepcopy(call))], orelse=[])]
    for name, (_, fields) in names.items():
        targets: list[ast.expr] = [ast.Name(f"_xp_{name}_{f}", ast.Store()) for f in fields]
        out.append(
            ast.Assign(targets=[ast.Tuple(targets, ast.Store())], value=ast.Name(name, ast.Load()))
        )
    return out


def _located(stmts: list[ast.stmt], where: ast.AST) -> list[ast.stmt]:
    """``stmts`` located at ``where``'s line (a traceback names the function's line)."""
    for st in stmts:
        for n in ast.walk(st):
            if "lineno" in n._attributes:
                n.lineno = n.end_lineno = where.lineno  # type: ignore[attr-defined]
                n.col_offset = n.end_col_offset = 0  # type: ignore[attr-defined]
    return stmts


def _unpacked_pairs(
    fn: types.FunctionType, fdef: ast.FunctionDef, reads: dict[str, int]
) -> dict[str, tuple[type, tuple[str, ...], int]]:
    """Locals ``x`` of ``x, y = p`` (a statement of the body, ``i``), ``p`` a parameter
    annotated ``tuple[X, Y]`` of plain named tuples and read only so, ``x`` assigned only
    there and its fields read often enough: ``x -> (X, fields, i)``. After statement ``i``
    the function can start again from its entry (no parameter is assigned, no loop)."""
    out: dict[str, tuple[type, tuple[str, ...], int]] = {}
    nodes = [n for st in fdef.body for n in ast.walk(st)]
    if any(isinstance(n, (ast.For, ast.While, ast.AsyncFor, ast.Try)) for n in nodes):
        return out
    stores: dict[str, int] = {}
    for n in nodes:
        if isinstance(n, ast.Name) and not isinstance(n.ctx, ast.Load):
            stores[n.id] = stores.get(n.id, 0) + 1
    a = fdef.args
    params = {x.arg for x in (*a.args, *a.kwonlyargs)}
    if params & set(stores):
        return out
    for name, classes in _annotated_pairs(fn).items():
        if name not in params:
            continue
        loads = [n for n in nodes if isinstance(n, ast.Name) and n.id == name]
        sites = [
            (i, st)
            for i, st in enumerate(fdef.body)
            if isinstance(st, ast.Assign)
            and isinstance(st.value, ast.Name)
            and st.value.id == name
            and len(st.targets) == 1
            and isinstance(st.targets[0], ast.Tuple)
            and len(st.targets[0].elts) == len(classes)
        ]
        if len(sites) != len(loads):  # p read otherwise
            continue
        for i, st in sites:
            for x, cls in zip(st.targets[0].elts, classes, strict=True):  # type: ignore[attr-defined]
                fields = plain_fields(cls) or ()
                if (
                    isinstance(x, ast.Name)
                    and stores.get(x.id) == 1
                    and reads.get(x.id, 0) >= max(2, len(fields) / 2)
                ):
                    out[x.id] = (cls, fields, i)
    return out


def _annotated_pairs(fn: types.FunctionType) -> dict[str, tuple[type, ...]]:
    """Parameters of ``fn`` annotated ``tuple[X, Y, ...]`` of plain named tuples."""
    out = {}
    for name, ann in getattr(fn, "__annotations__", {}).items():
        try:
            t = eval(ann, fn.__globals__) if isinstance(ann, str) else ann
        except Exception:  # a name only imported for type checking...
            continue
        args = typing.get_args(t)
        if typing.get_origin(t) is tuple and args and all(plain_fields(c) for c in args):
            out[name] = args
    return out


def fields_of(value: ast.expr, env: dict[str, Any]) -> tuple[object, list[ast.expr]] | None:
    """``(class, elements)`` when ``value`` is ``tuple.__new__(<named tuple>, (elements))``
    as the rewrite makes it (:func:`new_tuple`), else None."""
    if not (
        isinstance(value, ast.Call)
        and isinstance(value.func, ast.Name)
        and env.get(value.func.id) is tuple.__new__
        and len(value.args) == 2
        and isinstance(value.args[0], ast.Name)
        and isinstance(value.args[1], ast.Tuple)
        and not value.keywords
    ):
        return None
    cls = env.get(value.args[0].id)
    fields = plain_fields(cls)
    elements = value.args[1].elts
    if (
        fields is None
        or len(fields) != len(elements)
        or any(isinstance(e, ast.Starred) for e in elements)
    ):
        return None
    return cls, elements


def drop_fields(fdef: ast.FunctionDef, env: dict[str, Any]) -> bool:
    """Rewrite ``fdef`` so that a local named tuple of which only some fields are read is
    those fields, as locals (``sx.total`` -> ``_xp_field_sx_total``).

    A local qualifies if every read of it is a field read (``x.field``) and every
    assignment is ``x = <value>`` or ``..., x, ... = (..., <value>, ...)``; where the value
    is a named tuple the rewrite makes (:func:`new_tuple`), the fields read are assigned its
    elements and the others (names or constants only) are not made; where it is anything
    else (a call), its fields read are read once right after the assignment (the physics
    is free of side effects). At least one assignment must make the tuple, all of one
    class. Returns whether anything was rewritten.
    """
    nodes = [n for st in fdef.body for n in ast.walk(st)]
    if any(
        isinstance(n, (ast.For, ast.While, ast.AsyncFor, ast.Lambda, ast.FunctionDef))
        or isinstance(n, (ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp))
        or isinstance(n, (ast.ClassDef, ast.Global, ast.Nonlocal, ast.Try))
        for n in nodes
    ):
        return False
    params = {a.arg for a in (*fdef.args.args, *fdef.args.kwonlyargs, *fdef.args.posonlyargs)}
    used = {n.id for n in nodes if isinstance(n, ast.Name)} | params
    field_reads = {
        id(n.value): n.attr
        for n in nodes
        if isinstance(n, ast.Attribute)
        and isinstance(n.value, ast.Name)
        and isinstance(n.ctx, ast.Load)
    }
    # every store of a name as an assignment target: (statement, index in a tuple target)
    stores: dict[str, list[tuple[ast.Assign, int | None]]] = {}
    bad: set[str] = set(params)
    for n in nodes:
        if isinstance(n, ast.Assign) and len(n.targets) == 1:
            t = n.targets[0]
            if isinstance(t, ast.Name):
                stores.setdefault(t.id, []).append((n, None))
            elif isinstance(t, ast.Tuple) and not any(
                isinstance(e, ast.Starred) for e in (*t.elts, *getattr(n.value, "elts", ()))
            ):
                if isinstance(n.value, ast.Tuple) and len(t.elts) != len(n.value.elts):
                    continue
                for i, e in enumerate(t.elts):
                    if isinstance(e, ast.Name):
                        stores.setdefault(e.id, []).append((n, i))
    counted = {id(s.targets[0] if i is None else s.targets[0].elts[i])  # type: ignore[attr-defined]
               for v in stores.values() for s, i in v}  # fmt: skip
    reads: dict[str, set[str]] = {}
    for n in nodes:
        if not isinstance(n, ast.Name):
            continue
        if isinstance(n.ctx, ast.Load):
            if id(n) in field_reads:
                reads.setdefault(n.id, set()).add(field_reads[id(n)])
            else:
                bad.add(n.id)
        elif id(n) not in counted:  # an assignment expression, a del, an unpacked target...
            bad.add(n.id)
    chosen: dict[str, tuple[str, ...]] = {}
    for name, where in stores.items():
        if name in bad or name not in reads:
            continue
        made = [fields_of(_value(s, i), env) for s, i in where]
        classes = {id(m[0]) for m in made if m is not None}
        if len(classes) != 1:
            continue
        cls = next(m[0] for m in made if m is not None)
        fields = plain_fields(cls) or ()
        kept = tuple(f for f in fields if f in reads[name])
        new = [f"_xp_field_{name}_{f}" for f in kept]
        if len(kept) != len(reads[name]) or used & set(new):
            continue
        if any(
            not isinstance(e, (ast.Name, ast.Constant))
            for m in made
            if m is not None
            for f, e in zip(fields, m[1], strict=True)
            if f not in kept
        ):
            continue  # an element not made might raise: left as it is
        chosen[name] = kept
    if not chosen:
        return False
    _rewrite_fields(fdef, env, chosen)
    return True


def _value(st: ast.Assign, i: int | None) -> ast.expr:
    """What the assignment ``st`` assigns to its target (``i``: the element of a tuple)."""
    if i is None or not isinstance(st.value, ast.Tuple):
        return st.value  # all of it (a tuple target of a call: not a made tuple)
    return st.value.elts[i]


def _rewrite_fields(
    fdef: ast.FunctionDef, env: dict[str, Any], chosen: dict[str, tuple[str, ...]]
) -> None:
    """:func:`drop_fields` for the locals ``chosen`` (name -> the fields read)."""

    def local(name: str, field: str, ctx: ast.expr_context) -> ast.Name:
        return ast.Name(f"_xp_field_{name}_{field}", ctx)

    hoisted: set[int] = set()  # the reads made right after an assignment

    class Reads(ast.NodeTransformer):
        def visit_Attribute(self, n: ast.Attribute) -> ast.AST:
            self.generic_visit(n)
            v = n.value
            if (
                isinstance(v, ast.Name)
                and v.id in chosen
                and isinstance(n.ctx, ast.Load)
                and id(n) not in hoisted
            ):
                return ast.copy_location(local(v.id, n.attr, ast.Load()), n)
            return n

    def read_after(name: str) -> ast.stmt:
        reads: list[ast.expr] = [
            ast.Attribute(ast.Name(name, ast.Load()), f, ast.Load()) for f in chosen[name]
        ]
        hoisted.update(id(r) for r in reads)
        targets: list[ast.expr] = [local(name, f, ast.Store()) for f in chosen[name]]
        return ast.Assign(targets=[_pack(targets, ast.Store())], value=_pack(reads))

    def assignment(st: ast.Assign) -> list[ast.stmt]:
        t = st.targets[0]
        if isinstance(t, ast.Tuple) and not isinstance(st.value, ast.Tuple):  # of a call
            names = [getattr(e, "id", "") for e in t.elts]
            after = [read_after(name) for name in names if name in chosen]
            return [st, *(ast.copy_location(s, st) for s in after)]
        pairs = (
            list(zip(t.elts, st.value.elts, strict=True))  # type: ignore[attr-defined]
            if isinstance(t, ast.Tuple)
            else [(t, st.value)]
        )
        targets: list[ast.expr] = []
        values: list[ast.expr] = []
        after = []
        for target, value in pairs:
            name = getattr(target, "id", "")
            made = fields_of(value, env) if name in chosen else None
            if made is not None:  # the fields read, from the elements
                fields = plain_fields(made[0]) or ()
                for f, e in zip(fields, made[1], strict=True):
                    if f in chosen[name]:
                        targets.append(local(name, f, ast.Store()))
                        values.append(e)
            else:  # another value, read after the assignment when it is one chosen
                targets.append(target)
                values.append(value)
                if name in chosen:
                    after.append(read_after(name))
        new = ast.Assign(targets=[_pack(targets, ast.Store())], value=_pack(values))
        return [ast.copy_location(s, st) for s in (new, *after)]

    def block(stmts: list[ast.stmt]) -> list[ast.stmt]:
        out: list[ast.stmt] = []
        for st in stmts:
            for field in ("body", "orelse"):
                inner = getattr(st, field, None)
                if isinstance(inner, list) and inner and isinstance(inner[0], ast.stmt):
                    setattr(st, field, block(inner))
            if isinstance(st, ast.Assign) and any(
                isinstance(n, ast.Name) and n.id in chosen and isinstance(n.ctx, ast.Store)
                for n in ast.walk(st.targets[0])
            ):
                out.extend(assignment(st))
            else:
                out.append(st)
        return out

    fdef.body = [Reads().visit(st) for st in block(fdef.body)]


def _pack(items: list[ast.expr], ctx: ast.expr_context | None = None) -> ast.expr:
    """One expression, or a tuple of several (``ctx``: Store for a target)."""
    if len(items) == 1:
        return items[0]
    return ast.Tuple(elts=items, ctx=ctx or ast.Load())
