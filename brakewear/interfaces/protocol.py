"""What a wear step talks to: the interface protocol and its solution.

An *interface model* answers one question for the wear loop: the contact
pressure at the pad's friction nodes for a given extra gap (the worn depths),
and it describes the surfaces the wear is booked on.  Three implement it:
:class:`~brakewear.interfaces.FEInterface` (finite-element contact, elastic or
rigid rotor), :class:`~brakewear.interfaces.FoundationInterface` (an elastic
foundation, milliseconds per solve), and any user class with the same
attributes and :meth:`Interface.solve`.

Everything a solve needs comes in as an argument (gap offset, start set,
the implicit step's compliance, a Krylov start, the thermal load, the
friction coefficient) and everything it gives comes back in an
:class:`InterfaceSolution`; nothing is set on the interface from outside.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

logger = logging.getLogger(__name__)

__all__ = ["Interface", "InterfaceSolution"]


@dataclass
class InterfaceSolution:
    """One contact solve as the wear loop sees it.

    Attributes
    ----------
    pressure : ndarray
        (n_pad,) contact pressure at the pad's friction nodes (Pa), 0 where open.
    active : ndarray
        (n_pad,) bool, in contact.
    u : ndarray or None
        The displacement of the solve in the interface's unknowns (a start
        for the next implicit step), None where the model has none.
    info : dict
        The solver's figures (iterations, times).
    """

    pressure: np.ndarray
    active: np.ndarray
    u: np.ndarray | None = None
    info: dict = field(default_factory=dict)


@runtime_checkable
class Interface(Protocol):
    """The interface model of a wear history.

    Attributes
    ----------
    area : ndarray
        (n_pad,) tributary areas of the pad's friction nodes (m^2).
    r : ndarray
        (n_pad,) radii of the pad's friction nodes (m).
    pad_nodes : ndarray
        The pad mesh's node numbers of its friction nodes.
    W : sparse matrix
        (n_pad, n_rotor) interpolation from the rotor's wear nodes to the
        points under the pad nodes.
    ring, rotor_area, rotor_x
        Ring number, tributary area (m^2) and position (m) of each rotor wear node.
    rotor_nodes : ndarray or None
        The rotor mesh's node numbers of its wear nodes (None: no rotor mesh).
    normal_stiffness : ndarray
        (n_pad,) row sums of the normal stiffness at the pad's friction nodes
        (N/m): the bound of the pressure's response to a gap change.
    accepts_load : bool
        Whether :meth:`solve` takes a nodal load (thermal strain).
    """

    area: np.ndarray
    r: np.ndarray
    pad_nodes: np.ndarray
    ring: np.ndarray
    rotor_area: np.ndarray
    normal_stiffness: np.ndarray
    accepts_load: bool

    def solve(self, offset: np.ndarray, active: np.ndarray | None, *,
              compliance: np.ndarray | None = None, x0: np.ndarray | None = None,
              load: np.ndarray | None = None, mu: float | None = None) -> InterfaceSolution:
        """Contact with ``offset`` (m) added to the gap.

        ``active`` is the start set (None: the interface's own start);
        ``compliance`` (m/Pa per pad node) makes it the implicit wear step
        (contact through the step's wear compliance); ``x0`` starts the
        Krylov solves; ``load`` is an extra nodal load of the model (N per
        DOF, e.g. thermal strain); ``mu`` the friction coefficient of this
        solve (None: the interface's own).
        """
