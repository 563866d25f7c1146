"""A rust law with its own physics: removal above a pressure threshold, and friction
and pad wear on rust as their own inputs.

A rotor face that stood carries an oxide layer of thickness ``h_c``.  Under
the pad it is removed at

    dh/dt = k_r max(p - p_th, 0) v                  (over a corroded ring)

an Archard law with a threshold: below ``p_th`` the pad slides over the
oxide without removing it (a friable layer needs a least load to break up);
once a ring's mean removal reaches ``h_c`` the iron beneath wears with its own
``k`` (:data:`brakewear.MATERIALS` ``grey_cast_iron``).  On rust the friction
coefficient is ``mu_factor`` times the iron's and the pad wears
``pad_wear_factor`` times as fast (corrosion changes both for cast iron
against a pad material, Djafri et al. 2014; corrosion products penetrate
the pad, Motta, Fedrizzi and Andreatta 2023; how much is an assumption).

Every parameter is a named uncertain input (:data:`RUST_PRIORS`): a wide prior
and where it comes from, or that it is an assumption.  The removal rate
and the threshold are not known for a given pad and rust; a dynamometer
record fits them with their uncertainty (:mod:`brakewear.cleaning.rust_fit`).

:class:`RustLayer` keeps the layer of every rotor face the wear loop models
ring by ring and gives the loop its laws: the rotor's (:class:`RustedRotorLaw`:
the threshold law over corroded rings, the iron's elsewhere), the pad's (its
coefficient times ``pad_wear_factor`` over corroded rings) and the friction
coefficient of the next application (:meth:`RustLayer.friction`).  Whether
the band is cleaned is judged apart, by the cleaning criterion
(:mod:`brakewear.cleaning.corrosion`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..checks import check_number
from ..errors import WearError
from ..laws.base import WearLaw, node_inputs

__all__ = ["RustLaw", "RustedRotorLaw", "RustLayer", "RUST_PRIORS", "Prior"]


@dataclass(frozen=True)
class RustLaw:
    """The rust layer and how it goes (SI units).

    Parameters
    ----------
    thickness : float
        Oxide layer thickness ``h_c`` (m).
    k_rust : float
        Removal coefficient ``k_r`` above the threshold (1/Pa).
    threshold : float
        Contact pressure ``p_th`` below which no oxide is removed (Pa, >= 0).
    mu_factor : float
        Friction coefficient on rust over that on iron.
    pad_wear_factor : float
        The pad's wear coefficient on rust over that on iron.
    """

    thickness: float = 25e-6
    k_rust: float = 1e-12
    threshold: float = 0.0
    mu_factor: float = 1.0
    pad_wear_factor: float = 1.0

    def __post_init__(self):
        check_number("rust.thickness", self.thickness, 0.0, 1e-3, unit="m", kind=WearError)
        check_number("rust.k_rust", self.k_rust, 0.0, 1e-8, unit="1/Pa", kind=WearError)
        check_number("rust.threshold", self.threshold, 0.0, 10e6, lo_open=False, unit="Pa",
                     kind=WearError)
        check_number("rust.mu_factor", self.mu_factor, 0.0, 3.0, unit="", kind=WearError)
        check_number("rust.pad_wear_factor", self.pad_wear_factor, 0.0, 100.0, unit="",
                     kind=WearError)

    def removal_rate(self, p, v) -> np.ndarray:
        """``k_r max(p - p_th, 0) v`` (m/s) at pressure ``p`` (Pa) and speed ``v`` (m/s)."""
        p, v, _, _ = node_inputs(p, v, None, WearError)
        return self.k_rust * np.maximum(p - self.threshold, 0.0) * v

    def coefficient(self, p) -> np.ndarray:
        """The Archard coefficient the threshold law is at pressure ``p``:
        ``k_r max(p - p_th, 0) / p`` (1/Pa; 0 where ``p <= p_th > 0``).  With no
        threshold it is ``k_r`` everywhere, at ``p = 0`` too (its limit): an implicit
        step wears a node that closes within it with the coefficient taken at its start."""
        p = np.clip(np.asarray(p, dtype=float), 0.0, None)
        if self.threshold == 0.0:
            return np.full_like(p, self.k_rust)
        return np.divide(self.k_rust * np.maximum(p - self.threshold, 0.0), p,
                         out=np.zeros_like(p), where=p > 0)


@dataclass(frozen=True)
class Prior:
    """An uncertain input: ``kind`` ``"lognormal"`` (median ``a``, standard deviation
    ``b`` of the logarithm), ``"uniform"`` (``a`` .. ``b``) or ``"normal"`` (mean
    ``a``, standard deviation ``b``), in ``unit``; ``source``: where it comes from,
    or ``"assumption: ..."``."""

    kind: str
    a: float
    b: float
    unit: str
    source: str

    def sample(self, u: np.ndarray) -> np.ndarray:
        """The prior's values at probabilities ``u`` (0..1): its inverse distribution."""
        from scipy import stats

        u = np.asarray(u, dtype=float)
        if self.kind == "lognormal":
            return self.a * np.exp(self.b * stats.norm.ppf(u))
        if self.kind == "uniform":
            return self.a + (self.b - self.a) * u
        if self.kind == "normal":
            return stats.norm.ppf(u, self.a, self.b)
        raise WearError(f"prior kind {self.kind!r} is not allowed; allowed: lognormal, uniform, "
                        "normal")

    @property
    def bounds(self) -> tuple[float, float]:
        """The 0.5 % and 99.5 % points (the range a study samples)."""
        return tuple(float(x) for x in self.sample(np.array([0.005, 0.995])))


#: The rust law's inputs: name (a :class:`RustLaw` field) -> :class:`Prior`, in SI units.
#: Each was re-examined against the public dynamometer and vehicle reports on rust
#: removal (docs/cleaning.md, "The rust law's priors"): where a report says most of the
#: layer is gone after one to three firm stops, the priors allow it.
RUST_PRIORS = {
    "thickness": Prior("lognormal", 25e-6, 0.35, "m",
                       "estimate: days to weeks of standing grow 10-50 um of rust on grey "
                       "cast iron (docs/cleaning.md); no public report gives the layer's "
                       "thickness in numbers (Shin et al., Tribol. Lett. 37, 2010, measure it "
                       "by non-contacting probes); median 25 um, 0.5-99.5 % 10-62 um"),
    "k_rust": Prior("lognormal", 2e-12, 0.8, "1/Pa",
                    "Molina (Applus IDIADA), The Brake Report, Technical Corner on "
                    "corrosion-induced judder, part 3: most of the corroded material is "
                    "consumed during the first stop, no change from the third snub on; "
                    "Audi owner's manual: corrosion is cleaned by braking firmly a few times "
                    "from a moderately high speed.  A firm stop (3 m/s^2 from 80 km/h: about "
                    "1.4 MPa on the pads, 30 m of sliding at the mean radius, 15 % of it under "
                    "the pad) removes k_r x 6e6 m: at the median half of a 25 um layer, all of "
                    "it in one stop in a fifth of the draws and within three stops in two "
                    "thirds.  Calibrate it on a dynamometer record (brakewear.cleaning.rust_fit)"),
    "threshold": Prior("uniform", 0.0, 0.1e6, "Pa",
                       "assumption: a friable oxide breaks up only above a least contact "
                       "pressure; ordinary light braking removes flash rust (a few minutes of "
                       "driving and braking, NAPA Know How), so it lies below a light stop's "
                       "0.2-0.5 MPa at the pads: 0-0.1 MPa; calibrate it on stops at several "
                       "pressures"),
    "mu_factor": Prior("uniform", 0.85, 1.3, "",
                       "corroded discs raised the friction and its oscillation on a 1/5 scale "
                       "dynamometer (Shin, Cho, Kim and Jang, Tribol. Lett. 37, 2010, and the "
                       "same group's stick-slip study); corrosion scales first abrade, then "
                       "are crushed and spread as a solid lubricant (Blau, Truhan and Kenik, "
                       "Tribol. Int. 40, 2007): from 15 % below the iron's to 30 % above"),
    "pad_wear_factor": Prior("lognormal", 2.0, 0.5, "",
                             "the friction material's wear rate rose with the discs' corrosion "
                             "(Jang group, 1/5 scale dynamometer); corrosion changes it "
                             "(Djafri et al., Wear 321, 2014); how much is an assumption: "
                             "0.5-99.5 % 0.55-7.3 x iron's"),
}


@dataclass(frozen=True)
class RustedRotorLaw(WearLaw):
    """The rotor's wear law under a rust layer: per pad node the share ``covered`` of
    rust beneath it (an array the owner updates in place between steps) wears by
    the threshold law of ``rust``, the rest by ``k`` (the iron's Archard law, with
    its temperature rise if any): ``k_i = covered_i k_r(p_i) + (1 - covered_i) k(T)``
    (:meth:`RustLaw.coefficient`, taken at each step's start pressure)."""

    rust: RustLaw = field(default_factory=RustLaw)
    covered: np.ndarray | None = None

    def coefficient_at(self, p, v, T=None) -> np.ndarray:
        """The coefficient per pad node at pressure ``p`` (see the class)."""
        k_iron = super().coefficient_at(p, v, T)
        if self.covered is None:
            return k_iron
        pp = np.broadcast_to(np.asarray(p, dtype=float), k_iron.shape)
        return self.covered * self.rust.coefficient(pp) + (1.0 - self.covered) * k_iron


class RustLayer:
    """The rust layer of the rotor faces under the pads, ring by ring.

    Parameters
    ----------
    interface
        The wear loop's interface (``W``: pad nodes over rotor wear nodes,
        ``ring``: each rotor wear node's ring, ``area``: pad node areas).
    rust
        The :class:`RustLaw`.
    k_iron
        The iron's wear coefficient (1/Pa) once a ring is worn through.
    pad_law
        The pad's wear law on iron (a :class:`~brakewear.WearLaw`).

    Attributes
    ----------
    rotor_law, pad_law
        The laws to give the wear loop; they follow :meth:`update`.
    through : ndarray
        Per ring, whether its layer is worn through.

    As a schedule state (:mod:`brakewear.duty.states`, name ``"rust"``) it
    gives each braked application its friction factor over the layer under
    the last application's pressure (:meth:`friction`), takes every wear step's
    rotor wear (:meth:`update`) and reports the factor it gave.
    """

    name: ClassVar[str] = "rust"

    def __init__(self, interface, rust: RustLaw, k_iron: float, pad_law: WearLaw):
        from .corrosion import LayeredWearLaw

        if not isinstance(rust, RustLaw):
            raise WearError(f"rust = {rust!r} is not a brakewear.cleaning.rust.RustLaw")
        check_number("k_iron", k_iron, 0.0, 1e-8, unit="1/Pa", kind=WearError)
        self.rust, self.W, self.ring, self.area = rust, interface.W, interface.ring, interface.area
        n = self.area.size
        self.n_ring = int(self.ring.max()) + 1
        self._count = np.bincount(self.ring, minlength=self.n_ring)
        self.through = np.zeros(self.n_ring, dtype=bool)
        self.covered = np.ones(n)
        self.rotor_law = RustedRotorLaw(k_iron, rust=rust, covered=self.covered)
        if not isinstance(pad_law, WearLaw):
            raise WearError(f"pad_law = {pad_law!r} is not a brakewear.WearLaw")
        self.pad_law = LayeredWearLaw(pad_law.k, pad_law.a, pad_law.b, pad_law.T_threshold,
                                      pad_law.activation_energy, factor=np.ones(n))
        self._set_pad_factor()
        self.last_pressure = None
        self._factor = 1.0

    # --------------------------------------------------------- schedule state --
    def before(self, app, context: dict) -> dict | None:
        """A braked application's friction factor over the present layer."""
        if not app.braked:
            return None
        self._factor = self.friction(1.0, self.last_pressure)
        return {"mu_factor": self._factor}

    def step(self, pad_wear: np.ndarray, rotor_wear: np.ndarray) -> None:
        """The layer after a wear step (``rotor_wear``: since the layer formed)."""
        self.update(rotor_wear)

    def after(self, record) -> dict | None:
        """The friction factor the application ran with and the rings worn through."""
        if not record.braked:
            return None
        self.last_pressure = np.asarray(record.pressure, dtype=float).copy()
        return {"mu_factor": self._factor, "rings_through": int(self.through.sum())}

    def ring_means(self, rotor_wear: np.ndarray) -> np.ndarray:
        """Ring means of a field on the rotor's wear nodes (the removal depth)."""
        return np.bincount(self.ring, weights=rotor_wear, minlength=self.n_ring) / self._count

    def update(self, rotor_wear: np.ndarray) -> None:
        """Mark the rings whose mean wear (m, cumulative, per rotor wear node) reached
        the layer's thickness and set the laws' per-node shares (in place)."""
        self.through = self.ring_means(rotor_wear) >= self.rust.thickness
        node = np.where(self.through[self.ring], 0.0, 1.0)
        # W's rows sum to 1 to rounding: a share a few ulp past 1 gives the iron a
        # negative weight and the implicit step a negative compliance
        self.covered[:] = np.clip(self.W @ node, 0.0, 1.0)
        self._set_pad_factor()

    def _set_pad_factor(self) -> None:
        self.pad_law.factor[:] = 1.0 + (self.rust.pad_wear_factor - 1.0) * self.covered

    def rust_share(self, pressure: np.ndarray) -> float:
        """The share of the normal load ``sum(p A)`` the pad puts on rust."""
        load = np.maximum(np.asarray(pressure, dtype=float), 0.0) * self.area
        total = float(load.sum())
        return float((load * self.covered).sum() / total) if total > 0 else \
            float(np.mean(self.covered))

    def friction(self, mu_iron: float, pressure: np.ndarray | None = None) -> float:
        """The friction coefficient of the brake over the present layer:
        ``mu_iron (1 + (mu_factor - 1) s)``, ``s`` the load's share on rust under
        ``pressure`` (None: the share of the pad's nodes over rust)."""
        s = float(np.mean(self.covered)) if pressure is None else self.rust_share(pressure)
        return mu_iron * (1.0 + (self.rust.mu_factor - 1.0) * s)
