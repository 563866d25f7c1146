"""CPU cost of AMG settings on the brake systems (docs/amg_settings.md).

Two cases, each timed with ``time.process_time`` (the solves are single
threaded, so CPU time is steadier than wall time on a shared machine):

* ``tied`` -- the tied pad-rotor elasticity system of
  :func:`brakewear.static.solve_tied`: hierarchy setup (including
  the coarse factorisation) and AMG-CG from zero to 1e-9 and to 1e-6;
* ``comp`` -- one implicit wear step's compliant contact solve at mu = 0.4
  (:class:`brakewear.FEInterface`, an 18 s step of k = 5e-15 1/Pa
  at 55 rad/s), started from the converged rigid-contact active set: the
  base hierarchy's setup, then the solve's active-set iterations and
  V-cycles (FGMRES).

Each setting overrides :data:`brakewear.solvers.SA_OPTIONS` /
:data:`~brakewear.solvers.SMOOTHERS` for its run.  Run::

    OPENBLAS_NUM_THREADS=1 python studies/amg_settings.py tied 1e5 default jacobi_P th0.02
    OPENBLAS_NUM_THREADS=1 python studies/amg_settings.py comp 1e5 default jacobi_P

(size: target DOFs of :func:`brakewear.bench.brake_resolution`, or ``5mm``
for ``BrakeModel(size=5e-3)``).  Prints one markdown table row per setting.
Timings vary by 10-30 % between runs on a loaded machine: compare settings
within one run, and repeat close calls.
"""
from __future__ import annotations

import copy
import sys
import time

import numpy as np

import brakewear.solvers as S

_GS = "gauss_seidel"
#: setting name -> (SA_OPTIONS overrides, smoothers or None)
SETTINGS = {
    "default": ({}, None),
    # pyamg's usual choice: Jacobi prolongation (one step, omega 4/3), 1000 coarse blocks
    "jacobi_P": ({"smooth": ("jacobi", {"omega": 4.0 / 3.0, "degree": 1}), "max_coarse": 1000},
                 None),
    "energy_4": ({"smooth": ("energy", {"degree": 1, "maxiter": 4})}, None),
    "sym_gs": ({}, ((_GS, {"sweep": "symmetric"}),) * 2),
    "gs_2": ({}, ((_GS, {"sweep": "forward", "iterations": 2}),
                  (_GS, {"sweep": "backward", "iterations": 2}))),
    "jacobi_smoother": ({}, (("jacobi", {"omega": 2.0 / 3.0, "withrho": True}),) * 2),
    "th0.02": ({"strength": ("symmetric", {"theta": 0.02})}, None),
    "th0.1": ({"strength": ("symmetric", {"theta": 0.1})}, None),
    "mc100": ({"max_coarse": 100}, None),
    "mc1000": ({"max_coarse": 1000}, None),
    "cholesky": ({"coarse_solver": "cholesky"}, None),
}


def model_for(size: str):
    from brakewear.bench import brake_resolution
    from brakewear.model import BrakeModel

    if size == "5mm":
        return BrakeModel(size=5e-3, rotor="elastic")
    return brake_resolution(float(size))[1]


def tied_system(model):
    """(Kd, fd, coords, fixed) exactly as ``brakewear.static.solve_tied`` forms them."""
    from brakewear.fem import apply_dirichlet

    K, P, retained, col = model.tie_reduction(tie_interface=True)
    fixed = model.reduced_fixed_dofs(col, None)
    Kd, fd = apply_dirichlet((P.T @ K @ P).tobsr(blocksize=(3, 3)), P.T @ model.loads(1e6), fixed)
    return Kd, fd, model.coordinates()[:, retained], fixed


class _Setting:
    """Context: ``SA_OPTIONS``/``SMOOTHERS`` of one named setting."""

    def __init__(self, name: str):
        if name not in SETTINGS:
            raise KeyError(f"setting {name!r}; allowed: {', '.join(SETTINGS)}")
        self.opts, self.smoothers = SETTINGS[name]

    def __enter__(self):
        self.saved = copy.deepcopy(S.SA_OPTIONS), S.SMOOTHERS
        S.SA_OPTIONS.update(self.opts)
        if self.smoothers is not None:
            S.SMOOTHERS = self.smoothers

    def __exit__(self, *exc):
        S.SA_OPTIONS.clear()
        S.SA_OPTIONS.update(self.saved[0])
        S.SMOOTHERS = self.saved[1]


def _levels(solver) -> str:
    return "/".join(str(lv.A.shape[0]) for lv in solver.ml.levels)


def run_tied(model, names) -> None:
    Kd, fd, coords, fixed = tied_system(model)
    print(f"tied, {Kd.shape[0]} DOFs\n\n| setting | setup CPU s | V-cycles 1e-9 | solve CPU s | "
          "total CPU s | V-cycles 1e-6 | solve CPU s | total CPU s | levels (rows) |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|---|")
    for name in names:
        with _Setting(name):
            t0 = time.process_time()
            s = S.amg_solver(Kd, coords=coords, fixed=fixed, tol=1e-9, maxiter=400)
            Ac = s.ml.levels[-1].A  # the coarse factorisation belongs to the setup
            s.ml.coarse_solver(Ac, np.ones(Ac.shape[0]))
            setup = time.process_time() - t0
            cells = []
            for tol in (1e-9, 1e-6):
                s.tol = tol
                t1 = time.process_time()
                s.solve(fd)
                dt = time.process_time() - t1
                cells += [f"{s.info.iterations}", f"{dt:.2f}", f"{setup + dt:.2f}"]
            print(f"| {name} | {setup:.2f} | " + " | ".join(cells) + f" | {_levels(s)} |",
                  flush=True)


def run_compliant(model, names) -> None:
    from brakewear.contact import compliant_preconditioner, solve_compliant_contact
    from brakewear.interfaces import FEInterface

    itf = FEInterface(model, 1e6, 0.4)
    sol = itf.solve(np.zeros(itf.area.size), None)  # the rigid contact set
    active = sol.active
    eps = 5e-15 * 55.0 * itf.r * 18.0  # k v dt of an 18 s step
    cs = itf.cs
    print(f"compliant step, {cs.K.shape[0]} DOFs, mu 0.4\n\n| setting | setup CPU s | active "
          "sets | V-cycles | solve CPU s | total CPU s | levels (rows) |\n"
          "|---|---:|---:|---:|---:|---:|---|")
    for name in names:
        with _Setting(name):
            t0 = time.process_time()
            pre = compliant_preconditioner(cs.K, cs.fixed, cs.coords, itf.tol)
            t1 = time.process_time()
            # the FE interface's compliant solve (no abutment stops), with this hierarchy
            info = solve_compliant_contact(cs.K, cs.f, cs.fixed, cs.coords, itf.pair, eps,
                                           initial_active=active, tol=itf.tol,
                                           solver=pre).info
            t2 = time.process_time()
            print(f"| {name} | {t1 - t0:.2f} | {info['active_set_iterations']} | "
                  f"{info['linear_iterations']} | {t2 - t1:.2f} | {t2 - t0:.2f} | "
                  f"{_levels(pre)} |", flush=True)


if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] not in ("tied", "comp"):
        sys.exit(__doc__)
    case, size, *names = sys.argv[1:]
    for n in names:
        _Setting(n)  # unknown names fail before the model is built
    (run_tied if case == "tied" else run_compliant)(model_for(size), names or ["default"])
