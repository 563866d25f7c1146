"""Hertz sphere on a flat (docs/references.md), 3D quarter model: studies/hertz.py."""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

spec = importlib.util.spec_from_file_location(
    "hertz_study", Path(__file__).parents[1] / "studies" / "hertz.py")
hz = importlib.util.module_from_spec(spec)
spec.loader.exec_module(hz)


def test_boussinesq_field_is_the_half_space_point_load():
    """Equilibrium (finite differences), traction-free surface, sigma_zz and
    the surface deflection of Johnson's closed form, with our sign convention."""
    E, nu, F = hz.MATERIAL.E, hz.MATERIAL.nu, 7.0
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))

    def stress(x, eps=1e-7):
        g = np.zeros((3, 3, x.shape[1]))
        for j in range(3):
            e = np.zeros((3, 1))
            e[j] = eps
            g[:, j] = (hz.boussinesq(x + e, F) - hz.boussinesq(x - e, F)) / (2 * eps)
        s = 0.5 * (g + g.transpose(1, 0, 2))
        return lam * np.trace(s) * np.eye(3)[:, :, None] + 2 * mu * s

    rng = np.random.default_rng(1)
    x = rng.uniform(-1e-3, 1e-3, (3, 6))
    x[2] = -np.abs(x[2]) - 3e-4
    s = stress(x)
    d, rho = -x[2], np.linalg.norm(x, axis=0)
    np.testing.assert_allclose(s[2, 2], -3 * F * d ** 3 / (2 * np.pi * rho ** 5), rtol=1e-5)
    hstep = 1e-6
    div = sum(
        (stress(x + hstep * np.eye(3)[:, [j]])[:, j] - stress(x - hstep * np.eye(3)[:, [j]])[:, j])
        / (2 * hstep)
        for j in range(3)
    )
    assert np.abs(div).max() * 1e-3 < 1e-4 * np.abs(s).max()
    xs = np.array([[4e-4, -2e-4], [1e-4, 5e-4], [-1e-9, -1e-9]])
    assert np.abs(stress(xs)[:, 2]).max() < 1e-4 * np.abs(stress(xs)).max()
    u = hz.boussinesq(np.array([[5e-4], [0.0], [0.0]]), F)
    np.testing.assert_allclose(u[2], -F * (1 - nu ** 2) / (np.pi * E * 5e-4), rtol=1e-12)
    assert u[0] < 0  # surface points move toward the load


def test_mirrored_split_is_its_own_mirror_image():
    """The quarter model with symmetry conditions is the symmetric full model
    only if the tetrahedra of the full block map onto themselves under
    x -> -x and y -> -y; the plain Kuhn split does not (it folds)."""
    def node_index(p, q):  # index in p of each point of q (same point set)
        kp = np.round(p.T / 1e-9).astype(np.int64)
        kq = np.round(q.T / 1e-9).astype(np.int64)
        ip, iq = np.lexsort(kp.T[::-1]), np.lexsort(kq.T[::-1])
        assert np.array_equal(kp[ip], kq[iq])
        out = np.empty(len(kq), dtype=np.int64)
        out[iq] = ip
        return out

    def canon(t):
        t = np.sort(t, axis=0).T
        return t[np.lexsort(t.T[::-1])]

    h = 0.5 * hz.A0
    for split, symmetric in (("mirrored", True), ("kuhn", False)):
        m = hz.block_mesh(h, split=split, model="full")
        tets = canon(m.t)
        for axis in (0, 1):
            q = m.p.copy()
            q[axis] *= -1.0
            image = node_index(m.p, q)[m.t]      # the reflected tetrahedra, as nodes of m
            assert np.array_equal(canon(image), tets) is symmetric, (split, axis)


def test_recovered_pressure_cancels_the_node_type_pattern():
    """Nodal forces of a smooth pressure times a zero-mean period-2 node-type
    factor (the pattern of the mirrored split): the 2h tent window recovers
    the pressure to about (h^2/4) lap p; nodal force / area does not."""
    h, a = 0.1, 1.0
    g = np.arange(0, 13) * h
    X, Y = np.meshgrid(g, g, indexing="ij")
    i, j = np.rint(X / h).astype(int), np.rint(Y / h).astype(int)
    x, y = X.ravel(), Y.ravel()
    # quarter-model tributary areas of the union-jack surface pattern: 4/3, 2/3 h^2
    # by parity, halved on each symmetry plane
    A = np.where((i + j) % 2 == 0, 4 / 3, 2 / 3).ravel() * h ** 2
    A = A / np.where(x == 0, 2, 1) / np.where(y == 0, 2, 1)
    p = 1.0 - (x ** 2 + y ** 2) / (2 * a ** 2)            # lap p = -2 / a^2
    factor = {(0, 0): 0.92, (1, 1): 1.046, (1, 0): 1.05, (0, 1): 1.05}
    c = np.array([factor[(u % 2, v % 2)] for u, v in zip(i.ravel(), j.ravel())])
    # normalise the pattern to zero mean over a period (weights = areas)
    c = c / ((0.92 * 4 / 3 + 1.046 * 4 / 3 + 2 * 1.05 * 2 / 3) / 4)
    act = np.hypot(x, y) < 0.8
    f = c * p * A * act
    rec = hz.recovered_pressure(x, y, f, A, act, 2 * h)
    ok = act & (np.hypot(x, y) < 0.8 - 2.5 * h)
    err = rec[ok] - p[ok]                   # (h^2/4) lap p = -0.005, +-4 % by node type
    assert np.all(err < -0.45 * h ** 2 / a ** 2) and np.all(err > -0.55 * h ** 2 / a ** 2), err
    assert np.abs(f[ok] / A[ok] / p[ok] - 1).max() > 0.05   # the raw nodal pressure
    assert np.all(rec[~act] == 0.0)
    with pytest.raises(ValueError, match="width"):
        hz.recovered_pressure(x, y, f, A, act, 0.0)
    with pytest.raises(ValueError, match="force"):
        hz.recovered_pressure(x, y, f[:-1], A, act, 2 * h)


@pytest.fixture(scope="module")
def coarse():
    return hz.solve(0.25)


def test_hertz_coarse_mesh(coarse):
    r = coarse
    assert r["outer_iterations"] <= 4 and r["outer_residual"] < 1e-9, r["outer_iterations"]
    # observed at h/a = 1/4 (14.6k DOFs, mirrored split, ~5 s): p0 -1.35 %, a -0.26 %,
    # approach -1.09 %, L2 18.0 % (inside r < a - 2h: 2.05 %); raw nodal p0 -12.7 %.
    # The targets (p0 1 %) are met from h/a = 1/6; see the slow test and the study
    assert abs(r["p0_err"]) < 0.025, f"peak pressure error {r['p0_err']:+.3%}"
    assert abs(r["a_err"]) < 0.015, f"contact radius error {r['a_err']:+.3%}"
    assert abs(r["delta_err"]) < 0.02, f"approach error {r['delta_err']:+.3%}"
    assert r["l2_err"] < 0.21, f"L2 pressure error {r['l2_err']:.3%}"
    assert r["l2_inner_err"] < 0.03, f"L2 pressure error inside {r['l2_inner_err']:.3%}"
    # the recovery is what removes the node-type pattern of the nodal pressure
    assert abs(r["p0_nodal_err"]) > 0.05, r["p0_nodal_err"]


@pytest.mark.slow
def test_hertz_convergence(tmp_path):
    # observed (h/a = 1/2 ... 1/8, mirrored split, recovered pressure): L2 rate 1.00 (edge-
    # limited: the pressure is a square root at r = a), inside r < a - 2h 1.82; finest (1/8,
    # 42.6k DOFs, ~30 s alone): p0 -0.29 %, a +0.71 %, approach -0.64 %, L2 8.0 %, inside 0.82 %
    res = hz.main(levels=(1 / 2, 1 / 3, 1 / 4, 1 / 6, 1 / 8), out=tmp_path)
    assert res["l2_rate"] >= 0.8, res["l2_rate"]
    assert res["l2_inner_rate"] >= 1.3, res["l2_inner_rate"]
    fin = res["finest"]
    assert fin["l2_err"] < 0.095, f"L2 pressure error {fin['l2_err']:.3%}"
    assert fin["l2_inner_err"] < 0.011, f"L2 pressure error inside {fin['l2_inner_err']:.3%}"
    assert abs(fin["p0_err"]) < 0.01, f"peak pressure error {fin['p0_err']:+.3%}"
    assert abs(fin["a_err"]) < 0.02, f"contact radius error {fin['a_err']:+.3%}"
    assert abs(fin["delta_err"]) < 0.01, f"approach error {fin['delta_err']:+.3%}"
    assert (tmp_path / "hertz_convergence.csv").exists()
    assert (tmp_path / "hertz_convergence.json").exists()
    assert (tmp_path / "hertz_convergence.png").stat().st_size > 10_000
    assert (tmp_path / "hertz_pressure.png").stat().st_size > 10_000
