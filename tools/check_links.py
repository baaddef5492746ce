"""Check the internal links of a built HTML site: every relative href/src names a file that
exists, and every fragment (``page.html#id``, ``#id``) an element id on that page.

Usage: ``python tools/check_links.py docs/_build/html``. External links (http, https,
mailto, ...) are not followed: CI has no network. Exit status 1 lists each broken link.
"""

from __future__ import annotations

import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit


class _Page(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.links: list[tuple[str, str]] = []  # (attribute, value)

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if value is None:
                continue
            if name in ("id", "name") and tag != "meta":
                self.ids.add(value)
            elif (name == "href" and tag in ("a", "link")) or (
                name == "src" and tag in ("img", "script", "iframe", "source")
            ):
                self.links.append((name, value))


def _parse(path: Path, cache: dict[Path, _Page]) -> _Page:
    if path not in cache:
        page = _Page()
        page.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = page
    return cache[path]


def check(root: Path) -> list[str]:
    """Broken internal links under ``root``, as ``page: link (why)``."""
    root = root.resolve()
    cache: dict[Path, _Page] = {}
    broken = []
    # _static holds the theme's template fragments, not pages of the site
    pages = sorted(p for p in root.rglob("*.html") if "_static" not in p.relative_to(root).parts)
    if not pages:
        return [f"{root}: no HTML pages"]
    for page_path in pages:
        page = _parse(page_path, cache)
        for _, link in page.links:
            parts = urlsplit(link)
            if parts.scheme or link.startswith("//") or not link.strip():
                continue  # external (or data:, javascript:, mailto:)
            target = page_path if not parts.path else (page_path.parent / unquote(parts.path))
            where = f"{page_path.relative_to(root)}: {link}"
            try:
                target = target.resolve()
            except OSError:
                broken.append(f"{where} (unresolvable)")
                continue
            if root not in target.parents and target != root:
                broken.append(f"{where} (outside the site)")
                continue
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{where} (no such file)")
                continue
            fragment = unquote(parts.fragment)
            if fragment and target.suffix == ".html" and fragment not in _parse(target, cache).ids:
                broken.append(f"{where} (no id {fragment!r})")
    return broken


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    root = Path(argv[0])
    broken = check(root)
    n = sum(1 for p in root.rglob("*.html") if "_static" not in p.relative_to(root).parts)
    if broken:
        print("\n".join(broken))
        print(f"{len(broken)} broken internal links in {n} pages")
        return 1
    print(f"internal links: all good in {n} pages")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
