"""Load the built documentation site in headless Chromium and check its links and images.

    mkdocs build --strict && python scripts/check_site.py [SITE_DIR] [--page PATH ...]

Serves SITE_DIR (default ``site/``) with Python's http.server on a free local port, has headless
Chromium (``chromium``, ``chromium-browser`` or ``google-chrome``; on Debian ``apt-get install
chromium``) load each page (default: the front page and the examples gallery) and dump the DOM it
built, then requests every internal link target (``a href``) and image source (``img src``) of
that DOM from the server: any that does not answer 200 (or whose ``#anchor`` names no element of
its page) is reported, and the exit status is 1. External links are not followed.
"""

from __future__ import annotations

import argparse
import functools
import shutil
import subprocess
import sys
import tempfile
import threading
import urllib.error
import urllib.request
from html.parser import HTMLParser
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from urllib.parse import urldefrag, urljoin, urlparse

ROOT = Path(__file__).resolve().parents[1]
PAGES = ["", "gallery/"]
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")


def find_chromium() -> str | None:
    for name in BROWSERS:
        if path := shutil.which(name):
            return path
    return None


class _Refs(HTMLParser):
    """The ``a href``, ``img src`` and element ids of an HTML document."""

    def __init__(self):
        super().__init__()
        self.links, self.images, self.ids = [], [], set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        if tag == "a" and a.get("href"):
            self.links.append(a["href"])
        elif tag == "img" and a.get("src"):
            self.images.append(a["src"])


def parse(html: str) -> _Refs:
    p = _Refs()
    p.feed(html)
    return p


def dump_dom(browser: str, url: str, timeout: float = 60.0) -> str:
    """The DOM headless Chromium built for ``url`` (after its scripts ran)."""
    with tempfile.TemporaryDirectory() as profile:
        r = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                            f"--user-data-dir={profile}", "--virtual-time-budget=3000", "--dump-dom", url],
                           capture_output=True, text=True, timeout=timeout)
    if r.returncode != 0 or "<html" not in r.stdout.lower():
        raise RuntimeError(f"{Path(browser).name} could not load {url} ({r.returncode}): {r.stderr[-1500:]}")
    return r.stdout


class _Quiet(SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def serve(site: Path) -> ThreadingHTTPServer:
    """An HTTP server of ``site`` on a free port of 127.0.0.1, running in a thread."""
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(site)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def _get(url: str) -> tuple[int, bytes]:
    try:
        with urllib.request.urlopen(url, timeout=30) as resp:
            return resp.status, resp.read()
    except urllib.error.HTTPError as e:
        return e.code, b""


def check(site: Path, pages=PAGES, browser: str | None = None) -> tuple[list[str], int]:
    """(problems, number of links and images checked) for ``pages`` of the site in ``site``."""
    browser = browser or find_chromium()
    if browser is None:
        raise RuntimeError("no Chromium found (apt-get install chromium)")
    server = serve(site)
    base = f"http://127.0.0.1:{server.server_address[1]}/"
    bad, checked, ids_of = [], 0, {}
    try:
        for page in pages:
            url = urljoin(base, page)
            refs = parse(dump_dom(browser, url))
            if not refs.links and not refs.images:
                bad.append(f"{page or '/'}: Chromium's DOM has no links or images")
            for kind, targets in (("link", refs.links), ("image", refs.images)):
                for target in targets:
                    full = urljoin(url, target)
                    if urlparse(full).netloc != urlparse(base).netloc or urlparse(full).scheme not in ("http", "https"):
                        continue  # external, mailto:, javascript:, data:
                    checked += 1
                    doc, anchor = urldefrag(full)
                    if doc not in ids_of:
                        status, body = _get(doc)
                        ids_of[doc] = (status, parse(body.decode("utf-8", "replace")).ids
                                       if status == 200 and doc.endswith("/") else None)
                    status, ids = ids_of[doc]
                    if status != 200:
                        bad.append(f"{page or '/'}: {kind} {target!r}: HTTP {status}")
                    elif anchor and ids is not None and anchor not in ids:
                        bad.append(f"{page or '/'}: {kind} {target!r}: no element with id {anchor!r}")
    finally:
        server.shutdown()
        server.server_close()
    return bad, checked


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("site", nargs="?", default=str(ROOT / "site"), help="the built site (default site/)")
    ap.add_argument("--page", action="append", help="a page to load, relative to the site (default: '' and gallery/)")
    args = ap.parse_args(argv)
    site = Path(args.site)
    if not (site / "index.html").is_file():
        print(f"{site}: no index.html; build the site first (mkdocs build --strict)", file=sys.stderr)
        return 2
    try:
        bad, checked = check(site, args.page or PAGES)
    except RuntimeError as e:
        print(f"check_site: {e}", file=sys.stderr)
        return 2
    for line in bad:
        print(line)
    print(f"{checked} internal links and images checked on {len(args.page or PAGES)} pages: "
          f"{len(bad)} broken", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
