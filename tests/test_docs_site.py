"""The documentation site: ``mkdocs build --strict`` passes (warnings, such as a broken link or a
missing page, are errors), the examples gallery matches the shipped examples, and the built
front page and gallery, loaded in headless Chromium, have no broken internal link or image.
The build took 4 s on a shared 2-core machine (the browser check, 23 s, is marked slow);
nothing is rendered here."""

from __future__ import annotations

import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path

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
    for page in ("index.html", "gallery/index.html", "api/index.html", "performance/index.html",
                 "scenarios/index.html", "validation/index.html"):
        assert (site / page).is_file(), page
    api = (site / "api" / "index.html").read_text()
    assert "load_scenario" in api and "ScenarioRun" in api and "steady_state" in api  # mkdocstrings ran


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
def test_the_front_page_and_gallery_have_no_broken_link_or_image_in_chromium(site, tmp_path):
    bad, checked = check_site.check(site, browser=CHROMIUM)
    assert not bad, "\n".join(bad)
    assert checked >= 50  # the nav's pages, the gallery's pictures
    # and the check sees a missing picture
    broken = tmp_path / "site"
    shutil.copytree(site, broken)
    (broken / "gallery" / "default_walker.png").unlink()
    bad, _ = check_site.check(broken, pages=[""], browser=CHROMIUM)
    assert any("default_walker.png" in b and "404" in b for b in bad), bad
