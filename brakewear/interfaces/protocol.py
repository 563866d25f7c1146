"""What a wear step talks to: the interface protocol and its solution.

An *interface model* answers one question for the wear loop: the contact
pressure at the pad's friction nodes for a given extra gap (the worn depths),
and it describes the surfaces the wear is booked on.  The built-in models
implement it -- :class:`~brakewear.interfaces.FEInterface` (finite-element
contact, elastic or rigid rotor), :class:`~brakewear.interfaces.FoundationInterface`
(an elastic foundation, milliseconds per solve),
:class:`~brakewear.interfaces.CondensedInterface` -- and so may any class with
the same members, registered by name for scene files
(:mod:`brakewear.interfaces.registry`).  A run checks its interface against
the protocol once, when it starts (:func:`check_interface`).

Everything a solve needs comes in as an argument (gap offset, start set,
the implicit step's compliance, a Krylov start, the thermal load, the
friction coefficient) and everything it gives comes back in an
:class:`InterfaceSolution`; nothing is set on the interface from outside.

The implicit (backward Euler) step's compliance is a :class:`StepCompliance`:
the pad's wear per unit end pressure at each node and, when the rotor's
ring-averaged wear is implicit too, the rotor's, with the rings that average
it.  Every interface solves the same equations with it: the gap of pad node
``i`` opens by ``pad_i p_i + (ring_gap d)_i`` over the step, the ring depths
``d`` being the revolution average of the end-of-step pressures
(:meth:`StepCompliance.ring_depth`).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from ..errors import ContactError, WearError

logger = logging.getLogger(__name__)

__all__ = ["Interface", "InterfaceSolution", "StepCompliance", "check_interface", "capability"]


@dataclass(frozen=True)
class StepCompliance:
    """How an implicit wear step's wear depends on its end-of-step pressure.

    Attributes
    ----------
    pad : ndarray
        (n_pad,) m/Pa, > 0: the pad node ``i`` wears ``pad_i p_i`` over the
        step (``dt k_pad v_i`` for an Archard law).
    rotor : ndarray or None
        (n_pad,) m/Pa, >= 0: the rotor volume worn under pad node ``i`` per
        unit of its area, ``rotor_i p_i`` (``dt k_rot v_i``); None: the rotor's
        wear is not part of the solve (no rotor law, or an explicit rotor whose
        wear is in the gap offset).
    ring_gap : sparse matrix or None
        (n_pad, n_ring): the gap of each pad node per metre of each ring's
        depth (the interface's ``W`` summed over each ring's nodes,
        :func:`brakewear.mesh.rings.ring_coupling`).
    ring_area : ndarray or None
        (n_ring,) m^2: the area of each ring's rotor wear nodes.

    Over the step ring ``j`` is worn by ``d_j = sum_i ring_gap_ij rotor_i p_i
    A_i / ring_area_j`` (the rotor passes under the pad once per revolution:
    the volume the pad nodes above it take, spread over the whole ring), and
    pad node ``i``'s gap opens by ``pad_i p_i + sum_j ring_gap_ij d_j``.
    """

    pad: np.ndarray
    rotor: np.ndarray | None = None
    ring_gap: sp.spmatrix | None = None
    ring_area: np.ndarray | None = None

    def __post_init__(self):
        pad = np.asarray(self.pad, dtype=float)
        if pad.ndim != 1 or not np.all(np.isfinite(pad)) or np.any(pad <= 0):
            raise ContactError(f"compliance: pad must be (n_pad,) finite and > 0 m/Pa; got shape "
                               f"{pad.shape}, min {np.min(pad) if pad.size else None!r}")
        object.__setattr__(self, "pad", pad)
        if self.rotor is None:
            return
        n = pad.size
        rotor = np.asarray(self.rotor, dtype=float)
        if rotor.shape != (n,) or not np.all(np.isfinite(rotor)) or np.any(rotor < 0):
            raise ContactError(f"compliance: rotor must be ({n},) finite and >= 0 m/Pa; got "
                               f"shape {rotor.shape}")
        if self.ring_gap is None or self.ring_area is None:
            raise ContactError("compliance: a rotor compliance needs ring_gap and ring_area")
        B = self.ring_gap
        if not (sp.issparse(B) and B.format == "csr"):
            B = sp.csr_matrix(B)
        area = np.asarray(self.ring_area, dtype=float)
        if B.shape != (n, area.size):
            raise ContactError(f"compliance: ring_gap has shape {B.shape}; need ({n}, "
                               f"{area.size}), one column per ring of ring_area")
        # the rings some pad node sees (a vector sum: this runs once per wear step)
        used = np.bincount(B.indices, weights=np.abs(B.data), minlength=area.size) > 0
        if not np.all(np.isfinite(area)) or np.any(area[used] <= 0):
            raise ContactError("compliance: every ring under the pad needs an area > 0")
        object.__setattr__(self, "rotor", rotor)
        object.__setattr__(self, "ring_gap", B)
        object.__setattr__(self, "ring_area", area)

    @classmethod
    def of(cls, compliance) -> StepCompliance | None:
        """``compliance`` as a :class:`StepCompliance`: None stays None, an array
        is the pad's alone (m/Pa per pad node)."""
        if compliance is None or isinstance(compliance, cls):
            return compliance
        return cls(pad=compliance)

    @property
    def rings(self) -> bool:
        """Whether the rotor's ring wear is part of the step."""
        return self.rotor is not None

    def _inverse_ring_area(self) -> np.ndarray:
        return np.divide(1.0, self.ring_area, out=np.zeros_like(self.ring_area),
                         where=self.ring_area > 0)

    def ring_force_depth(self) -> sp.csr_matrix:
        """(n_ring, n_pad): each ring's depth per newton of end-of-step contact
        force at each pad node (m/N)."""
        return (sp.diags(self._inverse_ring_area()) @ self.ring_gap.T
                @ sp.diags(self.rotor)).tocsr()

    def ring_depth_of_forces(self, force: np.ndarray) -> np.ndarray:
        """(n_ring,) m: the rings' wear over the step under the end-of-step contact
        forces ``force`` (N per pad node): ``ring_force_depth() @ force`` as two
        vector products."""
        return self._inverse_ring_area() * (self.ring_gap.T @ (self.rotor * force))

    def ring_depth(self, pressure: np.ndarray, area: np.ndarray) -> np.ndarray:
        """(n_ring,) m: the rings' wear over the step under the end pressure (Pa at
        the pad nodes of area ``area``)."""
        return self.ring_depth_of_forces(np.asarray(pressure, dtype=float) * area)

    @property
    def ring_key(self) -> bytes:
        """The rings' part of the step as bytes (the rotor's compliance, the rings'
        areas and coupling): what tells one step's ring compliance from another's
        in a cache of factorisations."""
        if not self.rings:
            return b""
        B = self.ring_gap
        return b"".join(np.ascontiguousarray(a).tobytes() for a in (
            self.rotor, self.ring_area, B.data, B.indices, B.indptr))

    def gap(self, pressure: np.ndarray, area: np.ndarray) -> np.ndarray:
        """(n_pad,) m: how far the step's wear of both surfaces opens each pad
        node's gap under the end pressure."""
        g = self.pad * pressure
        return g if not self.rings else g + self.ring_gap @ self.ring_depth(pressure, area)

    def ring_compliance(self) -> np.ndarray:
        """(n_pad, n_pad) m/N, dense: the gap the rings' wear opens at each pad
        node per newton at each pad node (rank ``n_ring``; zero without rings)."""
        n = self.pad.size
        if not self.rings:
            return np.zeros((n, n))
        # B diag(1/A_ring) B^T diag(rotor), dense: rank n_ring, built from its thin factors
        B = self.ring_gap.toarray()
        return (B * self._inverse_ring_area()) @ (B.T * self.rotor)


@dataclass
class InterfaceSolution:
    """One contact solve as the wear loop sees it.

    Parameters
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
    """The interface model of a wear history (a protocol).

    Everything the wear loop, its records and its output ask of it; a class
    answers it (:mod:`~brakewear.interfaces.registry`), none is made from it.

    Attributes
    ----------
    x : ndarray
        (3, n_pad) positions of the pad's friction nodes (m).
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
        Ring number, tributary area (m^2) and position (3, n_rotor; m) of each
        rotor wear node (:func:`brakewear.mesh.rings.ring_wear_nodes` gives them for
        an unmeshed rotor).
    rotor_nodes : ndarray or None
        The rotor mesh's node numbers of its wear nodes (None: no rotor mesh).
    normal_stiffness : ndarray
        (n_pad,) row sums of the normal stiffness at the pad's friction nodes
        (N/m): the bound of the pressure's response to a gap change.
    line_pressure : float
        The line pressure (Pa) its solves are posed at.
    settings : dict
        Its own settings (numbers, strings, arrays): a checkpoint is resumed
        only by a run whose interface reports the same.
    accepts_load, follows_geometry, per_node_friction, quadratic : bool
    any_line_pressure, implicit_rings : bool
        Its capabilities (:data:`~brakewear.interfaces.registry.CAPABILITIES`;
        a missing one counts as False): a nodal load (thermal strain) in
        :meth:`solve`; :meth:`rebuilt` on a moved model; ``mu`` per pad node;
        quadratic meshes; ``at_line_pressure``; a :class:`StepCompliance`
        with rings in :meth:`solve` (without it, ``compliance`` is only ever
        an array, the pad's).

    Two methods go with capabilities (an interface without the capability
    needs neither): ``at_line_pressure(line_pressure) -> Interface``, this
    interface posed at another line pressure (Pa), sharing what it has built;
    ``rebuilt(model, opening=0.0) -> Interface``, this interface on ``model``,
    the same brake in a moved geometry whose worn surfaces opened by up to
    ``opening`` (m).
    """

    x: np.ndarray
    area: np.ndarray
    r: np.ndarray
    pad_nodes: np.ndarray
    W: Any
    ring: np.ndarray
    rotor_area: np.ndarray
    rotor_x: np.ndarray
    rotor_nodes: np.ndarray | None
    normal_stiffness: np.ndarray
    line_pressure: float
    settings: dict

    def solve(self, offset: np.ndarray, active: np.ndarray | None, *,
              compliance: StepCompliance | np.ndarray | None = None,
              x0: np.ndarray | None = None,
              load: np.ndarray | None = None, mu: float | None = None) -> InterfaceSolution:
        """Contact with ``offset`` (m) added to the gap.

        ``active`` is the start set (None: the interface's own start);
        ``compliance`` makes it the implicit wear step: a
        :class:`StepCompliance` (the pad's wear compliance and, when the
        rotor's ring wear is implicit too, the rotor's and its rings: every
        interface then solves the rings' depths with the pressure, so the
        returned pressure is the end-of-step pressure of both surfaces'
        wear) or an array (m/Pa per pad node, the pad's alone); ``x0``
        starts the Krylov solves; ``load`` is an extra nodal load of the
        model (N per DOF, e.g. thermal strain); ``mu`` the friction
        coefficient of this solve (None: the interface's own).  With rings,
        ``info["ring_depth"]`` holds the rings' depths (m) the solve found.
        """


#: the members every interface has (the capabilities' methods only where declared)
REQUIRED = ("x", "area", "r", "pad_nodes", "W", "ring", "rotor_area", "rotor_x",
            "rotor_nodes", "normal_stiffness", "line_pressure", "settings", "solve")

#: capability -> (the method it promises, what the run asks that needs it)
_PROMISES = {"any_line_pressure": ("at_line_pressure", "another line pressure"),
             "follows_geometry": ("rebuilt", "numerics.update = 'geometry'")}
#: capability with no method -> what the run asks that needs it
_ASKED = {"implicit_rings": "numerics.scheme = 'implicit' with a rotor that wears (or use "
                            "'implicit_pad': the rotor's wear explicit)"}


def capability(interface, name: str) -> bool:
    """Whether ``interface`` declares the capability ``name`` (missing: False)."""
    return getattr(interface, name, False) is True


def check_interface(interface, needs=()) -> None:
    """Refuse (a :class:`~brakewear.errors.WearError` naming what is missing) an
    interface that lacks a member of :class:`Interface` or a capability in
    ``needs``; checked once, when a run starts."""
    name = type(interface).__name__
    missing = [m for m in REQUIRED if not hasattr(interface, m)]
    missing += [meth for cap, (meth, _) in _PROMISES.items()
                if capability(interface, cap) and not callable(getattr(interface, meth, None))]
    if missing:
        raise WearError(f"the interface {name} is not a brakewear Interface: it has no "
                        f"{', '.join(missing)} (brakewear.interfaces.Interface lists what a "
                        "wear run uses)")
    if not callable(interface.solve):
        raise WearError(f"the interface {name}: solve is not a method")
    if not isinstance(interface.settings, dict):
        raise WearError(f"the interface {name}: settings is a "
                        f"{type(interface.settings).__name__}; need a dict")
    for cap in needs:
        if not capability(interface, cap):
            why = _PROMISES.get(cap, (None, _ASKED.get(cap, cap)))[1]
            raise WearError(f"the interface {name} does not declare {cap} = True, which "
                            f"{why} needs")
