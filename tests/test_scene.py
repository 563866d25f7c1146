"""The default brake, tied pad-rotor interface, under a line pressure."""
import numpy as np
import pytest

from brakewear.errors import GeometryError, SceneError
from brakewear.model import BrakeModel
from brakewear.static import solve_tied, static_summary


@pytest.fixture(scope="module")
def solved():
    m = BrakeModel("default", size=4e-3)
    return m, solve_tied(m, 1e6)


def test_interface_carries_the_clamp_force(solved):
    m, r = solved
    F = 1e6 * np.pi * 0.057 ** 2 / 4
    assert r.clamp_force == pytest.approx(F)
    assert abs(r.normal_force - F) / F < 1e-8, f"interface force {r.normal_force} vs {F}"
    # the pad as a free body: interface forces + abutment reactions + load = 0
    pad = m.meshes["pad"]
    f_pad = m.loads(1e6)[3 * m.offsets["pad"]:3 * (m.offsets["pad"] + pad.nvertices)]
    internal = (m.stiffness("pad") @ r.u["pad"] - f_pad).reshape(-1, 3)
    abut = np.unique(pad.facets[:, pad.boundaries["abutment"]])
    total = (r.interface_force.sum(axis=1) + internal[abut].sum(axis=0) * [1, 1, 0]
             + f_pad.reshape(-1, 3).sum(axis=0))
    assert np.abs(total).max() < 1e-8 * F, f"pad out of balance by {total} N"


def test_centre_of_pressure_under_the_piston(solved):
    m, r = solved
    s = static_summary(m, r)
    i = s["interface"]
    assert i["centre_of_pressure_r_m"] == pytest.approx(0.1165, rel=0.017), i   # 2 mm
    assert abs(i["centre_of_pressure_theta_deg"]) < 1.0, i
    assert i["pressure_max_Pa"] > i["pressure_mean_Pa"] > 0
    assert s["solver"]["relative_residual"] < 1e-9


def test_piston_body_and_traction_agree_on_resultants():
    a = BrakeModel("default", piston="body", size=5e-3)
    ra = solve_tied(a, 1e6)
    b = BrakeModel("default", piston="traction", size=5e-3)
    rb = solve_tied(b, 1e6)
    assert ra.normal_force == pytest.approx(rb.normal_force, rel=1e-8)
    ca, cb = static_summary(a, ra)["interface"], static_summary(b, rb)["interface"]
    assert ca["centre_of_pressure_r_m"] == pytest.approx(cb["centre_of_pressure_r_m"], rel=0.0086)


def test_bad_scene_input_is_refused_early():
    with pytest.raises(SceneError, match="piston"):
        BrakeModel("default", piston="hydraulic")
    with pytest.raises(SceneError, match="order"):
        BrakeModel("default", order=3)
    with pytest.raises(GeometryError):
        BrakeModel("no_such_geometry")
    m = BrakeModel("default", size=6e-3)
    with pytest.raises(SceneError, match="line_pressure"):
        solve_tied(m, -1.0)
