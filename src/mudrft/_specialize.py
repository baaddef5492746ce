r"""Specialize the one physics for one namespace: the same source, rewritten, not copied.

The equations are written once as element-wise functions of an array namespace ``xp``
(:mod:`mudrft._xp`, decision D80). On numpy and JAX they run as written. On one foot's
Python floats, passing ``xp=pyfloat`` works but pays for generality: every ``xp.where``
is a Python call that has evaluated both of its branches, every ``xp.exp`` an attribute
lookup and a call. :func:`on_floats` reads a function's own source and rewrites it for
floats:

* ``xp.where(c, a, b)`` becomes ``a if c else b`` and ``xp.maximum``/``xp.minimum`` a
  conditional on their two arguments (each evaluated once); the result is the same
  float, and the branch not taken is not computed;
* every other ``xp.f`` becomes a direct reference to the namespace's function, and a named
  tuple made by keywords is made by position;
* every call of a mudrft function is pointed at that function's own specialization (the
  ``xp=`` keyword dropped), so a whole step is specialized from its entry point;
* ``xp.tanh(x)`` skips its call at an exact 0, a callee that is one ``return`` is inlined
  wherever it is called with names or constants, and named-tuple arguments are unpacked
  once (:mod:`mudrft._specialize_tuples`);
* a callee with an early return (``if quasi_static: return ...``) is inlined as an ``if``
  statement (:mod:`mudrft._specialize_flow`), and a local named tuple of which only fields
  are read is those fields (``sx.total``, :func:`mudrft._specialize_tuples.drop_fields`).

The numba backend compiles the same rewrite (:func:`mudrft.backends.numba.compile_scalar`,
with ``rewrite_where=False`` and the namespace of compiled scalar functions). Source lines,
names and line numbers are the original ones, so a traceback points into the physics
modules. A specialization is made once per process and function, like a compilation: a
function replaced at run time (a test's ``monkeypatch``) is seen after
``on_floats.cache_clear()``. Without its source (an install without ``.py`` files) a
function runs as written, with ``xp=pyfloat``.
"""

from __future__ import annotations

import ast
import builtins
import copy
import functools
import inspect
import itertools
import re
import textwrap
import types
from collections.abc import Callable
from typing import Any, TypeAlias, TypeGuard

from ._specialize_copies import propagate_copies
from ._specialize_flow import (
    SELF,
    always_evaluated,
    as_branches,
    assign_in_branches,
    evaluated_parts,
    located_at,
)
from ._specialize_tuples import drop_fields, new_tuple, plain_fields, shared_test, unpack_fields
from ._typing import Namespace
from ._xp import pyfloat

__all__ = ["on_floats", "specialize"]

# An environment (``env``) is the globals a rewritten definition is executed in, as
# ``exec`` takes them: names bound to any Python object, hence ``dict[str, Any]``.

#: A rewritten definition and its environment: ``specialize``'s ``__specialized__``.
Rewritten: TypeAlias = tuple[ast.FunctionDef, dict[str, Any]]
#: What a mudrft function called by the rewritten one is called as instead (its own
#: specialization: a function, or a numba dispatcher).
Callee: TypeAlias = Callable[[types.FunctionType], object]
#: A mudrft function's rewritten definition for inlining, or None (see ``_float_def``).
Inliner: TypeAlias = Callable[[types.FunctionType], Rewritten | None]


class _Rewriter(ast.NodeTransformer):
    """Rewrite ``xp.`` calls and point calls of mudrft functions at their specializations."""

    def __init__(
        self, env: dict[str, Any], callee: Callee, rewrite_where: bool, drop: bool
    ) -> None:
        self.env = env
        self.callee = callee
        self.rewrite_where = rewrite_where
        self.drop = drop  # drop every call's xp= (numba cannot pass a namespace)
        self.targets: dict[str, types.FunctionType] = {}  # _k_ name -> the mudrft function
        self.names = itertools.count()

    def _resolve(self, node: ast.expr) -> object:
        if isinstance(node, ast.Name):
            return self.env.get(node.id)
        if isinstance(node, ast.Attribute):
            base = self._resolve(node.value)
            return getattr(base, node.attr, None) if isinstance(base, types.ModuleType) else None
        return None

    @staticmethod
    def _is_mudrft(target: object) -> TypeGuard[types.FunctionType]:
        return isinstance(target, types.FunctionType) and target.__module__.startswith("mudrft.")

    def _temp(self) -> str:
        return f"_xp_t{next(self.names)}"

    def _once(self, value: ast.expr, other: ast.expr) -> tuple[ast.expr, ast.expr]:
        """``value`` as its first evaluation and as a later read of the same float: a
        constant or a name as it is (read twice: the same float, no store), anything else
        through a temporary (evaluated once)."""
        if isinstance(value, ast.Constant) or (
            isinstance(value, ast.Name)
            and not any(
                isinstance(n, ast.NamedExpr) and n.target.id == value.id for n in ast.walk(other)
            )  # not reassigned between the two reads
        ):
            return value, copy.deepcopy(value)
        t = self._temp()
        return ast.NamedExpr(target=ast.Name(t, ast.Store()), value=value), ast.Name(t, ast.Load())

    def _extremum(self, args: list[ast.expr], op: ast.cmpop) -> ast.expr:
        # (a if a >= b else b) with a and b evaluated once: numpy's maximum for non-NaN
        # floats, and the same as mudrft._xp's scalar helpers for NaN
        a, a_again = self._once(args[0], args[1])
        b, b_again = self._once(args[1], args[0])
        test = ast.Compare(left=a, ops=[op], comparators=[b])
        return ast.IfExp(test=test, body=a_again, orelse=b_again)

    def _tanh(self, arg: ast.expr, tanh: Callable[[float], float]) -> ast.expr:
        # tanh(+-0) is +-0 exactly (C99 F.9.5.6, every libm): skip the call at 0, where a
        # switch or the sealing state rests (no retraction); the product with 1.0 keeps the
        # sign of the zero and makes an int 0 the float 0.0 that math.tanh returns
        self.env["_xp_tanh"] = tanh
        x, x_again = self._once(arg, ast.Constant(0.0))
        zero = ast.BinOp(left=x_again, op=ast.Mult(), right=ast.Constant(1.0))
        test = ast.Compare(left=x, ops=[ast.Eq()], comparators=[ast.Constant(0.0)])
        call = ast.Call(ast.Name("_xp_tanh", ast.Load()), [copy.deepcopy(x_again)], [])
        return ast.IfExp(test=test, body=zero, orelse=call)

    def visit_Call(self, node: ast.Call) -> ast.AST:
        self.generic_visit(node)
        if self.drop:
            node.keywords = [k for k in node.keywords if k.arg != "xp"]
        f = node.func
        if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id == "xp":
            args = node.args
            if self.rewrite_where and f.attr == "where" and len(args) == 3:
                return ast.IfExp(test=args[0], body=args[1], orelse=args[2])
            if self.rewrite_where and f.attr in ("maximum", "minimum") and len(args) == 2:
                return self._extremum(args, ast.GtE() if f.attr == "maximum" else ast.LtE())
            if self.rewrite_where and f.attr == "tanh" and len(args) == 1:
                return self._tanh(args[0], self.env["xp"].tanh)
            target = getattr(self.env["xp"], f.attr)
            if not self._is_mudrft(target):
                name = f"_xp_{f.attr}"
                self.env[name] = target
                node.func = ast.Name(id=name, ctx=ast.Load())
                return node
            # else a helper of mudrft._xp (sign, clip): specialized, and inlined, as any
        else:
            target = self._resolve(f)
        fields = getattr(target, "_fields", None)
        if (
            isinstance(target, type)
            and issubclass(target, tuple)
            and fields is not None
            and not node.args
            and sorted(k.arg or "" for k in node.keywords) == sorted(fields)
        ):  # a named tuple made by keywords: by position, 3x cheaper on floats
            by_name = {k.arg: k.value for k in node.keywords}
            node.args, node.keywords = [by_name[name] for name in fields], []
        if self.rewrite_where and not self.drop and _plain_named_tuple(target, node):
            # on floats: tuple.__new__(cls, (...)), without the Python frame of the named
            # tuple's own __new__ (half the cost of making it)
            self.env["_xp_tuple_new"], self.env["_xp_type"] = tuple.__new__, type
            self.env[name := f"_xp_nt_{target.__name__}_{id(target)}"] = target
            test = shared_test(node.args)
            fields = plain_fields(target)  # None: a field read its own way (x.f is not x[i])
            if test is None:
                return new_tuple(name, node.args, fields)
            # every field under one test (a where over a whole state, a channel made fresh):
            # one conditional of two tuples, and the argument itself for its own fields
            return ast.IfExp(
                test=test,
                body=new_tuple(name, [e.body for e in node.args], fields),  # type: ignore[attr-defined]
                orelse=new_tuple(name, [e.orelse for e in node.args], fields),  # type: ignore[attr-defined]
            )
        if fields is not None:
            return node
        if self._is_mudrft(target):
            name = f"_k_{target.__module__.replace('.', '_')}_{target.__name__}"
            self.env[name] = self.callee(target)
            self.targets[name] = target
            node.func = ast.Name(id=name, ctx=ast.Load())
            node.keywords = [k for k in node.keywords if k.arg != "xp"]
        return node


def _plain_named_tuple(target: object, node: ast.Call) -> TypeGuard[type[tuple[Any, ...]]]:
    """Whether ``node`` makes the named tuple ``target`` from all its fields by position,
    with the ``__new__`` that ``collections.namedtuple`` wrote (no subclass's own)."""
    if not (isinstance(target, type) and issubclass(target, tuple)):
        return False
    fields = getattr(target, "_fields", None)
    if fields is None or node.keywords or len(node.args) != len(fields):
        return False
    if any(isinstance(a, ast.Starred) for a in node.args):
        return False
    owner = next(k for k in target.__mro__ if "__new__" in vars(k))
    return "_fields" in vars(owner)


def specialize(
    fn: types.FunctionType,
    xp: Namespace,
    callee: Callee,
    *,
    rewrite_where: bool = True,
    positional: bool = False,
    inline: Inliner | None = None,
) -> types.FunctionType:
    """The source of ``fn`` rewritten for the namespace ``xp`` (see the module docstring).

    Parameters
    ----------
    fn : function
        A mudrft function whose namespace is a keyword-only ``xp`` argument.
    xp : namespace
        The element-wise namespace the rewrite binds (:data:`mudrft._xp.pyfloat`, or the
        numba backend's compiled scalar functions).
    callee : callable
        Maps a mudrft function that ``fn`` calls to what the rewrite calls instead (its
        own specialization).
    rewrite_where : bool
        Rewrite ``xp.where``, ``xp.maximum`` and ``xp.minimum`` as conditionals.
    positional : bool
        For numba: make the keyword-only arguments positional (numba takes none; callers
        pass them by name) and drop ``xp=`` from every call (it cannot pass a namespace).
        Otherwise ``xp=`` is dropped only from the calls pointed at a specialization, and
        any other function is called with the namespace as written.
    inline : callable, optional
        Maps a mudrft function that ``fn`` calls to its rewritten definition
        (``(FunctionDef, env)``, see :func:`_float_def`); a straight-line one is then
        inlined (:func:`_inline_block`) instead of called.

    Returns
    -------
    function
        Plain Python: the same arguments as ``fn`` without ``xp``; its rewritten
        ``FunctionDef`` and environment as ``__specialized__``.
    """
    tree = ast.parse(textwrap.dedent(inspect.getsource(fn)))
    fdef = tree.body[0]
    if not isinstance(fdef, ast.FunctionDef):
        raise TypeError(f"cannot specialize {fn!r}: not a plain function")
    fdef.decorator_list = []
    args = fdef.args
    keep = [(a, d) for a, d in zip(args.kwonlyargs, args.kw_defaults, strict=True) if a.arg != "xp"]
    if positional and keep:
        required = [a for a, d in keep if d is None]
        if required and args.defaults:
            raise TypeError(f"{fn.__name__}: required keyword-only arguments after defaults")
        args.args += required + [a for a, d in keep if d is not None]
        args.defaults += [d for _, d in keep if d is not None]
        keep = []
    args.kwonlyargs, args.kw_defaults = [a for a, _ in keep], [d for _, d in keep]
    for a in (*args.args, *args.kwonlyargs):
        a.annotation = None
    fdef.returns = None
    env = dict(fn.__globals__)
    env["xp"] = xp
    rewriter = _Rewriter(env, callee, rewrite_where, positional)
    tree = rewriter.visit(tree)
    ast.fix_missing_locations(tree)
    ast.increment_lineno(tree, fn.__code__.co_firstlineno - 1)
    if inline is not None:
        fdef.body = _inline_block(_body(fdef), env, rewriter.targets, inline)
        fdef.body = [_inline_expressions(st, env) for st in fdef.body]
        drop_fields(fdef, env)
        propagate_copies(fdef, env)
    ast.fix_missing_locations(tree)
    local: dict[str, Any] = {}
    exec(compile(tree, fn.__code__.co_filename, "exec"), env, local)
    out = local[fdef.name]
    plain = copy.deepcopy(fdef)  # what callers inline
    if rewrite_where and not positional and unpack_fields(fn, fdef, env, name := "_xp_plain"):
        propagate_copies(fdef, env)  # the copies of the fields unpacked
        env[name] = out  # what the unpacked function runs for other types
        exec(compile(tree, fn.__code__.co_filename, "exec"), env, local)
        out = local[fdef.name]
    out.__doc__ = fn.__doc__
    out.__specialized__ = (plain, env)
    out.__specialized_from__ = fn
    env[SELF] = out
    return out  # type: ignore[no-any-return]


@functools.cache
def on_floats(fn: types.FunctionType) -> types.FunctionType:
    """``fn`` specialized for one element on Python floats (see the module docstring).

    The result equals ``fn(..., xp=pyfloat)`` bit for bit and takes the same arguments
    without ``xp``.

    Examples
    --------
    >>> from mudrft.constitutive import laws
    >>> on_floats(laws.sealing)(1e-3, 2e-3) == laws.sealing(1e-3, 2e-3, xp=pyfloat)
    True
    """
    try:
        return specialize(fn, pyfloat, on_floats, inline=_float_def)
    except OSError:  # no source to read (an install without .py files): the generic code
        if "xp" in inspect.signature(fn).parameters:
            return functools.partial(fn, xp=pyfloat)  # type: ignore[return-value]
        return fn


def _float_def(fn: types.FunctionType) -> Rewritten | None:
    """The rewritten definition of ``fn`` on floats and its environment (for inlining), or
    None when it could not be rewritten."""
    return getattr(on_floats(fn), "__specialized__", None)


# -- inlining ------------------------------------------------------------------------------
#
# A call of a mudrft function whose rewritten body is straight-line (assignments, and if
# statements of assignments, then one return) is replaced by that body: its parameters and
# locals renamed apart, its globals bound in the caller's environment, the body placed
# before the statement that makes the call, the call replaced by the returned expression
# (an early return: mudrft._specialize_flow). Only calls that the statement always
# evaluates are inlined (not in a branch of a conditional expression, after the first
# operand of ``and``/``or``, in a ``while`` test, a comprehension or a lambda), so nothing is
# evaluated that the original would not evaluate; a statement with an assignment expression
# of the source keeps its calls in place (a call may read the name it assigns). The physics
# is free of side effects, so the result is the same float.

_names = itertools.count()
#: Names of the rewrite's own temporaries (maximum/minimum, and those of inlined bodies).
_OWN_TEMP = re.compile(r"_xp_t\d+$|_i\d+_")


def _body(fdef: ast.FunctionDef) -> list[ast.stmt]:
    """The statements of a function without its docstring."""
    b = fdef.body
    if b and isinstance(b[0], ast.Expr) and isinstance(b[0].value, ast.Constant):
        return b[1:]
    return b


def _straight_line(fdef: ast.FunctionDef) -> bool:
    """Whether a definition is assignments to names (:func:`_assignments`), then one return
    of a value."""
    a = fdef.args
    if a.vararg or a.kwarg or a.posonlyargs:
        return False
    body = _body(fdef)
    if not body or not isinstance(body[-1], ast.Return) or body[-1].value is None:
        return False
    if not _assignments(body[:-1]):
        return False
    return not any(
        isinstance(n, (ast.Lambda, ast.FunctionDef, ast.Yield, ast.Await, ast.Global))
        or isinstance(n, (ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp))
        for st in body
        for n in ast.walk(st)
    )


def _assignments(block: list[ast.stmt]) -> bool:
    """Whether ``block`` only assigns names: ``a = ...``, ``a, b = ...``, and ``if`` statements
    whose branches only assign names (the one return of an inlined body comes after)."""
    for st in block:
        if isinstance(st, ast.If):
            if not (_assignments(st.body) and _assignments(st.orelse)):
                return False
            continue
        if not (isinstance(st, ast.Assign) and len(st.targets) == 1):
            return False
        t = st.targets[0]
        names = t.elts if isinstance(t, (ast.Tuple, ast.List)) else [t]
        if not all(isinstance(n, ast.Name) for n in names):
            return False
    return True


def _expand(
    call: ast.Call, fn: types.FunctionType, fdef: ast.FunctionDef, callee_env: dict[str, Any],
    env: dict[str, Any],
) -> tuple[list[ast.stmt], ast.expr] | None:  # fmt: skip
    """The statements and the value that replace ``call`` of ``fn``, or None."""
    if any(isinstance(a, ast.Starred) for a in call.args) or any(
        k.arg is None for k in call.keywords
    ):
        return None
    k = next(_names)
    params = [a.arg for a in (*fdef.args.args, *fdef.args.kwonlyargs)]
    sig = inspect.signature(fn)
    given: dict[str, ast.expr] = dict(zip(params, call.args, strict=False))
    given.update({kw.arg: kw.value for kw in call.keywords if kw.arg is not None})
    if len(call.args) > len(fdef.args.args) or set(given) - set(params):
        return None
    stored = {
        n.id for n in ast.walk(fdef) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)
    }
    local = set(params) | stored
    pre: list[ast.stmt] = []
    subst: dict[str, ast.expr] = {}
    for p in params:
        if p in given:
            arg = given[p]
        else:
            default = sig.parameters[p].default
            if default is inspect.Parameter.empty:
                return None
            env[f"_i{k}_d_{p}"] = default
            arg = ast.Name(f"_i{k}_d_{p}", ast.Load())
        if isinstance(arg, (ast.Name, ast.Constant)) and p not in stored:
            subst[p] = arg  # used as it is: the inlined body assigns only its own names
        else:
            pre.append(ast.Assign(targets=[ast.Name(f"_i{k}_{p}", ast.Store())], value=arg))
    body = [copy.deepcopy(st) for st in _body(fdef)]
    free: dict[str, str] = {}

    class Rename(ast.NodeTransformer):
        def visit_Name(self, n: ast.Name) -> ast.AST:
            if n.id in subst:
                return copy.deepcopy(subst[n.id])
            if n.id in local:
                return ast.Name(f"_i{k}_{n.id}", n.ctx)
            if n.id not in free:  # a global of the callee's module, or a builtin
                if n.id in callee_env:
                    value = callee_env[n.id]
                elif hasattr(builtins, n.id):
                    value = getattr(builtins, n.id)
                else:
                    raise _NotInlined(n.id)
                free[n.id] = f"_i{k}_g_{n.id}"
                env[free[n.id]] = value
            return ast.Name(free[n.id], n.ctx)

    try:
        body = [Rename().visit(st) for st in body]
    except _NotInlined:
        return None
    ret = body.pop()
    assert isinstance(ret, ast.Return) and ret.value is not None
    return pre + body, ret.value


class _NotInlined(Exception):
    """A name the inlined body needs is not defined (left as a call)."""


def _inline_block(
    block: list[ast.stmt], env: dict[str, Any], targets: dict[str, types.FunctionType],
    inline: Inliner,
) -> list[ast.stmt]:  # fmt: skip
    """``block`` with its always-evaluated calls of straight-line mudrft functions inlined."""
    out: list[ast.stmt] = []
    work = list(block)
    while work:
        st = work.pop(0)
        done: tuple[list[ast.stmt], ast.expr | None] | None = None
        parts = evaluated_parts(st)
        if any(
            isinstance(n, ast.NamedExpr) and not _OWN_TEMP.match(n.target.id)
            for part in parts
            for n in ast.walk(part)
        ):  # an assignment expression of the source: a call after it in the statement may
            # read its name, so nothing is moved before the statement
            parts = []
        for part in parts:
            for call in always_evaluated(part):
                f = call.func
                fn = _target(f, env, targets)
                rewritten = None if fn is None else inline(fn)
                if fn is None or rewritten is None:
                    continue
                fdef, callee_env = rewritten
                branched = not _straight_line(fdef)
                if branched:  # an early return: inlined as an if statement
                    as_if = as_branches(fdef, st, call, _straight_line, _body(fdef))
                    if as_if is None:
                        continue
                    fdef = as_if
                expanded = _expand(call, fn, fdef, callee_env, env)
                if expanded is not None:
                    pre, value = expanded
                    if branched:  # the if statement assigns the statement's names
                        assign_in_branches(pre, value, st)  # type: ignore[arg-type]
                        done = pre, None
                    else:
                        _replace(st, call, value)
                        done = pre, value
                    work[:0] = located_at(pre, st)
                    break
            if done is not None:
                break
        if done is None:  # final: its nested blocks are inlined once, now
            for field in ("body", "orelse", "finalbody"):
                inner = getattr(st, field, None)
                if isinstance(inner, list) and inner and isinstance(inner[0], ast.stmt):
                    setattr(st, field, _inline_block(inner, env, targets, inline))
            if isinstance(st, ast.Try):
                for h in st.handlers:
                    h.body = _inline_block(h.body, env, targets, inline)
            out.append(st)
        elif done[1] is not None:
            work.insert(len(done[0]), st)  # the statement again, after its inlined parts
    return out


def _target(
    f: ast.expr, env: dict[str, Any], targets: dict[str, types.FunctionType]
) -> types.FunctionType | None:
    """The mudrft function a call's ``f`` names: one the source calls, or a specialization
    that an inlined body calls (under its renamed global)."""
    if not isinstance(f, ast.Name) or f.id.endswith(f"_g_{SELF}"):
        return None  # the early branch of an inlined if statement stays a call
    return targets.get(f.id) or getattr(env.get(f.id), "__specialized_from__", None)


def _inline_expressions(st: ast.stmt, env: dict[str, Any]) -> ast.stmt:
    """``st`` with every call of a specialization that is one ``return`` of an expression,
    with names and constants for arguments, replaced by that expression, wherever the call
    is (a branch, a loop test): the arguments are read where the call read them, and the
    expression evaluated right after, as the call would (``xp.sign`` in a conditional)."""

    class Calls(ast.NodeTransformer):
        def visit_Call(self, call: ast.Call) -> ast.AST:
            self.generic_visit(call)
            fn: Any = env.get(call.func.id) if isinstance(call.func, ast.Name) else None
            fdef: Any
            callee_env: Any
            fdef, callee_env = getattr(fn, "__specialized__", (None, None))
            if fdef is None or len(_body(fdef)) != 1 or not _straight_line(fdef):
                return call
            simple = (ast.Name, ast.Constant)
            if not all(
                isinstance(a, simple) for a in (*call.args, *(k.value for k in call.keywords))
            ):
                return call
            done = _expand(call, fn, fdef, callee_env, env)
            if done is None or done[0]:
                return call
            return located_at([ast.Expr(done[1])], call)[0].value  # type: ignore[attr-defined]

    return Calls().visit(st)  # type: ignore[no-any-return]


def _replace(root: ast.AST, old: ast.AST, new: ast.expr) -> None:
    """Replace the node ``old`` (by identity) under ``root`` with ``new``."""
    for parent in ast.walk(root):
        for field, value in ast.iter_fields(parent):
            if value is old:
                setattr(parent, field, new)
                return
            if isinstance(value, list):
                for i, v in enumerate(value):
                    if v is old:
                        value[i] = new
                        return
    raise AssertionError("node not found")
