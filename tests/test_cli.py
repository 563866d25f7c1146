"""The command line: the demo writes what it says; bad input exits 2 with a message."""
import json
import re

from brakewear.cli import main


def test_demo_writes_summary_vtu_and_figures(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path), "--size", "5", "--wear-duration", "0"]) == 0
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
    # the option and the value as the user gave them (MPa)
    assert "--pressure: -1.0 MPa is not allowed" in capsys.readouterr().err


# ---------------------------------------------------------------- brakewear run
import subprocess  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import pytest  # noqa: E402

import brakewear.output.progress as progress  # noqa: E402
from brakewear.scene import scene_file  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _tiny(tmp_path, **edits) -> Path:
    """The default scene on a 12 mm mesh (its per-body keys dropped), 4 fixed steps over
    800 s, no figures."""
    text = scene_file("default").read_text()
    text = re.sub(r"\n(rotor_size|friction_layers|backplate_layers|rotor_layers) = .*", "",
                  text)
    repl = {"size = 1.5 ": "size = 12.0 ", "duration = 3600.0": "duration = 800.0",
            "steps = 60": "steps = 4", "checkpoint_every = 5": "checkpoint_every = 2",
            "vtu_every = 50": "vtu_every = 2", "figures = true": "figures = false",
            'name = "default"': 'name = "tiny"'}
    repl.update(edits)
    for a, b in repl.items():
        assert a in text, a
        text = text.replace(a, b)
    path = tmp_path / "tiny.toml"
    path.write_text(text)
    return path


def test_run_writes_the_history_and_exits_0(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["run", str(_tiny(tmp_path)), "--out", str(out), "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["steps"] == 4 and s["final"]["time_s"] == pytest.approx(800.0)
    assert s["mu"] == 0.4 and s["line_pressure_Pa"] == 1e6
    assert s["scene"]["mesh_size_m"] == pytest.approx(0.012)
    # mean pad wear = k p_mean v t at the mean radius (Archard, volume is exact)
    assert s["pad_archard_m3"] > 0 and s["final"]["pad_wear_max_m"] > 0
    for f in ("history.csv", "pad.pvd", "rotor.pvd", "checkpoint.npz", "scene.json"):
        assert (out / f).exists(), f
    o = capsys.readouterr().out
    assert "4 steps to t = 800 s" in o and "pad wear max" in o


def test_interrupted_run_resumes_to_the_same_end(tmp_path, capsys, monkeypatch):
    scene = str(_tiny(tmp_path))
    ref, out = tmp_path / "ref", tmp_path / "out"
    assert main(["run", scene, "--out", str(ref), "--quiet"]) == 0
    ref_s = json.loads((ref / "summary.json").read_text())
    calls = progress.Progress.__call__

    def ctrl_c_at_step_3(self, s):
        calls(self, s)
        if s.step == 3:
            raise KeyboardInterrupt
    monkeypatch.setattr(progress.Progress, "__call__", ctrl_c_at_step_3)
    assert main(["run", scene, "--out", str(out), "--quiet"]) == 130
    err = capsys.readouterr().err
    assert "interrupted at step 3" in err and f"--out {out} --resume" in err
    monkeypatch.setattr(progress.Progress, "__call__", calls)
    assert main(["run", scene, "--out", str(out), "--resume", "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["resumed_from_step"] == 2 and s["steps"] == 4
    assert s["final"]["pad_wear_max_m"] == pytest.approx(ref_s["final"]["pad_wear_max_m"],
                                                         rel=1e-9)
    # a finished run resumed again: nothing to do
    assert main(["run", scene, "--out", str(out), "--resume", "--quiet"]) == 0
    assert "already holds the finished run" in capsys.readouterr().out


def test_resume_refuses_another_scene_and_a_missing_checkpoint(tmp_path, capsys):
    out, short = tmp_path / "out", {"duration = 3600.0": "duration = 200.0",
                                    "steps = 60": "steps = 1"}
    assert main(["run", str(_tiny(tmp_path, **short)), "--out", str(out), "--quiet"]) == 0
    (tmp_path / "other").mkdir()
    other = _tiny(tmp_path / "other", **short, **{"mu = 0.4": "mu = 0.3"})
    assert main(["run", str(other), "--out", str(out), "--resume", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "holds a run of a different scene (interface.mu: 0.4 then, 0.3 now)" in err
    assert main(["run", str(other), "--out", str(tmp_path / "none"), "--resume"]) == 2
    assert "checkpoint.npz does not exist" in capsys.readouterr().err


def test_resume_of_a_finished_run_refuses_a_changed_material(tmp_path, capsys):
    """The geometry file's custom material changed after the run finished: its resume
    is refused like an unfinished one (exit 2), naming the values in the file's units."""
    from brakewear.geometry import geometry_file
    g = geometry_file("default").read_text().replace('friction_material = "pad_resin"',
                                                     'friction_material = "soft_pad"')
    g += ('\n[materials.soft_pad]\ntype = "transversely_isotropic"\nbase = "pad_resin"\n'
          "E_p = 8.0\nE_t = 3.0\nnu_p = 0.25\nnu_tp = 0.2\nG_t = 1.5\nwear_k = 5e-15\n")
    (tmp_path / "g.toml").write_text(g)
    scene = str(_tiny(tmp_path, **{'geometry = "default"': 'geometry = "g.toml"'}))
    out = str(tmp_path / "out")
    assert main(["run", scene, "--out", out, "--quiet"]) == 0
    assert main(["run", scene, "--out", out, "--resume", "--quiet"]) == 0
    assert "already holds the finished run" in capsys.readouterr().out
    (tmp_path / "g.toml").write_text(g.replace("wear_k = 5e-15", "wear_k = 2e-14")
                                      .replace("E_t = 3.0", "E_t = 2.9"))
    assert main(["run", scene, "--out", out, "--resume", "--quiet"]) == 2
    o, err = capsys.readouterr()
    assert "nothing to do" not in o
    assert "was written by a run with other inputs" in err
    assert "friction_material.elastic.E_t: 3 GPa -> 2.9 GPa" in err
    assert "friction_material.wear_k: 5e-15 1/Pa -> 2e-14 1/Pa" in err


def test_bad_scene_exits_2_naming_the_key_without_traceback(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(scene_file("default").read_text().replace("omega = 55.0", "omgea = 55.0"))
    r = subprocess.run([sys.executable, "-m", "brakewear.cli", "run", str(bad), "--out",
                        str(tmp_path / "o")], cwd=ROOT, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 2, r.stderr
    assert "environment.omgea: unknown key 'omgea'" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "o").exists()


def test_unknown_scene_name_exits_2(capsys):
    assert main(["run", "no-such-scene"]) == 2
    err = capsys.readouterr().err
    assert "packaged scenes:" in err and ", default," in err


def test_solver_failure_exits_3(tmp_path, capsys, monkeypatch):
    import brakewear.output.runs
    from brakewear.errors import StepSizeError

    def fail(scene, out, resume=False, progress=None, **kw):
        raise StepSizeError("step 7: no acceptable wear step after 13 halvings")
    monkeypatch.setattr(brakewear.output.runs, "run_scene", fail)
    assert main(["run", "default", "--out", str(tmp_path), "--quiet"]) == 3
    err = capsys.readouterr().err
    assert "solver failed (StepSizeError): step 7" in err


def test_resume_with_a_longer_duration_extends_the_run(tmp_path, capsys):
    auto = {"steps = 60": "dp_tol = 0.2", "duration = 3600.0": "duration = 100.0"}
    out = tmp_path / "out"
    assert main(["run", str(_tiny(tmp_path, **auto)), "--out", str(out), "--quiet"]) == 0
    first = json.loads((out / "summary.json").read_text())
    longer = _tiny(tmp_path, **{**auto, "duration = 3600.0": "duration = 200.0"})
    assert main(["run", str(longer), "--out", str(out), "--resume", "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["resumed_from_step"] == first["steps"] and s["steps"] > first["steps"]
    assert s["final"]["time_s"] == pytest.approx(200.0)
    assert s["final"]["pad_wear_max_m"] > first["final"]["pad_wear_max_m"]
    shorter = _tiny(tmp_path, **{**auto, "duration = 3600.0": "duration = 50.0"})
    assert main(["run", str(shorter), "--out", str(out), "--resume", "--quiet"]) == 2
    assert "beyond environment.duration = 50.0 s" in capsys.readouterr().err


def test_interrupt_before_the_first_checkpoint_says_start_again(tmp_path, capsys, monkeypatch):
    def ctrl_c(self, s):
        raise KeyboardInterrupt
    monkeypatch.setattr(progress.Progress, "__call__", ctrl_c)
    out = tmp_path / "out"
    assert main(["run", str(_tiny(tmp_path)), "--out", str(out), "--quiet"]) == 130
    assert "no checkpoint was written yet: run again without --resume" in capsys.readouterr().err


def test_demo_runs_the_default_scene_after_the_static_solve(tmp_path, monkeypatch):
    import json

    import brakewear.scene as sf
    real = sf.load_scene

    def small(name):                       # the default scene on a coarse mesh, 2 steps
        import dataclasses
        s = real(name)
        return dataclasses.replace(s, mesh_size=1.2e-2, resolution={},
                                   numerics=dataclasses.replace(s.numerics, steps=2))
    monkeypatch.setattr(sf, "load_scene", small)
    assert main(["demo", "--out", str(tmp_path), "--size", "12", "--no-figures", "--quiet",
                 "--wear-duration", "30"]) == 0
    w = json.loads((tmp_path / "running_in" / "summary.json").read_text())
    assert w["steps"] == 2 and w["duration_s"] == 30.0
    assert (tmp_path / "summary.json").exists()
