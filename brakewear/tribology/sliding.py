"""Continuous sliding: a pin on a disc (ASTM G99) and a block on a ring (ASTM G77).

In both the counterface (the master: the disc, the ring) passes through the
contact with the same shape at every instant, so the contact is solved once
per revolution in the stationary body's frame, in gross sliding
(:func:`brakewear.contact.friction.solve_sliding`: the friction ``mu N``
against the counterface's motion at every node in contact).  The stationary
body (the slave: the pin, the block) wears at its nodes, ``dh = k p`` times the
sliding distance; the counterface's wear is spread over its circumference, as
a brake rotor's is:

* the disc: a point at radius ``r_track + y`` passes under the pin once per
  revolution and loses ``k int p dx`` along its path -- a groove ``h(y)``;
* the ring: every point of its circumference passes, and the ring wears
  uniformly, ``k P'`` per revolution (``P'`` the load per unit width).
"""
from __future__ import annotations

import logging
import math

import numpy as np

from ..analytic.tribometer import conforming_block_on_ring, spherical_cap_height
from ..checks import fail
from ..contact.friction import solve_sliding
from ..registry import OptionKey
from .bodies import block, face_triangles, ring
from .kinds import CycleResult, TribometerKind, register_tribometer
from .pair import ContactPair

logger = logging.getLogger(__name__)

__all__ = ["PinOnDisc", "BlockOnRing"]


def _with_normal(C: np.ndarray, W: np.ndarray) -> np.ndarray:
    """``C`` with ``W`` (m, m; m/N) added to its normal-normal block: the gap the
    step's wear opens per newton of contact force."""
    d = C.shape[0] // W.shape[0]
    out = C.copy()
    out[d - 1::d, d - 1::d] += W
    return out


def _figures(pair, sol) -> dict:
    touching = sol.normal > 0
    p = sol.normal / pair.slave.area
    return {"pressure_max_Pa": float(p.max()),
            "contact_area": float(np.sum(pair.slave.area[touching])),
            "newton_iterations": sol.iterations}


@register_tribometer
class PinOnDisc(TribometerKind):
    """A pin with a spherical or flat end on a rotating disc's face (3D)."""

    name = "pin_on_disc"
    bodies = ("pin", "disc")
    capabilities = {"dimension": 3, "slip": "sliding", "cycle": "revolution"}
    keys = (
        OptionKey("pin", "str", "sphere", choices=("sphere", "flat"),
                  doc="the pin's end: a sphere of radius `radius` or a flat of radius `radius`"),
        OptionKey("radius", "length", None, lo=0.0, unit="m", doc="the pin end's radius"),
        OptionKey("load", "force", None, lo=0.0, unit="N", doc="the normal load"),
        OptionKey("track_radius", "length", None, lo=0.0, unit="m",
                  doc="the wear track's radius on the disc"),
        OptionKey("speed", "angular_speed", 2 * math.pi, lo=0.0, unit="rad/s",
                  doc="the disc's speed (the time of the record only)"),
        OptionKey("distance", "length", None, lo=0.0, unit="m",
                  doc="the sliding distance at the track radius"),
    )

    @property
    def cycles(self) -> float:
        return self.distance / (2 * math.pi * self.track_radius)

    @property
    def cycle_time(self) -> float:
        return 2 * math.pi / self.speed

    def check(self, scene) -> None:
        pin = scene.bodies["pin"]
        zone = scene.mesh["zone"]
        if self.pin == "sphere" and pin.half_width * math.sqrt(2) >= self.radius:
            raise fail("bodies.pin.half_width", f"{pin.half_width:g} m: the pin's meshed block "
                       f"must fit inside its sphere; need half_width < radius / sqrt(2) = "
                       f"{self.radius / math.sqrt(2):g} m")
        if self.pin == "flat" and abs(pin.half_width - self.radius) > 1e-12 * self.radius:
            raise fail("bodies.pin.half_width", f"{pin.half_width:g} m: a flat pin is meshed "
                       f"as its cylinder; give half_width = test.radius = {self.radius:g} m")
        if self.track_radius <= 2 * max(zone, pin.half_width):
            raise fail("test.track_radius", f"{self.track_radius:g} m: the track must lie "
                       "well outside the pin (more than twice its meshed half-width)")

    def build(self, scene) -> ContactPair:
        pin, disc = (scene.bodies[b] for b in self.bodies)
        h, zone, growth = scene.mesh["size"], scene.mesh["zone"], scene.mesh["growth"]
        R = self.radius
        if self.pin == "sphere":
            A = block(pin.name, pin.elastic, pin.half_width, pin.depth, zone, h, 3, below=True,
                      growth=growth,
                      profile=lambda x, y: -(R - np.sqrt(np.clip(R * R - x * x - y * y, 0.0,
                                                                 None))))
            reach = zone
        else:
            A = block(pin.name, pin.elastic, R, pin.depth, R, h, 3, below=True,
                      growth=growth, round_section=True)
            reach = R
        B = block(disc.name, disc.elastic, disc.half_width, disc.depth, reach + 2 * h, h, 3,
                  below=False, growth=growth)
        return ContactPair(A, B, tris=face_triangles(B))

    def _rings(self, pair):
        """The disc's rings: their lateral positions y (the disc face nodes') and the
        hat functions of the pin nodes on them."""
        y = pair.master.x[1]
        h = float(np.sqrt(np.median(pair.master.area)))
        ys = np.unique(np.round(y / (1e-3 * h)) * (1e-3 * h))
        yp = pair.lateral[1]
        j = np.clip(np.searchsorted(ys, yp) - 1, 0, ys.size - 2)
        t = np.clip((yp - ys[j]) / (ys[j + 1] - ys[j]), 0.0, 1.0)
        width = np.gradient(ys)
        return ys, j, t, width

    def start(self, scene, pair) -> CycleResult:
        return CycleResult(rates={}, pressure=np.zeros(pair.slave.face.size),
                           slip=np.zeros(pair.slave.face.size), figures={}, carry=None)

    def advance(self, scene, pair, depths: dict, last: CycleResult, jump: float) -> CycleResult:
        """``jump`` revolutions in one backward-Euler step: the contact is solved with
        the wear of the step in its gap (the pin's at each node, the disc's rings')."""
        pin, disc = self.bodies
        kA, kB = scene.bodies[pin].k, scene.bodies[disc].k
        rt = self.track_radius
        y = pair.lateral[1]
        s = 2 * math.pi * (rt + y)                        # sliding distance per revolution
        ys, j, t, width = self._rings(pair)
        m = y.size
        hat = np.zeros((m, ys.size))                      # pin node -> rings
        hat[np.arange(m), j] = 1 - t
        hat[np.arange(m), j + 1] = t
        # ring depth per revolution per newton at each pin node; back at the pin nodes
        H = kB * (hat * (rt + y)[:, None]).T / ((rt + ys) * width)[:, None]
        W = jump * (np.diag(kA * s / pair.slave.area) + hat @ H)
        sol = solve_sliding(_with_normal(pair.compliance(0.0), W),
                            pair.gap(0.0, depths[pin], depths[disc]), scene.mu, self.load,
                            [1.0, 0.0], start=last.carry)
        pair.check_reach(0.0, sol.normal > 0)
        rate_pin = kA * sol.normal * s / pair.slave.area
        rate_disc = np.interp(pair.master.x[1], ys, H @ sol.normal)
        return CycleResult(rates={pin: rate_pin, disc: rate_disc},
                           pressure=sol.normal / pair.slave.area, slip=s,
                           figures=_figures(pair, sol), carry=sol.normal, forces=sol.forces)

    def closed_form(self, scene) -> dict | None:
        """A spherical pin on a disc that does not wear wears a flat cap of volume
        ``k F s`` (:func:`~brakewear.analytic.tribometer.spherical_cap_height`)."""
        if self.pin != "sphere" or scene.bodies["disc"].k > 0:
            return None
        R = self.radius
        cap = spherical_cap_height(scene.bodies["pin"].k * self.load * self.distance, R)
        r = np.linspace(-cap["radius"], cap["radius"], 201)
        return {"body": "pin", "name": "spherical cap of volume k F s",
                "depth_max": cap["h"], "scar_width": 2 * cap["radius"], "worn_volume": cap["V"],
                "profile": (r, cap["h"] - (R - np.sqrt(R * R - r * r)))}

    def profiles(self, pair, depths: dict) -> dict:
        """Sections through the pin's centre across the track (y) and the disc's groove."""
        pin, disc = self.bodies
        x, y = pair.lateral
        on = np.abs(x) <= 1e-9 + np.min(np.abs(x))
        order = np.argsort(y[on])
        ys, _, _, _ = self._rings(pair)
        groove = np.interp(ys, pair.master.x[1], depths[disc])
        return {pin: (y[on][order], depths[pin][on][order]), disc: (ys, groove)}


@register_tribometer
class BlockOnRing(TribometerKind):
    """A block pressed on a rotating ring's periphery (plane strain)."""

    name = "block_on_ring"
    bodies = ("block", "ring")
    capabilities = {"dimension": 2, "slip": "sliding", "cycle": "revolution"}
    keys = (
        OptionKey("ring_radius", "length", None, lo=0.0, unit="m", doc="the ring's outer radius"),
        OptionKey("bore", "length", None, lo=0.0, unit="m", doc="the ring's bore radius"),
        OptionKey("load", "force", None, lo=0.0, unit="N", doc="the normal load"),
        OptionKey("width", "length", None, lo=0.0, unit="m",
                  doc="the contact's length along the ring's axis (the block's width)"),
        OptionKey("speed", "angular_speed", 2 * math.pi, lo=0.0, unit="rad/s",
                  doc="the ring's speed (the time of the record only)"),
        OptionKey("distance", "length", None, lo=0.0, unit="m", doc="the sliding distance"),
    )

    @property
    def line_load(self) -> float:
        return self.load / self.width

    @property
    def cycles(self) -> float:
        return self.distance / (2 * math.pi * self.ring_radius)

    @property
    def cycle_time(self) -> float:
        return 2 * math.pi / self.speed

    def check(self, scene) -> None:
        if self.bore >= self.ring_radius:
            raise fail("test.bore", f"{self.bore:g} m is not allowed; it must be below "
                       f"test.ring_radius = {self.ring_radius:g} m")

    def build(self, scene) -> ContactPair:
        blk, rng = (scene.bodies[b] for b in self.bodies)
        h, zone, growth = scene.mesh["size"], scene.mesh["zone"], scene.mesh["growth"]
        A = block(blk.name, blk.elastic, blk.half_width, blk.depth, zone, h, 2, below=True,
                  growth=growth)
        B = ring(rng.name, rng.elastic, self.ring_radius, self.bore, zone + 2 * h, h,
                 growth=growth)
        return ContactPair(A, B)

    def start(self, scene, pair) -> CycleResult:
        return CycleResult(rates={}, pressure=np.zeros(pair.slave.face.size),
                           slip=np.zeros(pair.slave.face.size), figures={}, carry=None)

    def advance(self, scene, pair, depths: dict, last: CycleResult, jump: float) -> CycleResult:
        """``jump`` revolutions in one backward-Euler step (the block's and the ring's
        wear of the step in the gap)."""
        blk, rng = self.bodies
        kA, kB = scene.bodies[blk].k, scene.bodies[rng].k
        s = 2 * math.pi * self.ring_radius
        m = pair.slave.face.size
        # the ring wears k P' all round per revolution: a uniform opening of the gap
        W = jump * (np.diag(kA * s / pair.slave.area) + kB * np.ones((m, m)))
        sol = solve_sliding(_with_normal(pair.compliance(0.0), W),
                            pair.gap(0.0, depths[blk], depths[rng]), scene.mu, self.line_load,
                            [1.0], start=last.carry)
        pair.check_reach(0.0, sol.normal > 0)
        rate_block = kA * sol.normal * s / pair.slave.area
        rate_ring = np.full(pair.master.face.size, kB * float(sol.normal.sum()))
        touching = sol.normal > 0
        x = pair.lateral[0]
        fig = _figures(pair, sol)
        fig.update(contact_half_width_m=0.5 * fig.pop("contact_area"),
                   contact_from_m=float(x[touching].min()), contact_to_m=float(x[touching].max()))
        return CycleResult(rates={blk: rate_block, rng: rate_ring},
                           pressure=sol.normal / pair.slave.area,
                           slip=np.full(x.size, s), figures=fig, carry=sol.normal,
                           forces=sol.forces)

    def closed_form(self, scene) -> dict | None:
        """The block worn into the ring's shape, both rigid
        (:func:`~brakewear.analytic.tribometer.conforming_block_on_ring`)."""
        R = self.ring_radius
        c = conforming_block_on_ring(self.line_load, R, self.distance, scene.bodies["block"].k,
                                     scene.bodies["ring"].k)
        x = np.linspace(-0.5 * c["width"], 0.5 * c["width"], 201)
        return {"body": "block", "name": "block conforming to the ring (rigid bodies)",
                "depth_max": c["depth"], "scar_width": c["width"], "worn_area": c["area"],
                "worn_volume": c["area"] * self.width,
                "profile": (x, c["depth"] - (R - np.sqrt(R * R - x * x)))}

    def profiles(self, pair, depths: dict) -> dict:
        blk, rng = self.bodies
        return {blk: (pair.slave.x[0], depths[blk]), rng: (pair.master.x[0], depths[rng])}
