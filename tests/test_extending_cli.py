"""A user's parts, in a module outside the package, run by ``brakewear run``.

The module, the scene file and the package metadata are taken from
docs/extending.md as written there (its ``<!-- file: ... -->`` blocks), and
its commands (``<!-- run: ... -->``) run in a subprocess, as a reader would
run them: with ``--import``, with the scene's ``[scene] import`` key, and
installed through an entry point of the group ``brakewear.parts`` (the
distribution's metadata written as ``pip install`` writes it).  The three
runs give the same numbers, and those numbers are the parts' own: the
application turns the rotor its number of turns, and the pad's worn volume
is the mild law's Archard volume where the power density stays below the
limit, more where it does not.  The registration shape and the order of
the scene's checks (a part's name before its keys) are tested here too.
"""
from __future__ import annotations

import csv
import math
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from brakewear.errors import DutyError, LawError, SceneError
from brakewear.parts import import_parts, load_entry_points
from brakewear.registry import OptionKey

ROOT = Path(__file__).resolve().parents[1]
DOC = (ROOT / "docs" / "extending.md").read_text()
FILES = dict(re.findall(r"<!-- file: (\S+) -->\n```\w+\n(.*?)```", DOC, re.S))
RUNS = {k: [shlex.split(s) for s in v.strip().splitlines()]
        for k, v in re.findall(r"<!-- run: ([^>]+?) -->\n```sh\n(.*?)```", DOC, re.S)}

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.10 only
    import tomli as tomllib


def test_the_doc_holds_the_files_and_commands():
    assert {"my_parts.py", "bed.toml", "pyproject.toml"} <= set(FILES)
    assert RUNS["import"] == [["brakewear", "run", "bed.toml", "--import", "my_parts"]]
    assert RUNS["entry point"] == [["pip", "install", "."], ["brakewear", "run", "bed.toml"]]


def _brakewear(args: list[str], cwd: Path, path: Path | None = None
               ) -> subprocess.CompletedProcess:
    """``brakewear ARGS --quiet`` (the installed command) in ``cwd``, with ``path``
    (only) added to the Python path."""
    exe = Path(sys.executable).with_name("brakewear")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "brakewear"]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(MPLBACKEND="Agg", **({"PYTHONPATH": str(path)} if path else {}))
    return subprocess.run(cmd + args + ["--quiet"], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def _rows(out: Path) -> list[dict]:
    """The rows of ``applications.csv`` but their wall time."""
    with open(out / "applications.csv", newline="") as fh:
        return [{k: v for k, v in row.items() if k != "run_s"} for row in csv.DictReader(fh)]


def _write(folder: Path, *names: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for name in names:
        (folder / name).write_text(FILES[name])
    return folder


def _install(pyproject: str, site: Path) -> None:
    """What ``pip install .`` leaves of the distribution: its module and its metadata
    (METADATA, entry_points.txt) in ``site``."""
    meta = tomllib.loads(pyproject)
    project = meta["project"]
    for module in meta["tool"]["setuptools"]["py-modules"]:
        (site / f"{module}.py").write_text(FILES[f"{module}.py"])
    info = site / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {project['name']}\n"
                                   f"Version: {project['version']}\n")
    (info / "entry_points.txt").write_text("".join(
        f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in eps.items())
        for group, eps in project["entry-points"].items()))


def test_the_parts_run_from_the_command_line_three_ways(tmp_path):
    """``--import`` (the module in the working directory, the command run as the doc
    writes it), ``[scene] import`` (the .py file beside the scene, run from another
    folder) and an installed entry point each run the user's interface, law and
    application; the runs agree to the last digit, and without any of them the
    scene is refused naming the interface model, not one of its keys."""
    here = _write(tmp_path / "here", "my_parts.py", "bed.toml")
    (cmd,) = RUNS["import"]
    done = _brakewear(cmd[1:], here)
    assert done.returncode == 0, done.stderr
    assert "3 applications (2 braked)" in done.stdout
    by_import = _rows(here / "brakewear-bed")

    scenes = _write(tmp_path / "scenes", "my_parts.py")
    text = FILES["bed.toml"].replace('[scene]\nname = "bed"',
                                     '[scene]\nname = "bed"\nimport = ["my_parts.py"]')
    (scenes / "bed.toml").write_text(text)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    done = _brakewear(["run", str(scenes / "bed.toml"), "--out", "by_key"], elsewhere)
    assert done.returncode == 0, done.stderr
    by_key = _rows(elsewhere / "by_key")

    site, work = tmp_path / "site", _write(tmp_path / "work", "bed.toml")
    site.mkdir()
    pip, run = RUNS["entry point"]
    refused = _brakewear(run[1:], work, path=site)          # not installed yet
    assert refused.returncode == 2
    assert "interface.model: 'bed' is not allowed" in refused.stderr, refused.stderr
    assert "bed_modulus" not in refused.stderr
    _install(FILES["pyproject.toml"], site)                   # pip install .
    done = _brakewear(run[1:], work, path=site)
    assert done.returncode == 0, done.stderr
    by_entry_point = _rows(work / "brakewear-bed")

    assert [r["kind"] for r in by_import] == ["turns", "dwell", "turns"]
    assert by_import == by_key == by_entry_point
    _check_the_parts_numbers(by_import)


def _check_the_parts_numbers(rows: list[dict]) -> None:
    """The application's turns, and the law's Archard volume: mild at 0.5 MPa, where
    the bed's pressure times the sliding speed stays below pv_limit; above it at 1 MPa."""
    from brakewear.geometry import load_geometry

    scene = tomllib.loads(FILES["bed.toml"])
    k_mild = load_geometry("default").pad.friction_material.wear_k
    k_severe = scene["wear"]["pad"]["k_severe"]
    clamp_area = load_geometry("default").clamp_area
    first, _, second = rows
    for row, spec in ((first, scene["schedule"]["applications"][0]),
                      (second, scene["schedule"]["applications"][2])):
        omega, turns = spec["omega"], spec["turns"]
        assert float(row["rotor_angle"]) == pytest.approx(2 * math.pi * turns, rel=1e-12)
        assert float(row["duration"]) == pytest.approx(2 * math.pi * turns / omega, rel=1e-12)
        # sum over nodes of A k p v t, with v = omega r: k omega F r_eff t for one k
        archard = (omega * spec["line_pressure"] * 1e6 * clamp_area
                   * float(row["r_eff_mean"]) * float(row["duration"]))
        row["mild"], row["severe"] = k_mild * archard, k_severe * archard
    assert float(first["pad_volume_m3"]) == pytest.approx(first["mild"], rel=1e-9)
    assert second["mild"] * 1.01 < float(second["pad_volume_m3"]) < 0.99 * second["severe"]


def _scene_text(interface: str, pad: str) -> str:
    return (FILES["bed.toml"].replace('model = "bed"\nbed_modulus = 2e12         # Pa/m',
                                      interface)
            .replace('model = "severe"           # k_mild: the friction material\'s wear_k',
                     pad))


def test_a_part_is_named_before_its_keys(tmp_path):
    """A scene naming a part no table holds is refused naming the part (with the
    ways to register one), before its keys; a key of no registered part, with a
    built-in model named, is an unknown key."""
    from brakewear.scene import load_scene

    path = tmp_path / "bed.toml"
    path.write_text(FILES["bed.toml"])
    with pytest.raises(SceneError, match=r"interface\.model: 'bed' is not allowed; allowed: "
                                         r"'fe', .*--import"):
        load_scene(path)
    path.write_text(_scene_text('model = "fe"', 'model = "severe"'))
    with pytest.raises(SceneError, match=r"wear\.pad\.model: 'severe' is not allowed; "
                                         r"(no wear law is registered|allowed: )"):
        load_scene(path)
    path.write_text(_scene_text('model = "fe"\nbed_modulus = 2e12', "k = 5e-15"))
    with pytest.raises(SceneError, match=r"interface\.bed_modulus: unknown key 'bed_modulus' "
                                         r"in \[interface\]; allowed keys: model, .*, method$"):
        load_scene(path)


@pytest.fixture
def registered():
    """Parts registered by a test, taken out again."""
    from brakewear.duty import unregister_application
    from brakewear.interfaces import unregister_interface
    from brakewear.laws.base import unregister_wear_law

    names: list[tuple] = []
    yield names
    drop = {"interface": unregister_interface, "law": unregister_wear_law,
            "application": unregister_application}
    for table, name in names:
        drop[table](name)


def test_the_registration_shape_is_read_from_the_class(registered):
    """The registry reads a part's name, keys and capabilities from its class, and
    refuses, naming it, a class that inherits its name, declares a capability that is
    not True or False, makes its name a dataclass field, repeats a key, or gives an
    application key that is not one of its fields."""
    from dataclasses import dataclass

    from brakewear.duty import Drag, register_application
    from brakewear.interfaces import (
        FEInterface,
        allowed_for,
        capabilities_of,
        interface_model,
        register_interface,
    )
    from brakewear.laws.base import register_wear_law, wear_law_model

    class Mine(FEInterface):
        name, keys = "mine_fe", ()
        follows_geometry = False

    register_interface(Mine)
    registered.append(("interface", "mine_fe"))
    assert interface_model("mine_fe") is Mine
    assert capabilities_of(Mine) == capabilities_of(FEInterface) - {"follows_geometry"}
    assert "mine_fe" in allowed_for("any_line_pressure")
    assert "mine_fe" not in allowed_for("follows_geometry")

    class Inherits(FEInterface):
        pass

    with pytest.raises(SceneError, match=r"Inherits declares no name of its own \(it inherits "
                                         r"'fe'\)"):
        register_interface(Inherits)

    class Vague(Mine):
        name, quadratic = "vague", "yes"

    with pytest.raises(SceneError, match=r"Vague\.quadratic = 'yes'; a capability is True or "
                                         r"False"):
        register_interface(Vague)

    @dataclass(frozen=True)
    class Field:
        k: float
        name: str = "field"

        @classmethod
        def build(cls, options, material):
            return cls(1.0)

    with pytest.raises(LawError, match=r"Field\.name is a dataclass field"):
        register_wear_law(Field)

    class Twice:
        name, keys = "twice", (OptionKey("k"), OptionKey("k"))

        @classmethod
        def build(cls, options, material):
            return None

    with pytest.raises(LawError, match=r"Twice\.keys declares 'k' twice"):
        register_wear_law(Twice)
    register_wear_law(type("Once", (Twice,), {"name": "once", "keys": (OptionKey("k"),)}))
    registered.append(("law", "once"))
    assert wear_law_model("once", "wear.rotor.model").keys[0].name == "k"

    @dataclass(frozen=True)
    class Slow(Drag):
        name = "slow"
        keys = Drag.keys + (OptionKey("creep", unit="mm/s", scale=1e-3),)

    with pytest.raises(DutyError, match=r"Slow\.keys: 'creep' is not a field of Slow"):
        register_application(Slow)


def test_parts_are_imported_as_python_would_and_refused_by_name(tmp_path, monkeypatch,
                                                                registered):
    """``import_parts`` imports a module by name from its folder or a .py file by path,
    once; a module it cannot find, one that raises and a second file of the same
    module name are refused naming the key and the module."""
    (tmp_path / "extra_parts_a.py").write_text(
        "from brakewear.interfaces import FEInterface, register_interface\n"
        "@register_interface\nclass A(FEInterface):\n    name = 'extra_a'\n")
    (tmp_path / "broken_parts.py").write_text("raise RuntimeError('half written')\n")
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "extra_parts_a.py").write_text("")
    (module,) = import_parts(["extra_parts_a"], "scene.import", tmp_path)
    registered.append(("interface", "extra_a"))
    assert import_parts(["extra_parts_a.py"], "scene.import", tmp_path) == [module]
    assert str(tmp_path) not in sys.path
    with pytest.raises(SceneError, match=r"scene\.import: 'no_such_parts': no module named "
                                         r"'no_such_parts'"):
        import_parts(["no_such_parts"], "scene.import", tmp_path)
    with pytest.raises(SceneError, match=r"--import: 'broken_parts\.py': importing it raised "
                                         r"RuntimeError: half written"):
        import_parts(["broken_parts.py"], "--import", tmp_path)
    with pytest.raises(SceneError, match=r"--import: 'other/extra_parts_a\.py': a module named "
                                         r"'extra_parts_a' is imported already"):
        import_parts(["other/extra_parts_a.py"], "--import", tmp_path)
    with pytest.raises(SceneError, match=r"--import: 'gone\.py': no such file"):
        import_parts(["gone.py"], "--import", tmp_path)
    monkeypatch.delitem(sys.modules, "extra_parts_a")


def test_an_entry_point_that_fails_names_itself_and_its_distribution(tmp_path, monkeypatch):
    """An installed entry point whose module raises stops the lookup with a message
    naming the entry point, its distribution and what it raised; one that loads is
    loaded once."""
    info = tmp_path / "bad_parts-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: bad-parts\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[brakewear.test_parts]\nbad = bad_parts_mod\n"
                                           "[brakewear.test_good]\ngood = good_parts_mod\n")
    (tmp_path / "bad_parts_mod.py").write_text("import no_such_dependency_of_mine\n")
    (tmp_path / "good_parts_mod.py").write_text("LOADS = globals().get('LOADS', 0) + 1\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(SceneError, match=r"entry point bad = 'bad_parts_mod' of the group "
                                         r"'brakewear\.test_parts' \(distribution bad-parts\) "
                                         r"cannot be loaded: ModuleNotFoundError"):
        load_entry_points("brakewear.test_parts")
    assert load_entry_points("brakewear.test_good") == ("good_parts_mod",)
    assert load_entry_points("brakewear.test_good") == ("good_parts_mod",)
    assert sys.modules["good_parts_mod"].LOADS == 1
    monkeypatch.delitem(sys.modules, "good_parts_mod")
