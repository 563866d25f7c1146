"""The wear loop: contact -> pressure -> wear of pad and rotor -> new gap -> ...

:func:`wear_history` is a generator of :class:`WearStep` records.  The
geometry is updated in *gap-offset* mode: the meshes stay, and the worn
depths of pad and rotor are added to the contact gap (valid while wear is
far below the element size).

Time integration is explicit Euler.  The step is the smallest of

- ``max_dh``: no pad node wears more than this in one step (pad + rotor);
- the stability bound: explicit Euler on the wear ODE ``dg/dt = c p(g)`` is
  monotone (no oscillating short-wavelength modes) while ``dt c_i dp_i/dg``
  stays below one; the pressure's response to a local gap change is bounded
  by the row sums of the friction face's normal stiffness (Gershgorin, see
  docs/theory.md), so ``dt <= stability / max_i(c_i s_i / A_i)``;
- twice the last accepted step;

and a step after which the contact pressure changes by more than ``dp_tol``
(relative to its maximum), or the contact is lost, is rejected and retried
at half the size.

Checkpoints (``.npz``) hold the whole state; a run resumed from one repeats
the uninterrupted run exactly, because every step is solved from the stored
state alone (active set of the previous step, a hierarchy that depends only
on the stiffness).
"""
from __future__ import annotations

import logging
import os
import time as _time
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np
import scipy.sparse as sp

from .contact import ContactLostError, solve_contact, surface_nodes, tributary_areas
from .wear import WearError, WearLaw, rotor_rings, rotor_wear_rate

logger = logging.getLogger(__name__)

__all__ = ["WearStep", "wear_history", "StepSizeError", "FEInterface"]


class StepSizeError(RuntimeError):
    """The step control could not find an acceptable wear step."""


@dataclass
class WearStep:
    """State after an accepted step (cumulative quantities)."""

    step: int
    time: float                 # s
    dt: float                   # s, of this step
    sliding_distance: float     # m, at the pad's mean radius, since the start
    pressure: np.ndarray        # Pa at the pad's friction nodes, at the start of the step
    active: np.ndarray          # contact status at the start of the step
    pad_wear: np.ndarray        # m, cumulative, per pad friction node
    rotor_wear: np.ndarray      # m, cumulative, per rotor wear node (face node or ring)
    pad_volume: float           # m^3 worn from the pad (sum of depth x area)
    rotor_volume: float         # m^3 worn from the rotor
    pad_archard: float          # m^3, sum over steps of k_pad int p v dA dt
    rotor_archard: float        # m^3, the same with k_rotor
    rejected: int               # retries before this step was accepted
    contact_solves: int         # contact solves of this step (1 + rejected)
    solve_s: float              # s spent in contact solves in this step
    limit: str                  # what set the step: "max_dh", "stability", "growth", "end", "fixed"


class FEInterface:
    """The finite-element contact interface as the wear loop sees it.

    Holds the assembled contact system of a :class:`~brakewear.scene.BrakeModel`
    and answers one question: the pressure at the pad's friction nodes for a
    given extra gap (the worn depths).  Also provides what the rotor's
    revolution-averaged wear needs: the coupling ``W`` from pad nodes to the
    rotor's wear nodes, their rings and areas.  With an elastic rotor the
    wear nodes are the rotor's friction-face nodes; with a rigid rotor (the
    plane z = 0, nothing meshed) they are rings at the radii of the pad's
    nodes, each carrying the annulus between its neighbours' mid-radii.
    """

    def __init__(self, model, line_pressure: float, mu: float = 0.0, tol: float = 1e-9):
        self.model, self.tol = model, tol
        self.cs = cs = model.contact_system(line_pressure, mu)
        self.pair = pair = cs.pair
        self.g0 = pair.g0.copy()
        pad = model.meshes["pad"]
        self.pad_nodes = surface_nodes(pad, "friction")
        self.x = pad.p[:, self.pad_nodes]
        self.r = np.hypot(self.x[0], self.x[1])
        self.area = pair.area
        if model.rotor == "elastic":
            rotor = model.meshes["rotor"]
            self.rotor_nodes = face = surface_nodes(rotor, "friction")
            face_r = cs.col[face + model.offsets["rotor"]]      # retained numbering
            self.W = pair.coupling[:, face_r].tocsr()
            self.ring, _ = rotor_rings(np.hypot(rotor.p[0, face], rotor.p[1, face]))
            self.rotor_area = tributary_areas(rotor, "friction", face)
            self.rotor_x = rotor.p[:, face]
        else:
            ring, radii = rotor_rings(self.r)
            edges = np.concatenate([[radii[0]], 0.5 * (radii[1:] + radii[:-1]), [radii[-1]]])
            self.rotor_nodes = None
            self.W = sp.csr_matrix((np.ones(ring.size), (np.arange(ring.size), ring)),
                                   shape=(ring.size, radii.size))
            self.ring = np.arange(radii.size)
            self.rotor_area = np.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
            self.rotor_x = np.vstack([radii, np.zeros_like(radii), np.zeros_like(radii)])
        # normal stiffness row sums of the pad's friction face (Gershgorin bound
        # of the pressure response to a gap change, used by the stability bound)
        dz = 3 * pair.slave + 2
        Kzz = cs.K[dz][:, dz]
        self.normal_stiffness = np.asarray(abs(Kzz).sum(axis=1)).ravel()

    def solve(self, offset: np.ndarray, active: np.ndarray | None):
        """Contact solve with ``offset`` (m) added to the initial gap: (pressure, active, info)."""
        self.pair.g0 = self.g0 + offset
        init = None if active is None else [np.asarray(active, dtype=bool)]
        res = solve_contact(self.cs.K, self.cs.f, self.cs.fixed, self.cs.coords, [self.pair],
                            tol=self.tol, initial_active=init)
        return res.pressure[0], res.active[0], res.info


def _state_arrays(step: WearStep, active_next: np.ndarray, dt_next: float) -> dict:
    return {"step": step.step, "time": step.time, "pad_wear": step.pad_wear,
            "rotor_wear": step.rotor_wear, "pad_archard": step.pad_archard,
            "rotor_archard": step.rotor_archard, "active": active_next, "dt_next": dt_next}


def wear_history(model, line_pressure: float, omega: float, duration: float,
                 pad_law: WearLaw, rotor_law: WearLaw | None = None, mu: float = 0.0,
                 steps: int | None = None, max_dh: float | None = None, dp_tol: float = 0.05,
                 stability: float | None = 1.0,
                 checkpoint: str | os.PathLike | None = None, every: int = 10,
                 resume: bool = False, tol: float = 1e-9, max_halvings: int = 12,
                 interface=None) -> Iterator[WearStep]:
    """Run a wear history of the brake under constant line pressure and speed.

    Parameters
    ----------
    model
        A :class:`brakewear.scene.BrakeModel` (elastic or rigid rotor).
    line_pressure, omega, duration
        Pa, rad/s (rotor speed, > 0), s.
    pad_law, rotor_law
        Wear laws of pad and rotor (``rotor_law=None``: the rotor does not wear).
    mu
        Friction coefficient (sliding friction drags the pad along the rotor).
    steps
        Fixed number of equal steps (no step control, no stability bound);
        default: automatic step control.
    max_dh
        Largest wear (pad + rotor seen by the pad) per step at any pad node (m);
        default 1 % of the friction-layer thickness.
    dp_tol
        Largest accepted change of the pressure field per step, relative to
        its maximum (automatic control only).
    stability
        Fraction of the monotone explicit-Euler bound on the step (automatic
        control only; None switches it off).  1 keeps every mode of the wear
        ODE from overshooting; 2 is the stability limit.
    checkpoint, every, resume
        ``.npz`` file written every ``every`` accepted steps (and at the end);
        ``resume=True`` continues from it.
    interface
        The interface model (default: :class:`FEInterface` of ``model``); any
        object with the same attributes (``area``, ``r``, ``W``, ``ring``,
        ``rotor_area``, ``normal_stiffness``) and ``solve(offset, active)``.
    """
    if not (np.isfinite(omega) and omega > 0):
        raise WearError(f"omega = {omega!r} rad/s is not allowed; need a rotor speed > 0")
    if not (np.isfinite(duration) and duration > 0):
        raise WearError(f"duration = {duration!r} s is not allowed; need > 0")
    if steps is not None and (int(steps) != steps or steps < 1):
        raise WearError(f"steps = {steps!r} is not allowed; need a whole number >= 1")
    if resume and checkpoint is None:
        raise WearError("resume=True needs a checkpoint file")
    if resume and not Path(checkpoint).exists():
        raise WearError(f"resume=True but the checkpoint {checkpoint} does not exist")
    if not (np.isfinite(dp_tol) and dp_tol > 0):
        raise WearError(f"dp_tol = {dp_tol!r} is not allowed; need > 0")
    if stability is not None and not (np.isfinite(stability) and stability > 0):
        raise WearError(f"stability = {stability!r} is not allowed; need > 0 (or None)")
    if int(every) != every or every < 1:
        raise WearError(f"every = {every!r} is not allowed; need a whole number >= 1")
    for name, law in (("pad_law", pad_law), ("rotor_law", rotor_law)):
        if law is not None and not isinstance(law, WearLaw):
            raise WearError(f"{name} = {law!r} is not a WearLaw")
    g = model.geometry
    max_dh = 0.01 * g.pad.friction_thickness if max_dh is None else float(max_dh)
    if not max_dh > 0:
        raise WearError(f"max_dh = {max_dh!r} m is not allowed; need > 0")

    itf = FEInterface(model, line_pressure, mu, tol) if interface is None else interface
    A_pad, W, ring, A_rot = itf.area, itf.W, itf.ring, itf.rotor_area
    v = omega * itf.r                                  # sliding speed at each pad node
    r_mean = 0.5 * (g.pad.inner_radius + g.pad.outer_radius)
    # pressure response to a gap change, per unit area (Pa/m): Gershgorin row sums
    response = itf.normal_stiffness / A_pad

    state = {"step": 0, "time": 0.0, "pad_wear": np.zeros(A_pad.size),
             "rotor_wear": np.zeros(A_rot.size), "pad_archard": 0.0, "rotor_archard": 0.0,
             "active": None, "dt_next": duration / steps if steps else None}
    if resume:
        with np.load(checkpoint) as d:
            for k in state:
                state[k] = d[k].copy() if d[k].ndim else d[k].item()
        if state["pad_wear"].shape != (A_pad.size,) or state["rotor_wear"].shape != (A_rot.size,):
            raise WearError(f"checkpoint {checkpoint} holds {state['pad_wear'].size} pad and "
                            f"{state['rotor_wear'].size} rotor wear nodes; this model has "
                            f"{A_pad.size} and {A_rot.size}: it belongs to another model")
        if state["active"].size == 0:
            state["active"] = None
        if np.isnan(state["dt_next"]):
            state["dt_next"] = None
        logger.info("resumed at step %d, t = %.6g s", state["step"], state["time"])

    def solve(pad_w, rot_w, active):
        t0 = _time.perf_counter()
        p, act, _ = itf.solve(pad_w + W @ rot_w, active)
        return p, act, _time.perf_counter() - t0

    p, act, _ = solve(state["pad_wear"], state["rotor_wear"], state["active"])
    while state["time"] < duration * (1 - 1e-12):
        rate_pad = pad_law.rate(p, v)
        q_rot = rotor_law.rate(p, v) * A_pad if rotor_law is not None else np.zeros_like(p)
        rate_rot = rotor_wear_rate(q_rot, W, ring, A_rot)
        remaining = duration - state["time"]
        if steps:
            dt, limit = min(state["dt_next"], remaining), "fixed"
        else:
            cands = {"end": remaining}
            peak = float((rate_pad + W @ rate_rot).max())
            if peak > 0:
                cands["max_dh"] = max_dh / peak
            if stability is not None:
                # d(rate)/dp of both laws at the current pressure (a p^(a-1) k v^b)
                slope = _rate_slope(pad_law, p, v) + (
                    _rate_slope(rotor_law, p, v) if rotor_law is not None else 0.0)
                worst = float((slope * response)[act].max()) if act.any() else 0.0
                if worst > 0:
                    cands["stability"] = stability / worst
            if state["dt_next"] is not None:
                cands["growth"] = state["dt_next"]
            limit = min(cands, key=cands.get)
            dt = cands[limit]
        rejected, solve_s = 0, 0.0
        while True:
            pad_w = state["pad_wear"] + rate_pad * dt
            rot_w = state["rotor_wear"] + rate_rot * dt
            try:
                p_new, act_new, s = solve(pad_w, rot_w, act)
                solve_s += s
                change = np.abs(p_new - p).max() / max(p.max(), 1e-300)
                ok = steps is not None or change <= dp_tol
            except ContactLostError:
                change, ok = np.inf, False
            if ok:
                break
            rejected += 1
            if rejected > max_halvings:
                raise StepSizeError(
                    f"step {state['step'] + 1}: no acceptable wear step after {rejected} "
                    f"halvings (last dt {dt:.3e} s, pressure change {change:.2f} > dp_tol "
                    f"{dp_tol})")
            dt *= 0.5
        state["pad_wear"], state["rotor_wear"] = pad_w, rot_w
        state["pad_archard"] += float((rate_pad * A_pad).sum() * dt)
        state["rotor_archard"] += float(q_rot.sum() * dt)
        state["time"] += dt
        state["step"] += 1
        # next step: grow again, but never more than doubling the last accepted one
        state["dt_next"] = (duration / steps) if steps else 2.0 * dt
        record = WearStep(state["step"], state["time"], dt, omega * r_mean * state["time"],
                          p, act, pad_w.copy(), rot_w.copy(),
                          float((pad_w * A_pad).sum()), float((rot_w * A_rot).sum()),
                          state["pad_archard"], state["rotor_archard"], rejected,
                          rejected + 1, solve_s, limit)
        # the set the current solution started from: solving again from it
        # repeats the same computation, which is what makes resume exact
        state["active"] = act
        p, act = p_new, act_new
        if checkpoint is not None and (state["step"] % every == 0
                                       or state["time"] >= duration * (1 - 1e-12)):
            _write_checkpoint(checkpoint, _state_arrays(record, state["active"],
                                                        state["dt_next"]))
        yield record


def _rate_slope(law: WearLaw, p: np.ndarray, v: np.ndarray) -> np.ndarray:
    """d(rate)/dp of ``law`` at ``p`` (for a = 1 simply k v^b)."""
    if law.a == 1.0:
        return law.rate(1.0, v)
    pp = np.maximum(p, 1e-300)
    return law.a * law.rate(pp, v) / pp


def _write_checkpoint(path, arrays: dict) -> None:
    """Write atomically: a kill during the write leaves the previous checkpoint intact."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp.npz")
    out = {}
    for k, val in arrays.items():
        if val is None:
            val = np.nan if k == "dt_next" else np.zeros(0)
        out[k] = np.asarray(val)
    np.savez(tmp, **out)
    os.replace(tmp, path)
