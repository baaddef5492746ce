"""Which papers a run relied on: modules :func:`register` what they use, :func:`citations`
lists it as BibTeX."""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["BIBTEX", "citations", "register", "reset"]

_BIB = (Path(__file__).parent / "data" / "citations.bib").read_text(encoding="utf-8")
#: BibTeX entries of the works mudrft implements or compares with, by key.
BIBTEX: dict[str, str] = {
    m[1]: m[0] for m in re.finditer(r"^@\w+\{([^,\n]+),.*?^\}$", _BIB, re.MULTILINE | re.DOTALL)
}

_used: dict[str, None] = {}


def register(key: str) -> None:
    """Record that the current run used the work ``key`` (a key of :data:`BIBTEX`)."""
    if key not in BIBTEX:
        raise KeyError(f"unknown citation key {key!r}; known: {sorted(BIBTEX)}")
    _used.setdefault(key, None)


def reset() -> None:
    """Forget what has been registered (useful between independent runs)."""
    _used.clear()


def citations(*, bibtex: bool = True) -> list[str]:
    """The works the current process relied on, in the order first used: BibTeX entries, or
    their keys with ``bibtex=False``.

    >>> import mudrft
    >>> _ = mudrft.paper_parameters(0.25)
    >>> "chen2026mud" in mudrft.citations(bibtex=False)
    True
    """
    keys = list(_used)
    return [BIBTEX[k] for k in keys] if bibtex else keys
