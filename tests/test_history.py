"""Wear histories on disk: a run killed with SIGKILL and resumed ends where an
uninterrupted one does."""

import json
import os
import signal
import subprocess
import sys
import textwrap

import meshio
import numpy as np
import pytest

from brakewear.errors import WearError
from brakewear.laws.base import WearLaw
from brakewear.mesh.surface import surface_nodes, tributary_areas
from brakewear.model import BrakeModel
from brakewear.output.runs import run_wear
from brakewear.wear import Numerics, Run

PAD, ROTOR = WearLaw(5e-15), WearLaw(5e-16)
ARGS = (1e6, 55.0, 3000.0, PAD, ROTOR)

SCRIPT = textwrap.dedent("""
    import sys
    from brakewear import run_wear
    from brakewear import BrakeModel
    from brakewear import Run, WearLaw, Numerics
    m = BrakeModel("default", size=8e-3)
    run = Run(m, 1e6, 55.0, 3000.0, WearLaw(5e-15), WearLaw(5e-16),
              numerics=Numerics(scheme="implicit", steps=6))
    run_wear(run, sys.argv[1], every=1, vtu_every=1,
             progress=lambda s: print(s.step, flush=True))
""")


@pytest.fixture(scope="module")
def model():
    return BrakeModel("default", size=8e-3)


def test_outputs_open_and_hold_the_fields(model, tmp_path):
    summ = run_wear(
        Run(model, *ARGS, numerics=Numerics(scheme="implicit", steps=3)), tmp_path, vtu_every=1
    )
    assert summ["steps"] == 3 and summ["contact_solves"] == 4   # 3 steps + the first solve
    assert json.loads((tmp_path / "summary.json").read_text())["steps"] == 3
    pvd = (tmp_path / "pad.pvd").read_text()
    assert pvd.count("<DataSet") == 3
    m = meshio.read(tmp_path / "pad_00003.vtu")
    assert {"pressure", "pad_wear", "active"} <= set(m.point_data)
    # the pressure in the file balances the clamp force (pressure x tributary area)
    pad = model.meshes["pad"]
    nodes = surface_nodes(pad, "friction")
    F = (m.point_data["pressure"][nodes] * tributary_areas(pad, "friction", nodes)).sum()
    assert F == pytest.approx(1e6 * model.geometry.piston.hydraulic_area, rel=1e-8)
    assert m.point_data["pad_wear"].max() == pytest.approx(summ["final"]["pad_wear_max_m"])
    r = meshio.read(tmp_path / "rotor_00003.vtu")
    assert r.point_data["rotor_wear"].max() > 0
    lines = (tmp_path / "history.csv").read_text().strip().splitlines()
    assert len(lines) == 4


def test_resume_needs_a_checkpoint(model, tmp_path):
    with pytest.raises(WearError, match="does not exist"):
        run_wear(
            Run(model, *ARGS, numerics=Numerics(scheme="implicit", steps=3)), tmp_path, resume=True
        )


@pytest.mark.slow
def test_kill_9_and_resume_gives_the_same_wear(model, tmp_path):
    ref_dir, run_dir = tmp_path / "ref", tmp_path / "run"
    run_wear(
        Run(model, *ARGS, numerics=Numerics(scheme="implicit", steps=6)),
        ref_dir,
        every=1,
        vtu_every=1,
    )
    script = tmp_path / "run.py"
    script.write_text(SCRIPT)
    proc = subprocess.Popen([sys.executable, str(script), str(run_dir)], stdout=subprocess.PIPE,
                            text=True)
    try:
        for line in proc.stdout:
            if int(line) >= 3:
                os.kill(proc.pid, signal.SIGKILL)
                break
    finally:
        proc.wait(timeout=600)
    assert proc.returncode == -signal.SIGKILL
    with np.load(run_dir / "checkpoint.npz") as d:     # step 3 was reported, 2 is saved
        assert 2 <= int(d["step"]) < 6
    run_wear(
        Run(model, *ARGS, numerics=Numerics(scheme="implicit", steps=6)),
        run_dir,
        every=1,
        vtu_every=1,
        resume=True,
    )
    with np.load(ref_dir / "checkpoint.npz") as a, np.load(run_dir / "checkpoint.npz") as b:
        assert int(a["step"]) == int(b["step"]) == 6
        for k in ("pad_wear", "rotor_wear"):
            assert np.abs(a[k] - b[k]).max() <= 1e-12 * np.abs(a[k]).max(), k
    assert (run_dir / "pad.pvd").read_text() == (ref_dir / "pad.pvd").read_text()
    assert len((run_dir / "history.csv").read_text().splitlines()) == 7
