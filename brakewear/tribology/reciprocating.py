"""A cylinder reciprocating on a flat (fretting, ASTM G133 in its line-contact form).

Plane strain: a flat (the slave, below) and a cylinder of radius ``R`` (the
master, above) pressed by ``load`` per unit length; the cylinder's support
moves by ``stroke cos(2 pi f t)``.  Each cycle is solved in ``increments``
positions of the stroke with Coulomb friction whose slip is solved
(:func:`brakewear.contact.friction.solve_friction`): at each reversal the
contact sticks and slips from its rim inwards (Cattaneo-Mindlin), in the
stroke's middle it slides; a small stroke against a wide contact never
slides (partial slip).  Both faces wear where they slip, Archard's law on the
local slip: ``dh = k p |dw|``, the flat at its nodes, the cylinder at the
material points that met them.
"""
from __future__ import annotations

import logging
import math

import numpy as np

from ..contact.friction import OPEN, solve_friction
from ..registry import OptionKey
from .bodies import block
from .kinds import CycleResult, TribometerKind, register_tribometer
from .pair import ContactPair
from .sliding import _with_normal as _with_wear

logger = logging.getLogger(__name__)

__all__ = ["Reciprocating"]


@register_tribometer
class Reciprocating(TribometerKind):
    """Cylinder on flat, reciprocating (plane strain, stick and slip solved)."""

    name = "reciprocating"
    bodies = ("flat", "cylinder")
    capabilities = {"dimension": 2, "slip": "solved", "cycle": "cycle"}
    keys = (
        OptionKey("radius", "length", None, lo=0.0, unit="m", doc="the cylinder's radius"),
        OptionKey("load", "line_force", None, lo=0.0, unit="N/m",
                  doc="normal load per unit length of the line contact"),
        OptionKey("stroke", "length", None, lo=0.0, unit="m",
                  doc="the amplitude of the cylinder's support's motion (+- stroke)"),
        OptionKey("frequency", "frequency", 1.0, lo=0.0, unit="Hz",
                  doc="cycles per second (the time of the record only: Archard's law "
                      "does not depend on speed)"),
        OptionKey("cycles", "num", None, lo=0.0, doc="cycles of the test"),
        OptionKey("increments", "int", 20, lo=8, hi=400, lo_open=False,
                  doc="positions of the stroke solved per cycle"),
    )

    @property
    def cycles(self) -> float:
        return float(self.options["cycles"])

    @property
    def cycle_time(self) -> float:
        return 1.0 / self.frequency

    def build(self, scene) -> ContactPair:
        flat, cyl = (scene.bodies[b] for b in self.bodies)
        h, zone, growth = scene.mesh["size"], scene.mesh["zone"], scene.mesh["growth"]
        R = self.radius
        A = block(flat.name, flat.elastic, flat.half_width, flat.depth, zone, h, 2,
                  below=True, growth=growth)
        B = block(cyl.name, cyl.elastic, cyl.half_width, cyl.depth, zone + self.stroke, h, 2,
                  below=False, growth=growth,
                  profile=lambda x: R - np.sqrt(np.clip(R * R - x * x, 0.0, None)))
        return ContactPair(A, B)

    def _positions(self) -> np.ndarray:
        n = self.increments
        return self.stroke * np.cos(2.0 * math.pi * np.arange(1, n + 1) / n)

    def start(self, scene, pair) -> CycleResult:
        """The normal load at the stroke's middle, then the quarter stroke to its end."""
        P, mu = self.load, scene.mu
        sol = solve_friction(pair.compliance(0.0), pair.gap(0.0), mu, P, shift=[0.0])
        off = 0.0
        quarter = self.stroke * np.sin(0.5 * math.pi * np.arange(1, self.increments // 4 + 1)
                                       / (self.increments // 4))
        for x in quarter:
            sol, off = self._step(scene, pair, sol, off, x, None, None)
        return CycleResult(rates={}, pressure=sol.normal / pair.slave.area,
                           slip=np.zeros_like(sol.normal), figures={}, carry=sol,
                           forces=sol.forces, offset=off)

    def _step(self, scene, pair, sol, off, x, hA, hB, jump=0.0):
        """The increment to the stroke position ``x``.  With a ``jump``, the wear the
        increment books (``jump`` times ``k p |dw|`` on each face) is in its gap
        (backward Euler): the slip ``|dw|`` of a first solve sets the wear's
        compliance, the increment is solved again with it, until ``|dw|`` settles."""
        uA, uB = pair.displacements(sol.forces, off)
        w_prev = pair.relative_tangential(uA, uB, x)
        C, g0 = pair.compliance(x), pair.gap(x, hA, hB)
        ds = np.full(g0.size, abs(x - off))
        new = sol
        for _ in range(6 if jump > 0 else 1):
            Cw = C if jump == 0 else _with_wear(C, self._wear_compliance(scene, pair, x, ds,
                                                                          jump))
            new = solve_friction(Cw, g0, scene.mu, self.load, shift=[x - off], w_prev=w_prev,
                                 start=new)
            ds_new = np.linalg.norm(new.slip, axis=1)
            settled = np.max(np.abs(ds_new - ds)) <= 1e-3 * max(abs(x - off), 1e-300)
            ds = ds_new
            if settled:
                break
        pair.check_reach(x, new.state != OPEN)
        return new, x

    def _wear_compliance(self, scene, pair, x, ds, jump) -> np.ndarray:
        """(m, m) the gap the increment's wear opens at each slave node per newton at
        each (m/N): the flat's at the node, the cylinder's spread and read back
        through the pairing."""
        flat, cyl = self.bodies
        kA, kB = scene.bodies[flat].k, scene.bodies[cyl].k
        key = ("wear_back", float(x))
        if key not in pair._cache:          # the pairing's round trip, per stroke position
            Pi = pair.interpolation(x)
            pair._cache[key] = (Pi @ (Pi.T.multiply(1.0 / pair.master.area[:, None]))).toarray()
        W = kB * pair._cache[key] * ds[None, :]
        W[np.diag_indices_from(W)] += kA * ds / pair.slave.area
        return jump * W

    def advance(self, scene, pair, depths: dict, last: CycleResult, jump: float) -> CycleResult:
        """One cycle from ``last`` at the worn ``depths``, each increment's wear booked
        ``jump`` times before the next increment is solved."""
        flat, cyl = self.bodies
        kA, kB = scene.bodies[flat].k, scene.bodies[cyl].k
        hA, hB = depths[flat].copy(), depths[cyl].copy()
        sol, off = last.carry, last.offset
        slip = np.zeros(pair.slave.face.size)
        q_max, its = 0.0, 0
        for x in self._positions():
            sol, off = self._step(scene, pair, sol, off, x, hA, hB, jump)
            ds = np.linalg.norm(sol.slip, axis=1)
            slip += ds
            hA += jump * kA * sol.normal * ds / pair.slave.area
            hB += jump * kB * pair.master_forces((sol.normal * ds)[:, None], x)[:, 0] \
                / pair.master.area
            q_max = max(q_max, abs(float(sol.tangential.sum())))
            its += sol.iterations
        touching = sol.normal > 0
        x = pair.lateral[0]
        return CycleResult(
            rates={flat: (hA - depths[flat]) / jump, cyl: (hB - depths[cyl]) / jump},
            pressure=sol.normal / pair.slave.area, slip=slip,
            figures={"pressure_max_Pa": float(np.max(sol.normal / pair.slave.area)),
                     "contact_half_width_m": 0.5 * float(np.sum(pair.slave.area[touching])),
                     "contact_from_m": float(x[touching].min()),
                     "contact_to_m": float(x[touching].max()),
                     "tangential_force_max_N_per_m": q_max,
                     "slip_centre_m": float(np.interp(0.0, x, slip)),
                     "newton_iterations": its},
            carry=sol, forces=sol.forces, offset=off)

    def profiles(self, pair, depths: dict) -> dict:
        flat, cyl = self.bodies
        return {flat: (pair.slave.x[0], depths[flat]), cyl: (pair.master.x[0], depths[cyl])}
