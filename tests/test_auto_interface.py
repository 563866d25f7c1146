"""``interface.model = "auto"``: FE for a run too short to pay for the
condensation, condensed for a long one, FE wherever the condensation does not
apply; the choice and its reason in the run's first line and its summary, and
the answer the same (1e-8, against FE solves run to 1e-12) either way."""
import json

import numpy as np
import pytest

from brakewear import BrakeModel, FEInterface
from brakewear.interfaces import auto
from brakewear.interfaces.auto import choose_interface, condensation_solves
from brakewear.output.runs import run_scene
from brakewear.scene import InterfaceSpec, OutputSpec, Scene, load_scene
from brakewear.wear import Numerics


def _scene(steps, **kw):
    s = load_scene("default")
    return Scene(**{**dict(geometry=s.geometry, mesh_size=1.2e-2, duration=600.0,
                           numerics=Numerics(steps=steps, scheme="implicit", tol=1e-12),
                           output=OutputSpec(figures=False, vtu_every=100),
                           interface=InterfaceSpec(mu=0.4)), **kw})


@pytest.fixture(scope="module")
def small():
    model = BrakeModel(size=1.2e-2)
    return model, FEInterface(model, 1e6, 0.4)


def _choose(small, steps=None, tmp_path=None, **kw):
    model, fe = small
    return choose_interface(model, fe, kw.pop("numerics", Numerics(steps=steps)),
                            line_pressure=1e6, omega=55.0, duration=kw.pop("duration", 600.0),
                            wear_rate=lambda p, v: 5e-15 * p * v, cache=tmp_path, **kw)


def test_the_break_even_decides_between_a_short_and_a_long_run(small, tmp_path):
    model, fe = small
    even = condensation_solves(model.dofs, fe.area.size) / (
        auto.FE_STEP_SOLVES * (1 - auto.CONDENSED_STEP))
    short = _choose(small, max(1, int(even) - 1), tmp_path)
    long = _choose(small, int(even) + 2, tmp_path)
    assert short.model == "fe" and long.model == "condensed"
    assert short.break_even_steps == pytest.approx(even) == long.break_even_steps
    assert f"pays after {even:.0f} steps" in short.reason and "FE contact solves" in long.reason


def test_fe_wherever_the_condensation_does_not_apply(small, tmp_path):
    geometry = _choose(small, tmp_path=tmp_path,
                       numerics=Numerics(steps=10_000, update="geometry"))
    assert geometry.model == "fe" and "geometry update" in geometry.reason
    memory = _choose(small, tmp_path=tmp_path, numerics=Numerics(steps=10_000,
                                                                  memory_budget=1e-6))
    assert memory.model == "fe" and "GB" in memory.reason
    worn = _choose(small, 10_000, tmp_path, duration=1e7)   # millimetres of wear
    assert worn.model == "fe" and "range" in worn.reason


def test_a_cached_condensation_is_free(small, tmp_path):
    from brakewear import CondensedInterface

    model, fe = small
    assert _choose(small, 1, tmp_path).model == "fe"
    CondensedInterface(model, 1e6, 0.4, fe=fe, cache=tmp_path)
    cached = _choose(small, 1, tmp_path)
    assert cached.model == "condensed" and "cache" in cached.reason


def test_step_control_expects_steps_from_dp_tol_and_the_wear_per_step():
    n = Numerics(dp_tol=0.05)
    assert auto.expected_steps(n, wear=1e-6, dh_limit=1e-4) == pytest.approx(
        auto.CONTROLLED_STEPS / 0.05)
    assert auto.expected_steps(n, wear=1e-3, dh_limit=1e-5) == pytest.approx(100.0)
    assert auto.expected_steps(Numerics(steps=7), 1.0, 1e-9, applications=3) == 21.0


def test_auto_runs_say_what_they_chose_and_answer_as_fe(tmp_path, monkeypatch):
    """Both ways end to end: the short run stays FE, the long one condenses, the
    first line and summary.json say so, and the answers are FE's."""
    lines = []
    model = BrakeModel(size=1.2e-2)
    even = condensation_solves(model.dofs, FEInterface(model, 1e6, 0.4).area.size) / (
        auto.FE_STEP_SOLVES * (1 - auto.CONDENSED_STEP))
    short, long = max(1, int(even) - 1), int(even) + 2
    monkeypatch.setenv("BRAKEWEAR_CACHE", str(tmp_path / "cache"))
    a = run_scene(_scene(short), tmp_path / "short", announce=lines.append)
    b = run_scene(_scene(long), tmp_path / "long", announce=lines.append)
    fe = run_scene(_scene(long, interface=InterfaceSpec(mu=0.4, model="fe")), tmp_path / "fe")
    assert lines[0].startswith("interface: fe (auto): ") and a["interface"]["model"] == "fe"
    assert lines[1].startswith("interface: condensed (auto): ")
    written = json.loads((tmp_path / "long" / "summary.json").read_text())
    assert written["interface"]["model"] == "condensed"
    assert written["interface"]["requested"] == "auto" and written["interface"]["reason"]
    assert fe["interface"] == {"requested": "fe", "model": "fe"}
    for key in ("pad_wear_max_m", "pad_wear_mean_m", "pressure_max_Pa", "rotor_wear_max_m"):
        assert b["final"][key] == pytest.approx(fe["final"][key], rel=1e-8), key
    assert np.isclose(b["pad_archard_m3"], fe["pad_archard_m3"], rtol=1e-8)


def test_a_resumed_run_keeps_the_interface_it_was_run_on(small, tmp_path):
    from brakewear import CondensedInterface

    model, fe = small
    run_scene(_scene(1, interface=InterfaceSpec(mu=0.4, model="fe")), tmp_path / "run")
    CondensedInterface(model, 1e6, 0.4, fe=fe, cache=tmp_path)   # now it would be free
    kept = _choose(small, 1, tmp_path, resume=tmp_path / "run" / "checkpoint.npz")
    assert kept.model == "fe" and "resumed" in kept.reason


def test_the_cost_fit_holds_the_measured_condensations():
    """condensation_solves is fitted to the measured meshes (docs/data): within 15 %."""
    from pathlib import Path

    rows = json.loads((Path(__file__).resolve().parents[1] / "docs" / "data"
                       / "condensed_auto.json").read_text())["rows"]
    assert len(rows) >= 4
    for r in rows:
        fit = condensation_solves(r["dofs"], r["contact_nodes"])
        assert fit == pytest.approx(r["condensation_over_fe_solve"], rel=0.15), r["mesh"]


def test_the_cost_study_measures_the_rows_of_the_fit(tmp_path):
    from studyload import load_study

    study = load_study("condensed_cost")
    (row,) = study.auto_main(sizes=(3000,), scene=False, out=tmp_path)
    assert row["condensation_over_fe_solve"] == pytest.approx(
        row["condensation_cpu_s"] / row["fe_contact_solve_cpu_s"])
    assert row["factor_entries"] > 0 and row["contact_nodes"] > 0
    saved = json.loads((tmp_path / "data" / "condensed_auto.json").read_text())
    assert saved["rows"][0]["dofs"] == row["dofs"]


def test_the_p2_study_runs_both_orders_on_both_interfaces():
    from studyload import load_study

    study = load_study("p2_interfaces")
    rows = study.main(meshes=(("P2 18 mm", 2, study.mc.level_settings(1.0)),), steps=2, p1=None)
    fe, cd = rows
    assert (fe["interface"], cd["interface"]) == ("fe", "condensed")
    assert cd["condense_cpu_s"] > 0 == fe["condense_cpu_s"]
    assert cd["pad_wear_max_um"] == pytest.approx(fe["pad_wear_max_um"], rel=1e-8)
