"""The command lines the README and the docs show name commands and options that exist.

Every ``mudrft COMMAND ...`` in README.md and docs/**/*.md (in code blocks and in inline
code) is checked against the parser of :func:`mudrft.cli.build_parser`: the command must
exist and every ``--option`` must be one of that command's options, so that renaming an
option or a command breaks this test, not a user's copy of a line.
The lines are not run: they name placeholders (``DIR``, ``DATA.csv``) and long jobs.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from mudrft.cli import build_parser

REPO = Path(__file__).resolve().parents[2]
PAGES = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
SHELL = {"", "bash", "console", "sh", "shell", "text"}
INLINE = re.compile(r"`(mudrft [a-z][^`]*)`")


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    (sub,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _options(parser: argparse.ArgumentParser) -> set[str]:
    return {s for a in parser._actions for s in a.option_strings}


def _page_lines(text: str) -> list[str]:
    """``mudrft ...`` lines of the shell blocks, and inline code outside blocks."""
    found, fence, prose = [], None, []
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("```"):
            fence = stripped[3:].strip() if fence is None else None
            continue
        if fence is None:
            prose.append(line)
        elif fence in SHELL:  # `pip install ... && mudrft reproduce ...` holds one too
            parts = re.split(r"&&|;", stripped.removeprefix("$ ").split(" #", 1)[0])
            found += [q.strip() for q in parts if q.strip().startswith("mudrft ")]
    found += INLINE.findall("\n".join(prose))
    return [line.split(" #", 1)[0].strip() for line in found]


def _command_lines() -> list[tuple[str, str]]:
    return [
        (page.relative_to(REPO).as_posix(), line)
        for page in PAGES
        if "_build" not in page.parts
        for line in _page_lines(page.read_text(encoding="utf-8"))
    ]


LINES = _command_lines()


def test_the_docs_show_command_lines():
    """The search finds the README's quick start and the command overview."""
    shown = {line for _, line in LINES}
    assert "mudrft reproduce --out results" in shown
    assert len({line.split()[1] for line in shown}) >= 7  # every command is shown somewhere


def _unknown(line: str) -> list[str]:
    """Commands and options ``line`` names that the parser lacks (``simulate/calibrate``
    and ``--out/--plot`` in prose name each of them)."""
    commands = _subcommands()
    words = line.split()
    named = words[1].split("/")
    missing = sorted(set(named) - set(commands))
    if missing:
        return missing
    options = {
        o.split("=", 1)[0]
        for w in words[2:]
        for o in re.sub(r"[\[\]]", "", w).split("/")
        if o.startswith("--")
    }
    return sorted({o for c in named for o in options - _options(commands[c])})


def test_the_check_finds_a_renamed_option_or_command():
    page = "```bash\npip install . && mudrft calibrate a.csv --owerwrite\n```\nor `mudrft simualte`"
    lines = _page_lines(page)
    assert lines == ["mudrft calibrate a.csv --owerwrite", "mudrft simualte"]
    assert [_unknown(line) for line in lines] == [["--owerwrite"], ["simualte"]]
    assert _unknown("mudrft simulate/calibrate --thixotropy [--out/--plot FILE]") == []


@pytest.mark.parametrize(("page", "line"), LINES, ids=[f"{p}:{ln}" for p, ln in LINES])
def test_a_command_line_in_the_docs_names_real_options(page, line):
    unknown = _unknown(line)
    assert not unknown, f"{page}: `{line}` names commands or options mudrft lacks: {unknown}"
