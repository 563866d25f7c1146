"""The condensed interface: the FE contact model's answer from its compliance on
the contact nodes (pressures and wear to 1e-8 of the FE solves, run at a tight
tolerance), its cache, its memory check and its range of validity."""
from dataclasses import replace

import numpy as np
import pytest

from brakewear import (
    BrakeModel,
    CondensedInterface,
    CondensedRangeError,
    FEInterface,
    Numerics,
    SolverError,
    ThermalModel,
    WearError,
    WearLaw,
    wear_history,
)
from brakewear.interfaces.condensation import condense, free_modes
from brakewear.wear import Run

TOL = 1e-8      # relative agreement with the FE solves (which run to 1e-12)


@pytest.fixture(scope="module", params=["rigid", "elastic"])
def pair(request):
    model = BrakeModel(size=6e-3, rotor=request.param)
    return (model, FEInterface(model, 1e6, 0.4, tol=1e-12),
            CondensedInterface(model, 1e6, 0.4, cache=False))


def _rel(a, b):
    return float(np.abs(a - b).max() / np.abs(a).max())


def _offset(itf):
    # a radial non-conformity with some scatter: not every node in contact
    r = itf.r
    rng = np.random.default_rng(3)
    return 20e-6 * (r - r.min()) / np.ptp(r) + 0.5e-6 * rng.random(r.size)


@pytest.mark.parametrize("mu", [0.0, 0.4])
@pytest.mark.parametrize("implicit", [False, True])
def test_a_contact_solve_is_the_fe_solve(pair, mu, implicit):
    model, fe, cd = pair
    eps = 2e-12 * np.ones(fe.area.size) if implicit else None
    a = fe.solve(_offset(fe), None, compliance=eps, mu=mu)
    b = cd.solve(_offset(cd), None, compliance=eps, mu=mu)
    assert 0 < a.active.sum() < a.active.size       # a partial contact, a real test
    assert np.array_equal(a.active, b.active)
    assert _rel(a.pressure, b.pressure) < TOL
    # equilibrium: the contact carries the clamp force
    assert float((b.pressure * cd.area).sum()) == pytest.approx(fe.cs.clamp_force, rel=1e-9)


def test_the_free_mode_of_the_supported_pad_is_its_normal_translation(pair):
    model, fe, cd = pair
    Z = free_modes(fe.cs.K, fe.cs.coords, fe.cs.fixed)
    assert Z.shape[1] == 1
    z = Z[:, 0].reshape(-1, 3)
    moving = np.abs(z).max(axis=1) > 0
    # only z components, one value, on the pad (and not on the clamped rotor)
    assert np.allclose(z[:, :2], 0.0, atol=1e-14 * np.abs(z).max())
    assert np.ptp(z[moving, 2]) < 1e-12 * np.abs(z).max()
    pad = fe.cs.col[model.offsets["pad"]:model.offsets["pad"] + model.meshes["pad"].nvertices]
    assert moving[pad].all() and moving.sum() == pad.size


def _history(model, itf, scheme, thermal=False, steps=None, duration=20.0):
    th = ThermalModel(model, contact_conductance=1e4) if thermal else None
    return list(
        wear_history(
            Run(
                model,
                1e6,
                50.0,
                duration,
                WearLaw(5e-14),
                WearLaw(1e-15),
                0.4,
                interface=itf,
                thermal=th,
                numerics=Numerics(steps=steps, scheme=scheme, tol=1e-12),
            )
        )
    )


def _same_histories(model, scheme, steps, thermal):
    a = _history(model, FEInterface(model, 1e6, 0.4, tol=1e-12), scheme, thermal, steps)
    b = _history(model, CondensedInterface(model, 1e6, 0.4, cache=False), scheme, thermal, steps)
    assert len(a) == len(b) >= 5
    for x, y in zip(a, b):
        assert x.time == pytest.approx(y.time, rel=TOL)
        if x.limit != "end":        # the last step is the remainder of the duration
            # each growth-limited step scales the last one, so the steps carry the
            # solves' differences (1e-11..1e-9 per step) forward: 1e-8 after 20 steps
            assert x.dt == pytest.approx(y.dt, rel=10 * TOL)
        assert _rel(x.pressure_end, y.pressure_end) < TOL
        assert _rel(x.pad_wear, y.pad_wear) < TOL
        assert _rel(x.rotor_wear, y.rotor_wear) < TOL
    if thermal:
        assert b[-1].pad_temperature_max == pytest.approx(a[-1].pad_temperature_max, rel=1e-10)


@pytest.mark.parametrize("scheme,steps", [("explicit", None), ("implicit", 10)])
def test_wear_histories_are_the_fe_histories(pair, scheme, steps):
    _same_histories(pair[0], scheme, steps, thermal=False)


def test_a_thermal_history_is_the_fe_history():
    # heat flows between the faces through a contact conductance: an elastic rotor
    _same_histories(BrakeModel(size=6e-3, rotor="elastic"), "implicit", 5, thermal=True)


def test_the_cache_returns_the_same_compliance_for_any_line_pressure(tmp_path):
    model = BrakeModel(size=8e-3, rotor="rigid")
    cs1 = FEInterface(model, 1e6, 0.4).cs
    first = condense(cs1, 1e6, cache=tmp_path)
    assert len(list(tmp_path.glob("*.npz"))) == 1 and first.info["seconds"] > 0
    cs2 = FEInterface(model, 3e6, 0.4).cs
    again = condense(cs2, 3e6, cache=tmp_path)
    assert again.key == first.key and "cached" in again.info and again.info["seconds"] == 0
    for k in ("Hn", "Ht", "hf", "E", "Dt", "zf"):
        assert np.array_equal(getattr(first, k), getattr(again, k))
    # another brake (a stiffer friction layer) is another key
    g = model.geometry
    m = g.pad.friction_material
    stiffer = replace(m, elastic=replace(m.elastic, E_t=2 * m.elastic.E_t))
    other = BrakeModel(replace(g, pad=replace(g.pad, friction_material=stiffer)), size=8e-3,
                       rotor="rigid")
    assert condense(FEInterface(other, 1e6, 0.4).cs, 1e6, cache=False).key != first.key
    # Hn is the normal compliance: symmetric positive definite
    H = first.Hn
    assert np.abs(H - H.T).max() < 1e-10 * np.abs(H).max()
    assert np.linalg.eigvalsh(0.5 * (H + H.T)).min() > 0


def test_memory_is_checked_before_condensing(tmp_path):
    model = BrakeModel(size=8e-3, rotor="rigid")
    with pytest.raises(SolverError, match=r"needs about .* GB .* the memory budget you set"):
        CondensedInterface(model, 1e6, 0.4, cache=tmp_path, memory_budget=1e-6)
    assert not list(tmp_path.glob("*.npz"))


def test_offsets_beyond_the_range_are_refused_with_the_alternative(pair):
    model, fe, cd = pair
    off = np.zeros(cd.area.size)
    off[7] = 1.01 * cd.max_offset[7]
    with pytest.raises(CondensedRangeError, match=r"interface.model = 'fe' with "
                                                  r"numerics.update = 'geometry'"):
        cd.solve(off, None)
    with pytest.raises(WearError, match="FEInterface"):
        next(
            wear_history(
                Run(
                    model,
                    1e6,
                    50.0,
                    10.0,
                    WearLaw(5e-14),
                    None,
                    0.4,
                    interface=cd,
                    numerics=Numerics(update="geometry"),
                )
            )
        )


def test_the_cost_study_measures_both_interfaces(tmp_path):
    from studyload import load_study

    study = load_study("condensed_cost")
    (row,) = study.main(sizes=(3000,), steps=4, pressures=2, out=tmp_path)
    assert row["pad_wear_rel_diff"] < TOL and row["pressure_rel_diff"] < TOL
    assert row["condense_s"] > 0 and row["fe_step_s"] > 0 and row["condensed_step_s"] > 0
    assert row["fe_sweep_s"] == pytest.approx(2 * row["fe_running_in_s"])
    assert (tmp_path / "figures" / "condensed_cost.png").stat().st_size > 10_000
    assert (tmp_path / "data" / "condensed_cost.json").exists()


def test_the_cost_study_times_amg_columns_against_the_lu():
    from studyload import load_study

    study = load_study("condensed_cost")
    row = study.amg_columns(3000, columns=3)
    # the columns that reach 1e-12 are the LU's columns
    assert row["amg_column_rel_diff"] < TOL
    assert len(row["amg_iterations"]) + len(row["amg_stalled_residuals"]) == 3
    assert row["lu_s_per_column"] > 0 and row["amg_s_per_column"] > 0
    assert row["amg_all_columns_s"] > row["amg_setup_s"]


def test_a_resumed_condensed_run_repeats_the_uninterrupted_one(tmp_path):
    from itertools import islice

    model = BrakeModel(size=8e-3, rotor="rigid")
    law = WearLaw(5e-14)

    def run(**kw):
        itf = CondensedInterface(model, 1e6, 0.4, cache=tmp_path)
        return wear_history(
            Run(
                model,
                1e6,
                50.0,
                60.0,
                law,
                None,
                0.4,
                interface=itf,
                numerics=Numerics(steps=6, scheme="implicit"),
            ),
            **kw,
        )

    whole = list(run())
    ck = tmp_path / "run.npz"
    gen = run(checkpoint=ck, every=1)
    # stopped while step 3 is handled: step 2 is the last checkpointed (a step is
    # checkpointed once the caller asks for the next)
    assert len(list(islice(gen, 3))) == 3
    gen.close()
    rest = list(run(checkpoint=ck, every=1, resume=True))
    assert [s.step for s in rest] == [3, 4, 5, 6]
    assert np.array_equal(rest[-1].pad_wear, whole[-1].pad_wear)
    assert np.array_equal(rest[-1].pressure_end, whole[-1].pressure_end)


def test_a_set_near_a_factorised_one_is_solved_by_an_update(pair):
    model, fe, _ = pair
    cd = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)   # nothing factorised yet
    off = _offset(cd)
    cd.solve(off, None, mu=0.4)                  # factorises the sets it meets
    shifted = off + 0.3e-6 * np.sin(40 * cd.r)   # moves a few edge nodes
    b = cd.solve(shifted, None, mu=0.4)
    a = fe.solve(shifted, None, mu=0.4)
    assert b.info["updates"] >= 1
    assert np.array_equal(a.active, b.active)
    assert _rel(a.pressure, b.pressure) < TOL


def test_friction_on_an_interface_built_without_it_is_refused():
    model = BrakeModel(size=12e-3, rotor="rigid")
    cd = CondensedInterface(model, 1e6, 0.0, cache=False)
    with pytest.raises(WearError, match="built without friction"):
        cd.solve(np.zeros(cd.area.size), None, mu=0.3)
    assert cd.solve(np.zeros(cd.area.size), None, mu=0.0).active.any()


@pytest.mark.parametrize("fraction", [0.0, 1.5, float("nan")])
def test_a_bad_validity_fraction_is_refused_before_condensing(fraction, tmp_path):
    model = BrakeModel(size=12e-3, rotor="rigid")
    with pytest.raises(WearError, match=r"valid_fraction = .* is not allowed; need 0 <"):
        CondensedInterface(model, 1e6, 0.4, cache=tmp_path, valid_fraction=fraction)
    assert not list(tmp_path.glob("*.npz"))


def test_a_set_is_solved_the_same_whatever_was_solved_before(pair):
    """The set solves depend on the set alone (a resumed run repeats the
    uninterrupted one): a fresh interface gives the same bits."""
    model, fe, cd = pair
    eps = 2e-12 * np.ones(cd.area.size)
    near = _offset(cd) * 0.05                   # most nodes closed: solved from the base
    first = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)
    first.solve(_offset(cd), None, compliance=eps, mu=0.4)
    first.solve(near * 0.7, None, compliance=eps, mu=0.4)
    a = first.solve(near, None, compliance=eps, mu=0.4)
    fresh = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)
    b = fresh.solve(near, None, compliance=eps, mu=0.4)
    assert a.info["updates"] >= 1 and 0 < (~a.active).sum()
    assert np.array_equal(a.active, b.active)
    assert np.array_equal(a.pressure, b.pressure)
    ref = fe.solve(near, None, compliance=eps, mu=0.4)
    assert _rel(ref.pressure, a.pressure) < TOL


def test_a_settled_contact_is_solved_without_factorising(pair):
    """The same compliance step after step (fixed steps): the base is
    factorised once, and each later solve of a set near it takes its Schur
    system (kept per set), no factorisation."""
    model, fe, _ = pair
    cd = CondensedInterface(model, 1e6, 0.4, fe=fe, cache=False)
    eps = 2e-12 * np.ones(cd.area.size)
    off = _offset(cd) * 0.05
    infos = [cd.solve(off * s, None, compliance=eps, mu=0.4).info for s in (1.0, 1.0, 1.0)]
    assert infos[0]["factorisations"] >= 1
    assert [i["factorisations"] for i in infos[1:]] == [0, 0]
    assert all(i["updates"] >= 1 for i in infos)


def test_the_condensation_and_the_set_solves_run_on_one_blas_thread(monkeypatch):
    """Beside another busy process, OpenBLAS's threads spin against it: the
    sparse LU of the condensation and the dense set solves take one thread."""
    from threadpoolctl import threadpool_info

    import brakewear.interfaces.condensation as compliance
    import brakewear.interfaces.condensed as condensed

    seen = []

    def spy(fn):
        def wrapped(*a, **kw):
            seen.append({d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas"})
            return fn(*a, **kw)
        return wrapped
    monkeypatch.setattr(condensed, "lu_factor", spy(condensed.lu_factor))
    monkeypatch.setattr(compliance, "body_solves", spy(compliance.body_solves))
    model = BrakeModel(size=12e-3, rotor="rigid")
    cd = CondensedInterface(model, 1e6, 0.4, cache=False)
    cd.solve(np.zeros(cd.area.size), None, compliance=1e-12 * np.ones(cd.area.size))
    if not any(seen):
        pytest.skip("no BLAS library found in this process")
    assert len(seen) >= 2 and all(s == {1} for s in seen)
