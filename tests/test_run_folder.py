"""An output folder that holds a run is refused unless --overwrite or --resume; a resume of a
finished run says so at once; the progress bar's first estimate comes from the first steps."""
import json
import re
import types

import numpy as np
import pytest

from brakewear.cli import main
from brakewear.output.folder import check_new_out, clear_run, finished_run, held_run
from brakewear.output.progress import Progress
from brakewear.scene import scene_file


def _tiny(tmp_path):
    """The default scene on a 12 mm mesh, 3 fixed steps over 600 s, no figures."""
    text = scene_file("default").read_text()
    text = re.sub(r"\n(rotor_size|friction_layers|backplate_layers|rotor_layers) = .*", "", text)
    for a, b in {"size = 1.5 ": "size = 12.0 ", "duration = 3600.0": "duration = 600.0",
                 "\nsteps = 60": "\nsteps = 3", "figures = true": "figures = false"}.items():
        assert a in text, a
        text = text.replace(a, b)
    path = tmp_path / "tiny.toml"
    path.write_text(text)
    return path


def _snapshot(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_a_folder_with_a_run_is_refused_and_left_as_it_was(tmp_path, capsys):
    scene, out = _tiny(tmp_path), tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--quiet"]) == 0
    before = _snapshot(out)
    capsys.readouterr()
    assert main(["run", str(scene), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "already holds a run" in err and "--overwrite" in err and "--resume" in err, err
    assert "summary.json" in err
    assert _snapshot(out) == before, "a refused run wrote into the folder"
    assert main(["run", str(scene), "--out", str(out), "--overwrite", "--resume"]) == 2
    assert "--overwrite and --resume together" in capsys.readouterr().err
    assert _snapshot(out) == before


def test_overwrite_replaces_the_runs_files_and_keeps_the_users(tmp_path, capsys):
    scene, out = _tiny(tmp_path), tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--quiet"]) == 0
    stale = out / "pad_00099.vtu"                  # a step the new run will not write
    stale.write_text("x")
    mine = out / "notes.txt"
    mine.write_text("my notes")
    assert main(["run", str(scene), "--out", str(out), "--quiet", "--overwrite"]) == 0
    assert not stale.exists()
    assert mine.read_text() == "my notes"
    assert json.loads((out / "summary.json").read_text())["steps"] == 3


def test_resume_of_a_finished_run_says_so_before_building_the_model(tmp_path, capsys,
                                                                    monkeypatch):
    scene, out = _tiny(tmp_path), tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    from brakewear.scene import Scene
    build, said = Scene.build_model, []

    def watched(self):
        said.append(capsys.readouterr().out)      # what was printed before the model
        return build(self)

    monkeypatch.setattr(Scene, "build_model", watched)
    assert main(["run", str(scene), "--out", str(out), "--resume"]) == 0
    captured = capsys.readouterr()
    assert said and "holds a finished run (3 steps to t = 600 s)" in said[0], said
    assert "nothing to do" in captured.out
    assert "simulated" not in captured.err, f"a progress bar was drawn:\n{captured.err}"


def test_demo_refuses_a_folder_with_a_demo_run(tmp_path, capsys):
    (tmp_path / "summary.json").write_text("{}")
    assert main(["demo", "--out", str(tmp_path), "--wear-duration", "0"]) == 2
    err = capsys.readouterr().err
    assert "already holds a run" in err and "--overwrite" in err and "--resume" not in err


def test_held_run_clear_run_and_finished_run(tmp_path):
    assert held_run(tmp_path / "missing") == [] and held_run(tmp_path) == []
    (tmp_path / "running_in").mkdir()
    for name in ("summary.json", "brake_surfaces.png", "running_in/history.csv",
                 "running_in/pad_00012.vtu", "running_in/pad_wear.png", "keep.png"):
        (tmp_path / name).write_text("x")
    assert held_run(tmp_path) == ["summary.json", "running_in/history.csv"]
    with pytest.raises(ValueError, match="already holds a run"):
        check_new_out(tmp_path)
    assert check_new_out(tmp_path, overwrite=True) == tmp_path
    removed = {p.relative_to(tmp_path).as_posix() for p in clear_run(tmp_path)}
    assert removed == {"summary.json", "brake_surfaces.png", "running_in/history.csv",
                       "running_in/pad_00012.vtu", "running_in/pad_wear.png"}
    assert (tmp_path / "keep.png").exists() and held_run(tmp_path) == []
    assert finished_run(tmp_path, 10.0) is None


def test_the_first_estimate_leaves_out_the_first_step():
    """A first step of 20 s wall (setup, first solve) for 1 s simulated, then 1 s wall per
    10 s simulated: the estimate is the later rate's, not the first step's."""
    bar = Progress(types.SimpleNamespace(duration=3600.0, name="x", schedule=()), quiet=True)
    assert bar.remaining(1, 1.0, now=20.0) is None           # the first step: no rate yet
    assert bar.remaining(2, 11.0, now=21.0) is None
    assert bar.remaining(3, 21.0, now=22.0) is None
    left = bar.remaining(4, 31.0, now=23.0)                  # 30 s simulated in 3 s wall
    assert left == pytest.approx((3600.0 - 31.0) / 10.0, rel=1e-12)
    first_step_alone = (3600.0 - 1.0) * 20.0 / 1.0           # what the first step's rate says
    assert left < first_step_alone / 100


def test_the_progress_bar_shows_the_estimate(capsys):
    bar = Progress(types.SimpleNamespace(duration=600.0, name="x", schedule=()), quiet=False)
    bar.bar.mininterval, bar.bar.miniters = 0.0, 0          # draw every step
    for k, t in enumerate((1.0, 100.0, 200.0, 300.0, 400.0, 600.0), 1):
        bar(types.SimpleNamespace(step=k, time=t, dt=100.0, limit="steps", rejected=0,
                                  pad_wear=np.array([1e-6 * k]), pressure=np.array([1e6])))
    bar.close()
    err = capsys.readouterr().err
    assert "estimating the time left" in err and "left at the rate so far" in err, err
    assert err.rstrip().endswith("done; step 6, pad wear 6 um]"), err
