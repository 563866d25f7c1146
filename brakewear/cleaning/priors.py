"""The uncertain inputs of a cleaning routine, each with its prior and its source.

A routine's answer depends on inputs no one knows for a given car: the rust
layer's (:data:`~brakewear.cleaning.rust.RUST_PRIORS`), the friction on
iron, what bedding left against the cold rotor, the rotor's heat and
cooling, the pads' modulus, the car's mass and road load, and the caliper's
load path -- its rows' parameters over their plausible ranges
(:data:`brakewear.geometry.sections.LOAD_PATH_KEYS`, docs/load_path.md), the
fingers' radius and footprint -- and how the pads were bedded.  Each is a
:class:`~brakewear.cleaning.rust.Prior`: a distribution and where it comes
from, or that it is an assumption (docs/cleaning.md, "The inputs").

:func:`cleaning_inputs` gives them by name; :func:`draw` samples them (a
seeded generator's probabilities through each prior's inverse distribution),
:func:`values` maps probabilities to values, :func:`medians` gives every one
at its median.
"""
from __future__ import annotations

import logging

import numpy as np

from ..errors import WearError
from .rust import RUST_PRIORS, Prior

logger = logging.getLogger(__name__)

__all__ = ["OTHER_PRIORS", "BEDDED_PRIORS", "NEW_PAD_PRIORS", "LOAD_PATH_SPREAD",
           "cleaning_inputs", "load_path_priors", "draw", "values", "medians", "STARTS"]

#: how a routine starts: from the pads bedded to the rotor, or from a new pad
STARTS = ("bedded", "new")

#: the inputs besides the rust law's and the load path's: name -> Prior (SI units)
OTHER_PRIORS = {
    "mu": Prior("normal", 0.40, 0.03, "",
                "one pad type's friction on iron: 0.34-0.46 at two standard deviations within "
                "the 0.3-0.5 of passenger-car pads (references.md)"),
    "thermal_coning_factor": Prior("uniform", 0.8, 1.2, "",
                                   "estimate: the elastic hat rotor's thermal coning (the 3D FE "
                                   "2-4 % above the converged section model, thermal.md) "
                                   "+-20 % for other hats and their expansion"),
    "convection_factor": Prior("uniform", 1.0, 3.0, "",
                               "estimate: the laminar rotating disc (SpeedConvection.solid, "
                               "thermal.md) is the least a rotor sheds; a wheel housing's air "
                               "flow and radiation (6-18 W/m2K at 200-400 C, eps 0.6) add up "
                               "to as much again or twice"),
    "pad_modulus": Prior("lognormal", 1.0, 0.25, "",
                         "estimate: friction materials span 1-15 GPa (references.md); one pad "
                         "type's modulus a factor 0.5-1.9 of the resin's, taken on the levels "
                         "0.7, 1.0, 1.4"),
    "mass": Prior("uniform", 1600.0, 2100.0, "kg", "references.md, 'The study's car'"),
    "rolling_resistance": Prior("uniform", 0.0065, 0.012, "", "references.md, 'The study's car'"),
    "drag_area": Prior("uniform", 0.50, 0.72, "m^2", "references.md, 'The study's car'"),
    "drivetrain_drag": Prior("uniform", 10.0, 80.0, "N", "references.md, 'The study's car'"),
    "finger_radius": Prior("uniform", 118.0, 134.0, "mm",
                           "estimate: the fingers bear outboard of the piston (119 mm) where the "
                           "bridge reaches over the rotor's 150 mm edge: 118-134 mm on a 95-138 mm "
                           "lining (geometry/floating.toml, 126 mm); taken on the levels 120, "
                           "126, 132 mm"),
    "finger_diameter": Prior("uniform", 14.0, 26.0, "mm",
                             "estimate: a cast finger's pad on the backplate, 14-26 mm across "
                             "(geometry/floating.toml, 20 mm); taken on the levels 16 and 24 mm"),
}

#: the pads bedded to the rotor (the default start): how they were bedded, and what
#: the rotor adds against them when cold
BEDDED_PRIORS = {
    "bedding_heat": Prior("uniform", 0.0, 1.0, "",
                          "how hot the pads bedded: 0 cold (ordinary driving: 'Akebono, ATE: "
                          "400-500 miles of moderate driving', Tire Rack's bed-in page), 1 hot "
                          "(a burnish of firm stops: Raybestos' 5 hard stops from 80 mph, "
                          "Brembo's 30 from 60 mph); the bedded gap holds that share of the hot "
                          "duty's thermal coning (brakewear.cleaning.bedding)"),
    "static_coning": Prior("uniform", -10e-6, 10e-6, "m",
                           "estimate: what a face that stood adds to the bedded gap across the "
                           "band: rotor face flatness and runout within service limits (lateral "
                           "runout 0.03-0.06 mm, thickness variation 0.010-0.03 mm: GM and Ford "
                           "service manuals), a tenth to a third of it across a 43 mm band"),
}

#: a new pad's start (a labelled scenario): its non-conformity across the band
NEW_PAD_PRIORS = {
    "coning": Prior("uniform", 15e-6, 45e-6, "m",
                    "estimate: a new flat pad against a coned rotor, 15-45 um across the pad "
                    "(docs/cleaning.md, 'A new pad')"),
}

#: the load-path keys whose plausible ranges the inputs cover
LOAD_PATH_SPREAD = ("piston.seal_modulus", "piston.bore_clearance", "piston.engagement_length",
                    "piston.stand_out", "piston.rim_friction", "piston.bore_friction",
                    "support.abutment_friction", "support.spring_stiffness",
                    "caliper.bridge_tilt", "caliper.bore_tilt", "caliper.finger_stiffness")


def load_path_priors(geometry: str = "floating", keys=LOAD_PATH_SPREAD) -> dict:
    """``"load_path:<key>"`` -> a uniform :class:`Prior` over the key's plausible range
    (:data:`brakewear.geometry.sections.LOAD_PATH_KEYS`), in the geometry file's units."""
    import tomllib

    from ..geometry import geometry_file
    from ..geometry.sections import LOAD_PATH_KEYS, STIFFNESS_UNITS

    units = tomllib.loads(geometry_file(geometry).read_text()).get("units", {})
    out = {}
    for key in keys:
        _, unit, si, _, (lo, hi), what = LOAD_PATH_KEYS[key]
        name = unit
        if unit == "length":
            name = units.get("length", "mm")
            si = {"mm": 1e-3, "m": 1.0}[name]
        elif unit == "stiffness":
            name = units.get("stiffness", "N/mm")
            si = STIFFNESS_UNITS[name]
        out[f"load_path:{key}"] = Prior("uniform", float(lo / si), float(hi / si), name,
                                        f"the plausible range of {what} (docs/load_path.md)")
    return out


def cleaning_inputs(start: str = "bedded", geometry: str = "floating") -> dict:
    """Every uncertain input of a routine: name -> :class:`Prior` (the rust law's,
    :data:`OTHER_PRIORS`, the start's -- :data:`BEDDED_PRIORS` or
    :data:`NEW_PAD_PRIORS` -- and the load path's)."""
    if start not in STARTS:
        raise WearError(f"start = {start!r} is not allowed; allowed: {', '.join(STARTS)}")
    own = BEDDED_PRIORS if start == "bedded" else NEW_PAD_PRIORS
    return {**RUST_PRIORS, **OTHER_PRIORS, **own, **load_path_priors(geometry)}


def values(u: dict, priors: dict) -> dict:
    """The inputs at probabilities ``u`` (name -> 0..1)."""
    return {k: float(priors[k].sample(np.array([p]))[0]) for k, p in u.items()}


def draw(n: int, seed: int = 37, priors: dict | None = None) -> list[dict]:
    """``n`` independent draws of ``priors`` (default :func:`cleaning_inputs`)."""
    pri = cleaning_inputs() if priors is None else priors
    u = np.random.default_rng(seed).random((n, len(pri)))
    return [values(dict(zip(pri, row)), pri) for row in u]


def medians(priors: dict | None = None) -> dict:
    """Every input at its median."""
    pri = cleaning_inputs() if priors is None else priors
    return values({k: 0.5 for k in pri}, pri)
