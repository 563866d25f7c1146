"""The path of a run from a scene file to one wear step keeps to the layers.

The layers are those of the package's design (bottom to top): data and laws;
geometry; meshes, forms and solvers; contact; the model (data: meshes,
operators, the contact system); interfaces, thermal and motion, which take a
model; static solves, duties, the wear loop and scenes; output, the command
line, figures and benchmarks.  A call from a module of one layer into a module of a higher layer
*climbs back* (a callback, or a method of an object of the higher layer);
:func:`climbs` follows short runs of scene files call by call
(``sys.setprofile``: load the file, build, one wear step, write), one with
linear meshes and one with quadratic meshes and thermal coupling, and lists
each (caller module, callee module) pair that climbs, once.  A module's own
code, run when a registry imports it by name, is loading, not a call.  Run this file as
a script to print them::

    python tests/test_layers.py
"""
from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PKG = ROOT / "brakewear"

#: the layers, bottom first: a module belongs to the layer of the longest dotted
#: prefix (below ``brakewear``) that names it
LAYERS: tuple[tuple[str, ...], ...] = (
    ("errors", "checks", "parts", "registry", "storage", "analytic", "materials", "laws",
     "caliper.analytic",
     "cleaning.corrosion", "cleaning.rust", "cleaning.rust_fit", "cleaning.rust_model",
     "cleaning.rust_record", "cleaning.criteria"),
    ("geometry", "caliper.geometry"),
    ("mesh", "fem", "solvers", "rough", "caliper.loads", "caliper.parts",
     "caliper.complementarity"),
    ("contact", "caliper.rows"),
    ("model",),
    ("interfaces", "thermal", "motion", "caliper.condensation", "caliper.sets", "caliper.joint",
     "caliper.interface", "tribology.bodies", "tribology.pair"),
    ("static", "caliper.static", "duty", "cleaning.routine", "cleaning.heat",
     "cleaning.bedding", "cleaning.steady", "cleaning.priors", "cleaning.brake",
     "cleaning.car", "cleaning.sample", "cleaning.sweep", "cleaning.sensitivity", "wear",
     "scene", "tribology"),
    ("output", "cli", "bench", "tribology.runner", "tribology.output", "tribology.command",
     "cleaning.report", "cleaning.command"),
)

#: the most climbs the path may take (distinct caller -> callee module pairs)
MAX_CLIMBS = 0

SCENE = """
[units]
length = "mm"
pressure = "MPa"
time = "s"
angular_speed = "rad/s"
temperature = "C"

[scene]
name = "layers"
geometry = "default"

[components]
rotor = "elastic"
pad = "elastic"
piston = "traction"

[mesh]
size = 12.0

[environment]
line_pressure = 1.0
omega = 55.0
duration = 10.0

[interface]
model = "fe"
mu = 0.4

[wear.pad]
k = "material"

[wear.rotor]
k = "material"

[numerics]
steps = 1

[output]
figures = false
"""

#: the same scene on quadratic meshes, with thermal coupling
SCENE_P2_THERMAL = SCENE.replace("size = 12.0", "size = 12.0\norder = 2").replace(
    "[numerics]", "[thermal]\nenabled = true\n\n[numerics]")


def layer(module: str) -> int | None:
    """The layer of a ``brakewear`` module (None: not one of the package's)."""
    parts = module.split(".")
    if parts[0] != "brakewear" or len(parts) < 2:
        return None
    for n in range(len(parts) - 1, 0, -1):
        prefix = ".".join(parts[1:n + 1])
        for i, names in enumerate(LAYERS):
            if prefix in names:
                return i
    return None


def _module(frame) -> str | None:
    path = Path(frame.f_code.co_filename)
    try:
        rel = path.resolve().relative_to(PKG)
    except ValueError:
        return None
    parts = ("brakewear",) + rel.with_suffix("").parts
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def climbs(tmp: Path, scenes=(SCENE, SCENE_P2_THERMAL)) -> Counter:
    """(caller module, callee module) -> calls, for every call of the short runs of
    ``scenes`` (load the file, build, one wear step, write) that climbs to a higher
    layer."""
    from brakewear.output.runs import run_scene
    from brakewear.scene import load_scene

    seen: Counter = Counter()

    def profile(frame, event, arg):
        if event != "call" or frame.f_code.co_name == "<module>":
            return          # a module's own code runs when it is imported, not called
        callee = _module(frame)
        if callee is None:
            return
        up = frame.f_back
        while up is not None and _module(up) is None:
            up = up.f_back          # through numpy, scipy and the standard library
        if up is None:
            return
        caller = _module(up)
        lo, hi = layer(caller), layer(callee)
        if lo is not None and hi is not None and hi > lo:
            seen[(caller, callee)] += 1

    for i, text in enumerate(scenes):
        path = tmp / f"layers{i}.toml"
        path.write_text(text)
        sys.setprofile(profile)
        try:
            run_scene(load_scene(path), tmp / f"out{i}")
        finally:
            sys.setprofile(None)
    return seen


def test_every_module_has_a_layer():
    names = {".".join(("brakewear",) + p.relative_to(PKG).with_suffix("").parts)
             for p in PKG.rglob("*.py") if p.name not in ("__init__.py", "__main__.py")}
    assert not sorted(n for n in names if layer(n) is None)


def _imports(path: Path) -> set[str]:
    """The ``brakewear`` modules a package module imports (relative imports resolved)."""
    import ast

    rel = path.relative_to(PKG).with_suffix("")
    here = ["brakewear", *rel.parts[:-1]]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = here[:len(here) - node.level + 1] if node.level else []
            mod = ".".join(base + ([node.module] if node.module else []))
            found.add(mod)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    return {m for m in found if m.startswith("brakewear.")}


def test_the_model_sits_below_the_parts_that_take_it():
    """model.py is data: it imports nothing from the interfaces, the wear loop,
    thermal coupling, the geometry update or the static solves that take a model."""
    own = layer("brakewear.model")
    for consumer in ("brakewear.interfaces.fe", "brakewear.wear.stepper",
                     "brakewear.thermal.model", "brakewear.motion.brake", "brakewear.static"):
        assert layer(consumer) > own, consumer
    above = sorted(m for m in _imports(PKG / "model.py") if (layer(m) or 0) > own)
    assert not above, f"model.py imports from higher layers: {above}"


@pytest.mark.slow
def test_a_scene_run_never_climbs_back(tmp_path):
    found = climbs(tmp_path)
    assert len(found) <= MAX_CLIMBS, "\n".join(
        f"{a} -> {b} ({n} calls)" for (a, b), n in sorted(found.items()))


if __name__ == "__main__":
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        found = climbs(Path(d))
    for (a, b), n in sorted(found.items()):
        print(f"{a} (layer {layer(a)}) -> {b} (layer {layer(b)}): {n} calls")
    print(f"{len(found)} climbs")
