"""The contact conductance of rough faces: the law, its fit against fresh half-space solves,
its limits, and the scene keys that select it."""
import numpy as np
import pytest

from brakewear import analytic as an
from brakewear.errors import RoughnessError, SceneError
from brakewear.rough import RoughConductance, halfspace_conductance, self_affine
from brakewear.rough.conductance import HALFSPACE_FIT
from brakewear.scene import load_scene, scene_file, scene_from_dict
from studyload import load_study

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

ES = 3e9


def test_halfspace_law_is_linear_in_pressure_and_barbers_analogy():
    rc = RoughConductance(3e-6, None, ES, 4.0)
    p = np.array([0.0, 1e5, 1e6, 2e6])
    h = rc.conductance(p)
    assert h[0] == 0.0 and np.all(np.diff(h) > 0)
    assert h[3] == pytest.approx(2 * h[2], rel=1e-14)
    assert h[2] == pytest.approx(4.0 * 1e6 / (HALFSPACE_FIT["gamma"] * 3e-6 * ES), rel=1e-14)
    assert h[2] == pytest.approx(an.barber_conductance(rc.normal_stiffness(1e6), ES, 4.0))
    assert RoughConductance(6e-6, None, ES, 4.0).conductance(1e6) == pytest.approx(h[2] / 2)


def test_mikic_law_and_the_composite_of_two_faces():
    rc = RoughConductance.of_faces((3e-6, 0.2), (4e-6, 0.15), ES, 2.0, 50.0, "mikic")
    assert rc.rms_height == pytest.approx(5e-6) and rc.rms_slope == pytest.approx(0.25)
    assert rc.kappa == pytest.approx(2 * 2.0 * 50.0 / 52.0)
    assert rc.conductance(1e6) == pytest.approx(an.mikic_elastic_conductance(
        1e6, ES, 5e-6, 0.25 / np.sqrt(np.pi), rc.kappa), rel=1e-14)
    # the pad's low conductivity bounds the pair's: kappa_s < 2 kappa_pad
    assert rc.kappa < 2 * 2.0


def test_the_fit_holds_on_a_surface_it_was_not_fitted_on():
    """A fresh surface (another seed and Hurst exponent): the solves' k_n sigma / p lies
    within 25 % of 1 / gamma over the fit's range (the documented spread of the fit is
    -15 % to +26 %), and Barber's h_c follows from k_n."""
    t = self_affine(128, 1e-3, 0.65, rms_slope=0.1, rolloff=0.25e-3, cutoff=4e-3 / 128,
                    seed=17)
    lo, hi = HALFSPACE_FIT["range"]
    x = np.array([lo, np.sqrt(lo * hi), hi])
    r = halfspace_conductance(t, ES * t.rms_slope() * x, ES, kappa=2.0)
    ratio = r["k_n"] * t.rms_height() / r["p"] * HALFSPACE_FIT["gamma"]
    assert np.all(np.abs(ratio - 1) < 0.25), ratio
    assert np.allclose(r["h_c"], 2.0 * r["k_n"] / ES)
    assert np.all(np.diff(r["contact_fraction"]) > 0) and r["contact_fraction"][-1] < 0.2


@pytest.mark.parametrize("kw,match", [
    ({"rms_height": 0.0}, "rms_height"), ({"rms_slope": 3.0}, "small slopes"),
    ({"law": "cooper"}, "law"), ({"law": "mikic", "rms_slope": None}, "needs rms_slope"),
    ({"kappa": -1.0}, "kappa"), ({"modulus": 0.0}, "modulus")])
def test_bad_conductance_input_is_refused(kw, match):
    args = {"rms_height": 3e-6, "rms_slope": 0.2, "modulus": ES, "kappa": 3.0, **kw}
    with pytest.raises(RoughnessError, match=match):
        RoughConductance(**args)
    rc = RoughConductance(3e-6, 0.2, ES, 3.0)
    with pytest.raises(RoughnessError, match="pressure"):
        rc.conductance(-1.0)
    t = self_affine(32, 1e-3, 0.8, rms_height=1e-6, cutoff=1e-3 / 8)
    with pytest.raises(RoughnessError, match="increasing"):
        halfspace_conductance(t, [2e6, 1e6], ES)


def _rough_dict():
    return tomllib.loads(scene_file("thermal_rough").read_text())


def _rough_thermal(**thermal):
    d = _rough_dict()
    d["thermal"] = {**{k: v for k, v in d["thermal"].items()
                       if k not in thermal or thermal[k] is not None},
                    **{k: v for k, v in thermal.items() if v is not None}}
    for k, v in thermal.items():
        if v is None:
            d["thermal"].pop(k, None)
    return scene_from_dict(d, source="thermal_rough.toml")


def test_the_rough_scene_gives_the_law_at_the_nominal_pressure():
    s = load_scene("thermal_rough")
    t = s.thermal
    assert t.rough and t.pad_rms_height == pytest.approx(3e-6)   # 0.003 mm
    g = s.geometry
    p = s.line_pressure * g.clamp_area / g.pad.area
    law = t.rough_law(g)
    pad, rotor = g.pad.friction_material, g.rotor.material
    assert law.modulus == pytest.approx(an.effective_modulus(
        pad.elastic.E_normal, pad.elastic.nu_normal, rotor.elastic.E_normal,
        rotor.elastic.nu_normal))
    h = t.conductance(g, s.line_pressure)
    assert h == pytest.approx(float(law.conductance(p)), rel=1e-14)
    assert 100 < h < 2000, h          # far below the constant default of 1e5 W/m^2 K
    mikic = _rough_thermal(conductance_law="mikic").thermal.conductance(g, s.line_pressure)
    assert 1.0 < mikic / h < 2.0
    # the packaged thermal scene keeps its constant
    plain = load_scene("thermal")
    assert plain.thermal.conductance(plain.geometry, plain.line_pressure) == 1e5


@pytest.mark.parametrize("thermal,match", [
    ({"pad_rms_height": None}, r"thermal.pad_rms_height: missing"),
    ({"conductance_law": "mikic", "rotor_rms_slope": None},
     r"thermal.rotor_rms_slope: missing.*'mikic'"),
    ({"pad_rms_height": 2.0}, r"thermal.pad_rms_height: 2.0 mm is not allowed.*<= 1 mm"),
    ({"pad_rms_height": -0.001}, r"thermal.pad_rms_height"),
    ({"conductance_law": "cooper"}, r"thermal.conductance_law: 'cooper' is not allowed"),
    ({"contact_conductance": "smooth"}, r"thermal.contact_conductance: 'smooth' is not "
                                        r"allowed; allowed: 'rough'"),
    ({"contact_conductance": 1e5}, r"thermal.pad_rms_height: is used only with "
                                   r"contact_conductance = \"rough\""),
    ({"pad_rms_slope": 5.0}, r"thermal.pad_rms_slope: 5.0 is not allowed")])
def test_bad_rough_scene_keys_are_refused_by_name(thermal, match):
    with pytest.raises(SceneError, match=match):
        _rough_thermal(**thermal)


def test_rough_conductance_needs_an_elastic_rotor_and_no_schedule():
    d = _rough_dict()
    d["components"]["rotor"] = "rigid"
    with pytest.raises(SceneError, match="thermal.contact_conductance: 'rough'.*elastic rotor"):
        scene_from_dict(d)
    d = _rough_dict()
    for k in ("line_pressure", "omega", "duration"):
        d["environment"].pop(k)
    d["vehicle"] = {"mass": 1800.0, "front_share": 0.7, "tyre_radius": 320.0}
    d["schedule"] = {"stops": 2, "speed_from": 50.0, "deceleration": 1.5, "interval": 60.0}
    with pytest.raises(SceneError, match="thermal.contact_conductance: \"rough\" is evaluated "
                                         "at one nominal pressure.*give a number"):
        scene_from_dict(d)


def test_the_rough_conductance_makes_the_thermal_drag_run_away():
    """The documented consequence on a 12 mm mesh: with the rough faces' conductance the
    pad keeps its fixed share and its face passes T_max within seconds (the run stops,
    naming the pad), while the default constant keeps both faces together."""
    study = load_study("thermal_conductance")
    r = study.main(size=12e-3, duration=12.0, steps=4,
                   which=["rough faces, halfspace law", "1e+05 (default)"], write=False)
    rough, default = r["cases"]["rough faces, halfspace law"], r["cases"]["1e+05 (default)"]
    assert 100 < rough["h_c_W_m2K"] < 2000 and default["h_c_W_m2K"] == 1e5
    assert rough["stopped"] is not None and rough["stopped"]["body"] == "pad"
    assert rough["stopped"]["temperature_C"] > 900 and rough["stopped"]["time_s"] <= 12.0
    assert default["stopped"] is None and len(default["steps"]) == 4
    last = default["steps"][-1]
    assert abs(last["pad_T_max_C"] - last["rotor_T_max_C"]) < 0.2 * (last["rotor_T_max_C"] - 20)
    # the pad holds more of the heat with the weak exchange
    assert rough["steps"][0]["heat_pad_W"] > 2 * default["steps"][0]["heat_pad_W"]


def test_the_conductance_and_hertz_studies_on_small_settings(tmp_path):
    study = load_study("rough_conductance")
    r = study.main(n=128, fine=None, seeds=1, points=3, out_data=tmp_path, out_fig=tmp_path,
                   progress=None)
    assert r["gamma"] == pytest.approx(HALFSPACE_FIT["gamma"], rel=0.3)
    assert (tmp_path / "rough_conductance.png").stat().st_size > 0
    assert r["brake"]["rows"][1]["line_pressure_MPa"] == 1.0
    h = load_study("rough_hertz").main(grids=(64,), write=False)["rows"][0]
    assert abs(h["approach_error"]) < 1e-2 and abs(h["normal_stiffness_error"]) < 1e-2


def test_a_record_without_the_roughness_keys_resumes_as_before():
    """The new [thermal] keys default to None: a run's scene.json written without them
    reads the same as the scene now (resume compares the two records)."""
    from brakewear.scene.spec import first_difference
    now = load_scene("thermal").to_dict()
    before = {**now, "thermal": {k: v for k, v in now["thermal"].items() if k not in (
        "pad_rms_height", "rotor_rms_height", "pad_rms_slope", "rotor_rms_slope",
        "conductance_law")}}
    assert first_difference(before, now) is None
