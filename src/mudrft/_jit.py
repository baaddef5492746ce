r"""The one physics compiled with numba: the whole adapter.

numba compiles mudrft's own functions as they are written; nothing here reads, rewrites or
executes their source. What it needs, and what :func:`jit` gives it:

* **Which functions to compile.** A compiled function may only call functions numba knows.
  :func:`jit` registers with :func:`numba.extending.register_jitable` every plain function
  of mudrft that the entry point reaches through its global names (the names its code
  object uses, followed into the modules it calls through, such as ``laws.tau_xi``), and
  every function of the float namespace :mod:`mudrft._xp`.
* **What** ``xp`` **means.** The physics takes its array namespace as its last parameter.
  numba cannot take a module as an argument from Python, so the entry points (the drivers
  of :mod:`mudrft.terrains.rows`) pass the module :data:`mudrft._xp.pyfloat` by its global
  name: a namespace bound at compile time.
* **A cache that knows its sources.** Compilations are cached on disk (numba's
  ``cache=True``), so a new process loads them in a fraction of a second. numba checks only
  the file of the entry point; the stamp used here covers the source of every function the
  entry point reaches, so editing ``constitutive/laws.py`` recompiles what inlines it. If
  numba's cache locators change shape, caching is switched off rather than risk a stale
  compilation.

``NUMBA_DISABLE_JIT=1`` runs every entry point as plain Python (numba's own switch).
"""

from __future__ import annotations

import functools
import hashlib
import inspect
import types
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["jit", "reached_functions"]


def _is_mudrft_function(obj: object) -> bool:
    return inspect.isfunction(obj) and (obj.__module__ or "").startswith("mudrft.")


def reached_functions(entry: Callable[..., Any]) -> list[types.FunctionType]:
    """The mudrft functions ``entry`` reaches by its global names, ``entry`` first.

    A global naming a mudrft function is followed; a global naming a mudrft module is
    followed into the attributes the code uses (``kernel.channel_step``). Names that are
    locals (``xp.where``) are not globals and are not followed.
    """
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

    from . import _xp

    for name in _xp.ELEMENTWISE:
        obj = getattr(_xp, name)
        if inspect.isfunction(obj):
            register_jitable(obj)
    _install_locators(numba)
    return numba


_registered: set[Any] = set()
#: entry point -> the source files its compilation depends on
_SOURCES: dict[Any, tuple[str, ...]] = {}


def jit(entry: Callable[..., Any], *, parallel: bool = False, cache: bool = True) -> Any:
    """``entry`` compiled by numba (lazily, per argument types), cached on disk.

    Parameters
    ----------
    entry : function
        A driver on floats and float arrays whose callees are mudrft functions written on
        an ``xp`` namespace (see the module docstring).
    parallel : bool, keyword-only
        Compile ``numba.prange`` loops multi-threaded.
    cache : bool, keyword-only
        Cache the compilation on disk (off for entry points that read run-time addresses).

    Returns
    -------
    numba dispatcher
        Calls compile on first use (seconds, once per machine thanks to the cache).
    """
    return _jit(entry, parallel, cache)


@functools.cache
def _jit(entry: Callable[..., Any], parallel: bool, cache: bool) -> Any:
    numba = _numba()
    from numba.extending import register_jitable

    from . import _xp

    functions = reached_functions(entry)
    for fn in functions[1:]:
        if fn not in _registered:
            register_jitable(fn)
            _registered.add(fn)
    files = {inspect.getfile(fn) for fn in functions} | {inspect.getfile(_xp)}
    _SOURCES[entry] = tuple(sorted(files))
    options = {"cache": cache and _CACHE_OK, "parallel": parallel}
    return numba.njit(error_model="numpy", nogil=True, **options)(entry)


_CACHE_OK = True


def _stamp(files: tuple[str, ...]) -> str:
    """A digest of the contents of ``files`` (the freshness of a compilation)."""
    h = hashlib.sha256()
    for f in files:
        h.update(f.encode())
        h.update(Path(f).read_bytes())
    return h.hexdigest()


def _install_locators(numba: types.ModuleType) -> None:
    """Put locators first in numba's list that stamp a mudrft entry point's cache with all
    its sources; other functions are left to numba's own locators."""
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
                return _stamp(self._mudrft_sources)

        Locator.__name__ = f"Mudrft{base.__name__}"
        return Locator

    mine = [make(b) for b in bases]
    classes[:0] = [c for c in mine if c.__name__ not in {k.__name__ for k in classes}]
