"""Wear limits: a run ends when a surface has worn through (or, in a thermal
run, when a face passes its plausibility bound: :func:`check_temperature`).

The pad may wear its friction layer down to the backplate, the rotor down to
its minimum (discard) thickness.  :class:`WearLimits` holds the largest wear
depth of each surface and :meth:`WearLimits.check` tests every accepted wear
step: the first node past its limit gives a
:class:`~brakewear.errors.WornThroughError` that says which surface, when
(the time the node reached the limit, interpolated within the step), where
(radius and angle of the node) and how deep.  The command line exits with
code 4, and ``summary.json`` says ``"status": "worn_through"``.

Defaults: the pad's limit is the friction layer's thickness; the rotor's is
:data:`ROTOR_LIMIT` per friction face (a rotor is discarded about 2 mm below
its nominal thickness, worn from both faces), at most a quarter of the rotor
thickness.  Scene keys ``wear.pad.limit`` and ``wear.rotor.limit`` set them.
With the geometry update the pad stops :data:`GEOMETRY_MARGIN` of its layer
short of the backplate (the moved elements of the layer would degenerate).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from ..checks import shown_in
from ..errors import TemperatureLimitError, WearError, WornThroughError

logger = logging.getLogger(__name__)

__all__ = ["WearLimits", "ROTOR_LIMIT", "check_temperature"]

#: Default largest wear depth of one rotor friction face (m).
ROTOR_LIMIT = 1.0e-3
#: Geometry update: the part of the friction layer the moved mesh cannot wear away
#: (its elements flatten to nothing; at 1 % left their quality is below 0.02).
GEOMETRY_MARGIN = 0.05


@dataclass
class WearLimits:
    """Largest wear depths of the pad's and the rotor's friction faces.

    Build the defaults of a model with :meth:`for_model`.

    Parameters
    ----------
    pad, rotor
        The depths (m) at which each face is worn through; None: no limit.
    """

    pad: float | None
    rotor: float | None

    def __post_init__(self):
        for name in ("pad", "rotor"):
            v = getattr(self, name)
            if v is not None and not (isinstance(v, (int, float)) and not isinstance(v, bool)
                                      and v > 0 and not math.isnan(v)):
                raise WearError(f"{name} wear limit = {v!r} m is not allowed; need a depth "
                                "> 0 (m) or None")
        self._previous = None

    @classmethod
    def for_model(cls, model, pad: float | None = None, rotor: float | None = None,
                  update: str = "gap") -> WearLimits:
        """The limits of ``model`` (a BrakeModel): the given ones, else the defaults.

        With ``update = "geometry"`` the pad's limit is at most
        ``1 - GEOMETRY_MARGIN`` of the friction layer: the moved mesh flattens
        the layer's elements, which degenerate as the layer vanishes.
        """
        g = model.geometry
        pad = g.pad.friction_thickness if pad is None else pad
        if update == "geometry":
            pad = min(pad, (1.0 - GEOMETRY_MARGIN) * g.pad.friction_thickness)
        return cls(pad=pad,
                   rotor=min(ROTOR_LIMIT, 0.25 * g.rotor.thickness) if rotor is None else rotor)

    def check(self, step, itf) -> WornThroughError | None:
        """The error to raise if ``step`` (a WearStep) wore a surface past its limit.

        ``itf`` is the wear loop's interface (``x``: pad friction node
        positions; ``rotor_x``: rotor wear node positions).  Call once per
        accepted step, in order: the previous step's depths give the time at
        which the limit was reached.
        """
        prev = self._previous
        if prev is not None and not math.isclose(prev[0], step.time - step.dt, rel_tol=1e-9):
            prev = None                  # not the step before this one (a resumed run)
        self._previous = (step.time, step.pad_wear, step.rotor_wear)
        for body, depth, limit, x in (("pad", step.pad_wear, self.pad, itf.x),
                                      ("rotor", step.rotor_wear, self.rotor,
                                       getattr(itf, "rotor_x", None))):
            if limit is None or depth is None or depth.size == 0 or depth.max() < limit:
                continue
            before = np.zeros_like(depth) if prev is None else prev[1 if body == "pad" else 2]
            if before.shape != depth.shape:
                before = np.zeros_like(depth)
            over = np.nonzero(depth >= limit)[0]
            # fraction of the step at which each node reached the limit (wear is linear
            # in time within a step)
            frac = np.clip((limit - before[over]) / np.maximum(depth[over] - before[over],
                                                               1e-300), 0.0, 1.0)
            i = over[np.argmin(frac)]
            t = step.time - step.dt + float(frac.min()) * step.dt
            r = theta = float("nan")
            if x is not None:
                r = float(np.hypot(x[0, i], x[1, i]))
                theta = float(np.degrees(np.arctan2(x[1, i], x[0, i])))
            what = ("pad worn through its friction layer" if body == "pad"
                    else "rotor worn to its limit")
            # the time the node reached the limit goes with the limit; the step's end
            # time with the depth the step left it at
            return WornThroughError(
                f"{what} at t = {shown_in('time', t, 6)}: the node at r = "
                f"{shown_in('length', r)}, theta = {theta:.1f} deg reached the limit "
                f"{shown_in('length', limit)} (wear.{body}.limit) within step {step.step}, "
                f"which ended at t = {shown_in('time', step.time, 6)} with it worn "
                f"{shown_in('length', float(depth[i]))}; the run ends here",
                body=body, time=t, step=step.step, r=r, theta=theta,
                depth=float(depth[i]), limit=float(limit), step_end=float(step.time))
        return None


def check_temperature(step, thermal) -> None:
    """Raise :class:`~brakewear.errors.TemperatureLimitError` if ``step`` (a WearStep
    of a thermal run) left a face hotter than ``thermal.T_max``."""
    for body, T in (("pad", step.pad_temperature_max), ("rotor", step.rotor_temperature_max)):
        if not (np.isfinite(T) and T > thermal.T_max):
            continue
        backflow = (", contact_conductance 0 with a meshed rotor: no heat flows back to the "
                    "rotor; give thermal.contact_conductance > 0 (default 1e5 W/m^2 K)"
                    if thermal.contact_conductance == 0 and "rotor" in thermal.bodies else "")
        act = step.active if step.active_end is None else step.active_end
        p = step.pressure if step.pressure_end is None else step.pressure_end
        rigid = ("; with a rigid rotor nothing expands to meet the pad's hot spot: use "
                 "components.rotor = 'elastic'" if "rotor" not in thermal.bodies else "")
        raise TemperatureLimitError(
            f"step {step.step} (t = {shown_in('time', step.time, 6)}): the {body} face "
            f"reached {shown_in('temperature', T, decimals=0)}, beyond the plausibility bound "
            f"T_max = {shown_in('temperature', thermal.T_max, decimals=0)} (thermal.T_max). "
            "Likely causes: the heat "
            f"partition (pad share {float(np.mean(thermal.partition)):.3g}{backflow}), a duty "
            "beyond the brake's thermal capacity (line pressure x speed x duration), or a "
            f"contact concentrated on a few nodes (now {int(np.count_nonzero(act))} of "
            f"{act.size} pad nodes, up to {shown_in('pressure', float(np.max(p)), 3)}: "
            "thermoelastic "
            f"localisation{rigid}); raise thermal.T_max only if such temperatures are meant",
            body=body, temperature=float(T), T_max=thermal.T_max, step=step.step,
            time=step.time)
