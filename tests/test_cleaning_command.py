"""``brakewear clean``: its help, bad input refused before anything runs (naming the file,
the key, the value and what is allowed), the packaged car file, and the command on a
coarse mesh writing the design curve, the routine table, the maps and the summary."""
import json
import subprocess
import sys

import pytest

from brakewear import DutyError, SceneError
from brakewear.cleaning.car import packaged_car, read_car
from brakewear.cleaning.command import clean_input
from brakewear.cli import main
from brakewear.duty import study_car


def test_the_help_lists_the_ranges_and_the_cluster():
    r = subprocess.run([sys.executable, "-m", "brakewear", "clean", "--help"],
                       capture_output=True, text=True, check=True)
    for opt in ("--speeds", "--decels", "--intervals", "--car", "--geometry", "--samples",
                "--dask", "--start", "--resume", "[cleaning]"):
        assert opt in r.stdout, opt


def test_the_packaged_car_is_the_study_car():
    car, ref = packaged_car("study"), study_car()
    for k in ("mass", "front_share", "tyre_radius", "rolling_resistance", "drag_area",
              "regen_power_limit", "regen_decel_limit", "regen_cutoff_speed"):
        assert getattr(car, k) == pytest.approx(getattr(ref, k), rel=1e-12), k


@pytest.mark.parametrize("text, match", [
    ("[vehicle]\nmass = -3.0\n", r"car\.toml: vehicle\.mass = -3\.0 kg is not allowed; need a "
                                 r"number from 100 to 100000 kg"),
    ("[vehicle]\nmass = 1500.0\n[blending]\nregen_power_limit = 'a lot'\n",
     r"blending\.regen_power_limit = 'a lot' kW is not allowed"),
    ("[vehicle]\nmass = 1500.0\nwheels = 4\n", r"vehicle\.wheels: unknown key; allowed: mass"),
    ("[engine]\npower = 1\n", r"unknown table \[engine\]"),
    ("[road]\ndrag_area = 0.6\n", r"vehicle\.mass: missing \(kg\)"),
])
def test_a_bad_car_file_is_refused_naming_its_key(tmp_path, text, match):
    path = tmp_path / "car.toml"
    path.write_text(text)
    with pytest.raises(DutyError, match=match):
        read_car(path)


@pytest.mark.parametrize("table, match", [
    (dict(intervals=[30.0]), r"cleaning\.intervals = 30\.0 is not allowed; each value must be a "
                             r"number >= 60 and <= 600 s"),
    (dict(decels=[12.0]), r"cleaning\.decels = 12\.0 is not allowed.*9\.80665 m/s\^2"),
    (dict(speeds=[100.0], decels=[0.2], intervals=[120.0]),
     r"a stop from 100 km/h at 0\.2 m/s\^2 lasts 139 s"),
    (dict(geometry="default"), r"cleaning\.geometry = 'default' is not allowed; need a floating"),
    (dict(start="rusty"), r"cleaning\.start = 'rusty' is not allowed; allowed: bedded, new"),
    (dict(samples=1), r"cleaning\.samples = 1 is not allowed; need a whole number 2\.\.100000"),
    (dict(colour="red"), r"cleaning\.colour: unknown key; allowed: geometry"),
])
def test_a_bad_cleaning_table_is_refused(table, match):
    with pytest.raises(SceneError, match=match):
        clean_input(table, "cleaning.toml")


def test_the_command_refuses_bad_input_before_writing_anything(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["clean", "--intervals", "30", "--out", str(out)]) == 2
    assert "cleaning.intervals = 30.0 is not allowed" in capsys.readouterr().err
    assert not out.exists()
    f = tmp_path / "scene.toml"
    f.write_text("[cleaning]\nstops = 0\n")
    assert main(["clean", str(f), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert str(f) in err and "cleaning.stops = 0 is not allowed" in err and not out.exists()


@pytest.mark.slow
def test_the_command_on_a_coarse_mesh_writes_the_answer(tmp_path, capsys):
    """Two draws of one routine (two stops from 80 km/h at 2 m/s^2, 120 s apart) on the
    12 mm caliper, from a [cleaning] table with the command line over it: the design
    curve, the routine table, the pads' maps of both faces and the summary."""
    f = tmp_path / "clean.toml"
    f.write_text("[cleaning]\nspeeds = [80.0]\ndecels = [2.0]\nintervals = [120.0]\n"
                 "stops = 2\nsamples = 2\nsize = 12.0\n")
    out = tmp_path / "out"
    assert main(["clean", str(f), "--quiet", "--out", str(out), "--targets", "0.5"]) == 0
    assert "P >= 0.5" in capsys.readouterr().out
    s = json.loads((out / "summary.json").read_text())
    assert s["runs"] == 2 and s["failed"] == 0 and s["input"]["size"] == 12.0
    curve = json.loads((out / "design_curve.json").read_text())
    (pt,) = curve["points"]
    assert all(b >= a for a, b in zip(pt["P"], pt["P"][1:]))
    for name in ("design_curve.png", "face_in_first.png", "face_out_last.png",
                 "layer_left.png"):
        assert (out / name).stat().st_size > 10_000, name
    assert (out / "routines.csv").read_text().startswith("target,routine,stops")
    assert len((out / "design_curve.csv").read_text().splitlines()) == 1 + 2
    # run again: refused without --overwrite or --resume; resumed from the journal
    assert main(["clean", str(f), "--quiet", "--out", str(out)]) == 2
    assert main(["clean", str(f), "--quiet", "--out", str(out), "--resume",
                 "--targets", "0.5"]) == 0
