"""The rotor's ring wear as extra unknowns of the implicit wear step.

Backward Euler on both surfaces.  Over a step of length ``dt`` the pad node
``i`` wears ``eps_i p_i`` with its end-of-step pressure (the node's spring,
:mod:`brakewear.contact.compliant`), and the rotor's ring ``j`` wears by the
revolution average of the end-of-step contact forces ``lam = p A`` of the pad
nodes above it,

    d = G lam,      G = diag(1 / A_ring) B^T diag(eps_rot),

with ``eps_rot = dt k_rot v`` per pad node (m/Pa) and ``B`` (pad node x ring)
the rotor's coupling to the pad nodes summed over each ring's nodes.  The
ring depth opens the gap of every pad node above it by ``(B d)_i``, so the
force of an active node is ``lam_A = -kappa_A (g0_A + C_A u + B_A d)`` and
the ring depths join the displacements as ``m`` extra unknowns (one per ring):

    [ A + E                          (C_A^T + Gf_A) kappa_A B_A ] [u]   [ b_u                ]
    [ sigma G_A kappa_A C_A          sigma (I + G_A kappa_A B_A) ] [d] = [ -sigma G_A kappa_A g0_A ]

``A + E`` is the compliant operator of the active set with its friction
(``Gf`` the friction loads per newton), ``sigma`` a stiffness per ring that
gives the ring rows the scale of the force rows.  The system is unsymmetric
(a ring sums each node's force with that node's ``k_rot v``, and hands its
depth back with the coupling's weights), so flexible GMRES solves it, right
preconditioned by the block lower-triangular

    [ AMG V-cycle of A         0                         ]
    [ sigma G_A kappa_A C_A    sigma (I + G_A kappa_A B_A) ]

(one V-cycle and one ``m x m`` triangular solve per iteration).  With an
exact ``A^-1`` the preconditioned operator has the eigenvalue 1 on the
displacements and, on the rings, those of
``(I + G kappa B)^-1 (I + G K_eff B)``: ``K_eff <= kappa`` is the pad's
stiffness seen through the elastic body behind its springs, so a ring mode
that the body does not relieve has the eigenvalue 1 and the few that it
relieves (the pad's floating and tilting) lie in ``(0, 1]``.  ``G kappa B =
diag(1/A_ring) B^T diag(A k_rot / k_pad) B`` does not depend on the step: it
is the rotor's wear over the pad's, about ``(k_rot / k_pad)`` times the pad's
share of the ring, so neither the step nor the mesh size moves the spectrum.
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.linalg import lu_factor, lu_solve

from ..errors import ContactError
from ..solvers.operators import Bordered, BorderedPreconditioner

logger = logging.getLogger(__name__)

__all__ = ["RingBlock"]


class RingBlock:
    """The ring depths of a compliant solve as extra unknowns, one active set at a time.

    Parameters
    ----------
    ring_gap
        ``B`` (n_slave x m): the gap of each slave node per metre of each
        ring's depth.
    ring_depth
        ``G`` (m x n_slave): each ring's depth per newton of end-of-step
        contact force at each slave node.
    kappa, g0
        The slave nodes' spring stiffnesses (N/m) and gaps (m).
    """

    def __init__(self, ring_gap: sp.spmatrix, ring_depth: sp.spmatrix, kappa: np.ndarray,
                 g0: np.ndarray):
        ns = kappa.size
        self.B, self.G = sp.csr_matrix(ring_gap), sp.csr_matrix(ring_depth)
        m = self.B.shape[1]
        if self.B.shape != (ns, m) or self.G.shape != (m, ns):
            raise ContactError(f"ring_gap has shape {self.B.shape} and ring_depth "
                               f"{self.G.shape}; need ({ns}, m) and (m, {ns})")
        self.kappa, self.g0 = kappa, g0
        self.m = m
        self.d = None           # the ring depths of the last solve (m)
        self.lin = 0

    def for_set(self, active: np.ndarray, Ca: sp.spmatrix, Ga: sp.spmatrix | None,
                P: sp.spmatrix | None = None, c: np.ndarray | None = None) -> None:
        """The coupling blocks of one active set: ``Ca``, ``Ga`` the set's
        constraint rows and friction loads (all DOFs); with eliminated stops the
        unknowns are ``x`` in ``u = P x + c``."""
        ka = self.kappa[active]
        Ba = self.B[active]
        Gr = self.G[:, active]
        kB = (sp.diags(ka) @ Ba).tocsc()
        Ufull = (Ca.T @ kB).tocsr()
        if Ga is not None:
            Ufull = (Ufull + Ga @ kB).tocsr()
        Rx = (Gr @ sp.diags(ka) @ Ca).tocsr()
        g = self.g0[active] + (0.0 if c is None else Ca @ c)
        self.rhs_d = -(Gr @ (ka * g))
        self.Ufull = Ufull
        self.U = Ufull if P is None else (P.T @ Ufull).tocsr()
        self.Rx = Rx if P is None else (Rx @ P).tocsr()
        self.Dm = np.eye(self.m) + (Gr @ kB).toarray()
        self.lu = lu_factor(self.Dm, check_finite=False)
        # the ring rows' scale: a depth error delta moves the forces by |kappa B_j| delta,
        # and the row's own force term (G kappa B)_jj is taken out, so a force error
        # weighs in the ring rows as it does in the force rows
        sigma = np.sqrt(np.asarray(kB.multiply(kB).sum(axis=0)).ravel()) / np.diag(self.Dm)
        top = float(sigma.max()) if sigma.size else 0.0
        self.sigma = np.maximum(sigma, 1e-12 * top) if top > 0 else np.ones(self.m)

    def start(self, x: np.ndarray | None) -> np.ndarray:
        """The ring depths that balance a displacement ``x`` of this set."""
        rhs = self.rhs_d if x is None else self.rhs_d - self.Rx @ x
        return lu_solve(self.lu, rhs, check_finite=False)

    def solve(self, amg, op, b: np.ndarray, x: np.ndarray | None, tol: float,
              rtol0: float | None) -> np.ndarray:
        """The set's displacements ``x`` and ring depths (kept in :attr:`d`):
        FGMRES on the bordered system with the block preconditioner."""
        n, sig = b.size, self.sigma
        Aop = Bordered(op, self.U, self.Rx, self.Dm, sig)
        M = BorderedPreconditioner(amg.M, self.Rx, self.lu, sig)
        d0 = self.d if self.d is not None and x is not None else self.start(x)
        y0 = np.concatenate([np.zeros(n) if x is None else x, d0])
        amg.tol = tol
        y = amg.solve(np.concatenate([b, sig * self.rhs_d]), x0=y0, A=Aop, krylov="gmres",
                      rtol0=rtol0, M=M)
        self.lin += amg.info.iterations
        self.d = y[n:]
        return y[:n]

    def gap(self) -> np.ndarray | float:
        """The gap the last ring depths open at every slave node (m)."""
        return 0.0 if self.d is None else self.B @ self.d

    def force_residual(self) -> np.ndarray | float:
        """The ring depths' share of the set's force rows (all DOFs)."""
        return 0.0 if self.d is None else self.Ufull @ self.d
