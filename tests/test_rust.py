"""The rust law (brakewear.cleaning.rust) and its calibration on a dynamometer record
(brakewear.cleaning.rust_fit): the threshold law against its definition, the layer in a
wear history against the layered Archard law it generalises, and the fit
recovering known parameters within its stated intervals."""
import numpy as np
import pytest

from brakewear import MATERIALS, Numerics, WearError, WearLaw
from brakewear.cleaning.corrosion import CorrodedRotor
from brakewear.cleaning.rust import RUST_PRIORS, RustedRotorLaw, RustLaw, RustLayer
from brakewear.cleaning.rust_fit import (
    calibrate,
    predict_record,
    read_dyno_record,
    synthetic_record,
    write_dyno_record,
)
from brakewear.duty import Drag, run_schedule
from brakewear.errors import IdentifiabilityError
from brakewear.wear import Run

K_IRON = MATERIALS["grey_cast_iron"].wear_k


def test_threshold_law_removes_nothing_below_its_threshold():
    law = RustLaw(k_rust=2e-12, threshold=0.1e6)
    p = np.array([0.0, 0.05e6, 0.1e6, 0.3e6, 1.0e6])
    v = np.full(5, 7.0)
    rate = law.removal_rate(p, v)
    assert rate[:3].tolist() == [0.0, 0.0, 0.0]
    assert rate[3:] == pytest.approx(2e-12 * (p[3:] - 0.1e6) * 7.0, rel=1e-15)
    # as an Archard coefficient: k p v is the removal
    assert law.coefficient(p) * p * v == pytest.approx(rate, rel=1e-15, abs=0.0)
    mixed = RustedRotorLaw(K_IRON, rust=law, covered=np.array([1.0, 1.0, 0.5, 0.0, 1.0]))
    k = mixed.coefficient_at(p, v)
    assert k[3] == K_IRON and k[4] == pytest.approx(law.coefficient(p[4]), rel=1e-15)
    assert k[2] == pytest.approx(0.5 * K_IRON, rel=1e-15)     # at the threshold: no rust wear


def test_with_no_threshold_the_coefficient_is_k_rust_at_zero_pressure_too():
    """The limit of k_r (p - 0) / p: an implicit step takes the coefficient at its start
    pressure, and a node that closes within it must wear on rust."""
    p = np.array([0.0, 1e3, 1e6])
    assert RustLaw(k_rust=3e-12).coefficient(p).tolist() == [3e-12] * 3
    assert RustLaw(k_rust=3e-12, threshold=1.0).coefficient(p)[0] == 0.0


@pytest.mark.parametrize("kw, match", [
    (dict(thickness=-1e-6), r"rust\.thickness: -1e-06 m is not allowed"),
    (dict(k_rust=0.0), r"rust\.k_rust"),
    (dict(threshold=-5.0), r"rust\.threshold: -5\.0 Pa is not allowed"),
    (dict(mu_factor=4.0), r"rust\.mu_factor: 4\.0 is not allowed"),
])
def test_bad_rust_law_is_refused_by_name(kw, match):
    with pytest.raises(WearError, match=match):
        RustLaw(**kw)


def test_every_prior_names_its_source_and_the_assumptions_say_so():
    for name, prior in RUST_PRIORS.items():
        assert name in RustLaw.__dataclass_fields__
        assert len(prior.source) > 30
        lo, hi = prior.bounds
        assert lo < hi
    assert RUST_PRIORS["threshold"].source.startswith("assumption")
    # the removal rate and the friction on rust cite the public reports they were set from
    assert "IDIADA" in RUST_PRIORS["k_rust"].source
    assert "Blau" in RUST_PRIORS["mu_factor"].source and "Shin" in RUST_PRIORS["mu_factor"].source
    # wide: the removal coefficient spans more than a decade
    lo, hi = RUST_PRIORS["k_rust"].bounds
    assert hi / lo > 10
    # friction on rust may fall below the iron's (a crushed scale lubricates) or rise
    assert RUST_PRIORS["mu_factor"].bounds[0] < 1.0 < RUST_PRIORS["mu_factor"].bounds[1]


def test_the_removal_prior_allows_most_of_the_layer_gone_in_one_to_three_firm_stops():
    """IDIADA's dynamometer report (most of the layer gone in the first stop, nothing
    changing from the third) and the owner's manuals (a few firm stops): a firm stop, 3
    m/s^2 from 80 km/h (1.4 MPa at the pads, 30 m of sliding at the mean radius, 15 % of
    it under the pad), takes at least 70 % of the median layer in one stop in a quarter
    of the draws or more, and all of it within three stops in half of them or more."""
    from scipy import stats

    pri = RUST_PRIORS["k_rust"]
    per_k = 1.4e6 * 30.0 * 0.15            # m of oxide per (1/Pa) of k_rust, one stop
    h = RUST_PRIORS["thickness"].a
    above = lambda k: 1.0 - stats.norm.cdf(np.log(k / pri.a) / pri.b)   # noqa: E731
    assert above(0.7 * h / per_k) >= 0.25
    assert above(h / (3 * per_k)) >= 0.5


@pytest.fixture(scope="module")
def small():
    from brakewear import BrakeModel, FEInterface

    model = BrakeModel("default", size=12e-3, rotor="rigid")
    return model, FEInterface(model, 1e6, 0.4)


def _wear(model, itf, pad_law, rotor_law, update, mu=0.4):
    sched = [Drag(1.5e6, 20.0, omega=40.0)]
    last = None
    for rec in run_schedule(
        Run(
            model,
            pad_law=pad_law,
            rotor_law=rotor_law,
            mu=mu,
            schedule=sched,
            interface=itf,
            numerics=Numerics(scheme="implicit", steps=6),
        ),
        on_step=lambda r, s, pw, rw: update(rw),
    ):
        last = rec
    return last


def test_without_threshold_or_factors_the_layer_is_the_layered_archard_law(small):
    """RustLayer with p_th = 0 and factors 1 wears as CorrodedRotor (1e-12)."""
    model, itf = small
    g = model.geometry
    pad = WearLaw(MATERIALS["pad_resin"].wear_k)
    old = CorrodedRotor(itf, g.pad.inner_radius, g.pad.outer_radius, 2e-6, 1e-12, K_IRON)
    a = _wear(model, itf, pad, old.law, old.update)
    layer = RustLayer(itf, RustLaw(thickness=2e-6, k_rust=1e-12), K_IRON, pad)
    b = _wear(model, itf, layer.pad_law, layer.rotor_law, layer.update)
    assert old.through.any() and (old.through == layer.through).all()
    scale = np.abs(a.rotor_wear).max()
    assert np.abs(b.rotor_wear - a.rotor_wear).max() < 1e-12 * scale
    assert np.abs(b.pad_wear - a.pad_wear).max() < 1e-12 * np.abs(a.pad_wear).max()


def test_the_share_of_rust_under_a_node_stays_within_0_and_1(small):
    """W's rows sum to 1 to rounding: the covered share is clipped, so the iron never
    gets a negative weight (nor the implicit step's rings a negative compliance)."""
    from types import SimpleNamespace

    model, itf = small
    # rows a few ulp over 1, as a condensed or caliper interface's W can have
    fake = SimpleNamespace(W=itf.W * (1 + 4e-16), ring=itf.ring, area=itf.area)
    assert (fake.W @ np.ones(fake.W.shape[1])).max() > 1.0
    layer = RustLayer(fake, RustLaw(thickness=2e-6), K_IRON, WearLaw(1e-15))
    for frac in (0.0, 0.3, 0.7):
        wear = np.where(np.arange(itf.ring.size) % 10 < 10 * frac, 3e-6, 0.0)
        layer.update(wear)
        assert layer.covered.min() >= 0.0 and layer.covered.max() <= 1.0
        k = layer.rotor_law.coefficient_at(np.full(layer.covered.size, 1e5), 1.0)
        assert k.min() >= 0.0


def test_a_threshold_above_the_pressure_removes_no_rust_and_pad_wear_rises_on_rust(small):
    model, itf = small
    pad = WearLaw(MATERIALS["pad_resin"].wear_k)
    base = RustLayer(itf, RustLaw(thickness=50e-6, k_rust=1e-12), K_IRON, pad)
    ref = _wear(model, itf, base.pad_law, base.rotor_law, base.update)
    high = RustLayer(itf, RustLaw(thickness=50e-6, k_rust=1e-12, threshold=9e6,
                                  pad_wear_factor=3.0), K_IRON, pad)
    rec = _wear(model, itf, high.pad_law, high.rotor_law, high.update)
    assert rec.rotor_volume_m3 == 0.0 < ref.rotor_volume_m3
    assert rec.pad_volume_m3 == pytest.approx(3.0 * ref.pad_volume_m3, rel=0.02)
    # the friction of the next application over the layer, and once it is gone
    assert high.friction(0.4) == 0.4
    rough = RustLayer(itf, RustLaw(mu_factor=1.2), K_IRON, pad)
    assert rough.friction(0.4, rec.pressure) == pytest.approx(0.48, rel=1e-14)
    rough.update(np.full(itf.rotor_area.size, 1.0))
    assert rough.friction(0.4, rec.pressure) == pytest.approx(0.4, rel=1e-14)


# --------------------------------------------------------------- calibration --
TRUTH = dict(thickness=25e-6, k_rust=1.2e-12, threshold=0.06e6, mu_factor=1.15, mu_iron=0.40)
SHARE = 55.0 / 360.0


def _design(n=30):
    return np.resize(np.array([0.15, 0.3, 0.6, 1.0]) * 1e6, n), np.full(n, 35.0)


def test_the_packaged_synthetic_record_is_fitted_within_its_intervals():
    """The shipped record (made from TRUTH, marked synthetic in its name and header)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))
    import rust_calibration as rc

    path = rc.packaged_record()
    assert "synthetic" in path.name
    assert path.read_text().startswith("# SYNTHETIC")
    assert rc.TRUTH == TRUTH
    r = rc.main()
    for k, v in TRUTH.items():
        lo, hi = r["interval_95"][k]
        assert lo <= v <= hi, (k, v, lo, hi)


def test_the_intervals_cover_the_known_parameters_as_stated():
    """Twenty synthetic records: each 95 % interval holds the known value in at least
    16 (P < 0.3 % for a true 95 % interval to cover fewer)."""
    law = RustLaw(**{k: v for k, v in TRUTH.items() if k != "mu_iron"})
    p, s = _design()
    hits = dict.fromkeys(TRUTH, 0)
    for seed in range(20):
        cal = calibrate(synthetic_record(law, 0.40, p, s, SHARE, seed=100 + seed), SHARE)
        for k, v in TRUTH.items():
            lo, hi = cal.interval_95[k]
            hits[k] += lo <= v <= hi
    assert min(hits.values()) >= 16, hits


def test_a_record_without_removal_holds_the_thickness(tmp_path):
    law = RustLaw(**{k: v for k, v in TRUTH.items() if k != "mu_iron"})
    p, s = _design()
    rec = synthetic_record(law, 0.40, p, s, SHARE, seed=3)
    path = write_dyno_record(tmp_path / "r.csv", type(rec)(rec.pressure, rec.distance,
                                                           rec.friction, None), "test")
    back = read_dyno_record(path)
    assert back.removed is None and back.friction == pytest.approx(rec.friction, abs=1e-5)
    with pytest.raises(IdentifiabilityError, match="does not identify threshold: a record "
                       "without the oxide removed") as e:
        calibrate(back, SHARE, fixed={"thickness": 25e-6})
    assert set(e.value.parameters) == {"threshold"}
    cal = calibrate(back, SHARE, fit=("k_rust", "mu_factor", "mu_iron"),
                    fixed={"thickness": 25e-6, "threshold": 0.06e6})
    assert "thickness" not in cal.values and cal.fixed["thickness"] == 25e-6
    assert cal.interval_95["k_rust"][0] < 1.2e-12 < cal.interval_95["k_rust"][1]
    assert cal.law().thickness == 25e-6


def _study():
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))
    import rust_calibration

    return rust_calibration


def test_intervals_cover_and_degenerate_records_are_refused():
    """240 seeded synthetic records (studies/rust_calibration.py, ``coverage``): the
    ordinary ones are all fitted and their 95 % intervals hold the known values in
    93-97 % of the cases over all parameters (binomial: about 2 standard deviations
    either side of 95 % for 720 intervals) and in at least 90 % for each; every
    record of a degenerate kind is refused, naming exactly the parameters it does
    not constrain."""
    rc = _study()
    table = rc.coverage({"ordinary": 120, "removal_only": 40, "below": 20, "lasting": 20,
                         "friction_only": 20, "one_pressure": 20}, seed=7)
    held = fitted = 0
    for kind in ("ordinary", "removal_only"):
        row = table[kind]
        assert row["accepted"] == row["records"], (kind, row["refused"])
        for k, n in row["fitted"].items():
            held, fitted = held + row["covered"][k], fitted + n
    assert 0.93 <= held / fitted <= 0.97, (held, fitted)
    for k in ("k_rust", "threshold", "thickness", "mu_factor", "mu_iron"):
        n = sum(table[kind]["fitted"].get(k, 0) for kind in ("ordinary", "removal_only"))
        c = sum(table[kind]["covered"].get(k, 0) for kind in ("ordinary", "removal_only"))
        assert c >= 0.90 * n, (k, c, n)
    for kind, names in rc.REFUSE.items():
        row = table[kind]
        assert row["accepted"] == 0 and row["refused"] == {", ".join(sorted(names)): 20}, \
            (kind, row)


@pytest.mark.slow
def test_intervals_cover_at_their_stated_rate_over_800_records():
    """800 ordinary records: each parameter's intervals hold the known value in 92-97.5 %
    of the fitted ones, and all of them together in 93.5-96.5 % (measured: 92.4 %
    for mu_factor, 93.7-94.9 % for the others, 93.8 % together: the Laplace intervals
    run a little short, most for the friction split)."""
    row = _study().coverage({"ordinary": 800}, seed=200_000)["ordinary"]
    # a record whose run-out is barely visible is refused for it (measured: 1 of 800,
    # 1.8 um stops with 0.4 um noise and friction 1.7 % higher on rust)
    assert row["accepted"] >= 0.99 * 800, row["refused"]
    for k, n in row["fitted"].items():
        assert 0.92 <= row["covered"][k] / n <= 0.975, (k, row["covered"][k], n)
    pooled = sum(row["covered"].values()) / sum(row["fitted"].values())
    assert 0.935 <= pooled <= 0.965, pooled


def test_the_refusals_name_the_parameter_and_why():
    rc = _study()
    _, below, share = rc.draw_record("below", 3)
    with pytest.raises(IdentifiabilityError, match=r"k_rust: no stop removed oxide measurably "
                       r"\(the fit gains chi-square [-\d.e]+ over nothing removed, [\d.]+ "
                       r"needed\)") as e:
        calibrate(below, share)
    assert "above the record's highest pressure" in e.value.parameters["threshold"]
    assert e.value.exit_code == 2
    _, lasting, share = rc.draw_record("lasting", 4)
    with pytest.raises(IdentifiabilityError) as e:
        calibrate(lasting, share)
    assert set(e.value.parameters) == {"thickness", "mu_factor", "mu_iron"}
    assert "not seen to wear through" in e.value.parameters["thickness"]
    assert "bound it from below only" in e.value.parameters["thickness"]
    assert "never split between rust and iron" in e.value.parameters["mu_factor"]
    # holding what it cannot see, the lasting record still gives the removal law
    cal = calibrate(lasting, share, fit=("k_rust", "threshold"), fixed={"thickness": 1e-3})
    assert set(cal.names) == {"k_rust", "threshold"}
    _, one, share = rc.draw_record("one_pressure", 5)
    with pytest.raises(IdentifiabilityError, match=r"oxide is removed at [\d.]+ MPa only"):
        calibrate(one, share)


def test_a_run_out_at_the_end_of_a_stop_is_fitted_with_finite_intervals():
    """The layer wears through exactly as a stop ends: the fit may stop on the kink of
    the run-out, where one side's derivative of the removal with the thickness is
    zero; the curvature of both sides gives the thickness a finite interval."""
    p, s = _design()
    d = 1.2e-12 * (p - 0.06e6) * s * SHARE
    law = RustLaw(thickness=float(np.cumsum(d)[13]), k_rust=1.2e-12, threshold=0.06e6,
                  mu_factor=1.15)
    for seed in range(5):
        cal = calibrate(synthetic_record(law, 0.40, p, s, SHARE, seed=seed), SHARE)
        lo, hi = cal.interval_95["thickness"]
        assert 0 < lo < cal.values["thickness"] < hi < 2 * cal.values["thickness"], (lo, hi)


def test_the_record_model_derivatives_match_differences_and_its_sides_on_a_kink():
    from brakewear.cleaning.rust_model import COORDINATES, LOG, record_model

    p, s = _design()
    P = dict(TRUTH, thickness=25.3e-6)
    mu, rem, J_mu, J_rem = record_model(P, p, s, SHARE, jac=True)
    for i, c in enumerate(COORDINATES):
        e = 1e-6
        Q = dict(P, **{c: P[c] * np.exp(e) if c in LOG else P[c] + e * P[c]})
        m2, r2 = record_model(Q, p, s, SHARE)
        step = e if c in LOG else e * P[c]
        for J, a, b in ((J_mu, m2, mu), (J_rem, r2, rem)):
            assert np.abs((a - b) / step - J[:, i]).max() <= 1e-5 * np.abs(J[:, i]).max() + \
                1e-30, c
    # on the kink h = C_13 the two sides put the thickness's derivative in stop 13 or 14
    d = 1.2e-12 * (p - 0.06e6) * s * SHARE
    K = dict(TRUTH, thickness=float(np.cumsum(d)[13]))
    lo = record_model(K, p, s, SHARE, (-1, 0), jac=True)[3][:, 2]
    hi = record_model(K, p, s, SHARE, (1, 0), jac=True)[3][:, 2]
    assert np.flatnonzero(lo).tolist() == [13] and np.flatnonzero(hi).tolist() == [14]


def test_a_threshold_interval_stays_at_or_above_zero():
    law = RustLaw(thickness=25e-6, k_rust=1.2e-12, threshold=2e3, mu_factor=1.15)
    p, s = _design()
    lows = [calibrate(synthetic_record(law, 0.4, p, s, SHARE, seed=k), SHARE
                      ).interval_95["threshold"][0] for k in range(5)]
    assert min(lows) >= 0.0, lows


def test_forward_model_removes_the_layer_and_no_more():
    p, s = _design()
    mu, rem = predict_record(TRUTH, p, s, SHARE)
    assert rem.sum() == pytest.approx(25e-6, rel=1e-14)
    first = 1.2e-12 * (0.15e6 - 0.06e6) * 35.0 * SHARE
    assert rem[0] == pytest.approx(first, rel=1e-14)
    assert mu[0] == pytest.approx(0.46, rel=1e-14) and mu[-1] == pytest.approx(0.40, rel=1e-14)


@pytest.mark.parametrize("text, match", [
    ("contact_pressure_MPa,friction\n1,0.4\n", r"need the columns"),
    ("contact_pressure_MPa,sliding_distance_m,friction\n1,30,0.4\n-1,30,0.4\n1,3,0.4\n",
     r"row 3: contact_pressure_MPa = -1 is not allowed"),
    ("contact_pressure_MPa,sliding_distance_m,friction\n1,30,x\n1,3,0.4\n1,3,0.4\n",
     r"row 2: friction = 'x' is not a number"),
])
def test_a_bad_record_names_the_row(tmp_path, text, match):
    f = tmp_path / "bad.csv"
    f.write_text(text)
    with pytest.raises(WearError, match=match):
        read_dyno_record(f)
