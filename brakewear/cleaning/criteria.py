"""When is a rotor clean?  The candidate criteria, each judged on the worse face.

A corrosion layer of thickness ``h_c`` covers each rotor face's friction
band; the stops wear it ring by ring (the rotor's wear is a function of the
radius).  With ``d_j`` ring ``j``'s mean wear and ``A_j`` its area in the
band, the candidates are

* ``rings_through`` -- the band's share whose ring is worn through the layer
  (``d_j >= h_c``); met at 1.  A ring counts whole or not at all, so the
  innermost and outermost rings -- the least resolved -- decide it;
* ``band_inset`` -- the same on the band short of the pad's edges by
  ``inset`` on either side (rings clipped to it by area); met at 1;
* ``volume_removed`` -- the share of the layer's volume gone,
  ``sum A_j min(d_j, h_c) / (h_c sum A_j)``; met at ``volume_share``;
* ``iron_load`` -- the share of the pads' load carried on iron, each pad
  node's load weighted by the layer gone under it (the mean of
  ``min(d_j, h_c) / h_c`` over the rings under it); met at ``iron_share``.
  The friction coefficient is then within ``(1 - iron_share) |mu_factor - 1|``
  of the iron's (:class:`~brakewear.cleaning.rust.RustLayer`): friction
  recovered;
* ``dtv_left`` -- the thickness variation the layer left across the band:
  the largest minus the smallest, over the band's radii, of the layer left on
  both faces together (m); met at or below ``dtv``.  An untouched layer
  leaves none: it judges judder, not whether the layer is gone.

:class:`CleaningCriteria` evaluates all of them from the rotor's wear since
the layer formed and the last pressure; :data:`CHOSEN` names the one a
routine is judged by (docs/cleaning.md gives its convergence and why).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..errors import WearError
from .corrosion import BandCriterion

logger = logging.getLogger(__name__)

__all__ = ["CriteriaSettings", "CleaningCriteria", "CRITERIA", "CHOSEN"]

#: the candidate criteria, in the order they are reported
CRITERIA = ("rings_through", "band_inset", "volume_removed", "iron_load", "dtv_left")
#: the criterion a routine is judged by
CHOSEN = "volume_removed"


@dataclass(frozen=True)
class CriteriaSettings:
    """The stated widths and shares of the candidates (SI units): ``inset`` (m) off
    each edge of the band, ``volume_share`` and ``iron_share`` (0..1) and ``dtv``
    (m) at which each is met, and ``chosen``, the one a routine is judged by."""

    inset: float = 2e-3
    volume_share: float = 0.95
    iron_share: float = 0.95
    dtv: float = 10e-6
    chosen: str = CHOSEN

    def __post_init__(self):
        for name, v, ok in (("inset", self.inset, 0 <= self.inset < 0.05),
                            ("volume_share", self.volume_share, 0 < self.volume_share <= 1),
                            ("iron_share", self.iron_share, 0 < self.iron_share <= 1),
                            ("dtv", self.dtv, 0 < self.dtv < 1e-3)):
            if not (np.isfinite(v) and ok):
                raise WearError(f"criteria.{name} = {v!r} is not allowed")
        if self.chosen not in CRITERIA:
            raise WearError(f"criteria.chosen = {self.chosen!r} is not allowed; allowed: "
                            f"{', '.join(CRITERIA)}")


class CleaningCriteria:
    """Every candidate criterion of the rotor faces an interface models.

    Parameters
    ----------
    interface
        The wear loop's interface (``W``, ``ring``, ``rotor_x``, ``area``, ``x``).
    band
        The friction band ``(r_in, r_out)`` (m).
    thickness
        The layer's thickness ``h_c`` (m, > 0).
    settings
        :class:`CriteriaSettings`.
    """

    def __init__(self, interface, band: tuple[float, float], thickness: float,
                 settings: CriteriaSettings | None = None):
        self.settings = settings or CriteriaSettings()
        self.band = BandCriterion(interface, band[0], band[1], thickness)
        b, s = self.band, self.settings
        self.thickness, self.W, self.ring, self.area = thickness, b.W, b.ring, b.area
        self.faces = b.faces
        self.inset_area = self._clipped_areas(band[0] + s.inset, band[1] - s.inset)
        # the pad nodes of each face: the rings under a node are on its face
        ring_face = np.asarray(b.face)[self.ring]
        share = np.asarray(self.W @ (ring_face == "out").astype(float)).ravel()
        self.node_face = np.where(share > 0.5, "out", "in")

    def _clipped_areas(self, lo: float, hi: float) -> np.ndarray:
        """Each ring's area within ``lo..hi`` on its face (m^2)."""
        if not hi > lo:
            raise WearError(f"criteria.inset leaves no band ({lo * 1e3:.2f}..{hi * 1e3:.2f} mm)")
        return self.band.areas_within(lo, hi)

    def removed(self, rotor_wear: np.ndarray) -> np.ndarray:
        """Per ring the share of the layer gone (0..1)."""
        return np.clip(self.band.ring_means(rotor_wear) / self.thickness, 0.0, 1.0)

    def _worse(self, per_ring: np.ndarray, area: np.ndarray) -> tuple[float, dict]:
        faces = {f: float((per_ring * area)[self.band.face == f].sum()
                          / area[self.band.face == f].sum()) for f in self.faces}
        return min(faces.values()), faces

    def evaluate(self, rotor_wear: np.ndarray, pressure: np.ndarray) -> dict:
        """Every candidate: ``{name: {"value", "met", "faces"}}`` (the worse face's value
        and whether it meets the criterion, and each face's value)."""
        s, b = self.settings, self.band
        gone = self.removed(rotor_wear)
        through = (gone >= 1.0 - 1e-12).astype(float)
        out = {}
        v, f = self._worse(through, b.band_area)
        out["rings_through"] = {"value": v, "met": v >= 1.0 - 1e-12, "faces": f}
        v, f = self._worse(through, self.inset_area)
        out["band_inset"] = {"value": v, "met": v >= 1.0 - 1e-12, "faces": f}
        v, f = self._worse(gone, b.band_area)
        out["volume_removed"] = {"value": v, "met": v >= s.volume_share, "faces": f}
        load = np.maximum(np.asarray(pressure, dtype=float), 0.0) * self.area
        under = np.asarray(self.W @ gone[self.ring]).ravel()
        f = {}
        for face in self.faces:
            m = self.node_face == face
            f[face] = float((load[m] * under[m]).sum() / load[m].sum()) if load[m].sum() > 0 \
                else 0.0
        v = min(f.values())
        out["iron_load"] = {"value": v, "met": v >= s.iron_share, "faces": f}
        v = self.dtv_left(gone)
        out["dtv_left"] = {"value": v, "met": v <= s.dtv, "faces": {}}
        return out

    def dtv_left(self, gone: np.ndarray) -> float:
        """The layer left on both faces together, largest minus smallest over the
        band's radii (m; the outboard face's rings read at the inboard's radii)."""
        b = self.band
        left = self.thickness * (1.0 - gone)
        inside = b.band_area > 0
        rings = {f: np.nonzero((b.face == f) & inside)[0] for f in self.faces}
        r0 = np.sort(b.radii[rings[self.faces[0]]])
        total = np.zeros(r0.size)
        for idx in rings.values():
            order = np.argsort(b.radii[idx])
            total += np.interp(r0, b.radii[idx][order], left[idx][order])
        return float(total.max() - total.min())
