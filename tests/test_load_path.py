"""studies/load_path.py on coarse meshes: the load path's answers that must hold
on any mesh (proportionality of conforming contact, balance, the half model where
it holds, the fingers and the hot ring's cone where it does not)."""
from dataclasses import replace

import numpy as np
import pytest

from brakewear.geometry import CaliperGeometry, load_geometry
from brakewear.mesh.convergence import richardson
from studyload import load_study

lp = load_study("load_path")


@pytest.fixture(scope="module")
def floating():
    return lp.meshed(load_geometry("floating"), lp.level_mesh(1.0))


def _faces(run, k):
    return run["rows"][k]["faces"]


def test_conforming_contact_is_proportional_and_balanced(floating):
    run = lp.solve_case(floating, "full", [0.5, 2.0], [0.4])
    for face in ("in", "out"):
        a, b = _faces(run, 0)[face], _faces(run, 1)[face]
        assert b["coverage"] == pytest.approx(a["coverage"], rel=1e-6)
        assert b["normal_force_N"] == pytest.approx(4 * a["normal_force_N"], rel=1e-8)
    for row in run["rows"]:
        assert max(row["balance"].values()) < 1e-8
        # the caliper: the piston's force is the fingers' force, both the clamp force
        cal, F = row["caliper"], row["line_pressure_MPa"] * 1e6 * floating.clamp_area
        assert cal["force"] < 1e-8
        assert cal["inboard_force_N"] == pytest.approx(F, rel=1e-8)
        assert cal["outboard_force_N"] == pytest.approx(F, rel=1e-8)
    # the fingers sit outboard of the piston: so does the outboard centre of pressure
    f = _faces(run, 0)
    assert f["out"]["cop_r_mm"] > f["in"]["cop_r_mm"] + 2.0


def test_the_caliper_only_run_balances_every_full_case():
    out = lp.caliper_main([0.25, 4.0], lp.level_mesh(1.0))
    assert set(out["cases"]) == {"floating", "fingers_full", "fixed_full"}
    g = load_geometry("floating")
    for name, rows in out["cases"].items():
        for r in rows:
            F = r["line_pressure_MPa"] * 1e6 * g.clamp_area
            assert r["force"] < 1e-8
            assert r["outboard_force_N"] == pytest.approx(r["inboard_force_N"], rel=1e-8)
            # the pins carry the couple of the fingers' offset, F (x_fingers - x_piston),
            # to the footprints' quadrature on 6 mm facets (1.2 %; 0.2 % at 2.5 mm);
            # opposed pistons leave none
            x_f = 0.126 * np.cos(np.radians(12.0))
            my = F * (x_f - 0.119) if name != "fixed_full" else 0.0
            assert r["pin_moment_Nm"][1] == pytest.approx(my, abs=0.03 * F * (x_f - 0.119))


def test_a_hot_ring_cones_and_the_line_pressure_flattens_it(floating):
    cold = lp.solve_case(floating, "full", [1.0], [0.0])
    hot = lp.solve_case(floating, "full", [0.25, 1.0, 4.0], [0.0], dT=100.0)
    cov = {face: [r["faces"][face]["coverage"] for r in hot["rows"]] for face in ("in", "out")}
    for face in ("in", "out"):
        assert np.all(np.diff(cov[face]) > 0), cov                    # more pressure, more contact
        assert cov[face][0] < 0.6 * _faces(cold, 0)[face]["coverage"]  # the cone lifts the pads
    # the ring's outer edge moves toward the hat: away from the inboard pad, into the outboard
    h = hot["rows"][0]["faces"]
    assert h["in"]["cop_r_mm"] < _faces(cold, 0)["in"]["cop_r_mm"]
    assert h["out"]["cop_r_mm"] > _faces(cold, 0)["out"]["cop_r_mm"]
    for row in hot["rows"]:
        assert max(row["balance"].values()) < 1e-8


def test_half_model_within_a_percent_where_it_holds_and_not_with_fingers(floating):
    ring = replace(floating, rotor=replace(floating.rotor, mount="ring_clamp", hat=None))
    fixed = replace(ring, caliper=CaliperGeometry("fixed"))
    d_fixed = lp.half_differences(lp.solve_case(fixed, "full", [1.0], [0.0, 0.4]),
                                  lp.solve_case(fixed, "half", [1.0], [0.0, 0.4]))
    d_fingers = lp.half_differences(lp.solve_case(ring, "full", [1.0], [0.4]),
                                    lp.solve_case(ring, "half", [1.0], [0.4]))
    worst = lambda d: max(v for row in d for f in ("in", "out") for v in row[f].values())  # noqa: E731
    # (floor: 1 %) the full ring is its own mirror image through the
    # mid-plane, so each half is the half model's mesh and the two agree to the
    # solver's tolerance
    assert worst(d_fixed) < 1e-7
    assert worst(d_fingers) > 0.05


def test_coverage_convergence_reports_rates_and_estimates():
    out = lp.coverage_convergence(levels=(0.5, 0.75, 1.0), mus=(0.0,))
    assert [r["level"] for r in out["runs"]] == [0.5, 0.75, 1.0]
    assert out["runs"][0]["dofs"] < out["runs"][-1]["dofs"]
    for key in ("coverage_mu0_in", "coverage_mu0_out"):
        e = out["estimate"][key]
        assert len(e["values"]) == 3 and all(0 < v <= 1 for v in e["values"])
        assert "rate" in e


def test_richardson_with_uneven_ratios_recovers_a_known_rate():
    h = [1.0, 2 / 3, 0.5, 1 / 3]
    f = [0.6 + 0.1 * x ** 1.3 for x in h]
    ratios = [a / b for a, b in zip(h[:-1], h[1:])]
    e = richardson(f, ratios)
    assert e["rate"] == pytest.approx(1.3, rel=1e-6)
    assert e["estimate"] == pytest.approx(0.6, rel=1e-9)
    assert richardson([0.7, 0.6, 0.65, 0.6], ratios)["estimate"] is None


def test_the_docs_snippet_runs(capsys):
    """The snippet of docs/load_path.md, run as written (an 8 mm floating brake)."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "load_path.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S)[1]
    exec(compile(code, "docs/load_path.md", "exec"), {})
    lines = capsys.readouterr().out.strip().splitlines()
    assert [s.split()[0] for s in lines[:2]] == ["in", "out"]
    assert lines[2] == "True True True"
