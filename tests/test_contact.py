"""Surface projection and the tie constraint."""
import numpy as np
import pytest
import scipy.sparse as sp

from brakewear.contact import project_nodes, tie_prolongation
from brakewear.errors import ContactSearchError
from brakewear.fem import apply_dirichlet, assemble_stiffness, assemble_traction, boundary_dofs
from brakewear.materials import Isotropic
from brakewear.mesh import mapped_mesh, structured_tets
from brakewear.mesh.surface import facet_normals, surface_nodes, tributary_areas
from brakewear.solvers import direct_solve


def block(n, z0, z1, L=1.0):
    p, t = structured_tets(
        np.linspace(0, L, n + 1), np.linspace(0, L, n + 1), np.linspace(z0, z1, 3)
    )
    m = mapped_mesh(p, t, lambda x: x)
    return m.with_boundaries({"bottom": lambda x: np.abs(x[2] - z0) < 1e-12,
                              "top": lambda x: np.abs(x[2] - z1) < 1e-12})


def test_projection_weights_reproduce_points_and_gap_sign():
    lower = block(7, -1.0, 0.0)
    rng = np.random.default_rng(3)
    pts = np.vstack([rng.uniform(0, 1, 50), rng.uniform(0, 1, 50), rng.uniform(-0.01, 0.02, 50)])
    pr = project_nodes(pts, lower, "top")
    x = np.einsum("ij,kij->kj", pr.weights, lower.p[:, pr.nodes])
    scale = np.abs(lower.p).max()        # lengths: round-off of the block's coordinates
    assert np.allclose(x[:2], pts[:2], rtol=0, atol=1e-12 * scale)
    assert np.allclose(pr.gap, pts[2], rtol=0, atol=1e-12 * scale)  # outward normal is +z
    assert np.allclose(pr.normal, [[0], [0], [1]])
    assert np.all(pr.weights >= -1e-12) and np.allclose(pr.weights.sum(axis=0), 1)


def test_search_radius_error_names_the_point():
    lower = block(3, -1.0, 0.0)
    with pytest.raises(ContactSearchError, match="search radius"):
        project_nodes(np.array([[0.5], [0.5], [0.3]]), lower, "top", search_radius=0.1)


def test_facet_normals_point_out_and_areas_sum():
    m = block(4, 0.0, 1.0)
    assert np.allclose(facet_normals(m, m.boundaries["bottom"]), [[0], [0], [-1]])
    assert tributary_areas(m, "top").sum() == pytest.approx(1.0)


def test_chained_ties_are_refused():
    with pytest.raises(ValueError, match="chained"):
        tie_prolongation(4, np.array([0]), np.array([[0], [1], [2]]), np.ones((3, 1)) / 3)


@pytest.mark.parametrize("n_upper", [4, 12])
def test_tied_blocks_transmit_uniform_compression(n_upper):
    """Tied patch test: two stacked blocks (matching or 1:3 meshes) under uniform pressure."""
    lower, upper = block(4, -1.0, 0.0), block(n_upper, 0.0, 1.0)
    mat = Isotropic(E=1e9, nu=0.3)
    K = sp.block_diag([assemble_stiffness(m, mat)[0].tocsr() for m in (lower, upper)], format="csr")
    nl = lower.nvertices
    f = np.zeros(K.shape[0])
    f[3 * nl:] = assemble_traction(upper, "top", (0, 0, -1e6))
    slave = surface_nodes(upper, "bottom")
    pr = project_nodes(upper.p[:, slave], lower, "top")
    Pn, kept = tie_prolongation(nl + upper.nvertices, slave + nl, pr.nodes, pr.weights)
    P = sp.kron(Pn, sp.identity(3), format="csr")
    col = -np.ones(nl + upper.nvertices, int)
    col[kept] = np.arange(kept.size)
    # bottom: u_z = 0; rigid in-plane motion stopped at two bottom nodes (roller supports)
    bot = boundary_dofs(lower, "bottom", [2])
    n0 = np.nonzero(np.all(lower.p == 0, axis=0))[0][0]
    n1 = np.nonzero((lower.p[0] == 1) & (lower.p[1] == 0) & (lower.p[2] == -1))[0][0]
    fixed = np.unique(np.r_[bot, 3 * n0, 3 * n0 + 1, 3 * n1 + 1])
    fixed_r = 3 * col[fixed // 3] + fixed % 3
    Kd, fd = apply_dirichlet(P.T @ K @ P, P.T @ f, fixed_r)
    u = P @ direct_solve(Kd, fd)
    r = (K @ u - f).reshape(-1, 3)[slave + nl]
    p = r[:, 2] / tributary_areas(upper, "bottom", slave)
    assert r[:, 2].sum() == pytest.approx(1e6, rel=1e-10)
    assert np.abs(p / 1e6 - 1).max() < 1e-8, f"tied interface pressure {p.min()}..{p.max()}"
