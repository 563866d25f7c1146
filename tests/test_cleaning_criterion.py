"""The cleaning criterion by area, the touch threshold, the layered rotor law,
and the vehicle-based cleaning study on a coarse mesh."""

import numpy as np
import pytest

from brakewear import FEInterface, WearError
from brakewear.cleaning.corrosion import CorrodedRotor, coning_gap
from brakewear.model import BrakeModel
from studyload import load_study

study = load_study("cleaning_stops")


@pytest.fixture(scope="module")
def itf():
    return FEInterface(BrakeModel("default", size=12e-3, rotor="rigid"), 1e6, 0.4)


def _rotor(itf, **kw):
    g = itf.model.geometry.pad
    return CorrodedRotor(itf, g.inner_radius, g.outer_radius, 25e-6, 1e-12, 5e-16, **kw)


def test_cleaned_fraction_counts_area_not_width(itf):
    rot = _rotor(itf)
    g = itf.model.geometry.pad
    r = rot.radii[itf.ring]                 # radius of each rotor wear node
    r_mid = 0.5 * (g.inner_radius + g.outer_radius)
    outer = np.where(r > r_mid, 30e-6, 0.0)
    # the outer half of the band (by width) holds more than half of its area
    expected = rot.band_area[rot.radii > r_mid].sum() / rot.band_area.sum()
    assert expected > 0.55
    assert rot.cleaned_fraction(outer) == pytest.approx(expected, rel=1e-12)
    assert rot.cleaned_fraction(np.full(r.size, 25e-6)) == 1.0
    assert rot.cleaned_fraction(np.full(r.size, 24.9e-6)) == 0.0
    assert rot.band_area.sum() == pytest.approx(
        np.pi * (g.outer_radius ** 2 - g.inner_radius ** 2), rel=1e-12)


def test_touched_needs_the_threshold_and_the_law_follows_the_layer(itf):
    rot = _rotor(itf, threshold=0.1e6)
    p = np.where(itf.r < np.median(itf.r), 1e6, 0.05e6)     # inner half pressed, outer grazed
    assert 0.0 < rot.touched_fraction(p) < 0.6
    assert _rotor(itf).touched_fraction(p) == 1.0            # no threshold: grazing counts
    w = np.where(rot.radii[itf.ring] < np.median(itf.r), 30e-6, 0.0)
    rot.update(w)
    f = rot.law.factor
    assert set(np.round(f, 12)) <= {1.0, 5e-16 / 1e-12} | set(np.round(f[(f > 5e-4) & (f < 1)], 12))
    assert f[itf.r < 0.99 * np.median(itf.r)].max() == pytest.approx(5e-4, rel=1e-12)
    assert f[itf.r > 1.01 * np.median(itf.r)].min() == 1.0
    with pytest.raises(WearError, match="threshold = -1"):
        _rotor(itf, threshold=-1)


def test_coning_gap_opens_at_the_outer_radius_or_the_inner():
    r = np.linspace(0.1, 0.14, 5)
    assert coning_gap(r, 0.1, 0.14, 30e-6) == pytest.approx(np.linspace(0, 30e-6, 5), abs=1e-18)
    assert coning_gap(r, 0.1, 0.14, -30e-6) == pytest.approx(np.linspace(30e-6, 0, 5), abs=1e-18)


def test_vehicle_cleaning_study_on_a_coarse_mesh(tmp_path):
    # a fast-wearing layer so that a few stops decide
    res = study.main(decels=(1.0, 4.0), stops=4, out=tmp_path, executor=_Serial(),
                     size=12.0, k_corrosion=8e-12, coning=30.0)
    assert res["failed_runs"] == []
    low, high = res["runs"]
    # every stop dissipates the brake's share of the kinetic energy, whatever the deceleration
    for run in res["runs"]:
        for row in run["rows"]:
            assert row["target_face_kJ"] == pytest.approx(low["rows"][0]["target_face_kJ"],
                                                          rel=1e-12)
            # the line pressure is held over a stop: the model's friction work departs
            # from the demand by how far the effective radius moves within the stop --
            # up to ~9 % on this coarse mesh with a layer wearing 8x faster than the default
            assert row["friction_face_kJ"] == pytest.approx(row["target_face_kJ"], rel=0.1)
    # a higher deceleration is a higher line pressure, touches and cleans at least as much
    assert high["line_pressure_MPa"] > 3.5 * low["line_pressure_MPa"]
    assert high["rows"][0]["touched_fraction"] >= low["rows"][0]["touched_fraction"]
    assert high["rows"][-1]["cleaned_fraction"] >= low["rows"][-1]["cleaned_fraction"]
    M = study.cleaned_map(res)
    assert M.shape == (4, 2) and np.all(np.diff(M, axis=0) >= 0)
    assert (tmp_path / "figures" / "cleaning_stops_map.png").stat().st_size > 10_000
    assert (tmp_path / "data" / "cleaning_stops_map.csv").read_text().count("\n") == 5
    # the contact maps: the pressure at the end of the first and the last stop
    assert (tmp_path / "figures" / "cleaning_stops_contact.png").stat().st_size > 10_000
    n = len(low["pad_x_mm"])
    assert len(low["pressure_first_MPa"]) == len(high["pressure_last_MPa"]) == n
    assert max(high["pressure_first_MPa"]) > max(low["pressure_first_MPa"])


class _Serial:
    def map(self, fn, items):
        return [fn(x) for x in items]


def test_sensitivity_rows_and_tornado_from_the_sweeps_on_disk(tmp_path):
    """The tornado reads each variant's sweep from data/: stops to clean at the chosen
    deceleration (inf when it does not clean within the stops), the lowest cleaning
    deceleration, and a variant not run is left out (nan), not invented."""
    import json

    def sweep(stops_by_decel):
        runs = [{"decel": a, "stops_to_clean": n} for a, n in stops_by_decel.items()]
        lowest = next((r["decel"] for r in runs if r["stops_to_clean"] is not None), None)
        return {"runs": runs, "lowest_cleaning_decel": lowest}

    data = tmp_path / "data"
    data.mkdir()
    files = {"cleaning_stops": {1.0: None, 1.5: 16, 2.0: 15},
             "cleaning_stops_corr10": {1.0: 10, 1.5: 8, 2.0: 7},
             "cleaning_stops_corr50": {1.0: None, 1.5: None, 2.0: None},
             "cleaning_stops_mu03": {1.0: 12, 1.5: 11, 2.0: 11}}
    for name, d in files.items():
        (data / f"{name}.json").write_text(json.dumps(sweep(d)))
    rows = {r["parameter"]: r for r in study.write_sensitivity(tmp_path, decel=1.5, stops=20)}
    c = rows["corrosion (um)"]
    assert (c["base_stops"], c["low_stops"], c["high_stops"]) == (16, 8, float("inf"))
    assert (c["low_lowest"], c["high_lowest"], c["base_lowest"]) == (1.0, None, 1.5)
    m = rows["mu"]
    assert m["low_stops"] == 11 and m["high"] is None and np.isnan(m["high_stops"])
    assert np.isnan(rows["coning (um)"]["low_stops"])
    assert (tmp_path / "figures" / "cleaning_stops_tornado.png").stat().st_size > 10_000
    assert (data / "cleaning_stops_sensitivity.csv").read_text().startswith("parameter,")


def test_probability_of_clean_counts_the_samples(monkeypatch):
    """The Monte Carlo draws its inputs reproducibly, hands each sample to
    run_decel through the executor, counts a failed solve as not cleaned and
    reports the Wilson interval."""
    from concurrent.futures import ThreadPoolExecutor

    a, b = study.sample_inputs(50, seed=1), study.sample_inputs(50, seed=1)
    assert a == b and len({x["corrosion"] for x in a}) == 50
    assert all(15.0 <= x["coning"] <= 45.0 for x in a)
    assert np.median([x["k_corrosion"] for x in a]) == pytest.approx(1e-12, rel=0.3)

    def fake(task):      # thin layers clean, a few solves fail
        if task["coning"] > 42.0:
            return {"decel": task["decel"], "error": "ActiveSetError: ..."}
        clean = task["corrosion"] < 25.0
        return {"decel": task["decel"], "stops_to_clean": 12 if clean else None,
                "rows": [{"cleaned_fraction": 1.0 if clean else 0.8}], "run_s": 2.0}
    monkeypatch.setattr(study, "run_decel", fake)
    with ThreadPoolExecutor(2) as ex:
        r = study.probability_of_clean(1.0, 50, seed=1, executor=ex)
    expect = sum(x["corrosion"] < 25.0 and x["coning"] <= 42.0 for x in a)
    assert r["cleaned"] == expect and r["probability"] == expect / 50
    assert r["failed"] == sum(x["coning"] > 42.0 for x in a) > 0
    lo, hi = r["interval_95"]
    assert lo < r["probability"] < hi and (lo, hi) == pytest.approx(study.wilson(expect, 50))
    assert study.wilson(0, 10)[0] == 0.0 and study.wilson(10, 10)[1] == 1.0


@pytest.mark.parametrize("kw,words", [({"n": 0}, "n = 0"), ({"corrosoin": 25.0}, "settings")])
def test_probability_of_clean_refuses_bad_settings_before_running(kw, words, monkeypatch):
    monkeypatch.setattr(study, "run_decel", lambda task: pytest.fail("ran a sample"))
    with pytest.raises(ValueError, match=words):
        study.probability_of_clean(1.0, **{"n": 4, **kw}, executor=_Serial())


def test_the_floating_inboard_pad_cleans_with_its_energy_and_refuses_the_condensed_interface():
    """The inboard load path with the piston a traction (piston rim, push bracket, a
    rigid rotor) in the vehicle study: its stops dissipate the vehicle's energy as
    the default brake's do."""
    task = dict(study.DEFAULTS, decel=1.0, stops=2, size=12.0, k_corrosion=8e-12,
                geometry="floating", piston="traction", interface="fe")
    run = study.run_decel(task)
    assert "error" not in run
    for row in run["rows"]:
        assert row["friction_face_kJ"] == pytest.approx(row["target_face_kJ"], rel=0.03)
    with pytest.raises(ValueError, match="needs a bilateral pad support or the rigid piston, "
                                         "and geometry 'floating' has a 'push' one"):
        study.main(decels=(1.0,), stops=1, geometry="floating", piston="traction",
                   interface="condensed", executor=_Serial())


def test_the_floating_caliper_is_judged_on_both_faces():
    """The default brake of the study: the floating caliper as it holds its pads, both
    faces on the elastic hat rotor, each face its own layer; the answer is the worse
    face, and the stops dissipate the vehicle's energy on each face."""
    res = study.main(decels=(1.0,), stops=3, executor=_Serial(), size=12.0, k_corrosion=8e-12)
    assert res["failed_runs"] == [] and "both faces" in res["settings"]["brake"]
    (run,) = res["runs"]
    assert set(run["pad_face"]) == {"in", "out"} and set(run["ring_face"]) == {"in", "out"}
    for row in run["rows"]:
        assert set(row["cleaned_faces"]) == {"in", "out"}
        assert row["cleaned_fraction"] == min(row["cleaned_faces"].values())
        assert row["touched_fraction"] == min(row["touched_faces"].values())
        # the torque equation counts the clamp force the faces really carry
        assert row["friction_face_kJ"] == pytest.approx(row["target_face_kJ"], rel=0.05)


@pytest.mark.parametrize("argv, where", [
    (["--dask", "tcp://scheduler:8786"], ("tcp://scheduler:8786", 2)),
    (["--dask", "local", "--monte-carlo", "3"], ("local", 2)),
    (["--workers", "3", "--monte-carlo", "3"], (None, 3)),
])
def test_the_command_line_runs_where_it_is_told(argv, where, monkeypatch, tmp_path, capsys):
    """``--dask ADDRESS|local`` and ``--workers`` choose the executor that the sweep's and
    the Monte Carlo's runs go to (here a stand-in that runs them in this process)."""
    from contextlib import contextmanager

    asked, ran = [], []

    class Recording(_Serial):
        def map(self, fn, items):
            ran.extend(items)
            return super().map(fn, items)

    @contextmanager
    def executor(dask, workers):
        asked.append((dask, workers))
        yield Recording()

    def fake(task):
        return {"decel": task["decel"], "line_pressure_MPa": task["decel"], "stops_to_clean": 3,
                "rows": [{"stop": 3, "cleaned_fraction": 1.0, "touched_fraction": 1.0}],
                "run_s": 0.5}
    monkeypatch.setattr(study, "study_executor", executor)
    monkeypatch.setattr(study, "run_decel", fake)
    res = study._cli(["--decels", "1.0", "2.0", "--stops", "3", "--interface", "fe",
                      "--no-figures", "--out", str(tmp_path), *argv])
    assert asked == [where]
    mc = "--monte-carlo" in argv
    assert len(ran) == (3 if mc else 2) and ran[0]["interface"] == "fe"
    assert (res["samples"] == 3) if mc else (res["lowest_cleaning_decel"] == 1.0)
    assert ("P = 1.00" if mc else "lowest cleaning deceleration: 1.0") in capsys.readouterr().out


def test_the_default_executor_is_a_process_pool_of_the_workers_asked_for():
    from concurrent.futures import ProcessPoolExecutor

    from sweep_executor import study_executor

    with study_executor(None, 1) as ex:
        assert isinstance(ex, ProcessPoolExecutor)
        assert ex.submit(abs, -2).result() == 2
