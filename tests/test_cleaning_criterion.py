"""The cleaning criterion by area, the touch threshold, the layered rotor law, and the
candidate criteria (brakewear.cleaning.criteria) against what each must count."""

import numpy as np
import pytest

from brakewear import FEInterface, WearError
from brakewear.cleaning.corrosion import CorrodedRotor, coning_gap
from brakewear.cleaning.criteria import CRITERIA, CleaningCriteria, CriteriaSettings
from brakewear.model import BrakeModel


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


@pytest.fixture(scope="module")
def both():
    """The floating caliper's pads held square, both faces (12 mm)."""
    from dataclasses import replace

    from brakewear import load_geometry
    from brakewear.geometry import SupportGeometry

    g = replace(load_geometry("floating"), support=SupportGeometry())
    return FEInterface(BrakeModel(g, size=12e-3, layout="full", rotor="elastic"), 1e6, 0.4)


def _criteria(itf, **kw):
    g = itf.model.geometry.pad
    return CleaningCriteria(itf, (g.inner_radius, g.outer_radius), 20e-6,
                            CriteriaSettings(**kw))


def test_every_candidate_on_an_untouched_and_a_clean_band(both):
    c = _criteria(both)
    n, p = both.rotor_area.size, np.ones(both.area.size)
    none, clean = c.evaluate(np.zeros(n), p), c.evaluate(np.full(n, 20e-6), p)
    assert set(none) == set(CRITERIA) == set(clean)
    for name in ("rings_through", "band_inset", "volume_removed", "iron_load"):
        assert none[name]["value"] == 0.0 and not none[name]["met"]
        assert clean[name]["value"] == pytest.approx(1.0, rel=1e-12) and clean[name]["met"]
    # an even layer, untouched or gone, leaves no thickness variation: DTV judges judder
    assert none["dtv_left"]["value"] == clean["dtv_left"]["value"] == 0.0
    assert set(none["volume_removed"]["faces"]) == {"in", "out"}


def test_half_the_layer_everywhere_is_half_the_volume_and_no_ring(both):
    c = _criteria(both)
    half = c.evaluate(np.full(both.rotor_area.size, 10e-6), np.ones(both.area.size))
    assert half["volume_removed"]["value"] == pytest.approx(0.5, rel=1e-12)
    assert half["iron_load"]["value"] == pytest.approx(0.5, rel=1e-12)
    assert half["rings_through"]["value"] == 0.0


def test_the_worse_face_decides_and_the_inset_band_drops_the_edge_rings(both):
    c = _criteria(both, inset=4e-3)
    b = c.band
    r = b.radii[both.ring]
    face = np.asarray(b.face)[both.ring]
    g = both.model.geometry.pad
    # the inboard face clean; the outboard clean but for its innermost ring
    inner = b.radii[b.face == "out"][b.band_area[b.face == "out"] > 0].min()
    w = np.where((face == "in") | (r > inner + 1e-9), 20e-6, 0.0)
    res = c.evaluate(w, np.ones(both.area.size))
    share = b.band_area[(b.face == "out") & (b.radii <= inner + 1e-9)].sum() \
        / b.band_area[b.face == "out"].sum()
    assert res["rings_through"]["faces"]["in"] == pytest.approx(1.0, rel=1e-12)
    assert res["rings_through"]["value"] == pytest.approx(1.0 - share, rel=1e-12)
    # the inset band counts the ring only where it lies beyond the inset
    lo = g.inner_radius + 4e-3
    mid = 0.5 * (np.sort(b.radii[b.face == "out"])[1:] + np.sort(b.radii[b.face == "out"])[:-1])
    edge = mid[mid > inner][0]
    kept = max(edge ** 2 - lo ** 2, 0.0) / (((g.outer_radius - 4e-3) ** 2) - lo ** 2)
    assert res["band_inset"]["value"] == pytest.approx(1.0 - kept, rel=1e-9)
    # the outboard face's layer left at its inner ring against none elsewhere: DTV
    assert res["dtv_left"]["value"] == pytest.approx(20e-6, rel=1e-9)


def test_the_load_on_iron_weights_the_pressure(both):
    c = _criteria(both)
    b = c.band
    w = np.where(b.radii[both.ring] > np.median(b.radii), 20e-6, 0.0)
    outer = both.r > np.median(both.r)
    loaded_out = c.evaluate(w, np.where(outer, 1.0, 1e-6))["iron_load"]["value"]
    loaded_in = c.evaluate(w, np.where(outer, 1e-6, 1.0))["iron_load"]["value"]
    assert loaded_out > 0.8 and loaded_in < 0.3


@pytest.mark.parametrize("kw, match", [(dict(inset=-1.0), "criteria.inset"),
                                       (dict(volume_share=1.5), "criteria.volume_share"),
                                       (dict(chosen="shine"), "criteria.chosen = 'shine'")])
def test_bad_settings_are_refused(kw, match):
    with pytest.raises(WearError, match=match):
        CriteriaSettings(**kw)
