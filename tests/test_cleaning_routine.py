"""The cleaning routine as package API: a routine as a car maker states it, run through
the one schedule runner with its states, its draws and their priors, the design curve's
probabilities and the routine picked from it, and the sensitivity's Sobol indices."""
import json

import numpy as np
import pytest

from brakewear import DutyError
from brakewear.cleaning.brake import level
from brakewear.cleaning.priors import STARTS, cleaning_inputs, draw, medians
from brakewear.cleaning.routine import Routine
from brakewear.cleaning.sensitivity import routine_outputs, sobol_indices
from brakewear.cleaning.sweep import best_routine, map_tasks, wilson
from brakewear.duty import KMH, Dwell, Stop


def test_a_routine_is_stops_and_the_dwells_between_them():
    r = Routine(3, 80 * KMH, 2.0, 300.0)
    sched = r.schedule()
    assert [type(a) for a in sched] == [Stop, Dwell, Stop, Dwell, Stop]
    assert sched[1].duration == pytest.approx(300.0 - 80 * KMH / 2.0, rel=1e-12)
    assert sched[1].speed == pytest.approx(80 * KMH)
    assert r.words() == "3 friction-only stops from 80 km/h at 2 m/s^2, 300 s apart"


@pytest.mark.parametrize("kw, match", [
    (dict(interval=30.0), r"routine\.interval: 30\.0 s is not allowed"),
    (dict(interval=900.0), r"routine\.interval: 900\.0 s is not allowed"),
    (dict(decel=0.1, interval=100.0), r"a stop from 100 km/h at 0\.1 m/s\^2 lasts 278 s"),
    (dict(stops=0), r"routine\.stops"),
])
def test_a_routine_out_of_its_ranges_is_refused(kw, match):
    args = {**dict(stops=3, speed=100 * KMH, decel=2.0, interval=120.0), **kw}
    with pytest.raises(DutyError, match=match):
        Routine(**args)


def test_wilson_interval_holds_its_point_and_narrows():
    lo, hi = wilson(180, 200)
    assert lo < 0.9 < hi and hi - lo < 0.09
    lo2, hi2 = wilson(1800, 2000)
    assert hi2 - lo2 < (hi - lo) / 3
    assert wilson(0, 10)[0] == 0.0 and wilson(10, 10)[1] == 1.0


def test_the_routine_is_the_fewest_stops_then_the_lowest_deceleration_then_speed():
    def pt(v, a, P, t=120.0):
        return {"speed_kmh": v, "decel": a, "interval": t, "P": P, "line_pressure_MPa": 1.0,
                "interval_95": [wilson(round(p * 100), 100) for p in P]}
    points = [pt(50, 1.0, [0.1, 0.5, 0.85, 0.92]), pt(50, 2.0, [0.2, 0.6, 0.91, 0.95]),
              pt(80, 1.0, [0.3, 0.91, 0.96, 0.99]), pt(80, 2.0, [0.3, 0.93, 0.97, 0.99]),
              pt(80, 1.0, [0.3, 0.91, 0.96, 0.99], t=300.0)]
    r = best_routine(points, 0.9)
    assert (r["stops"], r["decel"], r["speed_kmh"], r["interval"]) == (2, 1.0, 80, 300.0)
    assert r["words"].startswith("2 friction-only stops from 80 km/h at 1 m/s^2, 300 s apart")
    assert best_routine(points, 0.95)["stops"] == 3
    assert best_routine(points, 0.999) is None


def test_inputs_come_from_their_priors_with_their_sources():
    for start in STARTS:
        pri = cleaning_inputs(start)
        assert all(len(p.source) > 20 for p in pri.values())
        assert {"thickness", "k_rust", "mu", "finger_radius", "finger_diameter"} <= set(pri)
    bed = cleaning_inputs("bedded")
    assert {"bedding_heat", "static_coning"} <= set(bed) and "coning" not in bed
    assert "coning" in cleaning_inputs("new")
    assert sum(k.startswith("load_path:") for k in bed) == 11
    med = medians(bed)
    assert med["k_rust"] == pytest.approx(2e-12, rel=1e-12)
    assert med["static_coning"] == pytest.approx(0.0, abs=1e-18)
    xs = draw(400, seed=3, priors=bed)
    assert all(1600 <= x["mass"] <= 2100 and 118 <= x["finger_radius"] <= 134 for x in xs)
    assert np.median([x["k_rust"] for x in xs]) == pytest.approx(2e-12, rel=0.2)
    assert level(0.6, (0.7, 1.0, 1.4)) == 0.7 and level(131.0, (120.0, 126.0, 132.0)) == 132.0


def test_the_outputs_of_a_routine_count_a_failure_as_not_clean():
    runs = [{"stops_to_clean": 2, "criteria": {"volume_removed": {"values": [0.5, 0.96]}}},
            {"stops_to_clean": None, "criteria": {"volume_removed": {"values": [0.3, 0.6]}}},
            {"error": "SolverError: ...", "stops_to_clean": None, "criteria": {}}]
    out = routine_outputs(runs, 2, "volume_removed")
    assert out == {"criterion_value": [1.0, 0.6, 0.0], "cleaned": [1.0, 0.0, 0.0]}


def _square(task):
    return {"y": task["x"] ** 2}


def test_a_journalled_sweep_resumes_without_running_again(tmp_path):
    journal = tmp_path / "runs.jsonl"
    tasks = [{"x": x} for x in range(4)]

    class Serial:
        def submit(self, fn, t):
            from concurrent.futures import Future
            f = Future()
            f.set_result(fn(t))
            return f
    first = map_tasks(tasks[:2], Serial(), journal=journal, function=_square)
    seen = []

    def counted(t):
        seen.append(t["x"])
        return _square(t)
    again = map_tasks(tasks, Serial(), journal=journal, function=counted)
    assert [r["y"] for r in again] == [0, 1, 4, 9] and first == again[:2]
    assert sorted(seen) == [2, 3]
    assert len(journal.read_text().splitlines()) == 4
    assert sorted(json.loads(x)["result"]["y"] for x in journal.read_text().splitlines()) == \
        [0, 1, 4, 9]


def test_sobol_indices_of_the_ishigami_function():
    """SALib through the package's wrapper (priors in probability space): the Ishigami
    function's first-order and total indices (a = 7, b = 0.1: S1 = 0.314, 0.442, 0;
    ST = 0.558, 0.442, 0.244) lie within three of their bootstrap half-widths."""
    pytest.importorskip("SALib")
    from brakewear.cleaning.rust import Prior

    pri = {n: Prior("uniform", -np.pi, np.pi, "", "test") for n in ("x1", "x2", "x3")}

    def f(xs):
        x = np.array([[d["x1"], d["x2"], d["x3"]] for d in xs])
        return {"y": np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2
                + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])}
    res = sobol_indices(list(pri), pri, f, 2048, seed=5)["indices"]["y"]
    for name, s1, st in (("x1", 0.314, 0.558), ("x2", 0.442, 0.442), ("x3", 0.0, 0.244)):
        assert abs(res[name]["S1"] - s1) < 3 * res[name]["S1_conf"] + 0.01
        assert abs(res[name]["ST"] - st) < 3 * res[name]["ST_conf"] + 0.01
