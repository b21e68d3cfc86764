"""The examples gallery: one picture per shipped example, and the page that shows them.

    MUJOCO_GL=egl python scripts/make_gallery.py            # render what changed, write the page
    MUJOCO_GL=egl python scripts/make_gallery.py --all      # render every example again
    python scripts/make_gallery.py --check                  # exit 1 if a picture or the page is stale

Each shipped example (``examples/**/*.toml``, installed as ``mjtether.examples``) gets a small
PNG under ``docs/gallery/``: a scenario is built as ``mjtether run`` builds it (its steady start)
and drawn offscreen from the side at t = 0, as ``mjtether render`` draws it (the tether coloured
by tension); a network of lines is built at its steady start and drawn the same way, every line
coloured by tension (``mjtether.io.network_view``). ``docs/gallery/manifest.json`` records
each example file's sha256 with its picture, and ``docs/gallery.md`` is written from the manifest
and each example's leading comment. ``--check`` renders nothing: it reads the manifest, the
example files and the pictures, so a test can run it in a second.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
GALLERY = ROOT / "docs" / "gallery"
MANIFEST = GALLERY / "manifest.json"
PAGE = ROOT / "docs" / "gallery.md"
WIDTH, HEIGHT = 400, 300
LATER = 20.0  # s: when a scenario that starts with nothing to see is drawn


def examples() -> list[str]:
    """Every shipped example, by the name ``mjtether run NAME`` takes (``networks/...`` for the
    networks), in a stable order."""
    return sorted(p.relative_to(EXAMPLES).with_suffix("").as_posix() for p in EXAMPLES.rglob("*.toml"))


def sha256(name: str) -> str:
    return hashlib.sha256((EXAMPLES / f"{name}.toml").read_bytes()).hexdigest()


def image_of(name: str) -> str:
    """The picture's file name under docs/gallery/."""
    return name.replace("/", "__") + ".png"


def description(name: str) -> str:
    """The example's leading comment, as one paragraph."""
    lines = []
    for line in (EXAMPLES / f"{name}.toml").read_text().splitlines():
        if not line.startswith("#"):
            break
        lines.append(line.lstrip("#").strip())
    return " ".join(x for x in lines if x)


def _is_network(name: str) -> bool:
    return name.startswith("networks/")


def render_scenario(name: str, out: Path) -> str:
    """Draw the scenario at its start with the video's renderer; the caption's how."""
    import imageio.v3 as iio

    from mjtether.io.render import FrameRenderer, VideoSettings
    from mjtether.scenario import load_scenario
    from mjtether.scenario.runner import ScenarioRun

    sc = load_scenario(name)
    run = ScenarioRun(sc)
    try:
        # a vehicle alone, or one that starts with nothing deployed, shows little at t = 0: drawn
        # after LATER seconds, following the vehicle
        later = not sc.tether.attached or run.named.deployed_length < 1.0
        while later and run.sim.time < LATER:
            run.step()
        fr = FrameRenderer(run, VideoSettings(width=WIDTH, height=HEIGHT, camera="track" if later else "side"))
        try:
            iio.imwrite(out, fr.render(), optimize=True)
        finally:
            fr.close()
    finally:
        run.close()
    if later:
        return f"at t = {LATER:g} s, as `mjtether render --camera track` draws it"
    return "its start (t = 0) from the side, as `mjtether render --camera side` draws it"


def render_network(name: str, out: Path) -> str:
    """Draw the network at its steady start (settled, where its file asks for that, as ``mjtether
    run`` starts it) with the video's renderer (``io.network_view``); the caption's how."""
    import imageio.v3 as iio

    from mjtether.io import moordyn
    from mjtether.io.network_view import NetworkView
    from mjtether.io.render import FrameRenderer, VideoSettings
    from mjtether.network.run import build, settle

    net = moordyn.load_any(name)
    r = build(net)
    try:
        if net.settle > 0 and net.start == "steady":
            settle(r, net.settle)
        fr = FrameRenderer(NetworkView(r), VideoSettings(width=WIDTH, height=HEIGHT, camera="side"))
        try:
            iio.imwrite(out, fr.render(), optimize=True)
        finally:
            fr.close()
    finally:
        r.sim.close()
    return "its start from the side, every line coloured by tension, as `mjtether render --camera side` draws it"


def load_manifest() -> dict:
    return json.loads(MANIFEST.read_text()) if MANIFEST.is_file() else {}


def page(manifest: dict) -> str:
    """docs/gallery.md from the manifest and the examples' comments."""
    out = ["# Examples gallery", "",
           "One picture per shipped example (`examples/`, installed with the package as",
           "`mjtether.examples`; run any of them by name from anywhere: `mjtether run NAME`).",
           "Made by `MUJOCO_GL=egl python scripts/make_gallery.py`; a test checks that every",
           "example has its picture and that none is older than its file",
           "(`docs/gallery/manifest.json` holds each file's sha256). Scenarios are drawn at their",
           "start, the tether coloured by tension (blue: slack, red: the top of the scale); networks",
           "of lines likewise, every line on one tension scale.", ""]
    for name in examples():
        entry = manifest.get(name, {})
        out += [f"## {name}", "", description(name), "",
                f"`mjtether run {name}`", "",
                f"![{name}: {entry.get('caption', '')}](gallery/{image_of(name)})", "",
                f"*{entry.get('caption', '')}*", ""]
    return "\n".join(out)


def problems() -> list[str]:
    """What is stale: a missing or extra picture, a changed example, an out-of-date page."""
    manifest = load_manifest()
    bad = []
    names = examples()
    for name in names:
        entry = manifest.get(name)
        if entry is None:
            bad.append(f"{name}: no picture in docs/gallery/manifest.json")
            continue
        if entry.get("sha256") != sha256(name):
            bad.append(f"{name}: examples/{name}.toml changed since its picture was made")
        if entry.get("image") != image_of(name) or not (GALLERY / image_of(name)).is_file():
            bad.append(f"{name}: no picture docs/gallery/{image_of(name)}")
    for name in sorted(set(manifest) - set(names)):
        bad.append(f"{name}: in the manifest but no longer an example")
    if not PAGE.is_file() or PAGE.read_text() != page(manifest):
        bad.append("docs/gallery.md is not what the manifest and the examples give")
    return bad


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="render nothing; exit 1 listing stale pictures")
    ap.add_argument("--all", action="store_true", help="render every example, changed or not")
    ap.add_argument("names", nargs="*", help="render only these examples")
    args = ap.parse_args(argv)
    if args.check:
        bad = problems()
        for line in bad:
            print(line)
        if bad:
            print(f"{len(bad)} stale gallery item(s): run MUJOCO_GL=egl python scripts/make_gallery.py",
                  file=sys.stderr)
            return 1
        print(f"the gallery's {len(examples())} pictures match the examples")
        return 0
    GALLERY.mkdir(parents=True, exist_ok=True)
    manifest = {k: v for k, v in load_manifest().items() if k in examples()}
    for name in args.names or examples():
        entry = manifest.get(name)
        if (not args.all and not args.names and entry and entry.get("sha256") == sha256(name)
                and (GALLERY / image_of(name)).is_file()):
            continue
        t0 = time.perf_counter()
        out = GALLERY / image_of(name)
        caption = (render_network if _is_network(name) else render_scenario)(name, out)
        manifest[name] = {"sha256": sha256(name), "image": image_of(name), "caption": caption}
        MANIFEST.write_text(json.dumps(dict(sorted(manifest.items())), indent=1) + "\n")
        print(f"{name}: {out.relative_to(ROOT)} ({out.stat().st_size // 1024} KiB, "
              f"{time.perf_counter() - t0:.0f} s)", flush=True)
    for stale in set(p.name for p in GALLERY.glob("*.png")) - {image_of(n) for n in examples()}:
        (GALLERY / stale).unlink()
    PAGE.write_text(page(manifest))
    print(f"wrote {PAGE.relative_to(ROOT)}")
    bad = problems()
    for line in bad:
        print(line, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
