"""Interface models: what a wear step asks of the pad-rotor interface.

A wear step gives an interface a gap offset (the worn depths), the last
active set and, for the implicit step, the wear compliance; the interface
returns the contact pressure, the active set and the displacement
(:class:`InterfaceSolution`).  Models: finite-element contact
(:class:`FEInterface`), an elastic (Winkler) foundation
(:class:`FoundationInterface` around :class:`WinklerInterface`, calibrated
against FE contact by :func:`calibrate`), and the FE model condensed onto its
contact nodes (:class:`CondensedInterface`, computed by :func:`condense`),
and the pads held by the caliper's rigid piston, fingers and abutments
(:class:`CaliperInterface`, condensed with the caliper's rows), all
behind the :class:`Interface` protocol of the wear loop
(:mod:`~brakewear.interfaces.protocol`); :func:`choose_interface` picks FE or
condensed for a run (``interface.model = "auto"``).  Each registers itself by
name in the table a scene chooses from (:mod:`~brakewear.interfaces.registry`).
"""

# the models register themselves in this order: "fe", "winkler", "condensed", "auto";
# "caliper" (brakewear.caliper.interface, above this package) on the table's first lookup
from . import fe, foundation, condensed, auto  # noqa: I001
from . import calibration, condensation, protocol, registry, winkler_bed
from .auto import *  # noqa: F403
from .calibration import *  # noqa: F403
from .condensation import *  # noqa: F403
from .condensed import *  # noqa: F403
from .fe import *  # noqa: F403
from .foundation import *  # noqa: F403
from .protocol import *  # noqa: F403
from .registry import *  # noqa: F403
from .winkler_bed import *  # noqa: F403

__all__ = [*auto.__all__, *calibration.__all__, *condensation.__all__,
           *condensed.__all__, *fe.__all__, *foundation.__all__, *protocol.__all__,
           *registry.__all__, *winkler_bed.__all__]
