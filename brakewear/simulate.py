"""The wear loop: contact -> pressure -> wear of pad and rotor -> new gap -> ...

:func:`wear_history` is a generator of :class:`WearStep` records.  This first
version updates the geometry in *gap-offset* mode: the meshes stay, and the
worn depths of pad and rotor are added to the contact gap (valid while wear
is far below the element size; moving the surfaces is the next step).
Time integration is explicit Euler; the step is chosen so that no pad node
wears more than ``max_dh`` in one step, and a step after which the contact
pressure changes by more than ``dp_tol`` (relative to its maximum), or the
contact is lost, is rejected and retried at half the size.

Checkpoints (``.npz``) hold the whole state; a run resumed from one repeats
the uninterrupted run exactly, because every step is solved from the stored
state alone (fresh AMG hierarchy, active set of the previous step).
"""
from __future__ import annotations

import logging
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from .contact import ContactLostError, solve_contact, surface_nodes, tributary_areas
from .wear import WearError, WearLaw, rotor_rings, rotor_wear_rate

logger = logging.getLogger(__name__)

__all__ = ["WearStep", "wear_history", "StepSizeError"]


class StepSizeError(RuntimeError):
    """The step control could not find an acceptable wear step."""


@dataclass
class WearStep:
    """State after an accepted step (cumulative quantities)."""

    step: int
    time: float                 # s
    dt: float                   # s, of this step
    pressure: np.ndarray        # Pa at the pad's friction nodes, at the start of the step
    active: np.ndarray          # contact status at the start of the step
    pad_wear: np.ndarray        # m, cumulative, per pad friction node
    rotor_wear: np.ndarray      # m, cumulative, per rotor friction node
    pad_volume: float           # m^3 worn from the pad (sum of depth x area)
    rotor_volume: float         # m^3 worn from the rotor
    pad_archard: float          # m^3, sum over steps of k_pad int p v dA dt
    rotor_archard: float        # m^3, the same with k_rotor
    rejected: int               # retries before this step was accepted


def _state_arrays(step: WearStep, active_next: np.ndarray, dt_next: float) -> dict:
    return {"step": step.step, "time": step.time, "pad_wear": step.pad_wear,
            "rotor_wear": step.rotor_wear, "pad_archard": step.pad_archard,
            "rotor_archard": step.rotor_archard, "active": active_next, "dt_next": dt_next}


def wear_history(model, line_pressure: float, omega: float, duration: float,
                 pad_law: WearLaw, rotor_law: WearLaw | None = None, mu: float = 0.0,
                 steps: int | None = None, max_dh: float | None = None, dp_tol: float = 0.05,
                 checkpoint: str | os.PathLike | None = None, every: int = 10,
                 resume: bool = False, tol: float = 1e-9, max_halvings: int = 12
                 ) -> Iterator[WearStep]:
    """Run a wear history of the brake under constant line pressure and speed.

    Parameters
    ----------
    model
        A :class:`brakewear.scene.BrakeModel` with an elastic rotor.
    line_pressure, omega, duration
        Pa, rad/s (rotor speed, > 0), s.
    pad_law, rotor_law
        Wear laws of pad and rotor (``rotor_law=None``: the rotor does not wear).
    steps
        Fixed number of equal steps; default: automatic step control.
    max_dh
        Largest wear (pad + rotor seen by the pad) per step at any pad node (m);
        default 1 % of the friction-layer thickness.
    dp_tol
        Largest accepted change of the pressure field per step, relative to
        its maximum (automatic control only).  0.05 keeps the explicit
        scheme's short-wavelength modes quiet: with 0.25 the default brake's
        p r spread fell to 5 % and then grew again to 36 % within two hours.
    checkpoint, every, resume
        ``.npz`` file written every ``every`` accepted steps (and at the end);
        ``resume=True`` continues from it.
    """
    if not (np.isfinite(omega) and omega > 0):
        raise WearError(f"omega = {omega!r} rad/s is not allowed; need a rotor speed > 0")
    if not (np.isfinite(duration) and duration > 0):
        raise WearError(f"duration = {duration!r} s is not allowed; need > 0")
    if model.rotor != "elastic":
        raise WearError("wear_history needs rotor='elastic' (the rigid rotor's wear "
                        "tracking is not built yet)")
    if steps is not None and (int(steps) != steps or steps < 1):
        raise WearError(f"steps = {steps!r} is not allowed; need a whole number >= 1")
    if resume and checkpoint is None:
        raise WearError("resume=True needs a checkpoint file")
    g = model.geometry
    max_dh = 0.01 * g.pad.friction_thickness if max_dh is None else float(max_dh)
    if not max_dh > 0:
        raise WearError(f"max_dh = {max_dh!r} m is not allowed; need > 0")

    cs = model.contact_system(line_pressure, mu)
    pair = cs.pair
    g0 = pair.g0.copy()
    pad = model.meshes["pad"]
    x = pad.p[:, surface_nodes(pad, "friction")]
    v = omega * np.hypot(x[0], x[1])                  # sliding speed at each pad node
    rotor = model.meshes["rotor"]
    face = surface_nodes(rotor, "friction")
    face_r = cs.col[face + model.offsets["rotor"]]    # retained numbering
    W = pair.coupling[:, face_r].tocsr()
    ring, _ = rotor_rings(np.hypot(rotor.p[0, face], rotor.p[1, face]))
    A_rot = tributary_areas(rotor, "friction", face)
    A_pad = pair.area

    state = {"step": 0, "time": 0.0, "pad_wear": np.zeros(pair.slave.size),
             "rotor_wear": np.zeros(face.size), "pad_archard": 0.0, "rotor_archard": 0.0,
             "active": None, "dt_next": duration / steps if steps else None}
    if resume:
        with np.load(checkpoint) as d:
            for k in state:
                state[k] = d[k].copy() if d[k].ndim else d[k].item()
        if isinstance(state["active"], float) or state["active"] is None or state["active"].size == 0:
            state["active"] = None
        logger.info("resumed at step %d, t = %.6g s", state["step"], state["time"])

    def solve(pad_w, rot_w, active):
        pair.g0 = g0 + pad_w + W @ rot_w
        init = None if active is None else [np.asarray(active, dtype=bool)]
        return solve_contact(cs.K, cs.f, cs.fixed, cs.coords, [pair], tol=tol,
                             initial_active=init)

    res = solve(state["pad_wear"], state["rotor_wear"], state["active"])
    while state["time"] < duration * (1 - 1e-12):
        p, act = res.pressure[0], res.active[0]
        rate_pad = pad_law.rate(p, v)
        q_rot = rotor_law.rate(p, v) * A_pad if rotor_law is not None else np.zeros_like(p)
        rate_rot = rotor_wear_rate(q_rot, W, ring, A_rot)
        remaining = duration - state["time"]
        if steps:
            dt = min(state["dt_next"], remaining)
        else:
            peak = float((rate_pad + W @ rate_rot).max())
            dt = remaining if peak <= 0 else min(remaining, max_dh / peak)
            if state["dt_next"] is not None:
                dt = min(dt, state["dt_next"])
        rejected = 0
        while True:
            pad_w = state["pad_wear"] + rate_pad * dt
            rot_w = state["rotor_wear"] + rate_rot * dt
            try:
                new = solve(pad_w, rot_w, act)
                change = np.abs(new.pressure[0] - p).max() / max(p.max(), 1e-300)
                ok = steps is not None or change <= dp_tol
            except ContactLostError:
                new, change, ok = None, np.inf, False
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
        state["pad_archard"] += float((pad_law.rate(p, v) * A_pad).sum() * dt)
        state["rotor_archard"] += float(q_rot.sum() * dt)
        state["time"] += dt
        state["step"] += 1
        # next step: grow again, but never more than doubling the last accepted one
        state["dt_next"] = (duration / steps) if steps else 2.0 * dt
        record = WearStep(state["step"], state["time"], dt, p, act, pad_w.copy(), rot_w.copy(),
                          float((pad_w * A_pad).sum()), float((rot_w * A_rot).sum()),
                          state["pad_archard"], state["rotor_archard"], rejected)
        res = new
        # the set the current solution started from: solving again from it
        # repeats the same computation, which is what makes resume exact
        state["active"] = act
        if checkpoint is not None and (state["step"] % every == 0
                                       or state["time"] >= duration * (1 - 1e-12)):
            _write_checkpoint(checkpoint, _state_arrays(record, state["active"],
                                                        state["dt_next"]))
        yield record


def _write_checkpoint(path, arrays: dict) -> None:
    """Write atomically: a kill during the write leaves the previous checkpoint intact."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp.npz")
    np.savez(tmp, **{k: (np.asarray(v) if v is not None else np.zeros(0)) for k, v in arrays.items()})
    os.replace(tmp, path)
