"""Cleaning a corroded rotor: a layered rotor wear law and the cleaning criterion.

A rotor face that stood (an electric car braking by regeneration) carries a
corrosion layer of thickness ``h_c`` that wears with ``k_layer`` (much
faster than the iron beneath, ``k_base``).  The pad must sweep the whole
friction band -- the annulus ``r_in <= r <= r_out`` the pad covers -- and
wear through the layer everywhere.

:class:`CorrodedRotor` keeps, per rotor ring, whether the layer is worn
through, and gives the wear loop a rotor law whose coefficient at each pad
node is that of the ring under it (``k_layer`` or ``k_base``); call
:meth:`CorrodedRotor.update` with the cumulative rotor wear after each step.

The criterion, per rotor face, by *area* (rings are annuli, so an outer ring
counts more than an inner one of the same width):

* ``cleaned_fraction`` -- the band's area whose ring wear reached ``h_c``;
* ``touched_fraction`` -- the band's area over which the pad presses with a
  mean pressure (over the pad's footprint at that radius) of at least
  ``threshold``: a ring grazed by one node at a few pascals does not count.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import WearError
from .laws import WearLaw

__all__ = ["LayeredWearLaw", "CorrodedRotor", "coning_gap"]


@dataclass(frozen=True)
class LayeredWearLaw(WearLaw):
    """Archard law ``k`` times a per-pad-node ``factor`` (an array the owner updates
    in place between steps: 1 over a corroded ring, ``k_base / k`` over bare iron)."""

    factor: np.ndarray | None = None

    def rate(self, p, v, T=None):
        r = super().rate(p, v, T)
        return r if self.factor is None else r * self.factor


def coning_gap(r: np.ndarray, r_in: float, r_out: float, coning: float) -> np.ndarray:
    """Initial gap (m) of a coning (or radial pad taper) of ``coning`` m across the band.

    Linear in radius, zero at ``r_in`` and ``coning`` at ``r_out``; a negative
    ``coning`` opens the gap at the inner radius instead (zero at ``r_out``).
    A coned rotor does the one on one face and the other on the opposite face.
    """
    g = coning * (np.asarray(r, dtype=float) - r_in) / (r_out - r_in)
    return g - g.min()


class CorrodedRotor:
    """The corrosion layer of one rotor face under the pad, ring by ring.

    Parameters
    ----------
    interface
        The wear loop's interface (``W``, ``ring``, ``rotor_x``, ``rotor_area``,
        ``area``: an :class:`~brakewear.interfaces.FEInterface`).
    r_in, r_out
        The friction band swept by the pad (m).
    thickness
        Corrosion layer thickness (m, > 0).
    k_layer, k_base
        Wear coefficients of the layer and of the iron beneath (1/Pa).
    threshold
        Smallest mean pad pressure (Pa, >= 0) over a ring for it to count as touched.
    """

    def __init__(self, interface, r_in: float, r_out: float, thickness: float,
                 k_layer: float, k_base: float, threshold: float = 0.0):
        for name, x in (("thickness", thickness), ("k_layer", k_layer), ("k_base", k_base)):
            if not (np.isfinite(x) and x > 0):
                raise WearError(f"{name} = {x!r} is not allowed; need > 0")
        if not (np.isfinite(threshold) and threshold >= 0):
            raise WearError(f"threshold = {threshold!r} Pa is not allowed; need >= 0")
        if not (0 < r_in < r_out):
            raise WearError(f"friction band {r_in!r}..{r_out!r} m is not allowed; need "
                            "0 < r_in < r_out")
        itf = interface
        self.W, self.ring, self.area = itf.W, itf.ring, itf.area
        self.thickness, self.k_layer, self.k_base = thickness, k_layer, k_base
        self.threshold = threshold
        r = np.hypot(itf.rotor_x[0], itf.rotor_x[1])
        n_ring = int(self.ring.max()) + 1
        self.radii = np.bincount(self.ring, weights=r, minlength=n_ring) / np.bincount(
            self.ring, minlength=n_ring)
        mid = 0.5 * (self.radii[1:] + self.radii[:-1])
        lo = np.clip(np.concatenate([[self.radii[0]], mid]), r_in, r_out)
        hi = np.clip(np.concatenate([mid, [self.radii[-1]]]), r_in, r_out)
        self.band_area = np.pi * (hi ** 2 - lo ** 2)        # of each ring inside the band
        if not self.band_area.sum() > 0:
            raise WearError(f"no rotor ring lies in the friction band {r_in}..{r_out} m")
        self._ring_nodes = np.asarray(self.W.T @ self.area).ravel()    # pad area over a node
        self.through = np.zeros(n_ring, dtype=bool)
        self.law = LayeredWearLaw(k_layer, factor=np.ones(self.area.size))

    def ring_means(self, rotor_wear: np.ndarray) -> np.ndarray:
        """Ring means of a field on the rotor's wear nodes (e.g. the wear depth)."""
        n = self.radii.size
        return np.bincount(self.ring, weights=rotor_wear, minlength=n) / np.bincount(
            self.ring, minlength=n)

    def update(self, rotor_wear: np.ndarray) -> None:
        """Mark the rings worn through by the cumulative ``rotor_wear`` (m, per wear
        node) and set the law's factor under each pad node."""
        self.through = self.ring_means(rotor_wear) >= self.thickness
        node_factor = np.where(self.through[self.ring], self.k_base / self.k_layer, 1.0)
        self.law.factor[:] = self.W @ node_factor

    def cleaned_fraction(self, rotor_wear: np.ndarray) -> float:
        """Share of the band's area whose layer is worn through."""
        done = self.ring_means(rotor_wear) >= self.thickness
        return float(self.band_area[done].sum() / self.band_area.sum())

    def ring_pressure(self, pressure: np.ndarray) -> np.ndarray:
        """Mean pad pressure over each ring (Pa): load over the pad area at that radius."""
        load = np.asarray(self.W.T @ (np.maximum(pressure, 0.0) * self.area)).ravel()
        per_ring = np.bincount(self.ring, weights=load, minlength=self.radii.size)
        pad = np.bincount(self.ring, weights=self._ring_nodes, minlength=self.radii.size)
        return np.divide(per_ring, pad, out=np.zeros_like(per_ring), where=pad > 0)

    def touched_fraction(self, pressure: np.ndarray) -> float:
        """Share of the band's area the pad presses with at least ``threshold``
        (and more than zero)."""
        pr = self.ring_pressure(pressure)
        on = (pr > 0) & (pr >= self.threshold)
        return float(self.band_area[on].sum() / self.band_area.sum())
