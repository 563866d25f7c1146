"""Your own brake: `brakewear new-scene` writes files that run, and the how-to's worked
example (docs/howto_own_brake.md) runs as written, on a coarse mesh for a minute."""
import json
import math
import re
from pathlib import Path

import pytest

from brakewear.cli import main
from brakewear.geometry import load_geometry
from brakewear.scene import load_scene, write_new_scene

ROOT = Path(__file__).resolve().parents[1]
HOWTO = (ROOT / "docs" / "howto_own_brake.md").read_text()


def _block(first_line: str) -> str:
    """The how-to's ```toml block that starts with ``first_line``."""
    blocks = [b for b in re.findall(r"```toml\n(.*?)```", HOWTO, re.S)
              if b.startswith(first_line)]
    assert len(blocks) == 1, f"one block starting {first_line!r} in the how-to"
    return blocks[0]


def _coarse(text: str, minutes: float = 1.0) -> str:
    """The scene on an 8 mm mesh (its per-body keys dropped), for ``minutes``, 2 steps."""
    text = re.sub(r"\n(rotor_size|friction_layers|backplate_layers|rotor_layers) = .*", "",
                  text)
    for a, b in {"size = 1.25 ": "size = 8.0 ", "duration = 30.0 ": f"duration = {minutes} ",
                 "steps = 30 ": "steps = 2 "}.items():
        assert a in text, a
        text = text.replace(a, b)
    return text


def test_the_worked_example_runs(tmp_path, capsys):
    (tmp_path / "my_brake.toml").write_text(_block("# my_brake.toml"))
    scene = _block("# my_brake_scene.toml")
    full = tmp_path / "full.toml"
    full.write_text(scene)
    sc = load_scene(full)                       # the scene as written: checked, not run
    assert sc.line_pressure == pytest.approx(2e6) and sc.duration == pytest.approx(1800.0)
    g = sc.geometry
    assert (g.rotor.outer_radius, g.pad.outer_radius - g.pad.inner_radius) == \
        pytest.approx((0.120, 0.036))
    assert g.pistons[0].bore_diameter == pytest.approx(0.048)
    assert g.materials["my_pad"].wear_k == pytest.approx(8e-15)
    assert math.degrees(g.pad.arc_angle) == pytest.approx(
        math.degrees(2 * math.asin(96 / 196)), abs=0.05)        # the chord the text gives
    (tmp_path / "my_brake_scene.toml").write_text(_coarse(scene))
    assert main(["run", str(tmp_path / "my_brake_scene.toml"), "--out",
                 str(tmp_path / "run"), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "not covered: another brake" in out          # the estimate says it extrapolates
    s = json.loads((tmp_path / "run" / "summary.json").read_text())
    clamp = 2e6 * math.pi * 0.048 ** 2 / 4
    assert float(s["final"]["normal_force_N"]) == pytest.approx(clamp, rel=1e-6)
    assert 0 < s["final"]["pad_wear_max_m"] and s["accuracy"]["caveats"]
    assert (tmp_path / "run" / "pad_wear.png").exists()


@pytest.mark.parametrize("start", ["default", "floating"])
def test_new_scene_writes_files_that_load_as_the_packaged_brake(tmp_path, start):
    geo, scn = write_new_scene("my_brake", tmp_path, start)
    assert (geo.name, scn.name) == ("my_brake.toml", "my_brake_scene.toml")
    assert geo.read_text().startswith("# my_brake: a brake geometry to edit from your drawing")
    assert "[rotor]" in geo.read_text() and "From the drawing:" in geo.read_text()
    mine, packaged = load_scene(scn), load_scene(start)
    assert mine.name == "my_brake" and Path(mine.geometry.source) == geo
    assert mine.geometry == load_geometry(start)              # the same values, another name
    assert mine == packaged                                   # every setting of the run
    assert "brakewear run my_brake_scene.toml" in scn.read_text()


def test_new_scene_never_overwrites(tmp_path, capsys):
    assert main(["new-scene", "b", "--dir", str(tmp_path)]) == 0
    assert "brakewear run" in capsys.readouterr().out
    (tmp_path / "b.toml").write_text("# mine\n")
    (tmp_path / "b_scene.toml").unlink()
    assert main(["new-scene", "b", "--dir", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "b.toml already exists; nothing was written" in err, err
    assert (tmp_path / "b.toml").read_text() == "# mine\n"
    assert not (tmp_path / "b_scene.toml").exists()
    for bad in ("../x", "x.toml", ""):
        assert main(["new-scene", bad, "--dir", str(tmp_path)]) == 2
        assert "is not allowed" in capsys.readouterr().err


def test_the_howto_quotes_what_the_run_prints(tmp_path):
    """The estimates the how-to quotes are what the rating gives for its scene."""
    from dataclasses import replace

    from brakewear.scene.accuracy import accuracy_lines, mesh_accuracy

    (tmp_path / "my_brake.toml").write_text(_block("# my_brake.toml"))
    (tmp_path / "s.toml").write_text(_block("# my_brake_scene.toml"))
    sc = load_scene(tmp_path / "s.toml")
    text = " ".join(HOWTO.split())
    for line in accuracy_lines(mesh_accuracy(sc)):
        assert " ".join(line.split()) in text, line
    coarse = accuracy_lines(mesh_accuracy(replace(sc, mesh_size=None, resolution={})))
    assert coarse[-1] in HOWTO and "6 + 2 layers" in coarse[0]
