"""How big a brake model gets, from its geometry alone, before anything is meshed.

:func:`estimate_model` counts the nodes and elements the parametric meshers
of :mod:`brakewear.mesh.brake` would make for a mesh size (the same cell
counts, in closed form, so that even an absurd size costs microseconds) and
turns them into DOFs and a peak memory.  :func:`check_model_size` is the one
size check that scene files, ``BrakeModel(size=...)`` and ``brakewear demo
--size`` share: the size must lie in (0, half the radial pad width] and the
model must fit the memory budget -- the machine's available memory, or
``BRAKEWEAR_MEMORY_GB`` / the scene key ``numerics.memory_budget`` (GB).

The memory model ``MEMORY_BASE + MEMORY_PER_DOF * DOFs`` was calibrated
against the peak resident memory of real runs (docs/scenes.md, "Model
size"): a scene run (contact solves of the wear loop) and the demo's tied
solve, at 6, 4, 3 and 2.5 mm on the default brake.
"""
from __future__ import annotations

import logging
import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import SceneError
from ..geometry.parts import MESH_BODY_KEYS

if TYPE_CHECKING:
    from ..geometry import BrakeGeometry

logger = logging.getLogger(__name__)

__all__ = ["ModelEstimate", "estimate_model", "mesh_layers", "check_model_size", "memory_budget",
           "MEMORY_ENV"]

#: Environment variable with a memory budget in GB (overrides the available memory).
MEMORY_ENV = "BRAKEWEAR_MEMORY_GB"
#: Peak memory of a run: the interpreter and libraries, plus a cost per DOF (bytes).
MEMORY_BASE = 100e6
MEMORY_PER_DOF = 12e3
#: The per-DOF cost of a quadratic (P2) model over a linear one: its stiffness rows hold
#: about twice the entries (77 against 37 per row on an 8^3 Kuhn block); not calibrated
#: against runs like the P1 figure.
P2_MEMORY_FACTOR = 2.0


@dataclass(frozen=True)
class ModelEstimate:
    """Estimated size of a brake model (before meshing)."""

    size: float                 # m
    nodes: dict                 # body -> nodes
    elements: dict              # body -> tetrahedra
    order: int = 1              # element order (2: nodes include the mid-edge nodes)

    @property
    def dofs(self) -> int:
        return 3 * sum(self.nodes.values())

    @property
    def memory(self) -> float:
        """Estimated peak memory of a run (bytes)."""
        per_dof = MEMORY_PER_DOF * (P2_MEMORY_FACTOR if self.order == 2 else 1.0)
        return MEMORY_BASE + per_dof * self.dofs


def _smallest_cell(length: float, n: int, ratio: float) -> float:
    """First cell of :func:`~brakewear.mesh.structured.graded` (closed form)."""
    if n == 1 or ratio == 1.0:
        return length / n
    q = ratio ** (1.0 / (n - 1))
    return length * (q - 1.0) / (q ** n - 1.0)


def _graded_cells(length: float, h_min: float, ratio: float) -> int:
    """Cells of the mesher's z grading: fewest whose first cell is <= 1.05 h_min."""
    if _smallest_cell(length, 1, ratio) <= 1.05 * h_min:
        return 1
    lo, hi = 1, 2
    while _smallest_cell(length, hi, ratio if hi > 1 else 1.0) > 1.05 * h_min:
        lo, hi = hi, 2 * hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _smallest_cell(length, mid, ratio) <= 1.05 * h_min:
            hi = mid
        else:
            lo = mid
    return hi


def _two_sided_cells(length: float, h_end: float, h_mid: float, growth: float = 1.3) -> int:
    """Number of cells of :func:`~brakewear.mesh.grids._two_sided`."""
    if h_mid <= h_end:
        return max(1, math.ceil(length / h_end))
    ramp, total = 1, h_end * growth
    h = h_end * growth
    while h * growth < h_mid:
        h *= growth
        ramp += 1
        total += h
    middle = length - 2.0 * total
    if middle < h_mid:
        return max(2, math.ceil(length / (0.5 * (h_end + h_mid))))
    return 2 * ramp + max(1, round(middle / h_mid))


def mesh_layers(geom: BrakeGeometry, size: float | None = None) -> dict:
    """The in-plane sizes (m) and element layers the meshers resolve for ``geom`` at
    ``size`` (m; default the geometry's): a body's own ``mesh.pad_size`` /
    ``rotor_size`` and layer counts where given, else the rules of ``size``
    (docs/geometry.md, ``[mesh]``).

    Returns
    -------
    dict
        ``pad_size``, ``rotor_size`` (m), ``friction_layers``, ``backplate_layers``,
        ``rotor_layers`` (through the rotor half).
    """
    ms, pad = geom.mesh, geom.pad
    size = ms.size if size is None else float(size)
    h_pad, h_rot = ms.pad_size or size, ms.rotor_size or size
    return {
        "pad_size": h_pad, "rotor_size": h_rot,
        "friction_layers": ms.friction_layers or _graded_cells(pad.friction_thickness,
                                                               0.5 * h_pad, ms.pad_z_ratio),
        "backplate_layers": ms.backplate_layers or max(1, math.ceil(pad.backplate_thickness
                                                                    / h_pad)),
        "rotor_layers": ms.rotor_layers or _graded_cells(0.5 * geom.rotor.thickness,
                                                         0.5 * h_rot, ms.rotor_z_ratio),
    }


def estimate_model(geom: BrakeGeometry, size: float | None = None, rotor: str = "elastic",
                   piston: str = "traction", order: int = 1, full: bool = False) -> ModelEstimate:
    """Nodes and elements of each meshed body at ``size`` (m; default the geometry's);
    a body's own ``mesh.pad_size`` / ``rotor_size`` and layer counts take precedence.
    Element ``order`` 2: each structured grid direction gets its midpoints, the
    piston about seven mid-edge nodes per vertex.  ``full``: both pads and the
    whole rotor thickness (``BrakeModel(layout="full")``)."""
    k = 2 if order == 2 else 1            # grid points per cell and direction
    ms, pad, rot, pis = geom.mesh, geom.pad, geom.rotor, geom.piston
    size = ms.size if size is None else float(size)
    lay = mesh_layers(geom, size)
    h = lay["rotor_size"]
    nodes, elements = {}, {}
    if rotor == "elastic":
        r_ref = 0.5 * (pad.inner_radius + pad.outer_radius)
        nr = max(2, math.ceil((rot.outer_radius - rot.inner_radius) / h))
        span = pad.arc_angle + 2.0 * ms.rotor_margin
        n_fine = max(2, math.ceil(span * r_ref / h))
        dth = span / n_fine
        nth = n_fine + _two_sided_cells(2 * math.pi - span, dth, ms.rotor_coarse_factor * dth)
        nz = lay["rotor_layers"] * (2 if full else 1)
        nodes["rotor"] = (k * nr + 1) * k * nth * (k * nz + 1)   # periodic in theta
        elements["rotor"] = 6 * nr * nth * nz
    h = lay["pad_size"]
    r_ref = 0.5 * (pad.inner_radius + pad.outer_radius)
    bri, bro = pad.backplate_radii     # a larger backplate adds radial cells (whole block)
    nr = (max(2, math.ceil((pad.outer_radius - pad.inner_radius) / h))
          + math.ceil((pad.inner_radius - bri) / h) + math.ceil((bro - pad.outer_radius) / h))
    nth = max(2, math.ceil(pad.arc_angle * r_ref / h))
    nz = lay["friction_layers"] + lay["backplate_layers"]
    nodes["pad"] = (k * nr + 1) * (k * nth + 1) * (k * nz + 1) * (2 if full else 1)
    elements["pad"] = 6 * nr * nth * nz * (2 if full else 1)
    if piston == "body":
        R = 0.5 * pis.diameter
        h = size
        rings = max(2, math.ceil(R / h))
        # about 2 pi r_k / h nodes on ring k (at least 6): the sum in closed form
        disc = 1 + sum(max(6, round(2 * math.pi * R * k / rings / h))
                       for k in range(1, rings + 1)) if rings < 10_000 else \
            1 + math.pi * R * (rings + 1) / h
        layers = max(2, math.ceil(pis.length / (1.5 * h)))
        rim = max(6, round(2 * math.pi * R / h))
        nodes["piston"] = int(disc * (layers + 1)) * (8 if order == 2 else 1)
        # a triangulated disc of n nodes, b on its rim: 2 n - b - 2 triangles, 3 tets each
        elements["piston"] = int(3 * (2 * disc - rim - 2) * layers)
    return ModelEstimate(size, nodes, elements, 2 if order == 2 else 1)


def memory_budget(budget_gb: float | None = None) -> tuple[float, str]:
    """(budget in bytes, where it comes from): the argument, ``BRAKEWEAR_MEMORY_GB``
    or the machine's available memory (``MemAvailable`` of /proc/meminfo, else
    ``os.sysconf`` physical pages)."""
    if budget_gb is not None:
        return float(budget_gb) * 1e9, "the memory budget you set"
    env = os.environ.get(MEMORY_ENV)
    if env:
        try:
            val = float(env)
        except ValueError:
            val = float("nan")
        if not (math.isfinite(val) and val > 0):
            raise SceneError(f"{MEMORY_ENV}={env!r} is not allowed; it must be a number of "
                             "GB > 0")
        return val * 1e9, f"{MEMORY_ENV}={env}"
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0, "the available memory"
    except OSError:
        pass
    try:
        return (float(os.sysconf("SC_AVPHYS_PAGES")) * os.sysconf("SC_PAGE_SIZE"),
                "the available memory")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        return float("inf"), "no known memory limit"


def _fmt(size_m: float, unit: str) -> str:
    return f"{size_m * 1e3:.6g} mm" if unit == "mm" else f"{size_m:.6g} m"


def check_model_size(geom: BrakeGeometry, size: float | None, rotor: str = "elastic",
                     piston: str = "traction", *, key: str = "mesh.size", unit: str = "mm",
                     budget_gb: float | None = None, budget_key: str = "numerics.memory_budget",
                     user_value: str | None = None, nodes: dict | None = None,
                     order: int = 1, full: bool = False) -> ModelEstimate:
    """Refuse a mesh size outside (0, half the pad width] or too big for the memory budget.

    Parameters
    ----------
    geom, size, rotor, piston
        The model (``size`` in m; None: the geometry's).
    key, unit, user_value
        How the message names the value: the scene key (or argument), the
        user's unit (``"mm"`` or ``"m"``) and, optionally, the value as the
        user wrote it.
    budget_gb, budget_key
        A memory budget in GB (None: ``BRAKEWEAR_MEMORY_GB`` or the available
        memory) and the key that sets it, for the message.
    nodes
        Node counts of bodies whose mesh is given (a mesh file): counted as
        they are, not estimated.
    order
        Element order of the meshes (2: quadratic, mid-edge nodes counted).
    full
        Both pads and the whole rotor thickness.

    Returns
    -------
    ModelEstimate
        The estimate (nothing is meshed).

    Raises
    ------
    SceneError
        Naming the key, the value in the user's units, the estimate and the
        smallest size that fits.
    """
    h = geom.mesh.size if size is None else size
    shown = user_value if user_value is not None else _fmt(h, unit)
    width = geom.pad.outer_radius - geom.pad.inner_radius
    if isinstance(h, bool) or not isinstance(h, (int, float)) or not math.isfinite(h) or h <= 0:
        raise SceneError(f"{key}: {shown} is not allowed; it must be a finite number > 0")
    if h > 0.5 * width:
        raise SceneError(f"{key}: {shown} is not allowed; allowed range (0, "
                         f"{_fmt(0.5 * width, unit)}] (half the radial pad width)")
    def estimate(size: float) -> ModelEstimate:
        e = estimate_model(geom, size, rotor, piston, order, full)
        for b, n in (nodes or {}).items():
            e.nodes[b], e.elements[b] = int(n), 0
        return e

    est = estimate(h)
    budget, where = memory_budget(budget_gb)
    if est.memory > budget:
        lo, hi = h, 0.5 * width          # memory falls with the size: bisect the boundary
        if estimate(hi).memory > budget:
            fits = f"not even {_fmt(hi, unit)} (the largest allowed size) fits"
            own = [k for k in MESH_BODY_KEYS if getattr(geom.mesh, k) is not None]
            if own:
                fits += f"; the geometry sets {', '.join(f'mesh.{k}' for k in own)} apart"
        else:
            for _ in range(60):
                mid = math.sqrt(lo * hi)
                if estimate(mid).memory > budget:
                    lo = mid
                else:
                    hi = mid
                if hi / lo < 1.001:
                    break
            fits = f"the smallest size that fits is {_fmt(_round_up(hi, unit), unit)}"
        setting = (f"set {budget_key} (GB) or {MEMORY_ENV}" if where == "the available memory"
                   else f"{where}")
        raise SceneError(
            f"{key}: {shown} is too fine for this machine: the model would have about "
            f"{est.dofs:.3g} DOFs ({sum(est.elements.values()):.3g} elements) and need about "
            f"{est.memory / 1e9:.3g} GB of memory, above {where} ({budget / 1e9:.3g} GB; "
            f"{setting}); {fits}")
    logger.info("model size estimate at %s: %d DOFs, %.3g GB", _fmt(h, unit), est.dofs,
                est.memory / 1e9)
    return est


def _round_up(size_m: float, unit: str) -> float:
    """A size a little above ``size_m`` with three significant digits in the user's unit."""
    x = size_m * (1e3 if unit == "mm" else 1.0)
    e = math.floor(math.log10(x)) - 2
    x = math.ceil(x / 10 ** e) * 10 ** e
    return x / (1e3 if unit == "mm" else 1.0)
