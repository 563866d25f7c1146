"""The interface a run takes when its scene says ``interface.model = "auto"``.

The condensed interface (:mod:`brakewear.interfaces.condensed`) gives the FE
interface's answer (to 1e-8 and better) at a dense solve per contact solve,
after a condensation that costs as much as a number of FE contact solves.
:func:`choose_interface` takes it when the run's expected wear steps pay
for that, the FE interface otherwise, and the FE interface wherever the
condensation does not apply:

* ``numerics.update = "geometry"`` (the meshes move; a condensation cannot
  follow them);
* a pad held by unilateral abutment stops (a second, nonlinear contact);
* a condensation that does not fit the memory budget;
* a run whose wear is expected to pass the condensed interface's range
  (a quarter of the height of the pad's elements at its face).

**The break-even.**  The condensation costs ``C(n, N)`` FE contact solves
of the same model (``n`` contact nodes, ``N`` DOFs), a fit to the measured
costs (:data:`CONDENSE_SOLVES`; docs/condensed.md, "The interface chosen
for the user"); an FE wear step costs
:data:`FE_STEP_SOLVES` of a contact solve and a condensed one about a
hundredth of that.  The condensed interface is taken when the expected
steps times the saving per step reach ``C(N)``; a condensation already in
the cache costs nothing, so a second run of the same brake always takes it.

**Expected steps.**  ``numerics.steps`` when the steps are fixed.  Under
step control: the larger of :data:`CONTROLLED_STEPS` ``/ dp_tol`` (the
pressure field of a running-in changes by about its own size, crossed in
steps of ``dp_tol``) and the worn depth expected at the pad's peak
pressure over the wear-per-step limit; a [schedule] multiplies it by its
applications.
"""
from __future__ import annotations

import logging
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .fe import METHOD, FEInterface
from .registry import register_interface

logger = logging.getLogger(__name__)

__all__ = ["InterfaceChoice", "choose_interface", "condensation_solves", "expected_steps",
           "AutoChoice"]

#: the condensation in FE contact solves of the same model, a fit to four measured
#: meshes of the default brake (8.8k-105k DOFs, 189-2280 contact nodes, within 13 %):
#: ``C = CONDENSE_SOLVES (n / 1000) ** CONDENSE_EXPONENTS[0] (N / 1e5) **
#: CONDENSE_EXPONENTS[1]`` (its column solves grow with the contact nodes ``n`` and
#: the factor, an FE contact solve with the DOFs ``N``)
CONDENSE_SOLVES = 14.4
CONDENSE_EXPONENTS = (2.13, -0.52)
#: an FE wear step in FE contact solves (warm-started Krylov solves, kept hierarchies)
FE_STEP_SOLVES = 0.2
#: a condensed wear step in FE wear steps
CONDENSED_STEP = 0.01
#: expected steps of a step-controlled run, times ``1 / dp_tol``
CONTROLLED_STEPS = 3.0
#: the pad's largest pressure over its nominal one (clamp force over face area), for
#: the worn depth a run is expected to reach
PEAK_PRESSURE = 3.0


@dataclass(frozen=True)
class InterfaceChoice:
    """Which interface a run takes, and why.

    Attributes
    ----------
    model
        ``"fe"`` or ``"condensed"``.
    reason
        One sentence for the run's first lines and its summary.
    expected_steps, break_even_steps
        The run's expected wear steps and the steps the condensation needs to
        pay (None where the decision did not need them).
    """

    model: str
    reason: str
    expected_steps: float | None = None
    break_even_steps: float | None = None

    def record(self) -> dict:
        """As JSON (``summary.json``'s ``interface``)."""
        return {"requested": "auto", **asdict(self)}


def condensation_solves(dofs: int, contact_nodes: int) -> float:
    """The condensation's cost in FE contact solves of a model of ``dofs`` DOFs
    and ``contact_nodes`` pad friction nodes (:data:`CONDENSE_SOLVES`)."""
    a, b = CONDENSE_EXPONENTS
    return CONDENSE_SOLVES * (contact_nodes / 1000.0) ** a * (float(dofs) / 1e5) ** b


def _expected_wear(model, fe, line_pressure: float, omega: float, duration: float,
                   wear_rate) -> float:
    """The largest pad wear (m) a run may reach: the pad's wear rate at
    :data:`PEAK_PRESSURE` times the nominal pressure and the fastest node's
    speed, over the whole duration."""
    nominal = line_pressure * model.geometry.clamp_area / float(np.sum(fe.area))
    return float(wear_rate(PEAK_PRESSURE * nominal, omega * float(np.max(fe.r)))) * duration


def expected_steps(numerics, wear: float, dh_limit: float, applications: int = 0) -> float:
    """The run's expected wear steps (see the module)."""
    if numerics.steps is not None:
        per = float(numerics.steps)
    else:
        per = max(CONTROLLED_STEPS / numerics.dp_tol, wear / max(dh_limit, 1e-300))
    return per * max(applications, 1)


def _resumed(checkpoint) -> str | None:
    """The interface a checkpoint's run took (None: no checkpoint, or not named)."""
    import json

    from ..storage import load_arrays

    if checkpoint is None or not Path(checkpoint).exists():
        return None
    # a damaged one is refused here, naming it
    d = load_arrays(checkpoint, "the checkpoint", required=("fingerprint",),
                    remedy="run again without --resume (with --overwrite)")
    try:
        prints = json.loads(str(d["fingerprint"]))
    except ValueError:
        prints = {}
    kind = prints.get("interface.type") if isinstance(prints, dict) else None
    return {"FEInterface": "fe", "CondensedInterface": "condensed"}.get(kind)


def choose_interface(model, fe, numerics, *, line_pressure: float, omega: float,
                     duration: float, wear_rate, applications: int = 0, thermal: bool = False,
                     cache=None, valid_fraction: float = 0.25,
                     resume=None) -> InterfaceChoice:
    """FE or condensed for a run (see the module); ``fe`` is the run's
    :class:`~brakewear.interfaces.FEInterface` (its contact system and
    supports), ``wear_rate(p, v)`` the pad's wear rate (m/s) at a pressure
    (Pa) and a sliding speed (m/s), ``applications``
    the length of a [schedule] (0: none), ``thermal`` whether the run is
    thermally coupled (the thermal load's operator costs one more
    factorisation of each body).  ``resume``: the checkpoint of a run being
    resumed, which keeps the interface it was run on."""
    from ..mesh.estimate import memory_budget
    from ..motion.brake import surface_element_height
    from .condensation import cache_dir, condensation_key, condensation_memory

    kept = _resumed(resume)
    if kept is not None:
        return InterfaceChoice(kept, f"the run resumed from {resume} was run on it")
    if numerics.update == "geometry":
        return InterfaceChoice("fe", "the geometry update moves the meshes, which a "
                                     "condensation cannot follow")
    if fe.supports:
        return InterfaceChoice("fe", f"the pad bears on {len(fe.supports)} unilateral abutment "
                                     "stop(s), a second contact the condensation cannot hold")
    n, N = int(fe.area.size), int(model.dofs)
    need = condensation_memory(n, fe.cs.K.shape[0])
    avail, source = memory_budget(numerics.memory_budget)
    if need > avail:
        return InterfaceChoice("fe", f"condensing {n} contact nodes needs about "
                                     f"{need / 1e9:.1f} GB; {source} is {avail / 1e9:.1f} GB")
    wear = _expected_wear(model, fe, line_pressure, omega, duration, wear_rate)
    heights = surface_element_height(model.meshes["pad"], "friction")
    if wear > valid_fraction * float(heights.min()):
        return InterfaceChoice("fe", f"the pad may wear {wear * 1e6:.0f} um, beyond the "
                                     f"condensed interface's range ({valid_fraction:g} of its "
                                     f"{heights.min() * 1e3:.2f} mm elements at the face)")
    dh = numerics.max_dh if numerics.max_dh is not None else \
        numerics.dh_fraction * float(heights.min())
    steps = expected_steps(numerics, wear, dh, applications)
    folder = cache_dir(cache)
    if folder is not None and (folder / f"{condensation_key(fe.cs)}.npz").exists():
        return InterfaceChoice("condensed", f"its condensation is in the cache ({folder}): "
                                            "the FE answer at a dense solve per step, free",
                               steps, 0.0)
    cost = condensation_solves(N, n) * (1.25 if thermal else 1.0)
    even = cost / (FE_STEP_SOLVES * (1.0 - CONDENSED_STEP))
    how = "fixed steps" if numerics.steps is not None else "under step control"
    if applications:
        how += f", {applications} applications"
    figures = (f"about {steps:.0f} wear steps expected ({how}); the condensation of {n} "
               f"contact nodes costs about {cost:.0f} FE contact solves at {N} DOFs and pays "
               f"after {even:.0f} steps")
    if steps >= even:
        return InterfaceChoice("condensed", figures, steps, even)
    return InterfaceChoice("fe", figures, steps, even)


@register_interface
class AutoChoice:
    """``interface.model = "auto"``: the condensed interface where the run's expected steps
    pay for its condensation, FE contact otherwise (:func:`choose_interface`).

    A choice, not an interface: it declares the FE interface's capabilities
    (it takes FE contact wherever the condensed interface lacks one the run
    needs) and gives the FE contact's answer either way.
    """

    name = "auto"
    keys = (METHOD,)
    accepts_load = follows_geometry = per_node_friction = quadratic = True
    any_line_pressure = implicit_rings = fe_answer = True

    @staticmethod
    def decide(request) -> tuple[str, dict]:
        """``"condensed"`` where it pays for the run (:func:`choose_interface`), ``"fe"``
        otherwise, with the choice's record; the FE interface it weighs is handed to
        the chosen model's builder (``request.built``), which builds on it.

        Parameters
        ----------
        request : BuildRequest
            The run's model, numerics and run (its speed, duration, laws).

        Returns
        -------
        name : str
            The model chosen.
        record : dict
            Why (``summary.json``'s ``interface``).
        """
        model, n, run = request.model, request.numerics, request.run
        fe = FEInterface(model, request.line_pressure, request.mu, n.tol)
        request.built["fe"] = fe
        thermal = None if run is None else run.thermal
        T = None if thermal is None else thermal.T_ambient

        def rate(p, v):
            return float(np.max(run.pad_law.rate(np.array([p]), np.array([v]), T)))

        choice = choose_interface(model, fe, n, line_pressure=request.line_pressure,
                                  omega=run.omega, duration=run.duration, wear_rate=rate,
                                  applications=len(run.schedule),
                                  thermal=thermal is not None, resume=request.checkpoint)
        return choice.model, choice.record()
