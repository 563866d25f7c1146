"""studies/mesh_convergence.py: the Richardson arithmetic on known sequences, a smoke
run on tiny meshes, and (slow) the observed rate of the pad wear on three meshes."""
import json

import numpy as np
import pytest

from brakewear.mesh.convergence import (
    estimate,
    field_richardson,
    fitted_rate,
    relative_l2,
    richardson,
)
from studyload import load_study

mc = load_study("mesh_convergence")


@pytest.mark.parametrize("levels", [(1.0, 1.5, 2.25), (2.0, 3.0, 4.0), (4.0, 6.0, 9.0)])
@pytest.mark.parametrize("p", [1.0, 2.0])
def test_richardson_recovers_rate_and_limit_of_f0_plus_c_h_to_the_p(levels, p):
    h = 1.0 / np.array(levels)
    f = 3.0 + 0.7 * h ** p
    ratios = tuple(b / a for a, b in zip(levels[:-1], levels[1:]))
    res = richardson(tuple(f), ratios)
    assert res["rate"] == pytest.approx(p, rel=1e-9)
    assert res["estimate"] == pytest.approx(3.0, rel=1e-12)
    assert res["asymptotic"]
    assert np.allclose(res["errors"], f / 3.0 - 1.0, rtol=1e-9, atol=1e-14)


def test_a_sequence_that_changes_direction_has_no_estimate():
    res = richardson((1.0, 1.2, 1.1), (1.5, 1.5))
    assert np.isnan(res["rate"]) and res["estimate"] is None and not res["asymptotic"]
    assert res["errors"] == [None] * 3


def test_field_richardson_recovers_the_limit_field():
    x = np.linspace(0.0, 1.0, 50)
    f0, shape = 1.0 + x, np.sin(3 * x)
    h = 1.0 / np.array([2.0, 3.0, 4.5])
    fields = [f0 + 0.5 * hk ** 2 * shape for hk in h]
    res = field_richardson(fields, np.full(x.size, 0.02), (1.5, 1.5))
    assert res["rate"] == pytest.approx(2.0, rel=1e-9)
    assert np.allclose(res["field"], f0, rtol=1e-12)
    norm = np.sqrt((0.02 * f0 ** 2).sum())
    expect = [np.sqrt((0.02 * (0.5 * hk ** 2 * shape) ** 2).sum()) / norm for hk in h]
    assert np.allclose(res["errors"], expect, rtol=1e-9)


def test_levels_scale_size_and_layers_together():
    a, b = mc.level_settings(4), mc.level_settings(6)
    assert a["size"] / b["size"] == pytest.approx(1.5)
    assert (a["backplate_layers"], b["backplate_layers"]) == (4, 6)
    assert a["friction_layers"] == a["rotor_layers"] == 4


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    out = tmp_path_factory.mktemp("mc")
    res = mc.main(levels=(1.0, 1.5, 2.0), steps=2, t_mid=150.0, duration=300.0,
                  orders=(1, 2), candidates=({"size": 1.5e-2},), out=out)
    return res, out


def test_tiny_study_has_its_keys_and_files(tiny):
    res, out = tiny
    assert res["case"]["levels"] == [1.0, 1.5, 2.0] and res["case"]["steps"] == 2
    p1 = res["orders"]["P1"]
    assert len(p1["runs"]) == 3 and len(p1["candidates"]) == 1
    for when in ("end", "mid"):
        assert set(p1[when]) == set(mc.SCALARS) | set(mc.FIELDS)
        for q in mc.SCALARS:
            assert {"rate", "estimate", "errors", "asymptotic"} <= set(p1[when][q])
    for r in p1["runs"] + p1["candidates"]:
        assert r["dofs"] > 0 and r["wall_s"] > 0 and r["cpu_s"] > 0 and r["contact_solves"] >= 2
        assert r["end"]["pad_wear_max"] > r["mid"]["pad_wear_max"] > 0
        assert r["end"]["time_s"] == pytest.approx(300.0)
        assert set(r["errors"]) == {"end", "mid"}
    assert p1["runs"][0]["dofs"] < p1["runs"][1]["dofs"] < p1["runs"][2]["dofs"]
    data = json.loads((out / "data" / "mesh_convergence.json").read_text())
    assert data["orders"]["P1"]["runs"][-1]["end"]["pad_wear"]       # the finest keeps its field
    assert "pad_wear" not in data["orders"]["P1"]["runs"][0]["end"]
    assert (out / "figures" / "mesh_convergence.png").stat().st_size > 10_000
    assert "| n=1: 18 mm, 1/1/1 |" in mc.table(res)


def test_a_refused_order_is_skipped_with_a_note(tiny):
    res, _ = tiny
    assert "P2" in res["orders"] or any(n.startswith("P2 skipped") for n in res["notes"])


def test_levels_must_be_three_coarse_to_fine():
    with pytest.raises(ValueError, match="three or more"):
        mc.main(levels=(2, 1, 3), out=None)


@pytest.mark.slow
def test_pad_wear_converges_on_three_p1_meshes():
    # the default scene's physics for 1200 s (16 steps of 75 s) on levels 4, 6, 9:
    # 4.5, 3, 2 mm with 4, 6, 9 layers (docs/performance.md: rate 1.27 and the
    # finest mesh about 3 % off at 1200 s)
    res = mc.main(levels=(4, 6, 9), steps=16, duration=1200.0, t_mid=None, out=None)
    est = res["orders"]["P1"]["end"]["pad_wear"]
    assert est["rate"] > 0.8, f"observed pad wear rate {est['rate']:.3g}"
    assert est["errors"][-1] < 0.05, f"finest pad wear error estimate {est['errors'][-1]:.3%}"
    assert est["errors"][0] > est["errors"][1] > est["errors"][2]


def test_estimate_keeps_a_settled_rate_and_withdraws_an_unsettled_one():
    levels = (2.0, 3.0, 4.0, 6.0)
    ratios = tuple(b / a for a, b in zip(levels[:-1], levels[1:]))
    f = [3.0 + 0.7 / n ** 1.5 for n in levels]
    est = estimate(f, ratios)
    assert est["rates"] == pytest.approx([1.5, 1.5], rel=1e-9)
    assert est["estimate"] == pytest.approx(3.0, rel=1e-12) and est["asymptotic"]
    # the triple before the finest changes direction: no estimate, however good the last
    est = estimate([3.1, 3.3, 3.2, 3.15], ratios)
    assert est["estimate"] is None and est["errors"] == [None] * 4 and not est["asymptotic"]


def test_fitted_rate_and_relative_l2():
    h = np.array([0.1, 0.05, 0.025])
    assert fitted_rate(h, 3.0 * h ** 2) == pytest.approx(2.0, rel=1e-12)
    w = np.array([1.0, 2.0, 1.0])
    ref = np.array([1.0, 2.0, 3.0])
    assert relative_l2(1.01 * ref, ref, w) == pytest.approx(0.01, rel=1e-12)


def test_the_docstring_examples_run():
    import doctest

    import brakewear.mesh.convergence as conv

    res = doctest.testmod(conv)
    assert res.attempted >= 2 and res.failed == 0
