"""The thermal-variants study on small settings: every variant balances its heat,
the hot maps wear the pad more, and the geometry update follows the gap offset."""
from studyload import load_study


def test_thermal_variants_study(tmp_path):
    r = load_study("thermal_variants").main(size=1.2e-2, duration=30.0, steps=3, repeats=1,
                                            out=str(tmp_path))
    c = r["cases"]
    assert (tmp_path / "data" / "thermal_variants.json").exists()
    for name, row in c.items():
        if name != "no thermal, mu 0.4":
            assert row["heat_balance_error_max"] < 1e-8, name
    gap, geo = c["thermal, mu 0.4"], c["thermal, geometry update, mu 0.4"]
    assert abs(geo["pad_T_max_C"] - gap["pad_T_max_C"]) < 0.02 * (gap["pad_T_max_C"] - 20.0)
    assert c["no thermal, mu 0.4"]["pad_wear_max_um"] > 0
