"""Print the oldest versions of the optional extras that pyproject.toml allows, as pins.

Usage: ``python tools/oldest_requirements.py > oldest.txt``, then ``pip install -e . -r
oldest.txt``: CI's "oldest extras" run (decision D149) tests every extra of ``all`` at its
floor, so that a floor in pyproject.toml is a version the suite has passed on.

A floor of three parts (``zarr>=3.1.1``) is pinned exactly; one of two parts
(``matplotlib>=3.8``) to that release series (``matplotlib==3.8.*``, its last bug-fix
release). numpy and scipy are not pinned here: their floors are tested by CI's core-only
run, and the extras' own floors decide which numpy they can share.
"""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"
REQUIREMENT = re.compile(r"(?P<name>[A-Za-z0-9_.-]+)(?P<extras>\[[^\]]*\])?>=(?P<floor>[0-9.]+)")


def requirements(
    extra: str, table: dict[str, list[str]], seen: set[str] | None = None
) -> list[str]:
    """The requirements of ``extra``, with ``mudrft[...]`` expanded, in order, once each."""
    seen = set() if seen is None else seen
    out: list[str] = []
    for req in table[extra]:
        req = req.replace(" ", "")
        self_ref = re.fullmatch(r"mudrft\[(.*)\]", req)
        if self_ref:
            for sub in self_ref[1].split(","):
                if sub not in seen:
                    seen.add(sub)
                    out += requirements(sub, table, seen)
        elif req not in out:
            out.append(req)
    return out


def pin(requirement: str) -> str:
    """``name>=X.Y`` -> ``name==X.Y.*``; ``name>=X.Y.Z`` -> ``name==X.Y.Z``."""
    m = REQUIREMENT.fullmatch(requirement)
    if m is None:
        raise SystemExit(f"{requirement!r}: every extra needs a plain floor (name>=version)")
    floor = m["floor"]
    version = floor if floor.count(".") >= 2 else f"{floor}.*"
    return f"{m['name']}{m['extras'] or ''}=={version}"


def main() -> int:
    table = tomllib.loads(PYPROJECT.read_text())["project"]["optional-dependencies"]
    for req in requirements("all", table):
        print(pin(req))
    return 0


if __name__ == "__main__":
    sys.exit(main())
