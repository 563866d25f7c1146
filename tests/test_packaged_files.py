"""The packaged geometry and scene files, their listings in docs/ and the command line agree."""
import re
import subprocess
import sys
from pathlib import Path

from brakewear.geometry import load_geometry
from brakewear.scene.reader import available_scenes, scene_file

ROOT = Path(__file__).resolve().parents[1]
SCENES_MD = (ROOT / "docs" / "scenes.md").read_text()


def _toml_block_after(text: str, heading: str) -> str:
    i = text.index(heading)
    a = text.index("```toml\n", i) + len("```toml\n")
    return text[a:text.index("```\n", a)]


def test_the_annotated_listing_is_the_packaged_default_scene():
    listing = _toml_block_after(SCENES_MD, "## The default scene, annotated")
    packaged = scene_file("default").read_text()
    assert listing == packaged, (
        "docs/scenes.md, 'The default scene, annotated', must be geometry/scenes/default.toml "
        "verbatim")


def test_the_floating_excerpt_quotes_the_packaged_file():
    excerpt = _toml_block_after(SCENES_MD, "## The floating-caliper scene")
    lines = set(scene_file("floating").read_text().splitlines())
    missing = [s for s in excerpt.splitlines() if s.strip() and s not in lines]
    assert not missing, f"lines of the excerpt not in geometry/scenes/floating.toml: {missing}"


def test_run_help_names_every_packaged_scene():
    out = subprocess.run([sys.executable, "-m", "brakewear", "run", "--help"],
                         capture_output=True, text=True, check=True).stdout
    names = available_scenes()
    assert {"default", "floating", "thermal"} <= set(names)
    for name in names:
        assert re.search(rf"\b{name}\b", out), f"{name} not in `brakewear run --help`:\n{out}"


def test_readme_names_every_benchmark():
    import argparse

    from brakewear.bench import add_bench_parser

    sub = argparse.ArgumentParser().add_subparsers()
    add_bench_parser(sub)
    readme = (ROOT / "README.md").read_text()
    for name in sub.choices:
        assert f"brakewear bench {name}" in readme, f"README does not mention bench {name}"


def _header(path: Path) -> str:
    """The comment lines before the first table, joined."""
    text = path.read_text()
    return " ".join(s.lstrip("# ") for s in text[:text.index("\n[")].splitlines())


def test_the_default_geometry_describes_itself_as_it_is():
    g = load_geometry("default")
    head = _header(ROOT / "geometry" / "default.toml")
    # what the file is: one pad (fixed caliper: the mirror plane), a solid ring, clamped inside
    assert g.caliper.type == "fixed" and not g.caliper.fingers and not g.extra_pistons
    assert g.rotor.mount == "ring_clamp" and g.rotor.vents is None
    assert g.support.type == "bilateral"
    for claim in ("idealised", "solid", "clamped at its inner radius", "mirror plane",
                  "both backplate ends"):
        assert claim in head, f"geometry/default.toml's header does not say {claim!r}"
    own = head.split("geometry/floating.toml")[0]      # what it says of itself
    for wrong in ("floating caliper", "vented", "hat rotor"):
        assert wrong not in own, f"geometry/default.toml calls itself {wrong!r}"


def test_the_floating_geometry_describes_itself_as_it_is():
    g = load_geometry("floating")
    head = _header(ROOT / "geometry" / "floating.toml")
    assert g.caliper.type == "floating" and g.rotor.mount == "hat" and g.rotor.vents is None
    assert g.support.type == "push"
    assert "floating caliper" in head and "hat" in head and "push" in head


def test_scene_comments_name_what_the_scene_is():
    bad = []
    for name in available_scenes():
        text = scene_file(name).read_text()
        if re.search(r"^test = ", text, re.M):
            continue  # a tribometer test: no brake geometry (docs/validation.md)
        geom = load_geometry(re.search(r'^geometry = "(\w+)"', text, re.M).group(1))
        rotor_line = re.search(r"^rotor = .*$", text, re.M).group(0)
        if geom.rotor.mount != "hat" and "hat" in rotor_line.replace("no hat", ""):
            bad.append(f"{name}: a hat on a rotor without one: {rotor_line}")
        if "pad_pad_" in text:
            bad.append(f"{name}: pad_pad_")
    assert not bad, "\n".join(bad)
