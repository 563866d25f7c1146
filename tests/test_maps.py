"""Friction and wear laws per node: measured maps (CSV tables), closed forms, and the
per-node calls of the existing laws."""
import importlib.resources
import re

import numpy as np
import pytest

from brakewear.errors import InputError, LawError, MapError
from brakewear.laws.base import FrictionLaw, WearLaw
from brakewear.laws.maps import (
    EXAMPLE_MAP,
    FrictionMap,
    MildSevereWear,
    NodeFrictionLaw,
    NodeWearLaw,
    StribeckFriction,
    TableMap,
    WearMap,
    example_map,
    read_map,
)
from studyload import load_study

RNG = np.random.default_rng(7)
#: nodes of a contact: pressures (Pa, with tension and lift-off), speeds (m/s), T (K)
P = np.array([-2e5, 0.0, 3e5, 1.2e6, 4.7e6, 7.9e6])
V = np.array([2.0, 5.5, 11.0, 17.0, 23.0, 29.0])
T = np.array([300.0, 350.0, 420.0, 500.0, 610.0, 700.0])


def _csv(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def _grid_csv(f, ps=(0.5, 2.0, 8.0), vs=(1.0, 10.0, 30.0), ts=(20.0, 250.0, 500.0),
              col="mu", p_unit=("MPa", 1e6)):
    """A full-grid CSV (p in ``p_unit``, v_m_s, T_C) of ``f(p Pa, v m/s, T K)``."""
    name, scale = p_unit
    rows = ["# source: test data", f"p_{name},v_m_s,T_C,{col}"]
    rows += [f"{p * 1e6 / scale!r},{v!r},{t!r},{f(p * 1e6, v, t + 273.15)!r}"
             for t in ts for v in vs for p in ps]
    return "\n".join(rows) + "\n"


# ---------------------------------------------------------------- the existing laws --

def test_existing_laws_answer_per_node_with_their_own_numbers():
    mu = FrictionLaw(0.4)
    assert not mu.needs_temperature
    np.testing.assert_array_equal(mu.mu_at(P, V), np.full(P.shape, 0.4))
    fade = FrictionLaw(0.42, slope=-4e-4, T_ref=623.15, mu_min=0.2)
    assert fade.needs_temperature
    np.testing.assert_array_equal(fade.mu_at(P, V, T), fade.mu(T))
    assert fade.mu_at(P, V).shape == P.shape          # T None: mu0 at every node

    k = WearLaw(5e-15)
    assert not k.needs_temperature and (k.a, k.b) == (1.0, 1.0)
    np.testing.assert_array_equal(k.coefficient_at(P, V), np.full(P.shape, 5e-15))
    np.testing.assert_array_equal(k.rate(P, V), 5e-15 * np.clip(P, 0, None) * V)
    hot = WearLaw(5e-15, T_threshold=503.15, activation_energy=8e4)
    assert hot.needs_temperature
    np.testing.assert_array_equal(hot.coefficient_at(P, V, T), hot.coefficient(T))
    # one node's speed broadcast against the nodes' pressures
    assert hot.coefficient_at(P[:, None], 3.0, T[None, :]).shape == (6, 6)


def test_a_layered_rotor_law_gives_the_coefficient_its_rate_uses():
    from brakewear.cleaning.corrosion import LayeredWearLaw

    law = LayeredWearLaw(2e-14, factor=np.array([1.0, 1.0, 0.05, 0.05, 1.0, 0.05]))
    k = law.coefficient_at(P, V)
    np.testing.assert_array_equal(k, 2e-14 * law.factor)
    np.testing.assert_allclose(law.rate(P, V), k * np.clip(P, 0, None) * V, rtol=1e-15)


@pytest.mark.parametrize("law", [FrictionLaw(0.4), WearLaw(5e-15)])
def test_existing_laws_refuse_a_negative_speed(law):
    call = law.mu_at if isinstance(law, FrictionLaw) else law.coefficient_at
    with pytest.raises(InputError, match=r"sliding speed -2\.0 m/s"):
        call(P, -V)


def test_every_law_follows_the_protocol():
    mu_table = TableMap(("v",), ((1.0, 30.0),), np.array([0.4, 0.38]), "mu")
    k_table = TableMap(("p",), ((1e6,),), np.array([5e-15]), "k")
    for law in (FrictionLaw(0.4), FrictionMap(mu_table), StribeckFriction(0.38, 0.45, 0.5)):
        assert isinstance(law, NodeFrictionLaw), law
        assert law.mu_at(P, V, T).shape == P.shape
    for law in (WearLaw(5e-15), WearMap(k_table), MildSevereWear(5e-15, 5e-14, 1e7)):
        assert isinstance(law, NodeWearLaw), law
        assert law.coefficient_at(P, V, T).shape == law.rate(P, V, T).shape == P.shape


# --------------------------------------------------------------------------- tables --

def test_a_constant_map_gives_the_constant_laws_numbers_bit_for_bit():
    one_point = TableMap(("p", "v", "T"), ((1e6,), (10.0,), (400.0,)),
                         np.full((1, 1, 1), 5e-15), "k")
    full_grid = TableMap(("T", "p"), ((300.0, 450.0, 700.0), (0.5e6, 3e6)),
                         np.full((3, 2), 5e-15), "k")
    for table in (one_point, full_grid):
        wear = WearMap(table)
        np.testing.assert_array_equal(
            wear.coefficient_at(P, V, T), WearLaw(5e-15).coefficient_at(P, V)
        )
        np.testing.assert_array_equal(wear.rate(P, V, T), WearLaw(5e-15).rate(P, V))
    mu = TableMap(("v", "p"), ((1.0, 7.0, 30.0), (1e5, 1e7)), np.full((3, 2), 0.4), "mu")
    np.testing.assert_array_equal(FrictionMap(mu).mu_at(P, V), FrictionLaw(0.4).mu_at(P, V))


def test_interpolation_reproduces_multilinear_data_between_the_grid_points(tmp_path):
    def f(p, v, t):            # linear in each axis (products across axes are allowed)
        return 0.3 * (1 + 0.04 * p / 1e6) * (1 - 0.01 * v) * (1 + 5e-4 * (t - 293.15))

    path = _csv(tmp_path, "linear.csv", _grid_csv(f, ps=(0.5, 1.5, 4.0, 8.0),
                                                 vs=(1.0, 4.0, 30.0), ts=(20.0, 180.0, 500.0)))
    law = FrictionMap(read_map(path, "mu"))
    p, v, t = (
        RNG.uniform(0.5e6, 8e6, 200),
        RNG.uniform(1, 30, 200),
        RNG.uniform(293.15, 773.15, 200),
    )
    exact = f(p, v, t)
    err = np.abs(law.mu_at(p, v, t) - exact) / exact
    assert err.max() < 1e-12, err.max()


def test_outside_the_grid_clamp_takes_the_edge_and_error_names_value_and_range(tmp_path):
    path = _csv(tmp_path, "edge.csv", "p_MPa,v_km_h,mu\n1,36,0.40\n8,36,0.35\n1,108,0.38\n"
                                      "8,108,0.33\n")
    clamp = FrictionMap(read_map(path, "mu"))
    mu = clamp.mu_at([0.2e6, 20e6, 20e6], [5.0, 10.0, 100.0])
    np.testing.assert_allclose(mu, [0.40, 0.35, 0.33], rtol=1e-12)
    strict = FrictionMap(read_map(path, "mu", outside="error"))
    with pytest.raises(MapError) as e:
        strict.mu_at([4e6, 12e6], [15.0, 20.0])
    assert all(s in str(e.value) for s in ("mu map", "edge.csv", "p = 12 MPa", "1 to 8 MPa"))
    with pytest.raises(MapError, match=r"v = 180 km/h .* 36 to 108 km/h"):
        strict.mu_at([4e6, 4e6], [15.0, 50.0])
    # speeds converted from km/h sit on the edge within round-off; unloaded nodes pass
    np.testing.assert_allclose(strict.mu_at([1e6, 0.0, -1e5], [10.0, 99.0, 0.0]),
                               [0.40, 0.38, 0.40], rtol=1e-12)


def test_a_map_over_temperature_needs_it(tmp_path):
    law = WearMap(read_map(_csv(tmp_path, "k.csv", _grid_csv(lambda p, v, t: 1e-14,
                                                             col="k_m2_N")), "k"))
    assert law.needs_temperature
    with pytest.raises(MapError, match="varies with temperature"):
        law.rate(P, V)


def test_units_and_both_value_columns_of_one_file(tmp_path):
    path = _csv(tmp_path, "units.csv", "T_K,p_bar,v_km_h,mu,k_mm3_Nm\n"
                                       "300,10,36,0.4,5e-6\n600,10,36,0.3,4e-5\n")
    mu, k = read_map(path, "mu"), read_map(path, "k")
    assert mu.axes == ("T", "p", "v") and mu.units == ("K", "bar", "km/h")
    assert mu.grid[1] == (1e6,) and mu.grid[2] == pytest.approx((10.0,), rel=1e-15)
    np.testing.assert_allclose(k.values.ravel(), [5e-15, 4e-14], rtol=1e-15)
    np.testing.assert_allclose(WearMap(k).rate(2e6, 3.0, 450.0), 0.5 * (5e-15 + 4e-14) * 6e6,
                               rtol=1e-12)


HEAD = "# source: test\np_MPa,v_m_s,mu\n"
#: name -> (file text, row, column, a fragment of the message)
BAD = {
    "unknown_column": ("# source: test\np_MPa,speed,mu\n1,2,0.4\n", 2, "speed",
                       "unknown column; allowed: axis columns p_Pa"),
    "unknown_unit": ("p_psi,v_m_s,mu\n1,2,0.4\n", 1, "p_psi",
                     "unknown unit 'psi' for p; allowed: p_Pa, p_kPa, p_MPa, p_bar"),
    "missing_value": ("p_MPa,v_m_s,k_m2_N\n1,2,1e-14\n", 1, "mu", "missing"),
    "no_axis": ("mu\n0.4\n", 1, "mu", "no axis column"),
    "two_pressures": ("p_MPa,p_bar,mu\n1,10,0.4\n", 1, "p_bar", "a second p column"),
    "not_a_number": (HEAD + "1,2,0.4\n1,x3,0.4\n", 4, "v_m_s", "'x3' is not a number"),
    "empty_cell": (HEAD + "1,,0.4\n", 3, "v_m_s", "'' is not a number"),
    "nan": (HEAD + "1,2,nan\n", 3, "mu", "need a finite number"),
    "inf": (HEAD + "1,inf,0.4\n", 3, "v_m_s", "need a finite number"),
    "negative_mu": (HEAD + "1,2,-0.1\n", 3, "mu", "-0.1 is not allowed; allowed: 0 to 2"),
    "mu_percent": (HEAD + "1,2,40\n", 3, "mu", "is implausible; allowed: 0 to 2"),
    "negative_k": ("p_MPa,v_m_s,k_m2_N\n1,2,-1e-14\n", 2, "k_m2_N", "is not allowed"),
    "k_in_mm3_Nm": ("p_MPa,v_m_s,k_m2_N\n1,2,5e-6\n", 2, "k_m2_N", "is implausible"),
    "negative_speed": (HEAD + "1,-2,0.4\n", 3, "v_m_s", "-2 m/s is not allowed"),
    "pa_under_mpa": (HEAD + "500000,2,0.4\n8000000,2,0.4\n", 3, "p_MPa",
                     "500000 MPa is implausible; allowed: 0 to 1000 MPa"),
    "mpa_under_pa": ("p_Pa,v_m_s,mu\n0.5,2,0.4\n8,2,0.4\n", 3, "p_Pa",
                     "largest pressure is 8 Pa"),
    "celsius_under_k": ("T_K,v_m_s,mu\n20,2,0.4\n", 2, "T_K", "20 K is implausible"),
    "fields": (HEAD + "1,2,0.4\n1,3\n", 4, "mu", "2 fields; the header has 3"),
    "duplicate": (HEAD + "1,2,0.4\n8,2,0.4\n1,2,0.41\n", 5, "p_MPa, v_m_s",
                  "p_MPa = 1, v_m_s = 2 is also on row 3"),
    "missing_point": (HEAD + "1,2,0.4\n8,2,0.4\n1,5,0.4\n", 3, "p_MPa, v_m_s",
                      "no row for the grid point p_MPa = 8, v_m_s = 5"),
    "no_rows": ("# source: test\np_MPa,mu\n", 2, "p_MPa, mu", "no rows"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_map_is_refused_naming_file_row_and_column(tmp_path, case):
    text, row, column, fragment = BAD[case]
    quantity = "k" if case in ("negative_k", "k_in_mm3_Nm") else "mu"
    path = _csv(tmp_path, f"bad_{case}.csv", text)
    with pytest.raises(MapError) as e:
        read_map(path, quantity)
    msg = str(e.value)
    assert f"bad_{case}.csv" in msg, msg
    assert re.search(rf"\brows? {row}\b", msg), msg
    assert f"column {column}" in msg or f"column {column!r}" in msg or \
        f"columns {column}" in msg, msg
    assert fragment in msg, msg


def test_a_map_file_that_cannot_be_read_is_named(tmp_path):
    with pytest.raises(MapError, match="nowhere.csv: cannot read"):
        read_map(tmp_path / "nowhere.csv", "mu")


def test_a_table_built_in_python_is_checked():
    with pytest.raises(MapError, match=r"axes = \('p', 'x'\)"):
        TableMap(("p", "x"), ((1e6,), (1.0,)), np.ones((1, 1)), "mu")
    with pytest.raises(MapError, match="strictly increasing"):
        TableMap(("v",), ((3.0, 1.0),), np.array([0.4, 0.4]), "mu")
    with pytest.raises(MapError, match=r"values have shape \(3,\)"):
        TableMap(("v",), ((1.0, 3.0),), np.array([0.4, 0.4, 0.4]), "mu")
    with pytest.raises(MapError, match="outside = 'extrapolate'"):
        TableMap(("v",), ((1.0,),), np.array([0.4]), "mu", outside="extrapolate")
    with pytest.raises(MapError, match="needs a TableMap of k"):
        WearMap(TableMap(("v",), ((1.0,),), np.array([0.4]), "mu"))


def test_fingerprints_hold_the_numbers_not_the_file(tmp_path):
    from brakewear.wear import fingerprint

    def f(p, v, t):
        return 0.4 - 1e-3 * v

    a = _csv(tmp_path, "a.csv", _grid_csv(f))
    b = _csv(tmp_path, "b.csv", _grid_csv(f, p_unit=("bar", 1e5)))   # the same in bar
    fa, fa2, fb = (fingerprint(mu=FrictionMap(read_map(x, "mu"))) for x in (a, a, b))
    assert fa == fa2 and fa == fb
    changed = _csv(tmp_path, "c.csv", _grid_csv(lambda p, v, t: f(p, v, t) + 1e-6 * (p > 4e6)))
    assert fingerprint(mu=FrictionMap(read_map(changed, "mu"))) != fa
    assert fingerprint(mu=FrictionMap(read_map(a, "mu", outside="error"))) != fa
    laws = (StribeckFriction(0.38, 0.45, 0.5), MildSevereWear(5e-15, 5e-14, 523.15, "T"))
    assert fingerprint(laws=laws) == fingerprint(laws=laws)


# --------------------------------------------------------------------- closed forms --

def test_stribeck_limits():
    law = StribeckFriction(mu_kinetic=0.38, mu_static=0.46, v_stribeck=0.8)
    assert law.mu_at(0.0, 0.0)[()] == 0.46
    assert law.mu_at(1e6, 100 * 0.8)[()] == 0.38
    mid = law.mu_at(1e6, 0.8)
    assert mid == pytest.approx(0.38 + 0.08 / np.e, rel=1e-12)
    mu = law.mu_at(P, np.linspace(0, 5, P.size))
    assert np.all(np.diff(mu) < 0)                     # falls with speed


@pytest.mark.parametrize("kwargs,field", [
    ({"mu_kinetic": -0.1, "mu_static": 0.4, "v_stribeck": 1.0}, "mu_kinetic = -0.1"),
    ({"mu_kinetic": 0.4, "mu_static": 45.0, "v_stribeck": 1.0}, "mu_static = 45.0"),
    ({"mu_kinetic": 0.4, "mu_static": 0.5, "v_stribeck": 0.0}, "v_stribeck = 0.0 m/s"),
    ({"mu_kinetic": 0.4, "mu_static": 0.5, "v_stribeck": 1.0, "delta": float("nan")},
     "delta = nan"),
])
def test_stribeck_refuses_bad_parameters(kwargs, field):
    with pytest.raises(LawError, match=rf"StribeckFriction: {re.escape(field)} is not "
                                       r"allowed; need"):
        StribeckFriction(**kwargs)


def test_mild_severe_switch_on_pv():
    km, ks, pv0 = 5e-15, 6e-14, 1e7
    sharp = MildSevereWear(km, ks, pv0, on="pv", width=0.0)
    p = np.array([1e6, 1e6, 1e6])
    k = sharp.coefficient_at(p, [9.99, 10.0, 10.01])
    np.testing.assert_array_equal(k, [km, 0.5 * (km + ks), ks])
    assert not sharp.needs_temperature
    smooth = MildSevereWear(km, ks, pv0)             # width: 5 % of the threshold
    assert smooth.width == pytest.approx(0.05 * pv0, rel=1e-15)
    k = smooth.coefficient_at(p, [0.1, 10.0, 20.0])
    assert k[0] == pytest.approx(km, rel=1e-7) and k[2] == pytest.approx(ks, rel=1e-7)
    assert k[1] == pytest.approx(0.5 * (km + ks), rel=1e-12)
    np.testing.assert_allclose(smooth.rate(p, 10.0), k[1] * 1e7, rtol=1e-12)
    np.testing.assert_array_equal(smooth.rate(-p, 10.0), 0.0)


def test_mild_severe_switch_on_temperature():
    law = MildSevereWear(5e-15, 5e-14, 523.15, on="T", width=5.0)
    assert law.needs_temperature
    k = law.coefficient_at(1e6, 10.0, [373.15, 523.15, 673.15])
    np.testing.assert_allclose(k, [5e-15, 2.75e-14, 5e-14], rtol=1e-6)
    with pytest.raises(LawError, match="give T"):
        law.coefficient_at(1e6, 10.0)


@pytest.mark.parametrize("args,kwargs,fragment", [
    ((0.0, 5e-14, 1e7), {}, "k_mild = 0.0 m^2/N is not allowed"),
    ((5e-14, 5e-15, 1e7), {}, "k_severe = 5e-15 m^2/N is not allowed"),
    ((5e-15, 5e-3, 1e7), {}, "k_severe = 0.005"),
    ((5e-15, 5e-14, 1e7), {"on": "v"}, "on = 'v' is not allowed"),
    ((5e-15, 5e-14, 25.0), {"on": "T"}, "threshold = 25.0 K"),
    ((5e-15, 5e-14, 1e7), {"width": 5e6}, "width = 5000000.0 W/m^2"),
    ((5e-15, 5e-14, 1e7), {"width": -1.0}, "width = -1.0 W/m^2"),
])
def test_mild_severe_refuses_bad_parameters(args, kwargs, fragment):
    with pytest.raises(LawError, match=re.escape(f"MildSevereWear: {fragment}")):
        MildSevereWear(*args, **kwargs)


# ------------------------------------------------------------------- the example map --

def test_the_illustrative_map_ships_with_the_package():
    res = importlib.resources.files("brakewear").joinpath(EXAMPLE_MAP)
    assert res.is_file()
    assert "ILLUSTRATIVE" in res.read_text().splitlines()[0]
    mu, k = example_map("mu"), example_map("k")
    assert mu.axes == k.axes == ("p", "v", "T") and mu.values.shape == (5, 4, 5)
    assert 0.33 <= mu.values.min() and mu.values.max() <= 0.45
    assert 4e-15 <= k.values.min() and k.values.max() <= 2e-13
    law_mu, law_k = FrictionMap(mu), WearMap(k)
    C = 273.15
    # mu falls slightly with speed, fades above 350 C; k rises steeply above 250 C
    assert law_mu.mu_at(2e6, 30.0, C + 100) < law_mu.mu_at(2e6, 1.0, C + 100)
    assert law_mu.mu_at(2e6, 10.0, C + 500) < 0.9 * law_mu.mu_at(2e6, 10.0, C + 300)
    assert law_k.coefficient_at(2e6, 10.0, C + 500) > 5 * law_k.coefficient_at(2e6, 10.0, C + 250)


def test_the_law_maps_study_returns_its_numbers(tmp_path):
    res = load_study("law_maps").main(out=tmp_path)
    assert (tmp_path / "laws_example_map.png").stat().st_size > 10_000
    assert (tmp_path / "laws_example_map.csv").read_text().startswith("T_C,")
    hot, cold = res["T_C"][1], res["T_C"][0]
    assert hot > cold
    mu_cold, mu_hot = np.array(res["mu"][0]), np.array(res["mu"][1])
    k_cold, k_hot = np.array(res["k_m2_N"][0]), np.array(res["k_m2_N"][1])
    assert (mu_hot < mu_cold).all() and (k_hot > 3 * k_cold).all()
