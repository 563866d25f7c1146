"""Step convergence of the wear loop on a coarse mesh: both schemes are first order."""
import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

from brakewear.errors import StepSizeError, WearError
from brakewear.interfaces import FEInterface
from brakewear.laws.base import WearLaw
from brakewear.mesh.rings import rotor_wear_rate
from brakewear.model import BrakeModel
from brakewear.wear import Numerics, Run, wear_history

spec = importlib.util.spec_from_file_location(
    "wear_steps", Path(__file__).parents[1] / "studies" / "wear_steps.py")
study = importlib.util.module_from_spec(spec)
spec.loader.exec_module(study)


@pytest.mark.slow
def test_fixed_steps_converge_at_first_order(tmp_path):
    res = study.main(size_mm=10.0, out=tmp_path, quick=True, figures=False)
    # the short horizon keeps the coarsest explicit step below the stability limit
    assert res["explicit"]["rows"][0]["dt_s"] < 2.0 * res["settings"]["explicit_monotone_bound_s"]
    for key in study.CASES:
        s = res[key]
        assert s["rate"] >= 0.8, f"{key}: observed rate {s['rate']:.3f}"
        finest = s["rows"][-1]["error"]
        assert finest < 0.01, f"{key}: finest error {finest:.3e}"
        # the reference's own error is far below the finest run's
        assert s["reference_error_estimate"] < 0.2 * finest
    data = json.loads((tmp_path / "data" / "wear_steps.json").read_text())
    # 4 horizons x (2 dp_tol + 2 wear_tol)
    assert len(data["control"]) == 16
    # the first solve and any rejected try count
    assert all(r["contact_solves"] >= r["steps"] + 1 for r in data["control"])


# --- the wear_tol step control (local wear error) --------------------------------------


@pytest.mark.parametrize("bad", [0.0, -1e-6, float("nan"), float("inf"), "1e-6", True])
def test_wear_tol_is_checked_before_any_solve(bad):
    # model=None: the check must come before anything touches the model
    with pytest.raises(WearError, match=r"numerics\.wear_tol: .*(not allowed|expected a number)"):
        next(
            wear_history(
                Run(
                    None,
                    1e6,
                    55.0,
                    100.0,
                    WearLaw(5e-15),
                    numerics=Numerics(scheme="explicit", wear_tol=bad),
                )
            )
        )


@pytest.fixture(scope="module")
def small():
    """Size 10 mm, rigid rotor (the study's quick setting), its interface and short horizon."""
    model = BrakeModel("default", size=10e-3, rotor="rigid")
    itf = FEInterface(model, study.P_LINE, study.MU)
    return model, itf, round(1.6 * 4 * study.stability_bound(itf), 1)   # 108.1 s


@pytest.mark.parametrize("scheme,norm", [("explicit", "l2"), ("implicit", "l2"),
                                         ("implicit", "max")])
def test_wear_tol_steps_keep_their_error_estimate(small, scheme, norm):
    """Every accepted step's embedded estimate dt/2 |rate(p_end) - rate(p_start)|,
    recomputed from the records (pad and rotor rates) in the control's norm (the root
    mean square over the face with the nodes' areas, or the largest nodal value), is
    within wear_tol; a tighter wear_tol takes more steps."""
    model, itf, T = small
    pad, rotor = WearLaw(study.K_PAD), WearLaw(5e-16)
    v = study.OMEGA * itf.r
    counts = []
    for tol in (1e-8, 1e-9):  # m; the run wears about 4 um
        recs = list(
            wear_history(
                Run(
                    model,
                    study.P_LINE,
                    study.OMEGA,
                    T,
                    pad,
                    rotor,
                    study.MU,
                    interface=itf,
                    numerics=Numerics(scheme=scheme, wear_tol=tol, norm=norm),
                )
            )
        )
        assert recs[-1].time == pytest.approx(T)
        for r in recs:
            d_rot = (rotor_wear_rate(rotor.rate(r.pressure_end, v) * itf.area, itf.W, itf.ring,
                                     itf.rotor_area)
                     - rotor_wear_rate(rotor.rate(r.pressure, v) * itf.area, itf.W, itf.ring,
                                       itf.rotor_area))
            d = pad.rate(r.pressure_end, v) - pad.rate(r.pressure, v) + itf.W @ d_rot
            est = 0.5 * r.dt * (np.abs(d).max() if norm == "max"
                                else np.sqrt((itf.area * d ** 2).sum() / itf.area.sum()))
            assert est <= tol * (1 + 1e-9), f"step {r.step}: est {est:.3e} > {tol:.1e}"
        assert any(r.limit == "wear_tol" for r in recs)
        counts.append(len(recs))
    assert counts[1] > counts[0]


def test_wear_tol_resume_repeats_the_run(small, tmp_path):
    model, itf, T = small
    kw = dict(interface=itf, numerics=Numerics(scheme="implicit", wear_tol=1e-9))
    args = (model, study.P_LINE, study.OMEGA, T, WearLaw(study.K_PAD), None, study.MU)
    full = list(wear_history(Run(*args, **kw)))
    ck = tmp_path / "run.npz"
    for s in wear_history(Run(*args, **kw), checkpoint=ck, every=3):
        if s.step == 4:     # "killed": the checkpoint holds step 3
            break
    rest = list(wear_history(Run(*args, **kw), checkpoint=ck, every=3, resume=True))
    assert [s.step for s in rest] == [s.step for s in full[3:]]
    assert [s.dt for s in rest] == [s.dt for s in full[3:]]
    assert np.abs(full[-1].pad_wear - rest[-1].pad_wear).max() <= 1e-12 * full[-1].pad_wear.max()


def test_wear_tol_beats_fixed_steps_over_a_long_history(small):
    """Running-in over 100 x the short horizon (10810 s, implicit): the wear error
    over the history (at every reported step) of the wear_tol control is no larger
    than that of 64 equal steps, with a quarter of the solves.  Measured (size 10 mm):
    wear_tol = 3e-3 max h: 16 solves, history error 2.2e-3; 64 fixed steps: 65 solves,
    3.2e-3 (16 fixed steps: 17 solves, 8.3e-3); reference error about 1.6e-4.  At the
    end time alone the fixed steps are as good (docs/wear.md, "Step convergence")."""
    model, itf, T = small
    T = 100 * T
    fixed = study.run(model, itf, "implicit", T, 64)
    hmax = float(fixed["pad_wear"].max())
    ref = study.run(model, itf, "implicit", T, None, wear_tol=1e-5 * hmax)
    chk = study.run(model, itf, "implicit", T, None, wear_tol=4e-5 * hmax)
    ctl = study.run(model, itf, "implicit", T, None, wear_tol=3e-3 * hmax)
    e_fixed = study.history_error(fixed, ref, hmax)
    e_ctl = study.history_error(ctl, ref, hmax)
    e_ref = study.history_error(chk, ref, hmax)
    assert e_ref < 0.2 * e_ctl, f"reference error {e_ref:.2e} vs {e_ctl:.2e}"
    assert e_ctl <= e_fixed, f"wear_tol {e_ctl:.3e} > fixed {e_fixed:.3e}"
    assert ctl["contact_solves"] < fixed["contact_solves"]
    # at most half: the dp_tol control (52 solves at its default 0.05) would fail here
    assert ctl["contact_solves"] <= 0.5 * fixed["contact_solves"]


def test_wear_tol_gives_up_with_its_figures(small):
    model, itf, T = small
    with pytest.raises(StepSizeError, match=r"after 3 retries .*wear error estimate .* > "
                                            r"wear_tol 1\.000e-15 m"):
        list(
            wear_history(
                Run(
                    model,
                    study.P_LINE,
                    study.OMEGA,
                    T,
                    WearLaw(study.K_PAD),
                    None,
                    study.MU,
                    interface=itf,
                    numerics=Numerics(scheme="implicit", wear_tol=1e-15, max_halvings=2),
                )
            )
        )


# --- implicit steps whose wear compliance is negligible are taken explicitly -----------

def test_implicit_floor_takes_stiff_steps_explicitly(small):
    """With implicit_floor = 1 every step of this history (8 steps, lambda dt about 0.8) is
    below the floor and taken explicitly: the same answer as the explicit scheme,
    to round-off; with implicit_floor = 0 the backward-Euler steps differ from it."""
    model, itf, T = small
    args = (model, study.P_LINE, study.OMEGA, T, WearLaw(study.K_PAD), None, study.MU)
    explicit = list(
        wear_history(Run(*args, interface=itf, numerics=Numerics(scheme="explicit", steps=8)))
    )
    floored = list(
        wear_history(
            Run(
                *args,
                interface=itf,
                numerics=Numerics(scheme="implicit", steps=8, implicit_floor=1.0),
            )
        )
    )
    implicit = list(
        wear_history(
            Run(
                *args,
                interface=itf,
                numerics=Numerics(scheme="implicit", steps=8, implicit_floor=0.0),
            )
        )
    )
    h = explicit[-1].pad_wear
    assert all(r.explicit for r in floored) and not any(r.explicit for r in implicit)
    assert np.abs(floored[-1].pad_wear - h).max() <= 1e-9 * h.max()
    assert np.abs(implicit[-1].pad_wear - h).max() > 1e-3 * h.max()


@pytest.mark.parametrize("bad", [-1e-3, 1.5, float("nan"), "0.001"])
def test_implicit_floor_is_checked(bad):
    with pytest.raises(WearError, match=r"numerics\.implicit_floor"):
        Numerics(implicit_floor=bad)


# --- the rotor's explicit ring wear is bounded by its own stability limit ---------------

def test_fast_rotor_layer_keeps_its_ring_wear_within_its_bound(small):
    """A rotor layer that wears 200 x faster than the pad (a corrosion layer), 20 s
    under the ``implicit_pad`` scheme with a loose dp_tol: the ring wear is explicit, and
    every step is within its monotone bound stability / max_j sum_i k v s_i / A_ring_j
    (recomputed here from each step's start), which sets steps.  Against a reference
    (a tenth of the bound, dp_tol 0.02) the bound cuts the rotor-wear error about
    ninefold (measured 7.5e-4 against 6.8e-3 without it), and half the bound halves
    it (first order)."""
    model, itf, T = small
    fast = WearLaw(200 * study.K_PAD)
    v = study.OMEGA * itf.r

    def run(stability, dp_tol=1.0):
        return list(
            wear_history(
                Run(
                    model,
                    study.P_LINE,
                    study.OMEGA,
                    20.0,
                    WearLaw(study.K_PAD),
                    fast,
                    study.MU,
                    interface=itf,
                    numerics=Numerics(scheme="implicit_pad", dp_tol=dp_tol, stability=stability),
                )
            )
        )
    recs = run(1.0)
    assert any(r.limit == "rotor_stability" for r in recs)
    for r in recs:
        q = np.where(r.active, fast.rate(1.0, v) * itf.normal_stiffness, 0.0)
        bound = 1.0 / rotor_wear_rate(q, itf.W, itf.ring, itf.rotor_area).max()
        assert r.dt <= bound * (1 + 1e-12), f"step {r.step}: dt {r.dt:.3e} > {bound:.3e}"
    ref = run(0.1, 0.02)[-1].rotor_wear

    def err(h):
        return np.abs(h - ref).max() / ref.max()
    e1, e_half, e_none = err(recs[-1].rotor_wear), err(run(0.5)[-1].rotor_wear), \
        err(run(None)[-1].rotor_wear)
    assert e1 < 0.25 * e_none, f"bounded {e1:.2e}, unbounded {e_none:.2e}"
    assert 0.3 < e_half / e1 < 0.7, f"half the bound: {e_half:.2e} against {e1:.2e}"


def test_a_change_that_does_not_shrink_with_the_step_is_a_jump():
    """Halving the step shrinks a change the step resolves; a change that stays
    within a factor 1.5 over four halvings is a jump of the contact state,
    taken in the shortest step, and only under the dp_tol control."""
    from brakewear.wear.control import StepControl
    from brakewear.wear.numerics import Numerics

    ctl = StepControl(Numerics(), 1.0, np.ones(3))
    assert ctl.spans_jump([0.9, 0.25, 0.22, 0.2, 0.19, 0.19])  # the last five: a jump
    assert not ctl.spans_jump([0.3, 0.22, 0.2, 0.19])                 # too few halvings
    assert not ctl.spans_jump([0.8, 0.4, 0.2, 0.1, 0.05])             # resolved: shrinks
    assert not ctl.spans_jump([0.3, np.inf, 0.2, 0.19, 0.19])         # contact lost
    assert not StepControl(Numerics(steps=10), 1.0, np.ones(3)).spans_jump([0.2] * 6)
    assert not StepControl(Numerics(wear_tol=1e-7), 1.0, np.ones(3)).spans_jump([0.2] * 6)
