"""Contact between bodies: surfaces, pairs, per-set operators and the active-set solves.

* :mod:`~brakewear.contact.surface` -- projection of points on facets, mortar
  coupling, ties (geometry only, no solver; normals and tributary areas of a
  mesh's facets are in :mod:`brakewear.mesh`);
* :mod:`~brakewear.contact.pairs` -- :class:`ContactPair` (slave nodes against a
  master surface, with its gaps);
* :mod:`~brakewear.contact.quadratic` -- the pairs of quadratic (P2) slave faces:
  dual mortar coupling, and :mod:`~brakewear.contact.basis`, their solves in the
  transformed basis (:class:`~brakewear.mesh.quadratic.SlaveBasis`; the surface
  geometry of P2 faces is in :mod:`brakewear.mesh.quadratic`);
* :mod:`~brakewear.contact.elimination` -- the eliminated operator of one active set;
* :mod:`~brakewear.contact.active_set` -- the one active-set driver (its policy and
  tuning in :class:`ActiveSetOptions`);
* :mod:`~brakewear.contact.lagrange` -- :func:`solve_contact`, rigid (Lagrange) contact;
* :mod:`~brakewear.contact.compliant` -- :func:`solve_compliant_contact`, contact
  through a compliant layer: the implicit wear step (its set problems, with or
  without rigid support pairs, in :mod:`~brakewear.contact.compliant_sets`);
* :mod:`~brakewear.contact.supports` -- the pad's support in the caliper bracket:
  abutment stops as unilateral pairs with a clearance (:func:`abutment_pairs`),
  radial rails and the anti-rattle spring as a stiffness (:func:`support_springs`).
"""

from . import basis, compliant, lagrange, pairs, supports, surface
from .basis import *  # noqa: F403
from .compliant import *  # noqa: F403
from .lagrange import *  # noqa: F403
from .pairs import *  # noqa: F403
from .supports import *  # noqa: F403
from .surface import *  # noqa: F403

__all__ = [*basis.__all__, *compliant.__all__, *lagrange.__all__, *pairs.__all__,
           *supports.__all__, *surface.__all__]
