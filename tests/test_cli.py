"""The command line: the demo writes what it says; bad input exits 2 with a message."""
import json

from brakewear.cli import main


def test_demo_writes_summary_vtu_and_figures(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path), "--size", "5"]) == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["interface"]["force_balance_error"] < 1e-8
    for f in ("rotor.vtu", "pad.vtu", "pad_interface_pressure.png", "brake_surfaces.png"):
        assert (tmp_path / f).stat().st_size > 1000, f
    assert "DOFs" in capsys.readouterr().out


def test_demo_bad_geometry_exits_2(tmp_path, capsys):
    from brakewear.geometry import geometry_file
    text = (geometry_file("default")).read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("inner_radius = 90.0", "inner_radius = -5.0"))
    assert main(["demo", "--geometry", str(bad), "--out", str(tmp_path / "o")]) == 2
    assert "inner_radius" in capsys.readouterr().err


def test_demo_bad_pressure_exits_2(tmp_path, capsys):
    assert main(["demo", "--pressure", "-1", "--out", str(tmp_path), "--no-figures"]) == 2
    assert "line_pressure" in capsys.readouterr().err
