"""The wear benchmark (``brakewear bench wear``): the cost per step of a wear history."""
from __future__ import annotations

import logging
import os
import time
from collections.abc import Sequence

import numpy as np

from ..errors import BenchError
from ..wear.run import Run
from .common import peak_rss_mb
from .contact import brake_resolution

logger = logging.getLogger(__name__)


__all__ = ['INTERFACES', 'LAYOUTS', 'WEAR_SIZES', 'run_wear_case', 'bench_wear',
           'format_wear_table']

WEAR_SIZES = (3e4, 1e5)


INTERFACES = ("fe", "condensed", "winkler")


#: model layouts: one pad and the rotor's half, or both pads and the whole rotor
LAYOUTS = ("half", "full")


def _loop_interface(kind: str, model, itf):
    """The interface the loop runs on, and the seconds (wall, CPU) it took to
    build beside ``itf``."""
    t0, c0 = time.perf_counter(), time.process_time()
    if kind == "condensed":
        from ..interfaces.condensed import CondensedInterface
        out = CondensedInterface(model, 1e6, 0.4, fe=itf, cache=False)
    elif kind == "winkler":
        from ..interfaces.foundation import FoundationInterface
        from ..interfaces.winkler_bed import WinklerInterface
        out = FoundationInterface(model, WinklerInterface.from_model(model), 1e6, 0.4)
    else:
        return itf, 0.0, 0.0
    return out, time.perf_counter() - t0, time.process_time() - c0


def _count_dense_work(itf, counts: dict) -> None:
    """Add up the dense factorisations and Schur updates of ``itf``'s solves
    (the condensed interface's ``info``) into ``counts``."""
    solve = itf.solve

    def counted(*a, **kw):
        out = solve(*a, **kw)
        for key in counts:
            counts[key] += int(out.info.get(key, 0))
        return out
    itf.solve = counted


def _check_case(steps, update: str, interface: str) -> None:
    if interface not in INTERFACES or (interface != "fe" and update != "gap"):
        raise BenchError(f"interface = {interface!r} with update = {update!r} is not allowed; "
                         f"allowed: {', '.join(INTERFACES)}, the last two with update 'gap'")
    if update not in ("gap", "geometry"):
        raise BenchError(f"update = {update!r} is not allowed; allowed: 'gap', 'geometry'")
    if int(steps) != steps or steps < 1:
        raise BenchError(f"steps = {steps!r} is not allowed; need a whole number >= 1")


def _bench_model(target_dofs: float, size: float | None, layout: str):
    """(size, model) of the default brake: ``size`` (m) or the size of about
    ``target_dofs`` DOFs in the half model; ``layout`` half or full."""
    from ..model import BrakeModel

    if layout not in LAYOUTS:
        raise BenchError(f"layout = {layout!r} is not allowed; allowed: {', '.join(LAYOUTS)}")
    if size is None:
        size, model = brake_resolution(target_dofs)
        if layout == "half":
            return size, model
    return size, BrakeModel(size=size, rotor="elastic", layout=layout)


def _plain_solve(itf) -> tuple[float, float]:
    """Wall and CPU seconds of one plain contact solve from the initial gaps: the
    faster of two (the first also pays for first-call set-up)."""
    walls, cpus = [], []
    for _ in range(2):
        t1, c1 = time.perf_counter(), time.process_time()
        itf.solve(np.zeros(itf.area.size), None)
        walls.append(time.perf_counter() - t1)
        cpus.append(time.process_time() - c1)
    return min(walls), min(cpus)


def run_wear_case(target_dofs: float, steps: int = 200, update: str = "gap",
                  duration: float = 3600.0, size: float | None = None,
                  interface: str = "fe", layout: str = "half") -> dict:
    """Time a two-surface running-in of the default brake (elastic rotor).

    1 MPa line pressure, 55 rad/s, ``mu = 0.4``, the pad's and the rotor's
    Archard coefficients from their materials, the implicit scheme with
    ``steps`` fixed steps over ``duration`` s (so the step count is exact).

    Returns a dict: ``dofs``, ``steps``, ``contact_solves``, ``total_s`` (the
    interface's assembly plus every step), ``per_step_s = total_s / steps``,
    the shares of ``total_s`` spent in contact solves (``contact_share``: every
    solve of the loop, including its first one before step 1, which the first
    :class:`~brakewear.wear.WearStep` counts; ``step_solves_s`` is the
    records' own sum), in
    assembling the contact system (``assembly_share``: the first build and,
    in geometry mode, every rebuild) and in moving the worn meshes with their
    partial stiffness update (``motion_share``, 0 in gap mode);
    ``contact_solve_s``: one plain (rigid, Lagrange) contact solve of the same
    model from the initial gaps, timed in the same process before the run,
    and ``step_over_contact = per_step_s / contact_solve_s`` (the faster of
    two solves: the first pays for first-call set-up).  The ``*_cpu_s`` keys
    are the same in process CPU time (steadier on a shared machine).

    ``layout``: ``"half"`` or ``"full"`` (both pads and the whole rotor on
    the half model's mesh size: about twice the DOFs).

    ``interface``: ``"fe"``, ``"condensed"`` (its condensation timed apart as
    ``interface_s`` and as ``interface_over_contact`` contact solves, in CPU
    time as ``interface_cpu_s`` and ``interface_over_contact_cpu``; its dense
    ``factorisations`` and Schur ``updates`` counted; per step, the seconds of
    its dense active-set solves, ``set_solves_per_step_s``, and of the rest of
    its solves -- the step's loads, the rings' compliance, the answer --
    ``loads_per_step_s``; gap mode only) or
    ``"winkler"`` (the elastic foundation).
    """
    from ..interfaces.fe import FEInterface
    from ..laws.base import WearLaw
    from ..materials import MATERIALS
    from ..motion.brake import BrakeMotion
    from ..wear import Numerics, wear_history

    _check_case(steps, update, interface)
    t0 = time.perf_counter()
    size, model = _bench_model(target_dofs, size, layout)
    model_s = time.perf_counter() - t0
    g = model.geometry
    pad_law = WearLaw(g.pad.friction_material.wear_k or MATERIALS["pad_resin"].wear_k)
    rotor_law = WearLaw(g.rotor.material.wear_k or MATERIALS["grey_cast_iron"].wear_k)
    spent = {"assembly": 0.0, "motion": 0.0, "contact": 0.0, "sets": 0.0}
    dense = {"factorisations": 0, "updates": 0}
    originals = {}

    def timed(cls, name, key):
        fn = getattr(cls, name)
        originals[(cls, name)] = fn

        def wrapper(*a, **kw):
            t = time.perf_counter()
            try:
                return fn(*a, **kw)
            finally:
                spent[key] += time.perf_counter() - t
        setattr(cls, name, wrapper)

    try:
        timed(FEInterface, "rebuild", "assembly")
        timed(FEInterface, "solve", "contact")   # also the loop's first solve (no record)
        timed(BrakeMotion, "__init__", "motion")
        timed(BrakeMotion, "apply", "motion")
        t0 = time.perf_counter()
        itf = FEInterface(model, 1e6, 0.4)
        build_s = time.perf_counter() - t0
        contact_solve_s, contact_solve_cpu = _plain_solve(itf)
        spent["contact"] = 0.0
        loop_itf, interface_s, interface_cpu = _loop_interface(interface, model, itf)
        if interface != "fe":
            timed(type(loop_itf), "solve", "contact")
            _count_dense_work(loop_itf, dense)
        if interface == "condensed":
            # the dense active-set solves apart from the rest of each solve (its loads)
            from ..interfaces import condensed
            timed(condensed, "solve_dense_sets", "sets")
        if update == "geometry":     # the loop builds its own interface (timed as assembly)
            spent["assembly"] = 0.0
        t2, c2 = time.perf_counter(), time.process_time()
        record_s, solves, n = 0.0, 0, 0
        run = Run(model, 1e6, 55.0, duration, pad_law, rotor_law, 0.4,
                  interface=loop_itf if update == "gap" else None,
                  numerics=Numerics(steps=int(steps), scheme="implicit", update=update))
        for s in wear_history(run):
            record_s += s.solve_s
            solves += s.contact_solves
            n += 1
        loop_s = time.perf_counter() - t2
        loop_cpu = time.process_time() - c2
    finally:
        for (cls, name), fn in originals.items():
            setattr(cls, name, fn)
    contact_s = spent["contact"]
    total_s = loop_s + (build_s if update == "gap" else 0.0)
    per_step = total_s / n
    return {"bench": "wear", "target_dofs": float(target_dofs), "size_m": float(size),
            "dofs": int(model.dofs), "update": update, "scheme": "implicit",
            "interface": interface, "layout": layout, "contact_nodes": int(itf.area.size),
            "interface_s": interface_s, "interface_over_contact": interface_s / contact_solve_s,
            "interface_cpu_s": interface_cpu,
            "interface_over_contact_cpu": interface_cpu / contact_solve_cpu, **dense,
            "steps": int(n), "contact_solves": int(solves), "duration_s": float(duration),
            "model_s": model_s, "total_s": total_s, "per_step_s": per_step,
            "contact_s": contact_s, "step_solves_s": record_s, "assembly_s": spent["assembly"],
            "set_solves_per_step_s": spent["sets"] / n,
            "loads_per_step_s": (contact_s - spent["sets"]) / n if spent["sets"] else None,
            "motion_s": spent["motion"], "contact_share": contact_s / total_s,
            "assembly_share": spent["assembly"] / total_s,
            "motion_share": spent["motion"] / total_s,
            "contact_solve_s": contact_solve_s, "step_over_contact": per_step / contact_solve_s,
            "per_step_cpu_s": loop_cpu / n, "contact_solve_cpu_s": contact_solve_cpu,
            "step_over_contact_cpu": loop_cpu / n / contact_solve_cpu,
            "peak_rss_mb": peak_rss_mb(), "cpus": os.cpu_count()}


def bench_wear(sizes: Sequence[float] = WEAR_SIZES, steps: int = 200, update: str = "gap",
               duration: float = 3600.0, progress=None,
               interfaces: Sequence[str] = ("fe",),
               layouts: Sequence[str] = ("half",)) -> list[dict]:
    """:func:`run_wear_case` at each target DOF count (of the half model),
    interface and layout (in this process; the full model on the half model's
    mesh size); one dict per case."""
    rows = []
    for target in sizes:
        size = None
        for layout in layouts:
            for kind in interfaces:
                rows.append(run_wear_case(target, steps, update, duration, size=size,
                                          interface=kind, layout=layout))
                size = rows[-1]["size_m"]
                if progress is not None:
                    progress(rows[-1])
    return rows


def format_wear_table(rows: Sequence[dict]) -> str:
    out = [f"{'dofs':>8} {'layout':>6} {'interface':>9} {'update':>8} {'steps':>5} {'total s':>8} "
           f"{'s/step':>7} "
           f"{'contact':>7} {'assembly':>8} {'motion':>6} {'solve s':>7} {'step/solve':>10}"]
    for r in rows:
        out.append(f"{r['dofs']:>8} {r.get('layout', 'half'):>6} {r.get('interface', 'fe'):>9} "
                   f"{r['update']:>8} "
                   f"{r['steps']:>5} {r['total_s']:>8.1f} "
                   f"{r['per_step_s']:>7.4f} {r['contact_share']:>7.2f} "
                   f"{r['assembly_share']:>8.2f} {r['motion_share']:>6.2f} "
                   f"{r['contact_solve_s']:>7.2f} {r['step_over_contact']:>10.2f}")
    out.append("shares of total_s; solve s = one plain contact solve of the same model; "
               "step/solve = per-step time / that solve")
    for h in rows:
        for f in rows:
            if (h.get("layout", "half"), f.get("layout")) == ("half", "full") and \
                    h["size_m"] == f["size_m"] and h["interface"] == f["interface"]:
                out.append(f"full over half at {h['size_m'] * 1e3:.3g} mm ({h['interface']}): "
                           f"{f['dofs'] / h['dofs']:.2f}x the DOFs, "
                           f"{f['per_step_s'] / h['per_step_s']:.2f}x the time per step")
    for r in rows:
        if r.get("interface", "fe") != "fe":
            out.append(f"{r['dofs']} DOFs, {r['interface']}: built in {r['interface_s']:.2f} s "
                       f"= {r['interface_over_contact']:.1f} contact solves "
                       f"({r['interface_over_contact_cpu']:.1f} in CPU time; "
                       f"{r['contact_nodes']} contact nodes); "
                       f"{r['factorisations']} dense factorisations, {r['updates']} updates")
    return "\n".join(out)


