"""Every figure in docs/ is what its command draws now: by name, panel count and pixel size.

docs/figures/manifest.toml names, for each PNG, the command that writes it, the
function that draws it, the (part of the) file name that function's file writes,
and its number of panels.  Checked here: the names both ways (every PNG in the
manifest, every manifest entry and every figure a page shows on disk); that the
drawing function exists and its file writes the name; the panel count and the
pixel size that the function's code fixes (``subplots(2, 3, figsize=...)`` with
``savefig(dpi=...)``, pyvista's ``shape=`` and ``window_size=``) against the
manifest and the PNG in docs/; and the demo's figures, drawn again on a coarse
mesh, against theirs (the same name, panels and size).
"""
from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

pytest.importorskip("pyvista")
from PIL import Image  # noqa: E402  (pyvista's dependency)

ROOT = Path(__file__).resolve().parents[1]
FIGS = ROOT / "docs" / "figures"
MANIFEST = tomllib.loads((FIGS / "manifest.toml").read_text())


def test_every_figure_in_docs_is_in_the_manifest_and_back():
    pngs = {p.relative_to(FIGS).as_posix() for p in FIGS.rglob("*.png")}
    elsewhere = [p for p in (ROOT / "docs").rglob("*.png") if FIGS not in p.parents]
    assert not elsewhere, f"figures outside docs/figures: {elsewhere}"
    assert pngs == set(MANIFEST), (f"not in the manifest: {sorted(pngs - set(MANIFEST))}; "
                                   f"in it but not on disk: {sorted(set(MANIFEST) - pngs)}")
    pages = " ".join(p.read_text() for p in (ROOT / "docs").rglob("*.md"))
    shown = set(re.findall(r"figures/([\w.\-]+\.png)", pages))
    assert shown <= pngs, f"pages show figures that are not there: {sorted(shown - pngs)}"
    named = {n for n in pngs if re.search(rf"\b{re.escape(n)}", pages)}
    assert pngs == named, f"figures no page shows or names: {sorted(pngs - named)}"


def _function(entry: dict) -> tuple[Path, ast.FunctionDef, str]:
    file, name = entry["draws"].split(":")
    src = (ROOT / file).read_text()
    fns = [n for n in ast.walk(ast.parse(src)) if isinstance(n, ast.FunctionDef)
           and n.name == name]
    assert fns, f"{entry['draws']}: no such function"
    return ROOT / file, fns[0], src


def test_the_drawing_code_writes_the_name():
    bad = []
    for name, entry in sorted(MANIFEST.items()):
        path, fn, src = _function(entry)
        # the name in docs is the name written, or the command says which file it copies
        if not (entry["writes"] in name or f"({entry['writes']})" in entry["command"]):
            bad.append(f"{name}: the manifest says it writes {entry['writes']!r}")
        # the file that draws it, or the command's own entry point, writes that name
        study = re.match(r"python (studies/\w+\.py)", entry["command"])
        writer = (ROOT / study.group(1)).read_text() if study else \
            (ROOT / "brakewear" / "cli.py").read_text()
        if entry["writes"] not in src and entry["writes"] not in writer:
            bad.append(f"{name}: neither {path.name} nor the command's script writes "
                       f"{entry['writes']!r}")
    assert MANIFEST, "the manifest is empty"
    assert not bad, "\n".join(bad)


def _literal(node):
    try:
        return ast.literal_eval(node)
    except ValueError:
        return None


def fixed_by_code(fn: ast.FunctionDef) -> tuple[int | None, tuple[int, int] | None]:
    """(panels, pixel size) as far as the function's code fixes them (None: data decide)."""
    panels = figsize = dpi = window = None
    tight = False
    args = fn.args
    for a, d in zip(args.args[len(args.args) - len(args.defaults):] + args.kwonlyargs,
                    args.defaults + args.kw_defaults):
        if a.arg == "window_size" and d is not None:
            window = _literal(d)
    for node in ast.walk(fn):
        if not isinstance(node, ast.Call):
            continue
        callee = node.func.attr if isinstance(node.func, ast.Attribute) else \
            getattr(node.func, "id", "")
        kw = {k.arg: k.value for k in node.keywords}
        if callee == "subplots":
            dims = [_literal(a) for a in node.args[:2]] + [1, 1][len(node.args[:2]):]
            panels = dims[0] * dims[1] if all(isinstance(x, int) for x in dims) else None
        if callee == "Plotter":
            shape = _literal(kw["shape"]) if "shape" in kw else (1, 1)
            panels = shape[0] * shape[1] if shape else None
            window = _literal(kw["window_size"]) if "window_size" in kw else window
        if "figsize" in kw:
            figsize = _literal(kw["figsize"])
        if callee == "savefig":
            dpi = _literal(kw["dpi"]) if "dpi" in kw else None
            tight = "bbox_inches" in kw
    size = None
    if window:
        size = tuple(int(v) for v in window)
    elif figsize and dpi and not tight:
        size = (round(figsize[0] * dpi), round(figsize[1] * dpi))
    return panels, size


def test_panels_and_size_are_what_the_code_fixes():
    """Every figure whose drawing code fixes its panel count or its pixel size has them;
    the others (panels and size set by the data) are counted, and stay a minority."""
    bad, checked = [], 0
    for name, entry in sorted(MANIFEST.items()):
        panels, size = fixed_by_code(_function(entry)[1])
        checked += (panels, size) != (None, None)
        if panels is not None and entry["panels"] != panels:
            bad.append(f"{name}: the manifest says {entry['panels']} panels, the code draws "
                       f"{panels}")
        if size is not None and Image.open(FIGS / name).size != size:
            bad.append(f"{name}: {Image.open(FIGS / name).size} px in docs, the code draws "
                       f"{size}: run `{entry['command']}` again")
    assert not bad, "\n".join(bad)
    assert checked >= 35, f"only {checked} of {len(MANIFEST)} figures checked against their code"


def test_the_static_reading_sees_what_it_should():
    src = ("def f(p, window_size=(900, 700)):\n"
           "    fig, ax = plt.subplots(2, 3, figsize=(10, 4))\n"
           "    fig.savefig(p, dpi=120)\n"
           "def g(p, n):\n"
           "    fig, ax = plt.subplots(1, n, figsize=(4 * n, 3))\n"
           "    fig.savefig(p, dpi=100)\n"
           "def h(p):\n"
           "    pl = pv.Plotter(shape=(1, 4), window_size=[2000, 500])\n")
    f, g, h = [n for n in ast.parse(src).body]
    assert fixed_by_code(f) == (6, (900, 700))
    assert fixed_by_code(g) == (None, None)
    assert fixed_by_code(h) == (4, (2000, 500))


def test_the_demo_draws_its_docs_figures_again(tmp_path, monkeypatch):
    """The demo's three figures, on a 12 mm mesh: the names the manifest gives, the
    panels it counts and the docs figures' pixel sizes."""
    import pyvista as pv

    from brakewear.cli import main

    panels = {}
    real = pv.Plotter.screenshot

    def count(self, filename=None, **kw):
        if filename:
            panels[Path(filename).name] = len(self.renderers)
        return real(self, filename, **kw)

    monkeypatch.setattr(pv.Plotter, "screenshot", count)
    assert main(["demo", "--out", str(tmp_path), "--size", "12", "--wear-duration", "0"]) == 0
    for name, entry in MANIFEST.items():
        if not entry["command"].startswith("brakewear demo"):
            continue
        drawn = tmp_path / entry["writes"]
        assert drawn.exists(), f"the demo did not write {entry['writes']}"
        assert panels[entry["writes"]] == entry["panels"], (name, panels)
        assert Image.open(drawn).size == Image.open(FIGS / name).size, name
