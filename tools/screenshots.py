"""Screenshots of the built documentation site with headless Chromium (docs/screenshots/).

Usage: ``python tools/screenshots.py docs/_build/html [--out docs/screenshots]``. Needs the
system's Chromium (Debian: ``apt-get install chromium``) and the ``playwright`` Python
package, which drives it (``pip install playwright``; no browser download: it launches
``/usr/bin/chromium``). The site is served on 127.0.0.1 for the run, so MathJax's fonts load
as they would from a web server. Each shot waits until MathJax has typeset the page, and
the script fails if a page shows raw TeX (``$$``, ``\\(``) or a broken image.
"""

from __future__ import annotations

import argparse
import functools
import http.server
import shutil
import sys
import threading
from pathlib import Path

SHOTS = (
    # (file, page, element to scroll to the top or None, window height [px])
    ("home.png", "index.html", None, 1000),
    ("model.png", "model.html", "#constitutive-model-sec-ii-b-eqs-15", 1000),
    ("gallery_example.png", "auto_examples/jax_gradient_calibration.html", None, 1750),
)


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format: str, *args: object) -> None:
        pass


def _serve(root: Path) -> tuple[http.server.ThreadingHTTPServer, str]:
    handler = functools.partial(_QuietHandler, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, f"http://127.0.0.1:{server.server_address[1]}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("site", type=Path, help="the built site (docs/_build/html)")
    ap.add_argument("--out", type=Path, default=Path("docs/screenshots"))
    ap.add_argument("--chromium", default=shutil.which("chromium") or "/usr/bin/chromium")
    args = ap.parse_args(argv)
    from playwright.sync_api import sync_playwright

    args.out.mkdir(parents=True, exist_ok=True)
    server, base = _serve(args.site)
    problems = []
    try:
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=args.chromium, args=["--no-sandbox"])
            page = browser.new_page(viewport={"width": 1600, "height": 1000})
            for name, path, anchor, height in SHOTS:
                page.set_viewport_size({"width": 1600, "height": height})
                page.goto(f"{base}/{path}", wait_until="networkidle")
                page.wait_for_function(
                    "() => !window.MathJax || (MathJax.startup && MathJax.startup.promise"
                    " && (MathJax.startup.promise.then(() => window.__typeset = true), window.__typeset))",
                    timeout=60_000,
                )
                raw = page.evaluate(
                    "() => Array.from(document.querySelectorAll('.math')).filter("
                    "e => !e.querySelector('mjx-container')).length"
                )
                broken = page.evaluate(
                    "() => Array.from(document.images).filter(i => i.complete && i.naturalWidth === 0)"
                    ".map(i => i.src)"
                )
                if raw:
                    problems.append(f"{path}: {raw} equations not typeset")
                if broken:
                    problems.append(f"{path}: broken images {broken}")
                if anchor:
                    page.eval_on_selector(
                        anchor,
                        "e => window.scrollTo(0, e.getBoundingClientRect().top + window.scrollY - 80)",
                    )
                    page.wait_for_timeout(300)
                page.screenshot(path=str(args.out / name))
                print(f"wrote {args.out / name}")
            browser.close()
    finally:
        server.shutdown()
    for p in problems:
        print(p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    raise SystemExit(main())
