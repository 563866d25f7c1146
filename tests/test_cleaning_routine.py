"""The cleaning routine's design curve and its sensitivity (studies/cleaning_routine.py,
studies/cleaning_sensitivity.py): the routine picked as stated, the probabilities and
their intervals, the inputs at their priors' points, SALib's Sobol indices against a
function with known ones, and a small design curve run end to end."""
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))
import cleaning_routine as cr  # noqa: E402
import cleaning_sensitivity as cs  # noqa: E402


def test_wilson_interval_holds_its_point_and_narrows():
    lo, hi = cr.wilson(180, 200)
    assert lo < 0.9 < hi and hi - lo < 0.09
    lo2, hi2 = cr.wilson(1800, 2000)
    assert hi2 - lo2 < (hi - lo) / 3
    assert cr.wilson(0, 10)[0] == 0.0 and cr.wilson(10, 10)[1] == 1.0


def test_the_routine_is_the_fewest_stops_then_the_lowest_deceleration_then_speed():
    def pt(v, a, P):
        return {"speed": v, "decel": a, "P": P, "line_pressure_MPa": 1.0,
                "interval_95": [cr.wilson(round(p * 100), 100) for p in P]}
    points = [pt(50, 1.0, [0.1, 0.5, 0.85, 0.92]), pt(50, 2.0, [0.2, 0.6, 0.91, 0.95]),
              pt(80, 1.0, [0.3, 0.91, 0.96, 0.99]), pt(80, 2.0, [0.3, 0.93, 0.97, 0.99])]
    r = cr.routine(points, 0.9)
    assert (r["stops"], r["decel"], r["speed_kmh"]) == (2, 1.0, 80)
    assert r["words"].startswith("2 friction-only stops from 80 km/h at 1 m/s^2")
    assert cr.routine(points, 0.95)["stops"] == 3
    assert cr.routine(points, 0.999) is None


def test_inputs_come_from_their_priors():
    pri = cr.inputs()
    assert {
        "thickness",
        "k_rust",
        "threshold",
        "mu_factor",
        "pad_wear_factor",
        "mu",
        "coning",
        "thermal_coning_factor",
        "convection_factor",
        "pad_modulus",
        "mass",
        "rolling_resistance",
        "drag_area",
        "drivetrain_drag",
    } <= set(pri)
    med = cr.medians()
    assert med["k_rust"] == pytest.approx(1e-12, rel=1e-12)
    assert med["threshold"] == pytest.approx(0.05e6, rel=1e-12)
    xs = cr.draw(400, seed=3)
    k = np.array([x["k_rust"] for x in xs])
    assert np.median(k) == pytest.approx(1e-12, rel=0.2)
    assert all(1600 <= x["mass"] <= 2100 for x in xs)
    assert cr._level(0.6) == 0.7 and cr._level(1.1) == 1.0 and cr._level(1.9) == 1.4


def test_tornado_moves_one_input_to_its_priors_points(monkeypatch):
    seen = []

    def fake(tasks, executor):
        seen.extend(tasks)
        return [{"stops_to_clean": None, "cleaned": [0.5, t["k_rust"] * 1e11]} for t in tasks]
    monkeypatch.setattr(cr, "map_tasks", fake)
    t = cs.tornado(1.0, 50.0, 2)
    pri = cr.inputs()
    assert len(seen) == 1 + 2 * len(pri)
    row = next(r for r in t["rows"] if r["input"] == "k_rust" and r["quantile"] == 0.95)
    assert row["value"] == pytest.approx(float(pri["k_rust"].sample(np.array([0.95]))[0]))
    assert row["cleaned_share"] == pytest.approx(row["value"] * 1e11)
    med = t["rows"][0]
    assert med["input"] == "median" and seen[0]["mass"] == pytest.approx(1850.0)


def test_sobol_indices_of_the_ishigami_function():
    """SALib through the study's wrapper (priors in probability space): the Ishigami
    function's first-order and total indices (a = 7, b = 0.1: S1 = 0.314, 0.442, 0;
    ST = 0.558, 0.442, 0.244) lie within three of their bootstrap half-widths."""
    pytest.importorskip("SALib")
    from brakewear.cleaning.rust import Prior

    pri = {n: Prior("uniform", -np.pi, np.pi, "", "test") for n in ("x1", "x2", "x3")}

    def f(xs):
        x = np.array([[d["x1"], d["x2"], d["x3"]] for d in xs])
        return {"y": np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2
                + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])}
    res = cs.sobol_indices(list(pri), pri, f, 2048, seed=5)["indices"]["y"]
    for name, s1, st in (("x1", 0.314, 0.558), ("x2", 0.442, 0.442), ("x3", 0.0, 0.244)):
        assert abs(res[name]["S1"] - s1) < 3 * res[name]["S1_conf"] + 0.01
        assert abs(res[name]["ST"] - st) < 3 * res[name]["ST_conf"] + 0.01


@pytest.mark.slow
def test_a_small_design_curve_runs_end_to_end(tmp_path):
    """Idealised brake at 8 mm, heat on: two decelerations from 80 km/h, three draws,
    four stops.  P(clean within N) never falls with N, friction on rust is above the
    iron's, the stops heat the ring and cone it, files written."""
    r = cr.design_curve([2.0, 3.0], [80.0], n=3, out=tmp_path, stops=4, size=8.0)
    for p in r["points"]:
        assert all(b >= a for a, b in zip(p["P"], p["P"][1:]))
        assert p["failed"] == 0
    assert r["routines"].keys() == {"0.9", "0.95"}
    one = cr.run_sample(dict(cr.DEFAULTS, **cr.medians(), decel=2.0, speed=80.0, stops=2,
                             size=8.0))
    rows = one["rows"]
    assert rows[0]["mu"] > cr.medians()["mu"]
    assert rows[1]["T_ring_C"] > rows[0]["T_ring_C"] > 20.0
    assert rows[1]["thermal_coning_um"] > 0
    assert (tmp_path / "data" / "cleaning_routine.json").exists()
    assert (tmp_path / "figures" / "cleaning_routine.png").exists()


@pytest.mark.slow
def test_the_curve_on_a_dask_cluster_is_the_curve_in_processes():
    """The same tiny design curve on a local dask.distributed cluster of two worker
    processes and on the default process pool: the same stops and cleaned shares."""
    distributed = pytest.importorskip("dask.distributed")
    kw = dict(n=2, stops=2, size=8.0, seed=4)
    here = cr.design_curve([3.0], [80.0], **kw)
    with distributed.Client(n_workers=2, threads_per_worker=1, processes=True,
                            dashboard_address=None) as client:
        there = cr.design_curve([3.0], [80.0], executor=client.get_executor(), **kw)
    a, b = here["points"][0], there["points"][0]
    assert a["stops_to_clean"] == b["stops_to_clean"]
    assert a["cleaned_last"] == pytest.approx(b["cleaned_last"], rel=1e-9)
