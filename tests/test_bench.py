"""The elasticity benchmark on a tiny size: keys, types, AMG against direct, JSON output."""
import json
import subprocess
import sys

import numpy as np
import pytest
import skfem as fem

import brakewear.bench as bench
from brakewear.fem import assemble_stiffness, elasticity_form, scalar_element
from brakewear.fem.forms import _intorder
from brakewear.mesh import annulus_mesh

KEYS = {"dofs": int, "mesh_s": float, "assemble_s": float, "amg_setup_s": float, "solve_s": float,
        "total_s": float, "iterations": int, "rel_residual": float, "peak_rss_mb": float,
        "direct_s": float, "direct_max_diff": float, "total_exponent": float}


@pytest.fixture(scope="module")
def rows():
    return bench.bench_elasticity(sizes=(2000, 4000), direct_max_dofs=10_000)


def test_rows_keys_and_types(rows):
    assert len(rows) == 2
    for row in rows:
        for key, typ in KEYS.items():
            assert isinstance(row[key], typ), (key, row[key])
        parts = row["assemble_s"] + row["amg_setup_s"] + row["solve_s"]
        assert row["total_s"] == pytest.approx(parts, rel=1e-9)
        assert row["rel_residual"] <= 1e-7
        assert row["iterations"] >= 1
        assert row["peak_rss_mb"] > 10
        assert 0.5 * row["target_dofs"] < row["dofs"] < 2 * row["target_dofs"]
    assert rows[0]["dofs"] < rows[1]["dofs"]


def test_amg_matches_direct(rows):
    for row in rows:
        assert row["direct_max_diff"] < 1e-6


def test_direct_skipped_above_limit():
    row = bench.run_elasticity_case(3000, direct_max_dofs=100)
    assert row["direct_s"] is None and row["direct_max_diff"] is None


def test_fit_exponent():
    rows = [{"dofs": n, "total_s": 2e-6 * n ** 1.1} for n in (1e4, 1e5, 1e6)]
    assert bench.fit_exponent(rows) == pytest.approx(1.1)
    assert bench.fit_exponent(rows[:1]) is None


def test_table(rows):
    text = bench.format_table(rows)
    assert "dofs" in text and "dofs^" in text
    assert str(rows[0]["dofs"]) in text


def test_cli_json_lines():
    out = subprocess.run([sys.executable, "-m", "brakewear.bench", "elasticity", "--json",
                          "--sizes", "1500", "--direct-max", "5000"],
                         capture_output=True, text=True, check=True).stdout
    lines = [json.loads(line) for line in out.splitlines() if line.strip()]
    assert len(lines) == 1
    assert lines[0]["direct_max_diff"] < 1e-6
    assert set(KEYS) - {"total_exponent"} <= set(lines[0])


def test_bench_parser():
    import argparse

    # as brakewear.cli wires it: the bench command's subparsers
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="command")
    b = sub.add_parser("bench")
    bench.add_bench_parser(b.add_subparsers(dest="bench", required=True))
    args = ap.parse_args(["bench", "elasticity", "--json", "--sizes", "3e4", "1e5",
                          "--direct-max", "5000"])
    assert args.json and args.sizes == [3e4, 1e5] and args.direct_max == 5000
    assert args.bench == "elasticity" and args.func is bench.run_bench


@pytest.mark.parametrize("order", [1, 2])
def test_fast_assembly_matches_bilinear_form(order):
    # the chunked assembly against skfem's BilinearForm, anisotropic C, small chunks
    rng = np.random.default_rng(3)
    A = rng.random((6, 6))
    C = A @ A.T + 6 * np.eye(6)
    m = annulus_mesh(0.09, 0.15, 0.01, 2, 8, 2, angle=np.pi / 2, order=order)
    K, pattern = assemble_stiffness(m, C, chunk=29)
    elem = scalar_element(m)
    ref = elasticity_form(C).assemble(
        fem.Basis(m, fem.ElementVector(elem), intorder=_intorder(elem))
    )
    assert abs(K - ref).max() <= 1e-12 * abs(ref).max()
    K2, _ = assemble_stiffness(m, C, pattern=pattern)
    assert abs(K2 - K).max() <= 1e-12 * abs(ref).max()


# ------------------------------------------------------------- contact bench --

CONTACT_KEYS = {"case": str, "dofs": int, "contact_solve_s": float, "elasticity_solve_s": float,
                "ratio": float, "active_set_iterations": int, "linear_iterations": int,
                "direct_kkt_superlu_s": float, "direct_kkt_s": float, "kkt_multiplier_diff": float,
                "assemble_s": float, "peak_rss_mb": float}


@pytest.fixture(scope="module")
def contact_rows():
    return bench.bench_contact(sizes=(4000,), cases=("hertz", "brake"), direct_max_dofs=20_000)


def test_contact_rows_keys_and_types(contact_rows):
    assert [r["case"] for r in contact_rows] == ["hertz", "brake"]
    for row in contact_rows:
        assert "error" not in row, row.get("error")
        for key, typ in CONTACT_KEYS.items():
            assert isinstance(row[key], typ), (row["case"], key, row[key])
        assert "direct_kkt_pardiso_s" in row  # None where pypardiso is not installed
        assert row["ratio"] == pytest.approx(row["contact_solve_s"] / row["elasticity_solve_s"])
        for key in ("contact_solve_s", "elasticity_solve_s"):  # the faster of two runs
            assert len(row[key + "_pair"]) == 2 and row[key] == min(row[key + "_pair"])
        assert row["active_set_iterations"] >= 1 and row["linear_iterations"] >= 1
        # the KKT system at the converged active set gives solve_contact's multipliers
        assert row["kkt_multiplier_diff"] < 1e-5
        assert 0.4 * row["target_dofs"] < row["dofs"] < 2.5 * row["target_dofs"]
    hertz, brake = contact_rows
    assert isinstance(hertz["p0_error"], float) and isinstance(hertz["a_error"], float)
    assert brake["p0_error"] is None and brake["a_error"] is None
    # a wear step with the shared hierarchy from the converged set: one set, same answer
    assert brake["contact_step_active_set_iterations"] <= 2
    assert brake["contact_step_diff"] < 1e-6
    assert brake["contact_step_linear_iterations"] < brake["linear_iterations"]
    # one solve at the converged set with its own hierarchy, and the speed-ups it gives
    for row in contact_rows:
        assert 1 <= row["fixed_set_linear_iterations"] < row["linear_iterations"], row["case"]
        assert row["speedup_vs_direct_fixed_set"] == pytest.approx(
            row["direct_kkt_s"] / row["fixed_set_solve_s"])
    assert brake["speedup_vs_direct_step"] == pytest.approx(
        brake["direct_kkt_s"] / brake["contact_step_s"])
    # Hertz at its converged set and last far field: one set, the same answer
    assert hertz["fixed_set_active_set_iterations"] == 1
    assert hertz["fixed_set_diff"] < 1e-7
    assert "speedup_vs_direct_step" not in hertz
    # PARDISO's symmetric mode is tried where the system is symmetric (frictionless)
    assert "direct_kkt_pardiso_sym_s" in hertz and "direct_kkt_pardiso_sym_s" not in brake
    for row in contact_rows:  # the cold problem solved by a direct active-set loop
        if row["direct_active_set_s"] is None:  # pypardiso not installed
            assert row["speedup_vs_direct_active_set"] is None
            continue
        assert row["direct_active_set_same_set"], row["case"]
        assert row["direct_active_set_force_diff"] < 1e-6
        assert row["speedup_vs_direct_active_set"] == pytest.approx(
            row["direct_active_set_s"] / row["contact_solve_s"])
    assert "case" in bench.format_contact_table(contact_rows)


def test_contact_direct_skipped_above_limit():
    row = bench.run_contact_case("hertz", 3000, direct_max_dofs=100)
    assert row["direct_kkt_s"] is None and row["direct_kkt_superlu_s"] is None
    assert row["direct_kkt_pardiso_s"] is None and row["speedup_vs_direct"] is None


@pytest.fixture(scope="module")
def hertz_kkt():
    """A coarse Hertz contact solve and the KKT system at its converged set."""
    from brakewear.contact import solve_contact
    from brakewear.contact.hertz import DELTA, GAP_TOL, hertz_force, hertz_problem

    prob = hertz_problem(0.5)
    vals = prob.fixed_values(hertz_force())
    res = solve_contact(prob.K, np.zeros(prob.dofs), prob.fixed, prob.mesh.p, [prob.pair],
                        fixed_values=vals, linear="direct", gap_tol=GAP_TOL * DELTA)
    M, rhs, free, idx = bench.kkt_system(prob.K, np.zeros(prob.dofs), prob.fixed, vals,
                                         prob.pair, res.active[0])
    return res, M, rhs, free, idx


def test_contact_kkt_system_matches_contact_solve(hertz_kkt):
    res, M, rhs, free, idx = hertz_kkt
    import scipy.sparse.linalg as spla

    x = spla.spsolve(M.tocsc(), rhs)
    np.testing.assert_allclose(x[:free.size], res.u[free], atol=1e-10 * np.abs(res.u).max())
    np.testing.assert_allclose(x[free.size:], res.force[0][idx],
                               atol=1e-8 * np.abs(res.force[0]).max())
    assert abs(M - M.T).max() <= 1e-12 * abs(M).max()  # frictionless: symmetric


def test_symmetric_upper_keeps_every_diagonal_entry():
    import scipy.sparse as sp

    M = sp.csr_matrix(np.array([[4.0, 1.0, 2.0], [1.0, 3.0, 0.0], [2.0, 0.0, 0.0]]))
    U = bench.symmetric_upper(M)
    assert U.nnz == 5 and U.has_sorted_indices  # (2, 2) stored though zero
    np.testing.assert_array_equal(U.toarray(), np.triu(M.toarray()))
    np.testing.assert_array_equal(U.diagonal(), [4.0, 3.0, 0.0])
    assert all(U.indices[U.indptr[i]] == i for i in range(3))  # diagonal first in each row


def test_pardiso_symmetric_kkt_matches_contact_solve(hertz_kkt):
    pytest.importorskip("pypardiso")
    res, M, rhs, free, idx = hertz_kkt
    row = {}
    bench.kkt_solves(M, rhs, free.size, res.force[0][idx], row, superlu=False, symmetric=True)
    assert row["kkt_multiplier_diff_pardiso"] < 1e-8
    assert row["kkt_multiplier_diff_pardiso_sym"] < 1e-8
    assert row["direct_kkt_s"] == min(row["direct_kkt_pardiso_s"], row["direct_kkt_pardiso_sym_s"])


def test_direct_active_set_finds_the_contact_solution():
    """The PARDISO active-set loop (the direct solve of a cold problem) ends at
    solve_contact's set and forces; a budget it cannot meet raises."""
    pytest.importorskip("pypardiso")
    from brakewear.contact import solve_contact
    from brakewear.contact.hertz import DELTA, GAP_TOL, hertz_force, hertz_problem

    prob = hertz_problem(0.5)
    vals = prob.fixed_values(hertz_force())
    args = (prob.K, np.zeros(prob.dofs), prob.fixed, vals, prob.pair, GAP_TOL * DELTA)
    res = solve_contact(prob.K, np.zeros(prob.dofs), prob.fixed, prob.mesh.p, [prob.pair],
                        fixed_values=vals, linear="direct", gap_tol=GAP_TOL * DELTA)
    out = bench.direct_active_set(*args, symmetric=True)
    assert out["iterations"] >= 2  # the start set (g0 <= gap_tol) is not the answer
    np.testing.assert_array_equal(out["active"], res.active[0])
    np.testing.assert_allclose(out["force"], res.force[0], atol=1e-8 * res.force[0].max())
    with pytest.raises(RuntimeError, match="did not settle in 1 iterations"):
        bench.direct_active_set(*args, symmetric=True, max_iter=1)


def test_direct_active_set_runs_on_the_shared_driver_with_any_factorisation():
    """The benchmark's direct active-set loop is the shared driver's: with SciPy's
    sparse LU in place of PARDISO it ends at solve_contact's set and forces (the
    same rule from the same start), and an exhausted budget is an ActiveSetError."""
    from scipy.sparse.linalg import spsolve

    from brakewear.contact import solve_contact
    from brakewear.contact.hertz import DELTA, GAP_TOL, hertz_force, hertz_problem
    from brakewear.errors import ActiveSetError

    prob = hertz_problem(0.5)
    vals = prob.fixed_values(hertz_force())
    args = (prob.K, np.zeros(prob.dofs), prob.fixed, vals, prob.pair, GAP_TOL * DELTA)
    res = solve_contact(prob.K, np.zeros(prob.dofs), prob.fixed, prob.mesh.p, [prob.pair],
                        fixed_values=vals, linear="direct", gap_tol=GAP_TOL * DELTA)
    lu = lambda M, rhs: spsolve(M.tocsc(), rhs)  # noqa: E731
    out = bench.direct_active_set(*args, symmetric=True, factorize=lu)
    assert out["iterations"] >= 2
    np.testing.assert_array_equal(out["active"], res.active[0])
    np.testing.assert_allclose(out["force"], res.force[0], atol=1e-8 * res.force[0].max())
    with pytest.raises(ActiveSetError, match="did not settle in 1 iterations"):
        bench.direct_active_set(*args, symmetric=True, max_iter=1, factorize=lu)


def test_contact_cli_json_and_parser():
    import argparse

    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="command")
    b = sub.add_parser("bench")
    bench.add_bench_parser(b.add_subparsers(dest="bench", required=True))
    args = ap.parse_args(["bench", "contact", "--json", "--sizes", "5e4", "--cases", "hertz",
                          "--direct-max", "1e4", "--repeats", "2"])
    assert args.bench == "contact" and args.func is bench.run_bench
    assert args.sizes == [5e4] and args.cases == ["hertz"] and args.direct_max == 1e4
    assert args.repeats == 2 and args.json
    out = subprocess.run([sys.executable, "-m", "brakewear.bench", "contact", "--json",
                          "--sizes", "3000", "--cases", "hertz", "--direct-max", "0"],
                         capture_output=True, text=True, check=True).stdout
    lines = [json.loads(line) for line in out.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0]["case"] == "hertz" and lines[0]["direct_kkt_s"] is None


# ------------------------------------------------------------------ wear ---

def test_wear_bench_keys_and_shares():
    row = bench.run_wear_case(3000, steps=3, duration=600.0, size=10e-3)
    for key in ("dofs", "steps", "total_s", "per_step_s", "contact_share", "assembly_share",
                "motion_share", "contact_solve_s", "step_over_contact"):
        assert key in row, key
    assert row["steps"] == 3 and row["contact_solves"] == 4   # and the first solve
    assert row["motion_share"] == 0.0            # gap mode moves nothing
    shares = row["contact_share"] + row["assembly_share"] + row["motion_share"]
    assert 0.0 < shares <= 1.0, shares
    assert row["per_step_s"] == pytest.approx(row["total_s"] / 3)
    assert row["step_over_contact"] == pytest.approx(row["per_step_s"] / row["contact_solve_s"])


def test_wear_bench_times_the_condensed_and_the_foundation_interface():
    rows = bench.bench_wear([3000], steps=3, duration=600.0,
                            interfaces=("fe", "condensed", "winkler"))
    assert [r["interface"] for r in rows] == ["fe", "condensed", "winkler"]
    fe, cd, wk = rows
    assert fe["interface_s"] == 0.0 and cd["interface_s"] > 0.0
    assert cd["interface_over_contact"] == pytest.approx(cd["interface_s"]
                                                         / cd["contact_solve_s"])
    assert cd["steps"] == wk["steps"] == 3 and cd["contact_nodes"] == fe["contact_nodes"]
    # every set solve of the running-in: from a factorisation or a Schur update
    assert cd["factorisations"] >= 1 and cd["factorisations"] + cd["updates"] >= 3
    assert cd["interface_over_contact_cpu"] == pytest.approx(cd["interface_cpu_s"]
                                                             / cd["contact_solve_cpu_s"])
    table = bench.format_wear_table(rows)
    assert "condensed: built in" in table and "winkler" in table
    with pytest.raises(ValueError, match="update 'gap'"):
        bench.run_wear_case(3000, steps=2, update="geometry", interface="condensed")


def test_wear_bench_times_the_full_model_on_the_half_models_mesh():
    rows = bench.bench_wear([3000], steps=2, duration=600.0, layouts=("half", "full"))
    half, full = rows
    assert (half["layout"], full["layout"]) == ("half", "full")
    assert full["size_m"] == half["size_m"]
    # both pads and the whole rotor: about twice the DOFs and the contact nodes
    assert 1.5 < full["dofs"] / half["dofs"] < 2.2
    assert full["contact_nodes"] == 2 * half["contact_nodes"]
    assert "full over half" in bench.format_wear_table(rows)
    with pytest.raises(ValueError, match="layout = 'quarter'"):
        bench.run_wear_case(3000, steps=2, layout="quarter")


@pytest.mark.slow
def test_wear_bench_geometry_mode_times_the_motion():
    row = bench.run_wear_case(3000, steps=2, duration=600.0, update="geometry", size=10e-3)
    assert row["motion_share"] > 0.0 and row["contact_solves"] == 5   # 1 + 2 x (trial, moved)
    assert row["contact_share"] + row["assembly_share"] + row["motion_share"] <= 1.0


def test_wear_bench_cli_json():
    out = subprocess.run([sys.executable, "-m", "brakewear.bench", "wear", "--json", "--sizes",
                          "3000", "--steps", "2", "--duration", "300"],
                         capture_output=True, text=True, check=True)
    row = json.loads(out.stdout.strip().splitlines()[-1])
    assert row["bench"] == "wear" and row["steps"] == 2


def test_rough_bench_rows_table_and_parser():
    """`brakewear bench rough` on a small grid: the half-space's figures, tamaas's when it is
    installed (the same area), the foundation far faster than the half-space."""
    import argparse
    import importlib.util

    from brakewear.bench import add_bench_parser, format_rough_table, run_rough_case
    row = run_rough_case(64, tol=1e-8, repeats=3)
    assert row["n"] == 64 and row["ours_iterations"] > 0
    assert 0 < row["ours_area_fraction"] < 0.2
    assert row["ours_gap_error"] < 1e-5 and row["ours_tol100_gap_error"] < row["ours_gap_error"]
    assert row["sphere_foundation_s"] > 0 and row["halfspace_over_foundation"] > 1
    if importlib.util.find_spec("tamaas") is not None:
        assert abs(row["area_difference"]) < 0.02
    else:
        assert "tamaas_s" not in row
    table = format_rough_table([row])
    assert "64^2" in table and table.count("\n") == 2
    ap = argparse.ArgumentParser()
    add_bench_parser(ap.add_subparsers(dest="bench"))
    args = ap.parse_args(["rough", "--sizes", "128", "--tol", "1e-6", "--json"])
    assert args.bench == "rough" and args.sizes == [128] and args.tol == 1e-6 and args.json
