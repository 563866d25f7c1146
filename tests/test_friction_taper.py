"""The friction-taper study on a coarse mesh with few steps: friction wears the pad
to a leading/trailing taper of the sign statics gives, mu = 0 leaves it symmetric,
and both runs conserve the Archard volume."""
import json

import pytest

from studyload import load_study

study = load_study("friction_taper")


@pytest.fixture(scope="module")
def res(tmp_path_factory):
    out = tmp_path_factory.mktemp("taper")
    # 10 mm (3.1k DOFs), 6 equal steps over the scene's hour: about 3 s with the figure
    return study.main(size=10.0, steps=6, mu_values=(0.0, 0.4), out=out), out


def test_the_leading_end_is_where_rotor_material_enters(res):
    r, _ = res
    # the default brake's rotor turns in +theta (the pair's drag), so rotor points
    # enter under the pad at its smaller-angle end
    assert r["leading_end"]["rotor_sense"] == 1
    assert r["leading_end"]["leading_edge_deg"] == pytest.approx(-27.5)


def test_friction_wears_the_leading_end_more(res):
    # Statics of the pad about the radial axis through its centre: the drag mu N acts
    # along the rotor's motion on the friction face (z = 0), the abutment holds the
    # pad at its backplate, a height `lever` above the face (10.5 to 16 mm), and the
    # piston pushes on the centre line.  The couple lever x mu N must be balanced by
    # the contact pressure's moment, so the centre of pressure moves by -lever mu
    # (against the motion: toward the leading end), the leading end carries more
    # pressure and, by Archard, wears more: lead - trail > 0, slope < 0.
    r, _ = res
    free, fric = r["runs"]["mu=0"], r["runs"]["mu=0.4"]
    assert fric["taper"] > 0.05, fric["taper"]
    assert fric["lead_minus_trail_um"] > 0 and fric["slope_um_per_deg"] < 0, fric
    # mu = 0: symmetric up to the mesh (its tetrahedra are not mirror-symmetric)
    assert abs(free["taper"]) < 0.15 * fric["taper"], (free["taper"], fric["taper"])
    assert abs(free["slope_um_per_deg"]) < 0.15 * abs(fric["slope_um_per_deg"])


def test_the_centre_of_pressure_shift_is_the_friction_couple(res):
    r, _ = res
    fric = r["runs"]["mu=0.4"]
    # the abutment's line of action lies in the backplate at first contact
    assert 10.5 < fric["lever_start_mm"] < 16.0, fric["lever_start_mm"]
    # moment balance: shift = -lever mu <cos theta>_p (the mu = 0 run removes the mesh's
    # own offset); 5 % of the shift leaves room for the piston footprint's facets
    assert fric["cop_shift_start_mm"] < 0
    assert fric["cop_shift_start_mm"] == pytest.approx(fric["statics_shift_mm"], rel=0.05), \
        (fric["cop_shift_start_mm"], fric["statics_shift_mm"])
    # running in: the worn taper takes load off the leading end, the centre of pressure
    # moves back and the abutment (held over the backplate's thickness) takes the couple
    assert abs(fric["cop_end_deg"]) < 0.5 * abs(fric["cop_start_deg"]), fric
    assert fric["lever_end_mm"] < 0.5 * fric["lever_start_mm"], fric


def test_worn_volumes_obey_archard(res):
    r, _ = res
    for key, run in r["runs"].items():
        for body in ("pad", "rotor"):
            V, arch = run[f"{body}_volume_m3"], run[f"{body}_archard_m3"]
            assert arch > 0, (key, body)
            assert abs(V - arch) <= 1e-10 * arch, (key, body, V, arch)
    # both runs carry the same clamp force at the same speed: nearly the same volume
    v0, v4 = (r["runs"][k]["pad_volume_m3"] for k in ("mu=0", "mu=0.4"))
    assert v4 == pytest.approx(v0, rel=0.01)


def test_files(res):
    r, out = res
    data = json.loads((out / "friction_taper.json").read_text())
    run = data["runs"]["mu=0.4"]
    assert run["taper"] == pytest.approx(r["runs"]["mu=0.4"]["taper"], rel=1e-12)
    assert len(run["nodes"]["pad_wear_um"]) == len(run["nodes"]["x_mm"]) > 50
    assert len(run["profile_deg"]) == len(run["profile_um"]) >= 10
    assert (out / "friction_taper.png").stat().st_size > 20_000
