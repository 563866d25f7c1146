"""A run that ends early (worn through, a face past T_max, a solver error, Ctrl-C)
writes summary.json with its status and the reason: a drag and a schedule."""
import json
from dataclasses import replace

import pytest

from brakewear import Numerics
from brakewear.contact.lagrange import solve_contact
from brakewear.errors import ActiveSetError, TemperatureLimitError
from brakewear.interfaces import fe
from brakewear.output.runs import run_scene
from brakewear.scene import InterfaceSpec, OutputSpec, Scene, ThermalSpec, load_scene


@pytest.fixture(scope="module")
def small():
    s = load_scene("default")
    return dict(geometry=s.geometry, mesh_size=1.2e-2, duration=20.0,
                numerics=Numerics(steps=3, scheme="explicit"), output=OutputSpec(figures=False),
                interface=InterfaceSpec(model="fe", mu=0.4))   # its solver is patched


def _summary(out):
    return json.loads((out / "summary.json").read_text())


def _fail_from(monkeypatch, call: int):
    """The contact solves from the ``call``-th on get one active-set iteration from a
    cold start (no start set: a loose first solve, which never confirms its set)."""
    calls = []

    def solve(*a, **kw):
        calls.append(1)
        if len(calls) >= call:
            kw.update(max_iter=1, initial_active=None)
        return solve_contact(*a, **kw)
    monkeypatch.setattr(fe, "solve_contact", solve)


def test_a_solver_error_writes_the_summary_of_the_steps_before_it(small, tmp_path,
                                                                   monkeypatch):
    _fail_from(monkeypatch, 3)       # the start, step 1, then step 2 fails
    out = tmp_path / "run"
    with pytest.raises(ActiveSetError):
        run_scene(Scene(**small), out)
    s = _summary(out)
    assert s["status"] == "solver_error" and s["steps"] == 1
    e = s["ended"]
    assert e["error"] == "ActiveSetError" and "did not settle in 1" in e["reason"]
    assert e["figures"]["iterations"] == 1 and e["figures"]["active_counts"][0] > 0
    assert e["where"]["step"] == 2
    assert s["final"]["step"] == 1 and (out / "history.csv").exists()
    assert s["scene"]["name"] == "scene"


def test_a_solver_error_in_the_first_solve_still_writes_the_summary(small, tmp_path,
                                                                    monkeypatch):
    _fail_from(monkeypatch, 1)
    out = tmp_path / "run"
    (out).mkdir()
    (out / "summary.json").write_text('{"status": "finished"}')     # an older run's
    with pytest.raises(ActiveSetError):
        run_scene(Scene(**small), out)
    s = _summary(out)
    assert s["status"] == "solver_error" and s["steps"] == 0
    assert s["ended"]["where"]["step"].startswith("0 (the contact solve of the start)")


def test_a_face_past_T_max_writes_the_summary(small, tmp_path):
    out = tmp_path / "hot"
    with pytest.raises(TemperatureLimitError) as exc:
        run_scene(Scene(**small, thermal=ThermalSpec(enabled=True, T_max=298.15)), out)
    s = _summary(out)
    assert s["status"] == "temperature_limit"
    f = s["ended"]["figures"]
    assert f["body"] == "pad" and f["temperature_K"] > f["T_max_K"] == pytest.approx(298.15)
    assert "T_max = 25 C" in s["ended"]["reason"] and s["ended"]["where"]["step"] == f["step"]
    assert exc.value.summary["status"] == "temperature_limit"


def test_ctrl_c_writes_the_summary_of_the_steps_done(small, tmp_path):
    def stop_at_2(s):
        if s.step == 2:
            raise KeyboardInterrupt
    out = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        run_scene(Scene(**small), out, progress=stop_at_2)
    s = _summary(out)
    assert s["status"] == "interrupted" and s["steps"] == 2
    assert "Ctrl-C" in s["ended"]["reason"] and s["final"]["step"] == 2


def test_worn_through_names_its_reason(small, tmp_path):
    from brakewear.errors import WornThroughError
    from brakewear.scene import WearSpec
    sc = Scene(**{**small, "duration": 7200.0, "numerics": Numerics()},
               line_pressure=5e6, pad_wear=replace(WearSpec(), limit=0.5e-3))
    out = tmp_path / "run"
    with pytest.raises(WornThroughError):
        run_scene(sc, out)
    s = _summary(out)
    assert s["status"] == "worn_through" and "pad worn through" in s["ended"]["reason"]
    assert s["ended"]["figures"]["depth_m"] >= 0.5e-3


# -------------------------------------------------------------------- schedules --
def _stops(small, **kw):
    from brakewear.duty import Dwell, Stop, Vehicle
    car = Vehicle(mass=1800.0, front_share=0.7, tyre_radius=0.32)
    return Scene(**small, rotor="rigid", vehicle=car,
                 schedule=(Stop(50 / 3.6, decel=1.5), Dwell(10.0), Stop(50 / 3.6, decel=1.5)),
                 **kw)


def test_a_schedule_stopped_by_ctrl_c_writes_the_applications_done(small, tmp_path):
    def stop_after_first(rec):
        raise KeyboardInterrupt
    out = tmp_path / "run"
    from brakewear.output.runs import run_scene as rs
    with pytest.raises(KeyboardInterrupt):
        rs(_stops(small), out, progress=stop_after_first)
    s = _summary(out)
    assert s["status"] == "interrupted" and s["applications"] == 1
    assert s["braked_applications"] == 1 and s["energy"]["dissipated_per_face_J"] > 0
    assert s["scene"]["name"] == "scene"


def test_a_schedule_stopped_by_a_solver_error_names_the_application(small, tmp_path,
                                                                     monkeypatch):
    """The contact solves after the first application get one cold iteration: the
    second stop fails, and the summary holds the first two applications (the stop and
    the dwell) and names the third as where it ended."""
    done = []

    def solve(*a, **kw):
        if done:
            kw.update(max_iter=1, initial_active=None)
        return solve_contact(*a, **kw)
    monkeypatch.setattr(fe, "solve_contact", solve)
    out = tmp_path / "run"
    with pytest.raises(ActiveSetError):
        run_scene(_stops(small), out, progress=lambda rec: done.append(rec.index))
    s = _summary(out)
    assert s["status"] == "solver_error" and s["applications"] == 2 == len(done)
    assert s["ended"]["where"]["application"] == "2 (stop)"
    assert s["ended"]["figures"]["iterations"] == 1
    assert s["energy"]["dissipated_per_face_J"] > 0
