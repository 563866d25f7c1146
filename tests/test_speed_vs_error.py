"""Smoke run of studies/speed_vs_error.py on tiny settings, and its comparison tools."""
import csv
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from brakewear.mesh.convergence import interpolate, pad_grid
from studyload import load_study

_path = Path(__file__).parents[1] / "studies" / "speed_vs_error.py"
_spec = importlib.util.spec_from_file_location("speed_vs_error", _path)
sve = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(sve)

METRICS = {"pad_wear_l2", "pressure_l2", "pad_wear_max", "pressure_max", "r_eff",
           "rotor_wear_l2"}


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("sve")
    res = sve.main(sizes=(1.5e-2, 1.2e-2), base_size=1.5e-2, ref_steps=2, implicit_steps=(1,),
                   explicit_steps=(2,), duration=1200.0, out=out, order_study=False,
                   reference=None)
    return res, out


def test_every_choice_runs_and_has_finite_errors(result):
    res, _ = result
    names = [r["name"] for r in res["runs"]]
    assert names == ["mesh 15 mm", "mesh 12 mm (reference)", "implicit 1 steps",
                     "explicit 2 steps", "geometry update", "rigid rotor", "condensed FE",
                     "Winkler (layer modulus)", "Winkler (stiffness-calibrated)"]
    for r in res["runs"]:
        if r["name"] == "explicit 2 steps":      # past the stability bound: refused
            continue
        assert "failed" not in r, r
        assert set(r["error"]) == METRICS
        assert all(np.isfinite(v) for v in r["error"].values()), r
        assert r["run_s"] > 0 and r["cpu_s"] > 0
        if r["group"] != "mesh size":
            assert set(r["error_vs_base"]) == METRICS


def test_the_condensed_row_has_the_base_models_answer(result):
    res, _ = result
    row = {r["name"]: r for r in res["runs"]}["condensed FE"]
    # the FE answer of the base mesh: its own error is that of the solver tolerance
    assert max(row["error_vs_base"].values()) < 1e-6
    assert row["error"]["pad_wear_l2"] > 1e-4


def test_reference_error_is_zero_and_others_are_not(result):
    res, _ = result
    ref = [r for r in res["runs"] if r["name"] == res["case"]["reference"]][0]
    assert all(v == 0.0 for v in ref["error"].values())
    assert ref["time_ratio"] == 1.0
    coarse = res["runs"][0]
    assert coarse["error"]["pad_wear_l2"] > 1e-4


def test_explicit_steps_beyond_the_stability_bound_are_refused(result):
    # 600 s explicit Euler steps are far past the scheme's stability bound (docs/theory.md):
    # refused before the run, naming the bound, instead of an overshooting answer
    runs = {r["name"]: r for r in result[0]["runs"]}
    failed = runs["explicit 2 steps"]["failed"]
    assert failed.startswith("NumericsError: numerics.steps = 2: the fixed step 600 s is "
                             "beyond the explicit scheme's stability bound"), failed


def test_files_written(result):
    res, out = result
    data = json.loads((out / "data" / "speed_vs_error.json").read_text())
    assert data["case"]["reference"] == "mesh 12 mm (reference)"
    rows = list(csv.DictReader(open(out / "data" / "speed_vs_error.csv")))
    assert len(rows) == len(res["runs"])
    assert float(rows[1]["err_pad_wear_l2"]) == 0.0
    png = out / "figures" / "speed_vs_error.png"
    assert png.stat().st_size > 10_000
    assert "| mesh 15 mm |" in sve.table(res)


def test_interpolation_to_the_reference_nodes_is_exact_for_linear_fields():
    rng = np.random.default_rng(0)
    xy = rng.uniform(0, 1, (2, 200))
    target = rng.uniform(0.2, 0.8, (2, 50))
    f = lambda p: 2.0 + 3.0 * p[0] - 1.5 * p[1]   # noqa: E731
    assert np.abs(interpolate(f(xy), xy, target) - f(target)).max() < 1e-12
    far = np.array([[5.0], [5.0]])                  # outside the hull: nearest value
    assert np.isfinite(interpolate(f(xy), xy, far)).all()


def test_pareto_front():
    pts = [(1.0, 0.5), (2.0, 0.6), (3.0, 0.1), (0.5, 0.9), (4.0, 0.1)]
    assert load_study("tradeoff_report").pareto(pts) == [3, 0, 2]


def test_element_order_on_the_cylinder():
    rows = sve.element_order(ns_p1=(2,), ns_p2=(1,))
    p1, p2 = rows
    assert (p1["order"], p2["order"]) == (1, 2)
    assert p2["energy_error"] < 0.5 * p1["energy_error"]


def test_base_size_must_be_one_of_the_sizes():
    with pytest.raises(ValueError, match="base_size"):
        sve.main(sizes=(1.5e-2,), base_size=1e-2, out=None)


def _converged_file(tmp_path, case, run, when="mid"):
    """A convergence-study JSON whose estimate is ``case``'s own fields on the grid."""
    from brakewear.geometry import load_geometry
    g = pad_grid(load_geometry())
    field = {"pad_wear": interpolate(case["_pad_wear"], case["_xy"], g["xy"]),
             "pressure": interpolate(case["_pressure"], case["_xy"], g["xy"]),
             "rotor_wear": np.interp(g["r"], case["_rotor_r"], case["_rotor_wear"])}
    est = {q: {"field": field[q].tolist()} for q in field}
    est.update({q: {"estimate": case[k]} for q, k in (("pad_wear_max", "pad_wear_max_m"),
                                                       ("pressure_max", "pressure_max_Pa"),
                                                       ("r_eff", "r_eff_m"))})
    data = {"case": {"duration_s": 3 * case["duration_s"], "t_mid_s": case["duration_s"],
                     "steps": 3 * case["steps"], **run},
            "orders": {"P1": {when: est, "runs": [{when: {}}]}},
            "grid": {k: np.asarray(v).tolist() for k, v in g.items()}}
    path = tmp_path / "mesh_convergence.json"
    path.write_text(json.dumps(data))
    return path


def test_the_converged_reference_is_read_at_the_runs_time(tmp_path):
    case = sve.run_case(1.5e-2, 600.0, 2)
    path = _converged_file(tmp_path, case, sve.RUN)
    ref = sve.converged_reference(path, 600.0, 2, sve.RUN)
    assert ref["name"].startswith("Richardson estimate")
    e = sve.errors(case, ref)
    # the run against its own fields on the grid: only the interpolation is left
    assert e["pad_wear_l2"] < 1e-3 and abs(e["pad_wear_max"]) < 1e-12, e
    assert abs(e["r_eff"]) < 1e-12 and e["rotor_wear_l2"] < 0.05, e
    # another time step, another line pressure or a missing file: no such reference
    assert sve.converged_reference(path, 600.0, 4, sve.RUN) is None
    assert sve.converged_reference(path, 600.0, 2, {**sve.RUN, "line_pressure": 2e6}) is None
    assert sve.converged_reference(tmp_path / "none.json", 600.0, 2, sve.RUN) is None
