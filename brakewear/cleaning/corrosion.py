"""Cleaning a corroded rotor: the cleaning criterion, judged per face, and a layered rust law.

A rotor face that stood (an electric car braking by regeneration) carries a
corrosion layer of thickness ``h_c`` that wears with ``k_layer`` (much
faster than the iron beneath, ``k_base``).  The pad must sweep the whole
friction band -- the annulus ``r_in <= r <= r_out`` the pad covers -- and
wear through the layer everywhere, on each friction face its pad touches.

Two things, kept apart:

* :class:`BandCriterion`, the judgement: per rotor face (the full model has
  the inboard ``"in"`` and the outboard ``"out"`` face, each its own rings
  and its own wear) and by *area* (rings are annuli, so an outer ring counts
  more than an inner one of the same width):

  - ``cleaned_fraction`` -- the band's area whose ring wear reached ``h_c``;
  - ``touched_fraction`` -- the band's area over which the pad presses with a
    mean pressure (over the pad's footprint at that radius) of at least
    ``threshold``: a ring grazed by one node at a few pascals does not count;

  the brake's answer is the worse face (the fraction of the face that has
  least);
* :class:`CorrodedRotor`, the rust law: per ring whether the layer is worn
  through, and a rotor law whose coefficient at each pad node is that of the
  ring under it (``k_layer`` or ``k_base``); call
  :meth:`CorrodedRotor.update` with the cumulative rotor wear after each
  step.  It judges through its :class:`BandCriterion`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import GeometryError, WearError
from ..laws.base import WearLaw

__all__ = ["read_gap_map", "map_gap", "GAP_COLUMNS", "LayeredWearLaw", "CorrodedRotor",
           "BandCriterion", "coning_gap", "nonconformity_gap", "outboard_nodes"]


@dataclass(frozen=True)
class LayeredWearLaw(WearLaw):
    """Archard law ``k`` times a per-pad-node ``factor`` (an array the owner updates
    in place between steps: 1 over a corroded ring, ``k_base / k`` over bare iron)."""

    factor: np.ndarray | None = None

    def coefficient_at(self, p, v, T=None) -> np.ndarray:
        """``k(T)`` times ``factor`` per pad node (the coefficient :meth:`rate` uses)."""
        k = super().coefficient_at(p, v, T)
        return k if self.factor is None else k * self.factor


def coning_gap(r: np.ndarray, r_in: float, r_out: float, coning: float) -> np.ndarray:
    """Initial gap (m) of a coning (or radial pad taper) of ``coning`` m across the band.

    Linear in radius, zero at ``r_in`` and ``coning`` at ``r_out``; a negative
    ``coning`` opens the gap at the inner radius instead (zero at ``r_out``).
    A coned rotor does the one on one face and the other on the opposite face.
    """
    g = coning * (np.asarray(r, dtype=float) - r_in) / (r_out - r_in)
    return g - g.min()


def outboard_nodes(x: np.ndarray, rotor_thickness: float) -> np.ndarray:
    """Mask of the pad friction nodes at ``x`` (3, n; m) on the rotor's outboard face
    (``z = -thickness``, full model); the inboard face is ``z = 0``."""
    return np.asarray(x)[2] < -0.5 * rotor_thickness


def nonconformity_gap(x: np.ndarray, r_in: float, r_out: float, rotor_thickness: float,
                      coning: float | dict = 0.0, pad_taper: float = 0.0) -> np.ndarray:
    """Initial gap (m) at pad friction nodes ``x`` (3, n; m) of a rotor coning and a
    radial pad taper, per friction face.

    On each face the gap is :func:`coning_gap` of that face's coning plus
    ``pad_taper`` (positive: open at the outer radius), zero where the face's
    pad first touches.  ``coning`` a number ``c``: a coned rotor, ``c`` on the
    inboard face (``z = 0``) and ``-c`` on the outboard one (``z = -thickness``):
    the rim dished toward one side opens the gap at the outer radius on one
    face and at the inner radius on the other.  ``coning`` a dict with keys
    ``"inboard"`` and ``"outboard"``: each face's own value in its own sense.
    The pads are mirror images, so a pad taper opens the same way on both.
    """
    faces = coning if isinstance(coning, dict) else {"inboard": coning, "outboard": -coning}
    r = np.hypot(x[0], x[1])
    out = outboard_nodes(x, rotor_thickness)
    g = np.zeros(r.size)
    for face, mask in (("inboard", ~out), ("outboard", out)):
        if mask.any():
            g[mask] = coning_gap(r[mask], r_in, r_out, faces[face] + pad_taper)
    return g


#: the columns of an initial-gap map (:func:`read_gap_map`)
GAP_COLUMNS = ("r_mm", "theta_deg", "gap_um")


def read_gap_map(path) -> np.ndarray:
    """An initial-gap map from a CSV file: columns ``r_mm``, ``theta_deg`` (the angle
    from the pad's centre line, the x axis of the brake) and ``gap_um``, one row per
    point; returns an ``(n, 3)`` array in m, rad, m.  Errors name the file and the row."""
    import csv
    from pathlib import Path

    path = Path(path)
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = list(csv.DictReader(fh))
    except OSError as e:
        raise GeometryError(f"{path}: cannot read the gap map ({e.strerror})") from None
    except (UnicodeDecodeError, csv.Error) as e:
        raise GeometryError(f"{path}: the gap map is not a CSV text file ({e})") from None
    header = list(rows[0]) if rows else []
    missing = [c for c in GAP_COLUMNS if c not in header]
    if missing:
        raise GeometryError(f"{path}: missing column(s) {', '.join(missing)}; need "
                            f"{', '.join(GAP_COLUMNS)} (the header is "
                            f"{', '.join(header) or '(empty file)'})")
    out, seen = [], {}
    for i, row in enumerate(rows, start=2):                 # row 1 is the header
        try:
            r, th, g = (float(row[c]) for c in GAP_COLUMNS)
        except (TypeError, ValueError):
            raise GeometryError(f"{path}, row {i}: not a number in {dict(row)!r}") from None
        if not (np.isfinite([r, th, g]).all() and r > 0 and abs(g) <= 1000.0):
            raise GeometryError(f"{path}, row {i}: r_mm = {row['r_mm']}, gap_um = "
                                f"{row['gap_um']} is not allowed; need r_mm > 0 and "
                                "|gap_um| <= 1000")
        if (r, th) in seen:          # two gaps at one point: which one is meant?
            other = out[seen[(r, th)] - 2][2] != g * 1e-6
            raise GeometryError(f"{path}, row {i}: the point r_mm = {row['r_mm']}, theta_deg = "
                                f"{row['theta_deg']} is also on row {seen[(r, th)]}"
                                f"{' with another gap' if other else ''}; give each point once")
        seen[(r, th)] = i
        out.append((r * 1e-3, np.radians(th), g * 1e-6))
    if len(out) < 3:
        raise GeometryError(f"{path}: a gap map needs at least three points")
    pts = np.array(out)
    span = np.c_[pts[:, 0], pts[:, 0].mean() * pts[:, 1]]
    if np.linalg.matrix_rank(span - span.mean(0), tol=1e-9 * np.abs(span).max()) < 2:
        raise GeometryError(f"{path}: the gap map's points lie on one line (in radius and "
                            "angle); it needs points spread over the pad face")
    return pts


def map_gap(points: np.ndarray, x: np.ndarray, source: str = "gap map") -> np.ndarray:
    """The gap of a map ``(n, 3)`` (r, theta, gap) at pad nodes ``x`` (3, m):
    linear between the points (triangulated in radius and arc length at the
    map's mean radius), shifted so that its smallest value is zero.  Raises
    :class:`~brakewear.errors.GeometryError` if a node lies outside the map."""
    from scipy.interpolate import LinearNDInterpolator

    r_m = float(points[:, 0].mean())
    f = LinearNDInterpolator(np.c_[points[:, 0], r_m * points[:, 1]], points[:, 2])
    r, th = np.hypot(x[0], x[1]), np.arctan2(x[1], x[0])
    g = f(np.c_[r, r_m * th])
    out = ~np.isfinite(g)
    if out.any():
        i = int(np.flatnonzero(out)[0])
        raise GeometryError(f"{source}: {int(out.sum())} pad node(s) lie outside the map, e.g. "
                            f"r = {r[i] * 1e3:.2f} mm, theta = {np.degrees(th[i]):.2f} deg; the "
                            f"pad face spans r {r.min() * 1e3:.1f}..{r.max() * 1e3:.1f} mm, theta "
                            f"{np.degrees(th.min()):.1f}..{np.degrees(th.max()):.1f} deg")
    return g - g.min()


class BandCriterion:
    """The cleaning criterion of every rotor face an interface models (see the module).

    Parameters
    ----------
    interface
        The wear loop's interface (``W``, ``ring``, ``rotor_x``, ``area``; its
        ``model.geometry.rotor.thickness`` tells the faces apart).
    r_in, r_out
        The friction band swept by the pad (m).
    thickness
        Corrosion layer thickness (m, > 0).
    threshold
        Smallest mean pad pressure (Pa, >= 0) over a ring for it to count as touched.

    Attributes
    ----------
    radii : ndarray
        Mean radius of each rotor ring (every face's rings).
    face : ndarray
        Each ring's face, ``"in"`` or ``"out"``.
    band_area : ndarray
        The area of each ring inside the band, on its own face (m^2).
    """

    def __init__(self, interface, r_in: float, r_out: float, thickness: float,
                 threshold: float = 0.0):
        if not (np.isfinite(thickness) and thickness > 0):
            raise WearError(f"thickness = {thickness!r} is not allowed; need > 0")
        if not (np.isfinite(threshold) and threshold >= 0):
            raise WearError(f"threshold = {threshold!r} Pa is not allowed; need >= 0")
        if not (0 < r_in < r_out):
            raise WearError(f"friction band {r_in!r}..{r_out!r} m is not allowed; need "
                            "0 < r_in < r_out")
        itf = interface
        self.W, self.ring, self.area = itf.W, itf.ring, itf.area
        self.thickness, self.threshold = thickness, threshold
        x = np.asarray(itf.rotor_x)
        n_ring = int(self.ring.max()) + 1
        count = np.bincount(self.ring, minlength=n_ring)
        self.radii = np.bincount(self.ring, weights=np.hypot(x[0], x[1]),
                                 minlength=n_ring) / count
        model = getattr(itf, "model", None)
        t = model.geometry.rotor.thickness if getattr(model, "full", False) else None
        z = np.bincount(self.ring, weights=x[2], minlength=n_ring) / count
        self.face = np.where(outboard_nodes(np.vstack([self.radii, 0 * z, z]), t), "out", "in") \
            if t is not None else np.full(n_ring, "in")
        self.band_area = self.areas_within(r_in, r_out)
        for f in self.faces:
            if not self.band_area[self.face == f].sum() > 0:
                raise WearError(f"no rotor ring of face {f!r} lies in the friction band "
                                f"{r_in}..{r_out} m")
        self._ring_nodes = np.asarray(self.W.T @ self.area).ravel()    # pad area over a node

    def areas_within(self, lo: float, hi: float) -> np.ndarray:
        """Each ring's area between radii ``lo`` and ``hi`` on its face (m^2): a ring
        reaches halfway to its neighbours."""
        out = np.zeros(self.radii.size)
        for f in self.faces:
            idx = np.nonzero(self.face == f)[0]
            idx = idx[np.argsort(self.radii[idx])]
            r = self.radii[idx]
            mid = 0.5 * (r[1:] + r[:-1])
            a = np.clip(np.concatenate([[r[0]], mid]), lo, hi)
            b = np.clip(np.concatenate([mid, [r[-1]]]), lo, hi)
            out[idx] = np.pi * (b ** 2 - a ** 2)
        return out

    @property
    def faces(self) -> list:
        """The faces judged: ``["in"]`` or ``["in", "out"]``."""
        return [f for f in ("in", "out") if np.any(self.face == f)]

    def ring_means(self, rotor_wear: np.ndarray) -> np.ndarray:
        """Ring means of a field on the rotor's wear nodes (e.g. the wear depth)."""
        n = self.radii.size
        return np.bincount(self.ring, weights=rotor_wear, minlength=n) / np.bincount(
            self.ring, minlength=n)

    def _fractions(self, on: np.ndarray) -> dict:
        return {f: float(self.band_area[on & (self.face == f)].sum()
                         / self.band_area[self.face == f].sum()) for f in self.faces}

    def cleaned_fractions(self, rotor_wear: np.ndarray) -> dict:
        """Per face, the share of its band's area whose layer is worn through."""
        return self._fractions(self.ring_means(rotor_wear) >= self.thickness)

    def cleaned_fraction(self, rotor_wear: np.ndarray) -> float:
        """The worse face's cleaned share of its band."""
        return min(self.cleaned_fractions(rotor_wear).values())

    def ring_pressure(self, pressure: np.ndarray) -> np.ndarray:
        """Mean pad pressure over each ring (Pa): load over the pad area at that radius."""
        load = np.asarray(self.W.T @ (np.maximum(pressure, 0.0) * self.area)).ravel()
        per_ring = np.bincount(self.ring, weights=load, minlength=self.radii.size)
        pad = np.bincount(self.ring, weights=self._ring_nodes, minlength=self.radii.size)
        return np.divide(per_ring, pad, out=np.zeros_like(per_ring), where=pad > 0)

    def touched_fractions(self, pressure: np.ndarray) -> dict:
        """Per face, the share of its band's area the pad presses with at least
        ``threshold`` (and more than zero)."""
        pr = self.ring_pressure(pressure)
        return self._fractions((pr > 0) & (pr >= self.threshold))

    def touched_fraction(self, pressure: np.ndarray) -> float:
        """The worse face's touched share of its band."""
        return min(self.touched_fractions(pressure).values())


class CorrodedRotor:
    """The corrosion layer of the rotor's faces under the pads, ring by ring: the
    layered rust law, judged by a :class:`BandCriterion`.

    Parameters
    ----------
    interface
        The wear loop's interface (``W``, ``ring``, ``rotor_x``, ``rotor_area``,
        ``area``: an :class:`~brakewear.interfaces.FEInterface` or its kin).
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
        for name, x in (("k_layer", k_layer), ("k_base", k_base)):
            if not (np.isfinite(x) and x > 0):
                raise WearError(f"{name} = {x!r} is not allowed; need > 0")
        self.criterion = BandCriterion(interface, r_in, r_out, thickness, threshold)
        c = self.criterion
        self.W, self.ring, self.area = c.W, c.ring, c.area
        self.thickness, self.k_layer, self.k_base = thickness, k_layer, k_base
        self.threshold, self.radii, self.band_area = threshold, c.radii, c.band_area
        self.through = np.zeros(self.radii.size, dtype=bool)
        self.law = LayeredWearLaw(k_layer, factor=np.ones(self.area.size))

    def ring_means(self, rotor_wear: np.ndarray) -> np.ndarray:
        """Ring means of a field on the rotor's wear nodes (e.g. the wear depth)."""
        return self.criterion.ring_means(rotor_wear)

    def update(self, rotor_wear: np.ndarray) -> None:
        """Mark the rings worn through by the cumulative ``rotor_wear`` (m, per wear
        node) and set the law's factor under each pad node."""
        self.through = self.ring_means(rotor_wear) >= self.thickness
        node_factor = np.where(self.through[self.ring], self.k_base / self.k_layer, 1.0)
        self.law.factor[:] = self.W @ node_factor

    def cleaned_fraction(self, rotor_wear: np.ndarray) -> float:
        """The worse face's share of its band whose layer is worn through."""
        return self.criterion.cleaned_fraction(rotor_wear)

    def ring_pressure(self, pressure: np.ndarray) -> np.ndarray:
        """Mean pad pressure over each ring (Pa)."""
        return self.criterion.ring_pressure(pressure)

    def touched_fraction(self, pressure: np.ndarray) -> float:
        """The worse face's share of its band the pad presses with at least ``threshold``."""
        return self.criterion.touched_fraction(pressure)
