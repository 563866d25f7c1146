"""pyamg solver: convergence factor, agreement with a direct solve, failures raise."""
import numpy as np
import pytest
import scipy.sparse as sp

from brakewear.errors import ConvergenceError
from brakewear.fem import apply_dirichlet, assemble_pressure, assemble_stiffness, boundary_dofs
from brakewear.materials import get_material
from brakewear.mesh import annulus_mesh
from brakewear.solvers import amg_solver, direct_solve, rigid_body_modes


@pytest.fixture(scope="module")
def ring():
    m = annulus_mesh(0.09, 0.15, 0.012, 10, 120, 4)
    K, _ = assemble_stiffness(m, get_material("grey_cast_iron"))
    f = assemble_pressure(m, "top", 1e6)
    fixed = boundary_dofs(m, "inner")
    Kd, fd = apply_dirichlet(K, f, fixed)
    return m, K, Kd, fd, fixed


def test_amg_matches_direct_and_converges_fast(ring):
    m, K, Kd, fd, fixed = ring
    s = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-10)
    u = s.solve(fd)
    ud = direct_solve(Kd, fd)
    err = np.abs(u - ud).max() / np.abs(ud).max()
    assert err < 1e-7, f"AMG vs direct: {err:.2e}"
    factor = s.info.convergence_factor
    assert factor < 0.6, f"mean residual reduction per iteration {factor:.3f}"
    assert s.info.converged and s.info.relative_residual < 1e-10


@pytest.mark.filterwarnings("ignore:Having less target vectors")
def test_near_nullspace_pays(ring):
    m, K, Kd, fd, fixed = ring
    with_b = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-8)
    with_b.solve(fd)
    without = amg_solver(Kd, B=np.ones((Kd.shape[0], 1)), tol=1e-8, maxiter=2000)
    without.solve(fd)
    assert with_b.info.iterations < without.info.iterations, (
        f"rigid-body modes: {with_b.info.iterations} its, constant only: {without.info.iterations}")


def test_hierarchy_reuse_on_changed_matrix(ring):
    m, K, Kd, fd, fixed = ring
    s = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-10)
    u1 = s.solve(fd)
    K2 = Kd * 1.05  # a stiffer material: the old hierarchy still preconditions well
    u2 = s.solve(fd, A=K2)
    assert s.builds == 1
    assert np.allclose(u2 * 1.05, u1, rtol=1e-6, atol=1e-9 * np.abs(u1).max())


def test_unconstrained_body_raises_with_figures():
    m = annulus_mesh(0.09, 0.15, 0.012, 3, 24, 2)
    K, _ = assemble_stiffness(m, get_material("grey_cast_iron"))
    f = assemble_pressure(m, "top", 1e6)  # net force on a floating body: no solution
    s = amg_solver(K.tocsr(), coords=m.p, tol=1e-10, maxiter=30)
    with pytest.raises(ConvergenceError, match="relative residual") as e:
        s.solve(f)
    assert "rigid motion" in str(e.value)
    assert not e.value.info.converged and e.value.info.relative_residual > 1e-10


def test_direct_refuses_large_systems():
    A = sp.identity(200_000, format="csr")
    with pytest.raises(ValueError, match="max_dofs"):
        direct_solve(A, np.ones(200_000))


def test_rigid_body_modes_zero_fixed_rows():
    B = rigid_body_modes(np.random.default_rng(1).normal(size=(3, 10)), fixed=np.array([0, 4]))
    assert B.shape == (30, 6) and np.all(B[[0, 4]] == 0) and np.linalg.matrix_rank(B) == 6


def test_solves_are_repeatable_and_leave_the_global_rng_alone(ring):
    m, K, Kd, fd, fixed = ring
    # the global generator itself is what is checked
    np.random.seed(7)  # noqa: NPY002
    expected_next = np.random.rand()  # noqa: NPY002
    np.random.seed(7)  # noqa: NPY002
    u1 = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-8).solve(fd)
    drawn = np.random.rand()  # noqa: NPY002
    assert drawn == expected_next, "the build consumed the caller's random numbers"
    u2 = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-8).solve(fd)
    assert np.array_equal(u1, u2), "two identical solves differ"


def test_refreshed_copy_leaves_the_base_alone_and_is_history_free(ring):
    m, K, Kd, fd, fixed = ring
    base = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-10)
    before = [lv.A.copy() for lv in base.ml.levels]
    rng = np.random.default_rng(5)
    bump = sp.diags(np.where(rng.random(Kd.shape[0]) < 0.01, 0.5, 0.0) * Kd.diagonal())
    A1, A2 = (Kd + bump).tocsr(), (Kd + 2 * bump).tocsr()
    direct = base.refreshed(A2).solve(fd)
    via = base.refreshed(A1)
    via.solve(fd)
    again = base.refreshed(A2).solve(fd)  # after another refresh: the same answer, bit for bit
    assert np.array_equal(direct, again)
    for lv, A0 in zip(base.ml.levels, before):
        assert (lv.A != A0).nnz == 0, "refreshed() changed the base hierarchy"
    ud = direct_solve(A2, fd)
    assert np.abs(direct - ud).max() < 1e-7 * np.abs(ud).max()


def test_refreshed_levels_are_the_galerkin_products_of_the_new_matrix(ring):
    """Every refreshed level is R A P of the one above, for a change that couples two
    distant DOFs (outside every level's pattern) and one on the diagonal."""
    m, K, Kd, fd, fixed = ring
    base = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-10)
    Kd = Kd.tocsr()
    free = np.setdiff1d(np.arange(Kd.shape[0]), fixed)
    i, j = free[10], free[-10]
    c = 0.1 * min(Kd[i, i], Kd[j, j])
    dA = sp.csr_matrix(([c, -c, -c, c], ([i, i, j, j], [i, j, i, j])), shape=Kd.shape)
    A = (Kd + dA).tocsr()
    new = base.refreshed(A)
    expected = A
    for k, lv in enumerate(new.ml.levels):
        assert abs(lv.A - expected).max() <= 1e-12 * abs(expected).max(), f"level {k}"
        if hasattr(lv, "P"):
            expected = (lv.R @ expected @ lv.P).tocsr()
    ud = direct_solve(A, fd)
    assert np.abs(new.solve(fd) - ud).max() < 1e-6 * np.abs(ud).max()


def test_v_cycle_is_pyamgs_v_cycle(ring):
    """The preconditioner (own V-cycle without pyamg's residual norms) applies the same cycle."""
    m, K, Kd, fd, fixed = ring
    s = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-8)
    r = np.random.default_rng(3).normal(size=Kd.shape[0])
    ours, theirs = s.M @ r, s.ml.aspreconditioner(cycle="V") @ r
    assert np.abs(ours - theirs).max() <= 1e-12 * np.abs(theirs).max()
    # symmetric (CG needs it): <M a, b> = <a, M b>
    a, b = r, np.random.default_rng(4).normal(size=r.size)
    lhs, rhs = (s.M @ a) @ b, a @ (s.M @ b)
    assert abs(lhs - rhs) <= 1e-10 * abs(lhs), f"<Ma,b> {lhs:.6e} vs <a,Mb> {rhs:.6e}"


def test_blas_threads_are_one_inside_and_restored_after():
    from threadpoolctl import threadpool_info

    from brakewear.solvers.threads import _single_threaded_blas

    def blas_threads():
        return [d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas"]

    before = blas_threads()
    if not before:
        pytest.skip("no BLAS library found in this process")
    with _single_threaded_blas():
        assert blas_threads() == [1] * len(before)
    assert blas_threads() == before


def test_batched_block_pinv_is_pyamgs():
    from pyamg.util.linalg import pinv_array

    from brakewear.solvers.patches import _block_pinv

    rng = np.random.default_rng(2)
    X = rng.normal(size=(400, 6, 9))
    a = X @ X.transpose(0, 2, 1)          # SPD blocks, as B^T B
    a[::7, 5, :] = a[::7, :, 5] = 0.0     # a supported DOF: singular
    a[3::11] = rng.normal(size=a[3::11].shape)  # general blocks
    a[5::13, :, 0] = a[5::13, :, 1] * (1 + 1e-13)  # nearly singular: pinv's cut-off acts
    a[6] = 0.0
    ref, got = a.copy(), a.copy()
    pinv_array(ref)
    looped = []
    _block_pinv(got, None, lambda b, tol: (looped.append(len(b)), pinv_array(b, tol)))
    assert sum(looped) < 0.3 * len(a), f"{sum(looped)} of {len(a)} blocks took pyamg's loop"
    scale = np.maximum(np.abs(ref).max(axis=(1, 2)), 1e-300)
    err = (np.abs(ref - got).max(axis=(1, 2)) / scale).max()
    assert err < 1e-8, f"batched pseudo-inverse differs from pyamg's by {err:.2e}"
    spd = a[1:3].copy()
    _block_pinv(spd)
    assert np.allclose(spd @ a[1:3], np.eye(6), atol=1e-9)


@pytest.mark.parametrize("duplicates", [False, True])
def test_vectorised_bsr_sum_duplicates_is_scipys(duplicates):
    """Unsorted blocks (as from tobsr) and, if asked, duplicate ones: the same
    arrays as scipy's own loop, and the patch is undone after the setup."""
    from brakewear.solvers.patches import _BSR_BASE, _bsr_sum_duplicates, _vectorised_bsr_dedupe

    rng = np.random.default_rng(4)
    n_brow, per_row = 50, 6
    rows = np.repeat(np.arange(n_brow), per_row)
    cols = np.concatenate([rng.permutation(40)[:per_row] for _ in range(n_brow)])
    if duplicates:
        cols[1::per_row] = cols[::per_row]  # the second block of each row repeats the first
    indptr = np.arange(0, rows.size + 1, per_row)
    data = rng.normal(size=(rows.size, 3, 3))

    def make():
        return sp.bsr_array((data.copy(), cols.copy(), indptr.copy()), shape=(150, 120))

    ref, got = make(), make()
    assert not got.has_canonical_format
    _BSR_BASE.sum_duplicates(ref)
    _bsr_sum_duplicates(got)
    assert got.has_canonical_format
    for name in ("indptr", "indices", "data"):
        np.testing.assert_array_equal(getattr(got, name), getattr(ref, name), err_msg=name)
    np.testing.assert_allclose(got.toarray(), make().toarray(), atol=1e-14)
    saved = _BSR_BASE.sum_duplicates
    with _vectorised_bsr_dedupe():
        assert _BSR_BASE.sum_duplicates is _bsr_sum_duplicates
    assert _BSR_BASE.sum_duplicates is saved


@pytest.mark.parametrize("seed", range(6))
def test_patched_matrix_is_the_sum_for_any_sequence_of_differences(seed):
    """M + D on the shared buffer, entry for entry, whatever difference came before;
    with Z inside M's pattern the structure is M's own arrays."""
    from brakewear.solvers import PatchedMatrix

    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 60))
    M = sp.random(n, n, density=0.3, random_state=seed, format="csr")
    M.sum_duplicates()  # canonical, as the levels of a hierarchy are
    Z = sp.random(n, n, density=0.1, random_state=seed + 100, format="csr")
    inside = seed % 2 == 0
    if inside:  # the coarse-level case: the pattern holds every difference already
        Z = sp.csr_matrix((np.ones(M.nnz), M.indices, M.indptr), shape=M.shape)
        Z = Z.multiply(rng.random((n, n)) < 0.5).tocsr()
    pm = PatchedMatrix(M, Z)
    if inside:
        assert np.shares_memory(pm.indices, M.indices) and np.shares_memory(pm.indptr, M.indptr)
    M0 = M.copy()
    for _ in range(4):
        D = Z.copy()
        D.data = rng.normal(size=D.nnz)
        D = D.multiply(rng.random((n, n)) < 0.6).tocsr()
        A = pm.matrix(D)
        assert np.array_equal(A.toarray(), (M + D).toarray())
    assert (M != M0).nnz == 0, "M itself changed"
    outside = sp.csr_matrix(([1.0], ([0], [0])), shape=M.shape)
    if Z[0, 0] == 0:
        with pytest.raises(ValueError, match="outside the pattern"):
            pm.matrix(outside)


def two_rings(ring):
    """Two copies of the ring, the second's inner face tied to the first's outer one
    by springs: a two-body operator."""
    m, K, Kd, fd, fixed = ring
    n = Kd.shape[0]
    A = sp.block_diag([Kd, Kd], format="csr")
    r = np.hypot(m.p[0], m.p[1])
    outer = np.flatnonzero(np.isclose(r, r.max()))[:20]
    k = Kd.diagonal().max()
    dofs = (3 * outer[:, None] + np.arange(3)).ravel()
    rows = np.concatenate([dofs, dofs + n, dofs, dofs + n])
    cols = np.concatenate([dofs, dofs + n, dofs + n, dofs])
    vals = np.concatenate([np.full(2 * dofs.size, k), np.full(2 * dofs.size, -k)])
    A = (A + sp.csr_matrix((vals, (rows, cols)), shape=A.shape)).tocsr()
    coords = np.hstack([m.p, m.p])
    fixed2 = np.concatenate([fixed, fixed + n])
    labels = np.repeat([0, 1], n // 3)
    return A, np.concatenate([fd, fd]), coords, fixed2, labels


def test_bodies_keep_every_prolongator_inside_its_body(ring):
    A, f, coords, fixed, labels = two_rings(ring)

    def shared_columns(s):
        """Coarse DOFs of the first level that take values in both bodies."""
        P = sp.csc_matrix(s.ml.levels[0].P)
        body = np.repeat(labels, 3)[P.indices]
        col = np.repeat(np.arange(P.shape[1]), np.diff(P.indptr))
        lo = np.full(P.shape[1], 2)
        hi = np.full(P.shape[1], -1)
        np.minimum.at(lo, col, body)
        np.maximum.at(hi, col, body)
        return int(np.count_nonzero(lo < hi))

    split = amg_solver(A.tobsr(blocksize=(3, 3)), coords=coords, fixed=fixed, tol=1e-10,
                       bodies=labels)
    joint = amg_solver(A.tobsr(blocksize=(3, 3)), coords=coords, fixed=fixed, tol=1e-10)
    assert shared_columns(joint) > 0, "the springs are too weak to matter"
    assert shared_columns(split) == 0, "a prolongator couples two bodies"
    x = split.solve(f)
    assert np.linalg.norm(A @ x - f) <= 1e-9 * np.linalg.norm(f)
    with pytest.raises(ValueError, match="bodies has shape"):
        amg_solver(A.tobsr(blocksize=(3, 3)), coords=coords, fixed=fixed, bodies=labels[:-1])
    with pytest.raises(ValueError, match="strength 'symmetric'"):
        amg_solver(A.tobsr(blocksize=(3, 3)), coords=coords, fixed=fixed, bodies=labels,
                   strength=("classical", {}))


def _base_and_free_dofs(ring, seed: int, count: int):
    """A hierarchy of the ring, its matrix in CSR, a generator and ``count`` free DOFs."""
    m, K, Kd, fd, fixed = ring
    base = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-10)
    free = np.setdiff1d(np.arange(Kd.shape[0]), fixed)
    rng = np.random.default_rng(seed)
    return base, Kd.tocsr(), rng, rng.choice(free, count, replace=False)


def test_level_buffers_give_the_same_levels_as_the_full_sums(ring):
    """refreshed(..., buffers=) writes the coarse operators in place: the same values as
    the full sums, for any sequence of differences inside the pattern."""
    m, K, Kd, fd, fixed = ring
    base, Kd, rng, pick = _base_and_free_dofs(ring, seed=1, count=30)
    Z = sp.csr_matrix((np.ones(pick.size ** 2), (np.repeat(pick, pick.size),
                                                 np.tile(pick, pick.size))), shape=Kd.shape)
    buffers = base.level_buffers(Z)
    before = [lv.A.copy() for lv in base.ml.levels]
    for trial in range(3):
        sub = pick[rng.random(pick.size) < 0.6]
        c = 0.05 * Kd.diagonal()[sub].min()
        dA = sp.csr_matrix((np.full(sub.size, c), (sub, sub)), shape=Kd.shape)
        dA = dA + sp.csr_matrix((np.full(sub.size - 1, -0.3 * c), (sub[:-1], sub[1:])),
                                shape=Kd.shape)
        dA = (dA + dA.T).tocsr()
        A = (Kd + dA).tocsr()
        fast = base.refreshed(A, dA=dA, buffers=buffers)
        full = base.refreshed(A, dA=dA)
        for k, (a, b) in enumerate(zip(fast.ml.levels, full.ml.levels)):
            assert abs(a.A - b.A).max() <= 1e-14 * abs(b.A).max(), f"set {trial}, level {k}"
        assert np.array_equal(fast.solve(fd), full.solve(fd))
    for lv, A0 in zip(base.ml.levels, before):
        assert (lv.A != A0).nnz == 0, "the buffers changed the base hierarchy"
    other = amg_solver(Kd, coords=m.p, fixed=fixed, tol=1e-10)
    with pytest.raises(ValueError, match="another hierarchy"):
        other.refreshed(Kd, buffers=buffers)


def test_fine_csr_is_the_finest_level_and_is_checked(ring):
    """The caller's CSR copy of A serves as the finest level (no conversion back from
    BSR), with the same solution; a wrong one is refused before the setup."""
    m, K, Kd, fd, fixed = ring
    A = sp.csr_matrix(Kd)
    s = amg_solver(A.tobsr(blocksize=(3, 3)), coords=m.p, fixed=fixed, tol=1e-10, fine_csr=A)
    assert s.ml.levels[0].A is A
    ref = amg_solver(A.tobsr(blocksize=(3, 3)), coords=m.p, fixed=fixed, tol=1e-10)
    assert np.array_equal(s.solve(fd), ref.solve(fd))
    with pytest.raises(ValueError, match="fine_csr must be A in CSR"):
        amg_solver(A.tobsr(blocksize=(3, 3)), coords=m.p, fixed=fixed, fine_csr=A.tocsc())
    with pytest.raises(ValueError, match="fine_csr must be A in CSR"):
        amg_solver(A.tobsr(blocksize=(3, 3)), coords=m.p, fixed=fixed, fine_csr=A[:-3, :-3])


def test_backward_sweep_over_the_reversed_copy_is_pyamgs_backward_sweep():
    """One forward sweep over J A J on reversed vectors is pyamg's backward sweep over A,
    also for an unsymmetric matrix with unsorted column indices; the copy is made after
    _COPY_AFTER sweeps of the same matrix, kept for it and remade for another."""
    from pyamg.relaxation.relaxation import gauss_seidel

    from brakewear.solvers.cycle import _COPY_AFTER, _BackwardSweeps

    rng = np.random.default_rng(5)
    n = 300
    A = sp.random(n, n, density=0.03, random_state=6, format="csr") + sp.eye(n) * 4.0
    A = sp.csr_matrix(A)
    perm = [rng.permutation(np.arange(A.indptr[i], A.indptr[i + 1])) for i in range(n)]
    A = sp.csr_matrix((A.data[np.concatenate(perm)], A.indices[np.concatenate(perm)],
                       A.indptr), shape=A.shape)
    assert not A.has_sorted_indices
    b, x0 = rng.normal(size=n), rng.normal(size=n)
    sweeps = _BackwardSweeps(2)
    for M in (A, (A * 2.0).tocsr()):
        ref = x0.copy()
        gauss_seidel(M, ref, b, iterations=1, sweep="backward")
        for k in range(_COPY_AFTER + 2):
            ours = x0.copy()
            sweeps(0, M, ours, b)
            copied = sweeps.copies[0] is not None and sweeps.copies[0][0] is M
            assert copied == (k >= _COPY_AFTER), f"sweep {k}: copied {copied}"
            assert np.abs(ours - ref).max() <= 1e-13 * np.abs(ref).max(), f"sweep {k}"
        kept = sweeps.copies[0]
        sweeps(0, M, x0.copy(), b)
        assert sweeps.copies[0] is kept


def test_refreshed_cycles_never_smooth_with_a_stale_reversed_copy(ring):
    """Refreshed copies written in place (level buffers) and the base they share levels
    with: each V-cycle, applied in any order, is pyamg's cycle of its own levels."""
    from brakewear.solvers.cycle import _COPY_AFTER

    base, Kd, rng, pick = _base_and_free_dofs(ring, seed=2, count=20)
    Z = sp.csr_matrix((np.ones(pick.size), (pick, pick)), shape=Kd.shape)
    buffers = base.level_buffers(Z)
    r = rng.normal(size=Kd.shape[0])
    for _ in range(_COPY_AFTER + 1):  # the base's copies exist before the refreshes
        base.M @ r
    where = []  # the memory of each refreshed copy's reversed finest level
    new = None
    for trial, scale in enumerate((0.5, 2.0, 0.1)):
        dA = sp.csr_matrix((scale * Kd.diagonal()[pick], (pick, pick)), shape=Kd.shape)
        new = None  # the last copy is dropped: its reversed copies go to the pool
        new = base.refreshed((Kd + dA).tocsr(), dA=dA, buffers=buffers)
        for k in range(_COPY_AFTER + 1):  # before and after the copies
            ours, theirs = new.M @ r, new.ml.aspreconditioner(cycle="V") @ r
            assert np.abs(ours - theirs).max() <= 1e-12 * np.abs(theirs).max(), \
                f"refresh {trial}, cycle {k}"
        where.append(new.M.backward.copies[0][3].__array_interface__["data"][0])
        ours, theirs = base.M @ r, base.ml.aspreconditioner(cycle="V") @ r
        assert np.abs(ours - theirs).max() <= 1e-12 * np.abs(theirs).max(), f"base {trial}"
    assert where[1] == where[0] and where[2] == where[0], "the pooled arrays were not reused"
    # unchanged coarse levels are smoothed with the base's copies (no second copy)
    new = base.refreshed((Kd + dA).tocsr(), dA=dA, depth=0)
    for _ in range(_COPY_AFTER + 1):
        new.M @ r
    for i in range(1, len(base.ml.levels) - 1):
        assert new.M.backward.copies[i] is base.M.backward.copies[i]
    assert new.M.backward.copies[0] is not base.M.backward.copies[0]



def test_a_patch_whose_target_changed_is_skipped_with_a_warning(monkeypatch, caplog):
    """A pyamg release whose function lost a parameter the patch relies on gets no
    patch (and a warning): the setup runs as pyamg ships it."""
    import pyamg.aggregation.smooth as smooth

    from brakewear.solvers import patches

    def changed(A, tol=0.01):            # no maxiter / restart any more
        return 1.0
    monkeypatch.setattr(smooth, "approximate_spectral_radius", changed)
    monkeypatch.setattr(patches, "_WARNED", set())
    with caplog.at_level("WARNING", logger="brakewear.solvers.patches"):
        with patches._single_pass_spectral_radius():
            assert smooth.approximate_spectral_radius is changed
    assert "running without that patch" in caplog.text and "maxiter" in caplog.text
    assert smooth.approximate_spectral_radius is changed
    # the shipped function is patched and restored
    monkeypatch.undo()
    shipped = smooth.approximate_spectral_radius
    with patches._single_pass_spectral_radius():
        assert smooth.approximate_spectral_radius is not shipped
    assert smooth.approximate_spectral_radius is shipped
