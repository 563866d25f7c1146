"""The thermal drag study (studies/thermal_drag.py) on tiny settings."""
import importlib.util
import json
import math
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def study():
    spec = importlib.util.spec_from_file_location("thermal_drag",
                                                  ROOT / "studies" / "thermal_drag.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def result(study, tmp_path_factory):
    out = tmp_path_factory.mktemp("thermal_drag")
    return out, study.main(size=1.2e-2, duration=20.0, steps=2, out=out, repeats=1,
                           figures=False, fresh_process=True)


def test_keys_and_files(result):
    out, res = result
    for key in ("settings", "summary", "timing", "wear_profile", "steps",
                "heat_balance_error_max"):
        assert key in res, key
    for key in ("off", "on", "on_over_off"):
        assert key in res["summary"], key
    for key in ("off_median_s", "on_median_s", "thermal_cost_ratio",
                "off_fresh_process_median_s"):
        assert res["timing"][key] > 0, key
    assert json.loads((out / "data" / "thermal_drag_scene.json").read_text())["settings"][
        "steps"] == 2
    for name in ("thermal_drag_steps.csv", "thermal_drag_wear_profile.csv"):
        assert (out / "data" / name).stat().st_size > 0


def test_thermal_on_is_hotter_and_balances_heat(result):
    _, res = result
    s = res["summary"]
    T_amb = res["settings"]["T_ambient_C"]
    on = [x for x in res["steps"] if x["run"] == "on"]
    off = [x for x in res["steps"] if x["run"] == "off"]
    assert len(on) == len(off) == 2
    # the isothermal run has no temperature; the coupled one heats up step by step
    assert all(math.isnan(x["pad_face_T_max_C"]) for x in off)
    assert on[0]["pad_face_T_max_C"] > T_amb + 10.0
    assert on[1]["pad_face_T_max_C"] > on[0]["pad_face_T_max_C"]
    assert s["on"]["rotor_face_T_max_C"] > T_amb + 10.0
    assert res["heat_balance_error_max"] <= 1e-8
    assert all(x["heat_balance_error"] <= 1e-8 for x in on)
    # worn volume = Archard integral with k(T) (implicit scheme, gap offsets)
    assert s["on"]["pad_volume_m3"] == pytest.approx(s["on"]["pad_archard_m3"], rel=1e-10)
    assert s["off"]["pad_volume_m3"] > 0 and s["on"]["pad_volume_m3"] > 0


def test_end_pressure_is_the_last_implicit_step_pressure(result):
    # the extra solve at the end reproduces the pressure the implicit step wore with
    _, res = result
    assert res["summary"]["off"]["end_pressure_vs_last_wear_increment"] <= 1e-6


def test_no_thermal_run_never_imports_thermal(result):
    _, res = result
    assert res["timing"]["fresh_process_imported_thermal"] is False


def test_bad_repeats_raise(study):
    with pytest.raises(ValueError, match="repeats"):
        study.main(size=1.2e-2, repeats=0, out=None)
