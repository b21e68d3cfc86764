"""The documentation site: ``mkdocs build --strict`` passes (warnings, such as a broken link or a
missing page, are errors), the examples gallery matches the shipped examples, every internal
reference of the built site names a file (so that a reader who opens it from disk never gets a
folder's listing) and nothing comes from the network, and the built front page and gallery,
loaded in headless Chromium from a server and from disk, have no broken internal link or image
and the search works from disk. The build took 4-10 s on a shared 2-core machine (the browser
check, 25 s, is marked slow); nothing is rendered here."""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _script(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "scripts" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(name, mod)
    spec.loader.exec_module(mod)
    return mod


gallery = _script("make_gallery")
check_site = _script("check_site")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    pytest.importorskip("mkdocs", reason="mkdocs is not installed (pip install -e '.[docs]')")
    out = tmp_path_factory.mktemp("site")
    r = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
                       cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, f"mkdocs build --strict failed:\n{r.stderr[-5000:]}"
    return out


def test_the_site_builds_with_strict(site):
    for page in ("index.html", "gallery.html", "api.html", "performance.html", "scenarios.html",
                 "validation.html", "search/search_index.js", "assets/javascripts/iframe-worker-shim.js"):
        assert (site / page).is_file(), page
    api = (site / "api.html").read_text()
    assert "load_scenario" in api and "ScenarioRun" in api and "steady_state" in api  # mkdocstrings ran


REF = re.compile(r"""<(a|img|script|link)\b[^>]*?\s(?:href|src)=["']?([^"'\s>]+)""", re.I)


def test_every_internal_reference_of_the_built_site_is_a_file_and_none_is_on_the_network(site):
    """Opened from disk (file://), a link to a folder shows the folder's listing, not a page: so
    every relative ``href``/``src`` of every built page must name a file of the site (mkdocs'
    default directory URLs fail this on every nav link), and no script, style sheet or image may
    come from the network (the site opens offline). The references are read here with a regular
    expression of the test's own, not with scripts/check_site.py's parser. 404.html is left
    out: a server sends it from any folder, so its references are from the server's root."""
    checked, bad = 0, []
    for page in sorted(site.rglob("*.html")):
        if page.name == "404.html":
            continue
        for tag, ref in REF.findall(page.read_text()):
            u = urlparse(ref.replace("&amp;", "&"))
            if u.scheme or u.netloc:
                if tag.lower() != "a" and u.scheme in ("http", "https", ""):
                    bad.append(f"{page.name}: <{tag}> {ref} is on the network")
                continue
            if not u.path:
                continue  # an anchor of the same page
            checked += 1
            target = (page.parent / unquote(u.path)).resolve()
            if not target.is_file() or site.resolve() not in target.parents:
                bad.append(f"{page.relative_to(site)}: <{tag}> {ref} -> "
                           f"{'a folder' if target.is_dir() else 'nothing'}")
    assert not bad, f"{len(bad)} references that a reader from disk cannot follow:\n" + "\n".join(bad[:40])
    assert checked > 20 * 30  # about 30 nav links on each of the 30 pages, and their pictures


def test_the_site_checker_sees_a_folder_link_a_missing_file_and_a_network_script(tmp_path):
    """scripts/check_site.py's browser-free part, on a three-file site made here."""
    (tmp_path / "guide").mkdir()
    (tmp_path / "guide" / "a.png").write_bytes(b"")
    (tmp_path / "ok.html").write_text('<h2 id="here">x</h2>')
    (tmp_path / "index.html").write_text(
        '<a href="ok.html#here">fine</a> <img src="guide/a.png"> <a href="#top">same page</a>'
        '<a href="guide/">folder</a> <a href="ok.html#nowhere">bad anchor</a> <img src="b.png">'
        '<script src="https://cdn.example/x.js"></script> <a href="https://example.org">external</a>')
    bad, checked = check_site.static_problems(tmp_path)
    assert checked == 5
    assert sorted(bad) == sorted([
        "index.html: link 'guide/': a folder, not a file: opened from disk, it shows the folder's listing",
        "index.html: link 'ok.html#nowhere': no element with id 'nowhere'",
        "index.html: image 'b.png': no such file",
        "index.html: script 'https://cdn.example/x.js': from the network (the site must open offline)"])


def test_every_page_of_docs_is_in_the_nav():
    """A page left out of mkdocs.yml's nav would be built but never reached."""
    nav = (ROOT / "mkdocs.yml").read_text()
    missing = [p.name for p in sorted((ROOT / "docs").glob("*.md")) if f": {p.name}" not in nav]
    assert not missing, f"docs pages missing from mkdocs.yml's nav: {missing}"


def test_the_validation_page_quotes_the_lowe_langley_table_as_generated():
    """docs/validation.md repeats the fairlead-tension table that
    scripts/reproduce_lowe_langley2006.py writes into docs/lowe_langley2006.md: the copy must
    be the generated one, so that regenerating the reproduction cannot leave it stale."""
    head = "| case | added_mass | RMS difference (kN) | largest (kN) | our range (kN) | paper's range (kN) |\n"

    def table(page):
        text = (ROOT / "docs" / page).read_text()
        i = text.index(head)
        return text[i:text.index("\n\n", i)]

    assert table("validation.md") == table("lowe_langley2006.md")


def test_the_gallery_matches_the_shipped_examples():
    """Every shipped example has its picture, made from the example file as it is now (the
    manifest's sha256), and docs/gallery.md is what the manifest gives (no rendering here:
    ``MUJOCO_GL=egl python scripts/make_gallery.py`` remakes what changed)."""
    assert len(gallery.examples()) >= 20
    bad = gallery.problems()
    assert not bad, "stale gallery (run MUJOCO_GL=egl python scripts/make_gallery.py):\n" + "\n".join(bad)
    for name in gallery.examples():
        png = gallery.GALLERY / gallery.image_of(name)
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size < 100_000, name


def test_the_gallery_check_sees_a_changed_example(tmp_path, monkeypatch):
    examples = tmp_path / "examples"
    shutil.copytree(gallery.EXAMPLES, examples)
    monkeypatch.setattr(gallery, "EXAMPLES", examples)
    assert not gallery.problems()
    with open(examples / "default_walker.toml", "a") as f:
        f.write("\n# changed\n")
    assert any("default_walker" in p and "changed" in p for p in gallery.problems())
    (examples / "extra.toml").write_text("# a new example\n")
    assert any(p.startswith("extra: no picture") for p in gallery.problems())


CHROMIUM = check_site.find_chromium()


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None, reason="no headless Chromium here (apt-get install chromium): the "
                                              "browser check of the built site is not run")
def test_the_front_page_and_gallery_work_in_chromium_from_a_server_and_from_disk(site, tmp_path):
    """The DOM Chromium builds (scripts run) for the front page and the gallery, loaded over
    http and from file://: every internal link, picture, script and style sheet is found (a file,
    not a folder), and ``index.html?q=catenary`` opened from disk lists search results."""
    bad, checked = check_site.check(site, browser=CHROMIUM)
    assert not bad, "\n".join(bad)
    assert checked >= 2 * 100  # the nav's pages and the gallery's pictures, loaded both ways
    # and the check sees a missing picture, a link to a folder and a search that cannot start
    broken = tmp_path / "site"
    shutil.copytree(site, broken)
    (broken / "gallery" / "default_walker.png").unlink()
    (broken / "search" / "search_index.js").unlink()
    index = broken / "index.html"
    index.write_text(index.read_text().replace('href="getting_started.html"', 'href="gallery/"', 1))
    bad, _ = check_site.check(broken, pages=["index.html"], browser=CHROMIUM)
    assert any(b.startswith("http") and "default_walker.png" in b and "404" in b for b in bad), bad
    assert any(b.startswith("file") and "default_walker.png" in b and "no such file" in b for b in bad), bad
    assert any(b.startswith("file") and "'gallery/'" in b and "a folder" in b for b in bad), bad
    assert any("?q=catenary" in b for b in bad), bad
