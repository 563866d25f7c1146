"""A single stop against the closed form (studies/stop_temperature.py).

The column: :class:`~brakewear.fem.HeatConduction` (P1, implicit Euler) under a
stop's linearly falling flux against :func:`brakewear.analytic.stop_surface_temperature`
and :func:`~brakewear.analytic.stop_temperature`, with observed rates in space
and in time.  The brake: one stop of the default brake without convection, the
friction work and the mean rise against the vehicle's energy and ``E / sum(m c)``,
the rotor face against the closed form within a band the geometry explains.
"""
import json

import numpy as np
import pytest

from brakewear import analytic as an
from brakewear.materials import MATERIALS
from studyload import load_study

st = load_study("stop_temperature")


@pytest.mark.parametrize("material", ["grey_cast_iron", "pad_resin"])
def test_column_surface_within_2_percent_at_the_peak_and_the_end(material):
    """10 graded cells (first 0.088 sqrt(a t_s)), 32 steps per stop."""
    run = st.run_column(material, cells=10, steps=32)
    for key in ("peak", "end"):
        assert run["errors"][key] < 0.02, f"{material}: {key} error {run['errors'][key]:.2e}"
    # the face is one temperature up to the Kuhn split's consistent capacity
    assert run["face_spread"] < 0.01, run["face_spread"]


def test_both_materials_give_the_same_relative_error_on_the_scaled_column():
    """Depth and cells scale with sqrt(a t_s): the relative errors are one problem's."""
    a, b = (st.run_column(m, cells=10, steps=32) for m in ("grey_cast_iron", "pad_resin"))
    for key in ("peak", "end"):
        assert a["errors"][key] == pytest.approx(b["errors"][key], rel=1e-6)


def test_column_inside_follows_the_closed_form():
    run = st.run_column("grey_cast_iron", cells=10, steps=32, history=True)
    th = MATERIALS["grey_cast_iron"].thermal
    for key, prof in run["profiles"].items():
        exact = an.stop_temperature(np.array(prof["x_m"]), prof["t_s"], run["q0_W_m2"],
                                    st.T_STOP, th.kappa, th.rho, th.c, st.T_AMB)
        err = np.abs(np.array(prof["T_K"]) - exact).max() / (exact[0] - st.T_AMB)
        assert err < 0.02, f"{key}: largest nodal error {err:.2e} of the surface rise"
    # deep enough: the insulated bottom acts as an image source at twice its depth,
    # whose share of the surface rise is nil over the stop and after it
    L = prof["x_m"][-1]
    for t in (st.T_STOP, 1.5 * st.T_STOP):
        image = an.stop_temperature(2 * L, t, run["q0_W_m2"], st.T_STOP, th.kappa, th.rho,
                                    th.c)
        assert image < 1e-8 * (exact[0] - st.T_AMB), image


def test_column_converges_in_space():
    """h -> 0 at dt = t_s / 4096 (Richardson in dt): rate ~2 at the peak and the end."""
    s = st.convergence("space", (10, 20, 40, 80), 4096)
    for key, finest in (("peak", 1e-4), ("end", 5e-5)):
        rate = s[f"rate_{key}"]
        assert rate > 1.8, f"{key}: space rate {rate:.2f}, errors {s[key]}"
        assert s[key][-1] < finest, f"{key}: finest error {s[key][-1]:.2e}"


def test_column_converges_in_time():
    """dt -> 0 on 640 cells: rate 1 at the end of the stop; at the peak dT/dt = 0, so
    implicit Euler's leading error (a lag of dt/2) vanishes there and it converges faster."""
    s = st.convergence("time", (8, 16, 32, 64), 640)
    assert 0.9 < s["rate_end"] < 1.1, f"time rate {s['rate_end']:.2f}, errors {s['end']}"
    assert s["end"][-1] < 7e-3, f"64 steps: error {s['end'][-1]:.2e}"
    assert s["rate_peak"] > 1.5, f"peak: time rate {s['rate_peak']:.2f}, errors {s['peak']}"
    assert s["peak"][-1] < 2e-5, s["peak"]


@pytest.mark.slow
def test_column_converges_over_more_levels():
    s = st.convergence("space", (10, 20, 40, 80, 160), 8192)
    assert s["rate_peak"] > 1.9 and s["rate_end"] > 1.9, (s["rate_peak"], s["rate_end"])
    assert s["peak"][-1] < 2e-5 and s["end"][-1] < 1e-5, (s["peak"], s["end"])
    t = st.convergence("time", (8, 16, 32, 64, 128, 256, 512), 1280)
    assert 0.95 < t["rate_end"] < 1.05, t["end"]
    assert t["end"][-1] < 1e-3, t["end"]


# ------------------------------------------------------------- the brake ---

@pytest.fixture(scope="module")
def stop():
    return st.brake_stop(size=12e-3, steps=16)


def test_stop_friction_work_is_the_vehicles_energy(stop):
    """``mu omega sum(p A r)`` over the stop = the kinetic energy share of the face:
    the contact pressure carries the clamp force (1e-8) and the steps' mean speeds
    integrate the linear fall exactly."""
    assert stop["friction_work_J"] == pytest.approx(stop["vehicle_face_J"], rel=1e-8)


def test_stop_mean_rise_is_the_bulk_rise(stop):
    """No convection: every joule stays, so the capacity-weighted mean rise of pad +
    rotor is ``E / sum(m c)`` to round-off; ``sum(m c)`` of the 12 mm mesh lies within
    2 % of the geometry's (P1 facets of the curved ring)."""
    E = stop["friction_work_J"]
    assert sum(stop["stored_J"].values()) == pytest.approx(E, rel=1e-9)
    assert stop["mean_rise_K"] == pytest.approx(stop["bulk_rise_K"], rel=1e-9)
    mc = sum(stop["mc_J_K"].values())
    assert mc == pytest.approx(stop["mc_geometry_J_K"], rel=0.02)
    assert stop["bulk_rise_K"] == pytest.approx(an.bulk_temperature_rise(E, 1.0, mc),
                                                rel=1e-14)


def test_stop_rotor_face_lies_in_the_band_of_the_closed_form(stop):
    """The rotor face's mean over the swept ring, against the half-space under the mean
    ring flux: the rotor is a 12 mm plate with an insulated midplane, so in 1D the
    face lies between the half-space and the half-space plus the plate's mean rise
    (the image sources are a Riemann sum of a falling profile); the coarse mesh and
    the unheated parts of the ring pull it down, but never below the rotor's own
    mean (heat enters at the face).  Peak at t_s / 2 within one step."""
    rise = stop["ring_mean_peak_rise_K"]
    closed = stop["closed_form_peak_rise_K"]
    assert stop["rotor_bulk_rise_K"] < rise < closed + stop["swept_slab_bulk_rise_K"], (
        stop["rotor_bulk_rise_K"], rise, closed, stop["swept_slab_bulk_rise_K"])
    assert 0.6 < rise / closed < 1.2, f"ring mean / closed form = {rise / closed:.3f}"
    assert abs(stop["ring_mean_peak_time_s"] - stop["t_stop_s"] / 2) <= stop["t_stop_s"] / 16


# ------------------------------------------------------------- the study ---

def test_study_writes_its_figure_and_numbers(tmp_path):
    res = st.main(cells=6, steps=8, after=0.25, space_levels=(5, 10, 20), space_steps=256,
                  time_levels=(4, 8, 16), time_cells=80, brake_sizes=(12e-3,), brake_steps=4,
                  out=tmp_path)
    data = json.loads((tmp_path / "stop_temperature.json").read_text())
    assert (tmp_path / "stop_temperature.png").stat().st_size > 10_000
    assert set(data) == {"settings", "column", "space", "time", "brake"}
    assert data["space"]["levels"] == [5, 10, 20] and len(data["space"]["peak"]) == 3
    assert set(data["column"]) == {"grey_cast_iron", "pad_resin"}
    assert res["brake"][0]["mean_rise_K"] == pytest.approx(res["brake"][0]["bulk_rise_K"],
                                                           rel=1e-9)
