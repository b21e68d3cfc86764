"""Load the built documentation site in headless Chromium, from a server and from disk, and check
its links, images and search.

    mkdocs build --strict && python scripts/check_site.py [SITE_DIR] [--page PATH ...]

Three checks, each reported per page with what is wrong:

- **from a server**: serves SITE_DIR (default ``site/``) with Python's http.server on a free local
  port, has headless Chromium (``chromium``, ``chromium-browser`` or ``google-chrome``; on Debian
  ``apt-get install chromium``) load each page (default: the front page and the examples gallery)
  and dump the DOM it built, then requests every internal link target (``a href``), image
  (``img src``), script (``script src``) and style sheet or icon (``link href``) of that DOM from the
  server: any that does not answer 200, is a folder rather than a file, or whose ``#anchor`` names
  no element of its page, is reported;
- **from disk**: the same pages opened as ``file://`` URLs (as a reader who double-clicks
  ``site/index.html`` does): every internal target must be a file of the site (a folder would
  give the reader its listing), with its anchor, and nothing (no script, style sheet, font or
  image) may come from the network;
- **search from disk**: ``index.html?q=WORD`` opened from disk must show search results (the
  offline plugin's inlined index and the vendored Web Worker shim; see mkdocs.yml).

:func:`static_problems` makes the disk check on the HTML files of the whole site, without a
browser. The exit status is 1 when anything is reported. External links are not followed.
"""

from __future__ import annotations

import argparse
import functools
import re
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
from urllib.parse import unquote, urldefrag, urljoin, urlparse

ROOT = Path(__file__).resolve().parents[1]
PAGES = ["index.html", "gallery.html"]
SEARCH_WORD = "catenary"  # a word several pages have
BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
SERVER_ONLY = {"404.html"}  # a server's error page: its links are absolute, from the server's root


def find_chromium() -> str | None:
    for name in BROWSERS:
        if path := shutil.which(name):
            return path
    return None


class _Refs(HTMLParser):
    """The references (``a href``, ``img src``, ``script src``, ``link href``) and element ids of an
    HTML document; ``refs`` holds (kind, target) pairs, kind one of link, image, script, resource."""

    def __init__(self):
        super().__init__()
        self.refs, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"])
        kind, attr = {"a": ("link", "href"), "img": ("image", "src"), "script": ("script", "src"),
                      "link": ("resource", "href")}.get(tag, (None, None))
        if kind and a.get(attr):
            self.refs.append((kind, a[attr]))

    @property
    def links(self):
        return [t for k, t in self.refs if k == "link"]

    @property
    def images(self):
        return [t for k, t in self.refs if k == "image"]


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


def _ids(path: Path) -> set | None:
    """The element ids of an HTML file of the site (None for any other file)."""
    return parse(path.read_text(encoding="utf-8", errors="replace")).ids if path.suffix == ".html" else None


def _target_problem(site: Path, path: Path, anchor: str, ids_of: dict) -> str | None:
    """What is wrong with a reference to ``path`` (a local path) and ``anchor``, or None."""
    try:
        path.relative_to(site)
    except ValueError:
        return "outside the site"
    if path.is_dir():
        return "a folder, not a file: opened from disk, it shows the folder's listing"
    if not path.is_file():
        return "no such file"
    if anchor:
        if path not in ids_of:
            ids_of[path] = _ids(path)
        if ids_of[path] is not None and anchor not in ids_of[path]:
            return f"no element with id {anchor!r}"
    return None


def static_problems(site: Path) -> tuple[list[str], int]:
    """(problems, references checked) of every HTML file of the built site as written (no browser,
    no scripts run): each relative ``href``/``src`` must name a file of the site, and its anchor an
    element of it. 404.html is left out: a server sends it for a missing path, from any folder,
    so its references are absolute, from the server's root."""
    site = site.resolve()
    bad, checked, ids_of = [], 0, {}
    for page in sorted(site.rglob("*.html")):
        name = page.relative_to(site).as_posix()
        if name in SERVER_ONLY:
            continue
        for kind, target in parse(page.read_text(encoding="utf-8", errors="replace")).refs:
            u = urlparse(target)
            if u.scheme or u.netloc:
                if kind in ("image", "script", "resource") and u.scheme in ("http", "https", ""):
                    bad.append(f"{name}: {kind} {target!r}: from the network (the site must open offline)")
                continue  # an external link, mailto:, data:
            if not u.path:
                continue  # '#anchor' on the same page: the browser check sees those
            checked += 1
            problem = _target_problem(site, (page.parent / unquote(u.path)).resolve(), u.fragment, ids_of)
            if problem:
                bad.append(f"{name}: {kind} {target!r}: {problem}")
    return list(dict.fromkeys(bad)), checked


def _page(page: str) -> str:
    """A page as a file's path: '' and 'folder/' are their index.html."""
    return page + "index.html" if page == "" or page.endswith("/") else page


def _check_over_http(site: Path, pages, browser: str) -> tuple[list[str], int]:
    server = serve(site)
    base = f"http://127.0.0.1:{server.server_address[1]}/"
    bad, checked, ids_of = [], 0, {}
    try:
        for page in pages:
            url = urljoin(base, page)
            refs = parse(dump_dom(browser, url))
            if not refs.links and not refs.images:
                bad.append(f"http {page or '/'}: Chromium's DOM has no links or images")
            for kind, target in refs.refs:
                full = urljoin(url, target)
                if urlparse(full).netloc != urlparse(base).netloc or urlparse(full).scheme not in ("http", "https"):
                    continue  # external, mailto:, javascript:, data: (the disk check refuses external resources)
                checked += 1
                doc, anchor = urldefrag(full)
                if doc not in ids_of:
                    status, body = _get(doc)
                    local = (site / unquote(urlparse(doc).path).lstrip("/")).resolve()
                    is_html = doc.endswith((".html", "/"))
                    ids_of[doc] = (status, local.is_dir(), parse(body.decode("utf-8", "replace")).ids
                                   if status == 200 and is_html else None)
                status, is_dir, ids = ids_of[doc]
                if status != 200:
                    bad.append(f"http {page or '/'}: {kind} {target!r}: HTTP {status}")
                elif is_dir:
                    bad.append(f"http {page or '/'}: {kind} {target!r}: a folder, not a file (a reader from "
                               f"disk gets its listing)")
                elif anchor and ids is not None and anchor not in ids:
                    bad.append(f"http {page or '/'}: {kind} {target!r}: no element with id {anchor!r}")
    finally:
        server.shutdown()
        server.server_close()
    return bad, checked


def _check_from_disk(site: Path, pages, browser: str) -> tuple[list[str], int]:
    site = site.resolve()
    bad, checked, ids_of = [], 0, {}
    for page in pages:
        url = (site / _page(page)).as_uri()
        refs = parse(dump_dom(browser, url))
        if not refs.links and not refs.images:
            bad.append(f"file {page or '/'}: Chromium's DOM has no links or images")
        for kind, target in refs.refs:
            full = urlparse(urljoin(url, target))
            if full.scheme != "file":
                if kind in ("image", "script", "resource") and full.scheme in ("http", "https"):
                    bad.append(f"file {page or '/'}: {kind} {target!r}: from the network (the site must open offline)")
                continue
            checked += 1
            problem = _target_problem(site, Path(unquote(full.path)).resolve(), full.fragment, ids_of)
            if problem:
                bad.append(f"file {page or '/'}: {kind} {target!r}: {problem}")
    return bad, checked


def _check_search_from_disk(site: Path, browser: str, word: str = SEARCH_WORD) -> list[str]:
    url = f"{(site.resolve() / 'index.html').as_uri()}?q={word}"
    dom = dump_dom(browser, url)
    m = re.search(r'class="md-search-result__meta"[^>]*>\s*([^<]*?)\s*<', dom)
    found = m[1] if m else "(no search result box)"
    if not re.match(r"[1-9]\d* matching document", found):  # not "No matching documents"
        return [f"file index.html?q={word}: the search shows {found!r}, not its results (the offline "
                f"plugin's search_index.js and the iframe-worker shim of mkdocs.yml)"]
    return []


def check(site: Path, pages=PAGES, browser: str | None = None, search: bool = True) -> tuple[list[str], int]:
    """(problems, number of references checked) for ``pages`` of the site in ``site``, loaded in
    headless Chromium from a local server and from disk, and (``search``) the search from disk."""
    browser = browser or find_chromium()
    if browser is None:
        raise RuntimeError("no Chromium found (apt-get install chromium)")
    site = Path(site)
    missing = [f"{page}: no such page in {site}" for page in pages if not (site / _page(page)).is_file()]
    pages = [page for page in pages if (site / _page(page)).is_file()]
    bad, checked = _check_over_http(site, pages, browser)
    bad_file, checked_file = _check_from_disk(site, pages, browser)
    if search:
        bad_file += _check_search_from_disk(site, browser)
    return list(dict.fromkeys(missing + bad + bad_file)), checked + checked_file  # (each problem once)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("site", nargs="?", default=str(ROOT / "site"), help="the built site (default site/)")
    ap.add_argument("--page", action="append",
                    help="a page to load, relative to the site (default: index.html and gallery.html)")
    args = ap.parse_args(argv)
    site = Path(args.site)
    if not (site / "index.html").is_file():
        print(f"{site}: no index.html; build the site first (mkdocs build --strict)", file=sys.stderr)
        return 2
    pages = args.page or PAGES
    bad, checked = static_problems(site)
    try:
        more, checked_browser = check(site, pages)
    except RuntimeError as e:
        print(f"check_site: {e}", file=sys.stderr)
        return 2
    bad += more
    for line in bad:
        print(line)
    print(f"{checked} references in the site's HTML files, {checked_browser} in Chromium's DOM of {len(pages)} "
          f"pages (from a server and from disk) and the search from disk checked: {len(bad)} problems",
          file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
