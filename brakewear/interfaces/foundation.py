"""The elastic foundation as the wear loop's interface model (:class:`FoundationInterface`)."""
from __future__ import annotations

import logging

import numpy as np

from ..errors import ContactLostError, WearError
from ..mesh.surface import surface_nodes
from ..rings import ring_wear_nodes
from .protocol import InterfaceSolution

logger = logging.getLogger(__name__)

__all__ = ["FoundationInterface"]


class FoundationInterface:
    """An elastic-foundation (Winkler) interface as the wear loop's interface model.

    Wraps a :class:`brakewear.interfaces.WinklerInterface` (pad face on a rigid
    backing, foundation modulus per node); the rotor wears by rings of the pad
    nodes' radii as an unmeshed rotor does.  Milliseconds per solve.  The
    implicit step puts the step's wear compliance in series with the
    foundation: modulus ``1 / (1/k + eps)``.
    """

    #: a nodal load (thermal strain) has no place in a foundation
    accepts_load = False

    def __init__(self, model, winkler, line_pressure: float, mu: float = 0.0):
        self.model, self.winkler, self.line_pressure, self.mu = model, winkler, line_pressure, mu
        pad = model.meshes["pad"]
        self.pad_nodes = surface_nodes(pad, "friction")
        if winkler.nodes is not None and not np.array_equal(winkler.nodes, self.pad_nodes):
            raise WearError("the foundation's nodes are not the pad's friction nodes of this "
                            "model (build it with WinklerInterface.from_model(model))")
        self.x = pad.p[:, self.pad_nodes]
        self.r = np.hypot(self.x[0], self.x[1])
        self.area = np.asarray(winkler.area, dtype=float)
        self.rotor_nodes = None
        self.W, self.ring, self.rotor_area, self.rotor_x = ring_wear_nodes(self.r)
        self.normal_stiffness = np.asarray(winkler.modulus) * self.area

    def solve(self, offset: np.ndarray, active, *, compliance=None, x0=None, load=None,
              mu: float | None = None) -> InterfaceSolution:
        """The foundation's pressure with ``offset`` (m) added to the gap (the
        :class:`~brakewear.interfaces.Interface` protocol).  ``active`` and ``x0``
        are not needed (a foundation solve is direct); a nodal ``load`` has no
        place in a foundation and is refused."""
        if load is not None:
            raise WearError("the foundation interface takes no nodal load (thermal strain); "
                            "use the FE interface for thermal coupling")
        if mu is not None:
            if np.ndim(mu):
                raise WearError("the foundation interface takes one friction coefficient; a "
                                "friction law per node (mu(p, v, T)) needs the FE or the "
                                "condensed interface")
            self.mu = float(mu)
        w = self.winkler
        if compliance is not None:
            w = w.with_modulus(1.0 / (1.0 / np.asarray(w.modulus) + compliance))
        res = w.solve(self.line_pressure, self.mu, gap=offset)
        if not res.active.any():
            raise ContactLostError("foundation: no node in contact")
        return InterfaceSolution(res.pressure, res.active, None,
                                 {"iterations": res.iterations, "time_s": res.time_s})
