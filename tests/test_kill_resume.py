"""A run killed at any point (``kill -9``) and resumed, or resumed after any of its
files was damaged, ends as the clean run does, row for row -- or is refused with
exit code 2 naming the damaged file (never a traceback, never numpy's advice to
unpickle), after which ``--overwrite`` gives the clean run.  A damaged cache or
ParaView index is rebuilt with a warning.

Two small scenes (the default brake on a 14 mm mesh, 24 fixed steps, a
checkpoint every 3): FE contact and the condensed interface (what ``auto``
chooses for a long run).  The kills are at seeded random moments: anywhere in
the process's life, or within its writing (after its first history row).
"""
from __future__ import annotations

import csv
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from brakewear.cli import main
from brakewear.scene import scene_file

INTERFACES = ("fe", "condensed")
STEPS, EVERY, STOP = 24, 3, 14
slow = pytest.mark.slow


def _scene(folder: Path, interface: str) -> Path:
    text = scene_file("default").read_text()
    text = re.sub(r"\n(rotor_size|friction_layers|backplate_layers|rotor_layers) = .*", "",
                  text)
    for a, b in {"size = 1.5 ": "size = 14.0 ", "duration = 3600.0": "duration = 2400.0",
                 "steps = 60": f"steps = {STEPS}",
                 "checkpoint_every = 5": f"checkpoint_every = {EVERY}",
                 "vtu_every = 50": "vtu_every = 4", "figures = true": "figures = false",
                 'name = "default"': f'name = "kill-{interface}"',
                 'model = "auto"': f'model = "{interface}"'}.items():
        assert a in text, a
        text = text.replace(a, b)
    path = folder / f"{interface}.toml"
    path.write_text(text)
    return path


def rows(out: Path) -> list[dict]:
    """history.csv without its wall-clock column."""
    with open(out / "history.csv", newline="") as fh:
        return [{k: v for k, v in r.items() if k != "solve_s"} for r in csv.DictReader(fh)]


def pvd_steps(out: Path) -> list[str]:
    return re.findall(r'file="(pad_\d+\.vtu)"', (out / "pad.pvd").read_text())


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    """Per interface: the scene, the clean run's folder, and a folder stopped at step
    STOP (Ctrl-C from the progress callback: the checkpoint before it, rows to it)."""
    from brakewear.output.runs import run_scene
    from brakewear.scene import load_scene

    root = tmp_path_factory.mktemp("kill")
    cache = root / "cache"
    old = os.environ.get("BRAKEWEAR_CACHE")
    os.environ["BRAKEWEAR_CACHE"] = str(cache)
    out = {}
    for itf in INTERFACES:
        scene = _scene(root, itf)
        clean = root / f"clean-{itf}"
        assert main(["run", str(scene), "--out", str(clean), "--quiet"]) == 0
        stopped = root / f"stopped-{itf}"

        def stop(s):
            if s.step == STOP:
                raise KeyboardInterrupt

        with pytest.raises(KeyboardInterrupt):
            run_scene(load_scene(scene), stopped, progress=stop)
        out[itf] = dict(scene=scene, clean=clean, stopped=stopped, rows=rows(clean),
                        pvd=pvd_steps(clean))
    yield root, cache, out
    if old is None:
        os.environ.pop("BRAKEWEAR_CACHE", None)
    else:
        os.environ["BRAKEWEAR_CACHE"] = old


def recover(scene: Path, out: Path, capsys) -> tuple[int, str]:
    """``--resume``; if refused (exit 2), the remedy the message gives: ``--overwrite``.
    Returns the resume's exit code and message."""
    rc = main(["run", str(scene), "--out", str(out), "--resume", "--quiet"])
    err = capsys.readouterr().err
    if rc == 2:
        assert main(["run", str(scene), "--out", str(out), "--overwrite", "--quiet"]) == 0
    return rc, err


def same_as_clean(out: Path, ref: dict) -> None:
    got = rows(out)
    assert len(got) == STEPS and got == ref["rows"], \
        next((i + 1, a, b) for i, (a, b) in enumerate(zip(got, ref["rows"])) if a != b) \
        if len(got) == STEPS else len(got)
    assert pvd_steps(out) == ref["pvd"]
    assert sorted(p.name for p in out.glob("pad_*.vtu")) == ref["pvd"]


# ----------------------------------------------------------------------- kills --

def _kill(scene: Path, out: Path, delay: float, writing: bool, cache: Path) -> None:
    env = {**os.environ, "BRAKEWEAR_CACHE": str(cache)}
    proc = subprocess.Popen([sys.executable, "-m", "brakewear", "run", str(scene), "--out",
                             str(out), "--quiet"], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, env=env)
    t0 = time.monotonic()
    if writing:       # from the first history row on
        while not (out / "history.csv").exists() and proc.poll() is None:
            time.sleep(0.005)
        t0 = time.monotonic()
    while time.monotonic() - t0 < delay and proc.poll() is None:
        time.sleep(0.002)
    if proc.poll() is None:
        proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=600)


def _kills(setup, capsys, count: int, seed: int) -> dict:
    root, cache, ref = setup
    rng = np.random.default_rng(seed)
    tally = {"kills": 0, "with_checkpoint": 0, "before_any_checkpoint": 0,
             "after_the_end": 0}
    for k in range(count):
        itf = INTERFACES[k % 2]
        writing = bool(k % 4 >= 2)
        out = root / f"k{seed}-{k}"
        _kill(ref[itf]["scene"], out, float(rng.uniform(0.0, 0.8 if writing else 4.0)),
              writing, cache)
        tally["kills"] += 1
        ck = out / "checkpoint.npz"
        done = (out / "summary.json").exists() and ck.exists()
        key = "after_the_end" if done else "with_checkpoint" if ck.exists() else \
            "before_any_checkpoint"
        tally[key] += 1
        rc, err = recover(ref[itf]["scene"], out, capsys)
        assert "Traceback" not in err and "allow_pickle" not in err, err
        if key != "before_any_checkpoint":
            assert rc == 0, (itf, k, err)       # a checkpoint is always resumable
        same_as_clean(out, ref[itf])
    return tally


def test_kills_while_writing_resume_to_the_clean_run(setup, capsys):
    """Four kills: FE and condensed, anywhere and while writing."""
    tally = _kills(setup, capsys, 4, seed=1)
    assert tally["kills"] == 4


@pytest.mark.slow
def test_kills_at_32_random_points_resume_to_the_clean_run(setup, capsys):
    """32 kills (16 FE, 16 condensed; half anywhere, half while writing)."""
    tally = _kills(setup, capsys, 32, seed=2)
    print("kills:", tally)
    assert tally["kills"] == 32 and tally["with_checkpoint"] >= 8, tally


# --------------------------------------------------------------- damaged files --

def _flip(path: Path, seed: int) -> None:
    b = bytearray(path.read_bytes())
    rng = np.random.default_rng(seed)
    i = int(rng.integers(len(b)))
    b[i] ^= 1 << int(rng.integers(8))
    path.write_bytes(bytes(b))


def _cut(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _foreign(path: Path) -> None:
    np.savez(path.with_suffix(".x.npz"), step=np.array(3), other=np.zeros(4))
    os.replace(path.with_suffix(".x.npz"), path)


def _pickled(path: Path) -> None:
    np.savez(path.with_suffix(".x.npz"), step=np.array([{"a": 1}], dtype=object))
    os.replace(path.with_suffix(".x.npz"), path)


def _drop_rows(path: Path) -> None:
    lines = path.read_text().splitlines(keepends=True)
    path.write_text("".join(lines[:10]))


DAMAGE = {
    "empty": lambda p: p.write_bytes(b""),
    "cut": _cut,
    "text": lambda p: p.write_text("step,time_s\n1,2.0\n"),
    "foreign": _foreign,
    "pickled": _pickled,
    **{f"flip{s}": (lambda p, s=s: _flip(p, s)) for s in range(4)},
}


FAST = {("fe", "empty"), ("fe", "text"), ("fe", "pickled"), ("fe", "flip0"),
        ("condensed", "cut")}


@pytest.mark.parametrize("itf, how", [
    pytest.param(i, h, marks=() if (i, h) in FAST else slow)
    for i in INTERFACES for h in DAMAGE])
def test_a_damaged_checkpoint_is_refused_naming_it_or_resumes_whole(setup, capsys, itf,
                                                                     how):
    root, _, ref = setup
    out = root / f"ck-{itf}-{how}"
    shutil.copytree(ref[itf]["stopped"], out)
    DAMAGE[how](out / "checkpoint.npz")
    rc, err = recover(ref[itf]["scene"], out, capsys)
    assert "Traceback" not in err and "allow_pickle" not in err
    if how.startswith("flip") and rc == 0:
        pass        # a flip in the archive's dates or names: the state is whole
    else:
        assert rc == 2 and "checkpoint.npz" in err, err
    same_as_clean(out, ref[itf])


@pytest.mark.parametrize("how", ["deleted", "rows", *(pytest.param(h, marks=slow) for h in
                                                     ("cut", "binary", "other-run"))])
def test_a_damaged_history_is_refused_naming_it(setup, capsys, how):
    root, _, ref = setup
    out = root / f"hist-{how}"
    shutil.copytree(ref["fe"]["stopped"], out)
    h = out / "history.csv"
    if how == "deleted":
        h.unlink()
    elif how == "cut":
        _cut(h)
    elif how == "rows":
        _drop_rows(h)
    elif how == "binary":
        h.write_bytes(bytes(range(256)) * 4)
    else:                               # the clean run's history: other times
        text = h.read_text().replace(ref["fe"]["rows"][STOP - 3]["time_s"], "1.5", 1)
        h.write_text(text)
    rc, err = recover(ref["fe"]["scene"], out, capsys)
    assert rc == 2 and "history.csv" in err and "Traceback" not in err, err
    same_as_clean(out, ref["fe"])


@pytest.mark.parametrize("name", [pytest.param("scene.json", marks=slow), "summary.json"])
def test_a_damaged_record_of_a_finished_run_is_refused_naming_it(setup, capsys, name):
    root, _, ref = setup
    out = root / f"rec-{name}"
    shutil.copytree(ref["fe"]["clean"], out)
    _cut(out / name)
    rc, err = recover(ref["fe"]["scene"], out, capsys)
    assert rc == 2 and name in err and "Traceback" not in err, err
    same_as_clean(out, ref["fe"])


def test_a_damaged_paraview_index_is_rebuilt(setup, capsys):
    root, _, ref = setup
    out = root / "pvd"
    shutil.copytree(ref["fe"]["stopped"], out)
    _cut(out / "pad.pvd")
    rc, _ = recover(ref["fe"]["scene"], out, capsys)
    assert rc == 0
    same_as_clean(out, ref["fe"])


@pytest.mark.parametrize("how", ["cut", *(pytest.param(h, marks=slow) for h in
                                         ("empty", "text", "flip0", "foreign"))])
def test_a_damaged_condensation_cache_is_rebuilt_with_a_warning(setup, capsys, caplog, how):
    root, cache, ref = setup
    files = sorted(cache.glob("*.npz"))
    assert files, "the condensed runs wrote their cache"
    for f in files:
        DAMAGE[how](f)
    out = root / f"cache-{how}"
    with caplog.at_level("WARNING"):
        rc = main(["run", str(ref["condensed"]["scene"]), "--out", str(out), "--quiet"])
    assert rc == 0
    if how != "flip0":            # (a flip may land in the archive's dates)
        assert any(str(files[0]) in r.getMessage() and "computing it again" in r.getMessage()
                   for r in caplog.records), [r.getMessage() for r in caplog.records]
    same_as_clean(out, ref["condensed"])
    from brakewear.storage import load_arrays

    for f in sorted(cache.glob("*.npz")):           # written anew, whole
        load_arrays(f, "condensation cache")
