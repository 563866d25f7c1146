"""Contact between bodies: surfaces, pairs, per-set operators and the active-set solves.

* :mod:`~brakewear.contact.surface` -- projection of points on facets, mortar
  coupling, ties (geometry only, no solver; normals and tributary areas of a
  mesh's facets are in :mod:`brakewear.mesh`);
* :mod:`~brakewear.contact.pairs` -- :class:`ContactPair` (slave nodes against a
  master surface, with its gaps);
* :mod:`~brakewear.contact.elimination` -- the eliminated operator of one active set;
* :mod:`~brakewear.contact.active_set` -- the one active-set driver (its policy and
  tuning in :class:`ActiveSetOptions`);
* :mod:`~brakewear.contact.lagrange` -- :func:`solve_contact`, rigid (Lagrange) contact;
* :mod:`~brakewear.contact.compliant` -- :func:`solve_compliant_contact`, contact
  through a compliant layer: the implicit wear step.
"""

from .compliant import (
    CompliantResult,
    compliant_preconditioner,
    constraint_rows,
    solve_compliant_contact,
)
from .lagrange import ContactResult, contact_preconditioner, solve_contact
from .pairs import ContactPair, pair_to_rigid, pair_to_surface
from .surface import Projection, project_nodes, tie_prolongation

__all__ = [
    "constraint_rows",
    "solve_compliant_contact",
    "compliant_preconditioner",
    "CompliantResult",
    "ContactResult",
    "solve_contact",
    "contact_preconditioner",
    "ContactPair",
    "pair_to_surface",
    "pair_to_rigid",
    "Projection",
    "project_nodes",
    "tie_prolongation",
]
