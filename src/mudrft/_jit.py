r"""The one physics compiled with numba, as written: nothing reads, rewrites or runs its source.

:func:`jit` registers every mudrft function an entry point reaches by its global names (and
:mod:`mudrft._xp`) as jitable; the disk cache is stamped with all their source files and
this one (its compile options).
"""

from __future__ import annotations

import functools
import hashlib
import inspect
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

from . import _xp

__all__ = ["WARM_UP_STEPS", "jit", "jit_callback", "jit_or_interpreted", "reached_functions"]


def _is_mudrft_function(obj: object) -> bool:
    return inspect.isfunction(obj) and (obj.__module__ or "").startswith("mudrft.")


def reached_functions(entry: Callable[..., Any]) -> list[types.FunctionType]:
    """The mudrft functions ``entry`` reaches by its global names (and the attributes it
    uses of mudrft modules, ``kernel.channel_step``), ``entry`` first."""
    seen: dict[types.FunctionType, None] = {}
    todo = [entry]
    while todo:
        fn = todo.pop()
        if fn in seen or (seen and not _is_mudrft_function(fn)):
            continue
        seen[fn] = None  # type: ignore[index]
        names = _code_names(fn.__code__)
        for name in names:
            obj = fn.__globals__.get(name)
            if isinstance(obj, types.ModuleType) and obj.__name__.startswith("mudrft."):
                todo.extend(getattr(obj, n) for n in names if hasattr(obj, n))
            elif _is_mudrft_function(obj):
                todo.append(obj)  # type: ignore[arg-type]
    return list(seen)  # type: ignore[arg-type]


def _code_names(code: types.CodeType) -> set[str]:
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            names |= _code_names(const)
    return names


@functools.cache
def _numba() -> types.ModuleType:
    import numba
    from numba.extending import register_jitable

    for name in _xp.ELEMENTWISE:
        obj = getattr(_xp, name)
        if inspect.isfunction(obj):
            register_jitable(obj)
    _install_locators(numba)
    return numba


_registered: set[Any] = set()
#: entry point -> the source files its compilation depends on
_SOURCES: dict[Any, tuple[str, ...]] = {}


def _register(entry: Callable[..., Any]) -> types.ModuleType:
    """Make what ``entry`` reaches callable from numba, and stamp its cache; numba."""
    numba = _numba()
    from numba.extending import register_jitable

    functions = reached_functions(entry)
    for fn in functions[1:]:
        if fn not in _registered:
            register_jitable(fn)
            _registered.add(fn)
    # this file too: its compile options are part of the machine code, not of the index
    files = {inspect.getfile(fn) for fn in functions} | {inspect.getfile(_xp), __file__}
    _SOURCES[entry] = tuple(sorted(files))
    return numba


@functools.cache
def jit(entry: Callable[..., Any], *, parallel: bool = False, cache: bool = True) -> Any:
    """``entry``, a driver on floats and float arrays, compiled by numba on first call;
    ``parallel`` compiles ``numba.prange`` loops multi-threaded, ``cache`` caches on disk."""
    numba = _register(entry)
    options = {"cache": cache and _CACHE_OK, "parallel": parallel}
    return numba.njit(error_model="numpy", nogil=True, **options)(entry)


#: Steps a process runs in the interpreter before it loads numba: importing numba and loading
#: cached machine code cost about 0.7 s, the time of about 3,000 interpreted steps.
WARM_UP_STEPS = 3000
_interpreted = [0]


def jit_or_interpreted(entry: Callable[..., Any], steps: int) -> Any:
    """:func:`jit` of ``entry``, or ``entry`` itself, interpreted, while this process has
    run fewer than :data:`WARM_UP_STEPS` steps and has loaded no compiled code (equal to
    round-off: the same operations on the same floats)."""
    if jit.cache_info().currsize == 0 and _interpreted[0] + steps <= WARM_UP_STEPS:
        _interpreted[0] += steps
        return entry
    return jit(entry)


@functools.cache
def jit_callback(entry: Callable[..., Any]) -> Any:
    """``entry(m, d)`` compiled now as a C callback ``void(int64, int64)`` (two
    addresses, such as MuJoCo's ``mjcb_passive``), cached on disk as :func:`jit`."""
    numba = _register(entry)
    signature = numba.types.void(numba.types.int64, numba.types.int64)
    return numba.cfunc(signature, cache=_CACHE_OK, error_model="numpy")(entry)


_CACHE_OK = True


def _install_locators(numba: types.ModuleType) -> None:
    """Put first in numba's list locators that stamp an entry point's cache with all its
    sources (caching goes off if numba's caching changed shape)."""
    global _CACHE_OK
    try:
        from numba.core import caching

        def public(name: str) -> Any:  # numba 0.68 dropped the leading underscores
            return getattr(caching, name, None) or getattr(caching, "_" + name)

        names = ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator")
        bases = tuple(public(n) for n in names)  # NUMBA_CACHE_DIR first, as numba's own
        classes = public("CacheImpl")._locator_classes
    except AttributeError:  # pragma: no cover - a numba whose caching changed shape
        _CACHE_OK = False
        return

    def make(base: type) -> type:
        class Locator(base):  # type: ignore[misc, valid-type]
            @classmethod
            def from_function(cls, py_func: Any, py_file: str) -> Any:
                if py_func not in _SOURCES:
                    return None
                self = super().from_function(py_func, py_file)
                if self is not None:
                    self._mudrft_sources = _SOURCES[py_func]
                return self

            def get_source_stamp(self) -> str:
                h = hashlib.sha256()
                for f in self._mudrft_sources:
                    h.update(f.encode())
                    h.update(Path(f).read_bytes())
                return h.hexdigest()

        Locator.__name__ = f"Mudrft{base.__name__}"
        return Locator

    mine = [make(b) for b in bases]
    classes[:0] = [c for c in mine if c.__name__ not in {k.__name__ for k in classes}]
