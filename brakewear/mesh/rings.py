"""The rotor's rings and the revolution average: what a rotor point sees of the pad.

A rotor point at radius ``r`` passes under the pad once per revolution, so
whatever the pad does to the rotor -- wear, frictional heat -- reaches the
rotor as the circumferential mean: the volume (or power) the pad delivers
per unit time at radius ``r`` is spread over the whole ring of rotor nodes
at that radius.  The distribution conserves the total exactly.
"""
from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from ..errors import WearError

logger = logging.getLogger(__name__)

__all__ = ["rotor_rings", "face_rings", "rotor_wear_rate", "RingAverage", "ring_coupling",
           "ring_wear_nodes", "ring_profile"]



def rotor_rings(r_nodes: np.ndarray, tol: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Group rotor friction-face nodes into rings of equal radius.

    Returns ``ring`` (index per node) and the ring radii.  Nodes whose radii
    differ by less than ``tol`` (default 1e-9 of the largest radius) share a
    ring; the rotor meshes of brakewear are structured in r, so every ring is
    a full circle of nodes.

    Examples
    --------
    >>> ring, radii = rotor_rings(np.array([0.12, 0.10, 0.12, 0.11, 0.10]))
    >>> ring.tolist(), radii.tolist()
    ([2, 0, 2, 1, 0], [0.1, 0.11, 0.12])
    """
    r = np.asarray(r_nodes, dtype=float)
    tol = 1e-9 * r.max() if tol is None else tol
    order = np.argsort(r)
    new = np.concatenate([[True], np.diff(r[order]) > tol])
    ring_sorted = np.cumsum(new) - 1
    ring = np.empty(r.size, dtype=np.int64)
    ring[order] = ring_sorted
    radii = np.bincount(ring, weights=r) / np.bincount(ring)
    return ring, radii


def face_rings(model, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`rotor_rings` of rotor friction-face nodes at ``x`` (3, n) of a
    :class:`~brakewear.model.BrakeModel`: in the full model a ring is a radius
    on one face (each face passes under its own pad), the outboard face's rings
    numbered after the inboard face's."""
    ring, radii = rotor_rings(np.hypot(x[0], x[1]))
    if getattr(model, "full", False):
        out = x[2] < -0.5 * model.geometry.rotor.thickness
        ring = ring + out * radii.size
        radii = np.concatenate([radii, radii])
    return ring, radii


def rotor_wear_rate(volume_rate: np.ndarray, coupling: sp.spmatrix, ring: np.ndarray,
                    area: np.ndarray) -> np.ndarray:
    """Revolution-averaged rotor wear rate at each rotor friction-face node (m/s).

    Parameters
    ----------
    volume_rate
        (n_slave,) volume the pad removes from the rotor per unit time at each
        pad contact node (``k_rotor p v A``, m^3/s).
    coupling
        (n_slave, n_rotor) which rotor nodes lie under each pad node (rows sum
        to one: a contact pair's coupling restricted to the rotor's face nodes).
    ring, area
        Ring index and tributary area of each rotor face node (:func:`rotor_rings`,
        :func:`brakewear.mesh.surface.tributary_areas`).

    The volume each pad node takes from the rotor nodes under it is summed
    per ring and spread uniformly (by area) over the whole ring: the rotor
    passes under the pad once per revolution.  The rotor's volume rate equals
    ``volume_rate.sum()`` exactly.

    Examples
    --------
    Two pad nodes over the first of two rotor nodes of one ring: the ring's
    volume spreads over both nodes, and none is lost.

    >>> coupling = sp.csr_matrix(np.array([[1.0, 0.0], [1.0, 0.0]]))
    >>> area = np.array([1e-4, 3e-4])
    >>> rate = rotor_wear_rate(np.array([1e-12, 3e-12]), coupling, np.array([0, 0]), area)
    >>> rate.tolist(), float(rate @ area) == 4e-12
    ([1e-08, 1e-08], True)
    """
    per_node = sp.csr_matrix(coupling).T @ np.asarray(volume_rate, dtype=float)
    n_ring = int(ring.max()) + 1
    ring_volume = np.bincount(ring, weights=per_node, minlength=n_ring)
    ring_area = np.bincount(ring, weights=area, minlength=n_ring)
    if np.any((ring_volume > 0) & (ring_area <= 0)):
        raise WearError("a rotor ring receives wear but has no area")
    return (ring_volume / np.where(ring_area > 0, ring_area, 1.0))[ring]


class RingAverage:
    """:func:`rotor_wear_rate` of one coupling, its rings and areas, with their
    transposed coupling and ring areas made once (the wear loop calls it several
    times a step): ``RingAverage(coupling, ring, area)(volume_rate)`` equals
    ``rotor_wear_rate(volume_rate, coupling, ring, area)``."""

    def __init__(self, coupling: sp.spmatrix, ring: np.ndarray, area: np.ndarray):
        self.ring = np.asarray(ring)
        self.n_ring = int(self.ring.max()) + 1
        self.coupling_t = sp.csr_matrix(sp.csr_matrix(coupling).T)
        self.ring_area = np.bincount(self.ring, weights=area, minlength=self.n_ring)
        self.empty = self.ring_area <= 0
        self.divisor = np.where(self.empty, 1.0, self.ring_area)

    def __call__(self, volume_rate: np.ndarray) -> np.ndarray:
        per_node = self.coupling_t @ np.asarray(volume_rate, dtype=float)
        ring_volume = np.bincount(self.ring, weights=per_node, minlength=self.n_ring)
        if np.any((ring_volume > 0) & self.empty):
            raise WearError("a rotor ring receives wear but has no area")
        return (ring_volume / self.divisor)[self.ring]


def ring_coupling(coupling: sp.spmatrix, ring: np.ndarray,
                  area: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """The rings as :func:`rotor_wear_rate` sees them: ``(B, ring_area)``.

    ``B`` (n_slave x n_ring) is ``coupling`` summed over each ring's nodes: the
    gap a pad node sees per metre of a ring's depth, and (transposed) the
    share of a pad node's worn volume that goes to each ring; ``ring_area``
    the area of each ring's nodes.  So ``rotor_wear_rate(q, coupling, ring,
    area) == (B.T @ q / ring_area)[ring]``.
    """
    ring = np.asarray(ring)
    n_ring = int(ring.max()) + 1
    R = sp.csr_matrix((np.ones(ring.size), (np.arange(ring.size), ring)),
                      shape=(ring.size, n_ring))
    B = (sp.csr_matrix(coupling) @ R).tocsr()
    return B, np.bincount(ring, weights=area, minlength=n_ring)


def ring_wear_nodes(r: np.ndarray):
    """Rotor wear nodes of an unmeshed rotor: one ring per distinct pad-node radius.

    Each ring carries the annulus between its neighbours' mid-radii (the first
    and last from their own radius), so the rings tile the swept band exactly.

    Parameters
    ----------
    r
        The pad nodes' radii (m).

    Returns
    -------
    W : sparse matrix
        (n_pad, n_ring): pad node -> its ring.
    ring : ndarray
        The rings' numbers (0, 1, ...).
    area : ndarray
        The rings' areas (m^2).
    x : ndarray
        (3, n_ring) a point of each ring (m).

    Examples
    --------
    >>> W, ring, area, x = ring_wear_nodes(np.array([0.10, 0.12, 0.11, 0.12]))
    >>> W.toarray().argmax(axis=1).tolist(), x[0].tolist()
    ([0, 2, 1, 2], [0.1, 0.11, 0.12])
    >>> bool(np.isclose(area.sum(), np.pi * (0.12 ** 2 - 0.10 ** 2), rtol=1e-12))
    True
    """
    ring, radii = rotor_rings(r)
    edges = np.concatenate([[radii[0]], 0.5 * (radii[1:] + radii[:-1]), [radii[-1]]])
    W = sp.csr_matrix((np.ones(ring.size), (np.arange(ring.size), ring)),
                      shape=(ring.size, radii.size))
    x = np.vstack([radii, np.zeros_like(radii), np.zeros_like(radii)])
    return W, np.arange(radii.size), np.pi * (edges[1:] ** 2 - edges[:-1] ** 2), x


def ring_profile(itf, values: np.ndarray | None = None):
    """Rotor wear nodes grouped by ring: (ring radii, ring means of ``values``).

    ``itf`` is the wear loop's interface (``rotor_x``, ``ring``); ``values`` one
    number per rotor wear node (e.g. ``WearStep.rotor_wear``); None gives the
    radii only (second item None).
    """
    n = np.bincount(itf.ring)
    r = np.bincount(itf.ring, weights=np.hypot(itf.rotor_x[0], itf.rotor_x[1])) / n
    return r, None if values is None else np.bincount(itf.ring, weights=values) / n
