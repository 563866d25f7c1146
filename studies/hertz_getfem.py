"""Hertz in GetFEM beside brakewear: the same problem, mesh and measures.

The model of :mod:`brakewear.contact.hertz` (rigid sphere on a quarter block,
symmetry planes, Boussinesq far field of the force found by the secant
iteration ``F_bc = F(F_bc)``) solved per mesh size by both codes, each in a
fresh process, interleaved: brakewear's ``hertz_problem`` + ``solve_problem``
(node-to-rigid Lagrange contact, active set), and GetFEM (``python3-getfem``,
not on PyPI, so not a dependency: run by ``--getfem-python``, default
``/usr/bin/python3``) on the same nodes and P1 tetrahedra with
``add_nodal_contact_with_rigid_obstacle_brick`` (frictionless, Alart-Curnier,
the vertical gap to the sphere as in brakewear), the symmetry and far-face
DOFs as one ``add_constraint_with_multipliers``, Newton by ``Model.solve``
with MUMPS; between the force iteration's solves only the far-field data change.

Both are measured by :func:`brakewear.contact.hertz.measure` on their nodal
contact forces (p0 recovered in the 2h window and as raw nodal force over
tributary area; the radius from the p^2 fit, the active area and the
outermost active node); for GetFEM also the peak of the L2 projection of the
nodal forces onto P1 on the top face. Times exclude imports; "build" is mesh,
spaces, assembly and set-up (brakewear generates its mesh in it, GetFEM
starts from the node and tetrahedron arrays), "solve" the force iteration's
contact solves; CPU time is the process's, all threads.

Run ``python studies/hertz_getfem.py [--sizes 6 8 12] [--data docs/data]``.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

GETFEM_PYTHON = "/usr/bin/python3"
SIZES = (6, 8, 12)          # a / h
MAX_OUTER = 8
OUTER_TOL = 1e-9
NEWTON_RES = 1e-12          # Newton residual / Hertz force
KEYS = ("p0_err", "p0_nodal_err", "a_err", "a_area_err", "a_outer_err", "delta_err", "n_active")


def getfem_status(python: str = GETFEM_PYTHON) -> tuple[bool, str]:
    """Whether ``python`` imports getfem, and its version or the reason it does not."""
    try:
        out = subprocess.run([python, "-c", "import getfem as g; print(g.getfem_env('release'))"],
                             capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return False, f"{python}: {exc}"
    if out.returncode != 0:
        return False, f"{python} cannot import getfem: {out.stderr.strip().splitlines()[-1]}"
    return True, f"GetFEM {out.stdout.strip()} ({python})"


def _clock() -> tuple[float, float]:
    return time.perf_counter(), time.process_time()


def _since(t0: tuple[float, float]) -> tuple[float, float]:
    return tuple(b - a for a, b in zip(t0, _clock()))


# GetFEM side: runs under a Python with getfem and without brakewear

def _boussinesq(x, F, E, nu):
    """Johnson eq. 3.20, the point force into z < 0 (as brakewear.contact.hertz.boussinesq)."""
    G = E / (2.0 * (1.0 + nu))
    d = -x[2]
    rho = np.sqrt(x[0] ** 2 + x[1] ** 2 + d ** 2)
    c = F / (4.0 * np.pi * G)
    ud = c * (2.0 * (1.0 - nu) / rho + d ** 2 / rho ** 3)
    ur = c * (d / rho ** 3 - (1.0 - 2.0 * nu) / (rho * (rho + d)))
    return np.vstack([ur * x[0], ur * x[1], -ud])


def getfem_child(npz_in: str, npz_out: str) -> None:
    """Build and solve one mesh size in GetFEM; write the top-face forces and times."""
    import getfem as gf
    import scipy.sparse as sp
    from scipy.sparse.linalg import spsolve

    gf.util_trace_level(0)

    d = np.load(npz_in)
    E, nu, R, delta, F0 = (float(d[k]) for k in ("E", "nu", "R", "delta", "F0"))
    t0 = _clock()
    m = gf.Mesh("ptND", d["p"], d["t"])
    faces = m.outer_faces()
    n = m.normal_of_faces(faces)
    TOP, X0, Y0, FAR = 1, 2, 3, 4
    for region, sel in ((TOP, n[2] > 0.5), (X0, n[0] < -0.5), (Y0, n[1] < -0.5),
                        (FAR, (n[0] > 0.5) | (n[1] > 0.5) | (n[2] < -0.5))):
        m.set_region(region, faces[:, sel])
    mfu, mfs = gf.MeshFem(m, 3), gf.MeshFem(m, 1)
    mfu.set_classical_fem(1)
    mfs.set_classical_fem(1)
    mim = gf.MeshIm(m, 2)
    xu = mfu.basic_dof_nodes()
    comp = np.arange(xu.shape[1]) % 3          # GetFEM orders vector dofs component fastest
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_initialized_data("lambda", [E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))])
    md.add_initialized_data("mu", [E / (2.0 * (1.0 + nu))])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "lambda", "mu")
    # symmetry (u_x on x = 0, u_y on y = 0) and the far faces (all components) as one
    # constraint B u = ubc on distinct DOFs, as brakewear fixes them
    far = np.zeros(xu.shape[1], bool)
    far[mfu.basic_dof_on_region(FAR)] = True
    sym = np.zeros(xu.shape[1], bool)
    for region, c in ((X0, 0), (Y0, 1)):
        dofs = mfu.basic_dof_on_region(region)
        sym[dofs[comp[dofs] == c]] = True
    fixed = np.flatnonzero(far | sym)
    on_far = far[fixed]

    def far_field(F):            # prescribed values of the fixed DOFs
        v = np.zeros(fixed.size)
        x = xu[:, fixed[on_far]]
        v[on_far] = _boussinesq(x, F, E, nu)[comp[fixed[on_far]], np.arange(x.shape[1])]
        return v

    B = gf.Spmat("copy", gf.Spmat("identity", xu.shape[1]), fixed.tolist(),
                 list(range(xu.shape[1])))
    md.add_variable("mult_bc", fixed.size)
    md.add_initialized_data("ubc", far_field(F0))
    md.add_constraint_with_multipliers("u", "mult_bc", B, "ubc")
    cdof = np.sort(mfu.basic_dof_on_region(TOP))[::3]   # one row of lambda_n per top node
    md.add_variable("lambda_n", cdof.size)
    md.add_initialized_data("r", [E * float(d["h"])])     # augmentation: a nodal stiffness
    obstacle = f"{R - delta!r} - sqrt({R * R!r} - x*x - y*y) - z"   # vertical gap to the sphere
    md.add_nodal_contact_with_rigid_obstacle_brick(mim, "u", "lambda_n", "r", TOP, obstacle, 1)
    build = _since(t0)

    t1 = _clock()
    F_bc, hist, newton, solves = F0, [], [], []
    for _ in range(MAX_OUTER):
        ts = _clock()
        md.set_variable("ubc", far_field(F_bc))
        its, conv = md.solve("max_res", NEWTON_RES * F0, "max_iter", 100, "lsolver", "mumps")
        solves.append(_since(ts))
        newton.append(int(its))
        if not conv:
            raise RuntimeError(f"GetFEM Newton: no convergence in {its} iterations")
        lam = md.variable("lambda_n")
        F_out = -4.0 * float(lam.sum())                   # quarter model; lambda_n <= 0
        hist.append((F_bc, F_out))
        if abs(F_out - F_bc) <= OUTER_TOL * abs(F_out):
            break
        if len(hist) == 1:
            F_bc = F_out
        else:
            (x0, g0), (x1, g1) = hist[-2], hist[-1]
            F_bc = x1 + (g1 - x1) / (1.0 - (g1 - g0) / (x1 - x0))
    solve, total = _since(t1), _since(t0)

    # post-processing (not timed): tributary areas and the L2-projected pressure
    zeros = np.zeros(mfs.nbdof())
    area = np.asarray(gf.asm_generic(mim, 1, "Test_t", TOP, "t", 1, mfs, zeros))
    M = gf.asm_generic(mim, 2, "Test_t*Test2_t", TOP, "t", 1, mfs, zeros)
    ind = M.csc_ind()
    M = sp.csc_matrix((M.csc_val(), ind[1], ind[0]), shape=M.size())
    s = cdof // 3                                        # scalar dof of each top node
    assert np.array_equal(mfs.basic_dof_nodes()[:, s], xu[:, cdof])
    force = -lam
    p_l2 = spsolve(M[s][:, s].tocsc(), force)
    np.savez(npz_out, x=xu[:, cdof], force=force, area=area[s], p_l2=p_l2, F=F_out,
             F_bc=hist[-1][0], outer=len(hist), newton=np.array(newton),
             solve_s=np.array(solves), build=np.array(build), solve=np.array(solve),
             total=np.array(total), dofs=mfu.nbdof(), all_dofs=md.nbdof(),
             version=gf.getfem_env("release"))


def brakewear_child(ah: str, json_out: str) -> None:
    """Build and solve one mesh size with brakewear; write the measures and times."""
    from brakewear.contact import hertz as hz

    t0 = _clock()
    prob = hz.hertz_problem(1.0 / float(ah))
    build = _since(t0)
    t1 = _clock()
    out, _, _ = hz.solve_problem(prob)
    solve, total = _since(t1), _since(t0)
    row = {k: out[k] for k in KEYS + ("F", "outer_iterations", "active_set_iterations")}
    row.update(dofs=prob.dofs, build=build, solve=solve, total=total,
               solve_s=[float(t) for t in out["solve_s"]])
    Path(json_out).write_text(json.dumps(row))


def getfem_measures(data, ah: float) -> dict:
    """brakewear's measures of GetFEM's nodal contact forces, plus the L2-projected peak."""
    from brakewear.analytic import hertz_sphere
    from brakewear.contact import hertz as hz

    x, f, A, F = data["x"], data["force"], data["area"], float(data["F"])
    res = SimpleNamespace(force=[f], pressure=[f / A], active=[f > 1e-12 * f.max()])
    pair = SimpleNamespace(slave=np.arange(f.size), area=A, basis=None)
    out = hz.measure(SimpleNamespace(p=x), pair, res, F, h=hz.A0 / ah)
    origin = int(np.argmin(np.hypot(x[0], x[1])))
    out["p0_l2_err"] = float(data["p_l2"][origin]) / hertz_sphere(F, hz.R, hz.ES)["p0"] - 1.0
    return out


def _run(cmd: list[str]) -> None:
    from brakewear.errors import SolverError

    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        raise SolverError(f"{' '.join(cmd)} failed:\n{out.stderr[-2000:]}")


def run_brakewear(ah: float, tmp: Path) -> dict:
    """One brakewear solve at h = a / ``ah`` in a fresh process."""
    dest = tmp / f"bw_{ah:g}.json"
    _run([sys.executable, __file__, "--brakewear-child", str(ah), str(dest)])
    return _times("brakewear", ah, json.loads(dest.read_text()))


def run_getfem(ah: float, tmp: Path, python: str = GETFEM_PYTHON) -> dict:
    """One GetFEM solve at h = a / ``ah`` in a fresh process (same nodes and tetrahedra)."""
    from brakewear.contact import hertz as hz

    h = hz.A0 / ah
    xs = hz.axis(h, hz.FINE_XY * hz.A0, hz.L_OVER_A * hz.A0)
    p, t = hz.mirrored_tets(xs, xs, -hz.axis(h, hz.FINE_Z * hz.A0, hz.L_OVER_A * hz.A0)[::-1])
    src, dest = tmp / f"gf_in_{ah:g}.npz", tmp / f"gf_out_{ah:g}.npz"
    np.savez(src, p=p, t=t, E=hz.MATERIAL.E, nu=hz.MATERIAL.nu, R=hz.R, delta=hz.DELTA,
             F0=hz.hertz_force(), h=h)
    _run([python, __file__, "--getfem-child", str(src), str(dest)])
    data = dict(np.load(dest))
    meas = getfem_measures(data, ah)
    row = {k: meas[k] for k in KEYS}
    row.update(p0_l2_err=meas["p0_l2_err"], F=float(data["F"]), dofs=int(data["dofs"]),
               all_dofs=int(data["all_dofs"]), outer_iterations=int(data["outer"]),
               newton_iterations=[int(i) for i in data["newton"]],
               solve_s=[list(map(float, s)) for s in data["solve_s"]],
               build=data["build"].tolist(), solve=data["solve"].tolist(),
               total=data["total"].tolist(), version=str(data["version"]))
    return _times("getfem", ah, row)


def _times(code: str, ah: float, row: dict) -> dict:
    return {"code": code, "h_over_a": 1.0 / ah, "wall_s": row["total"][0],
            "cpu_s": row["total"][1], "solve_wall_s": row["solve"][0],
            "solve_cpu_s": row["solve"][1], **row}


def main(sizes=SIZES, python: str = GETFEM_PYTHON, getfem: bool = True,
         data: str | None = None) -> dict:
    """Both codes at each ``a / h`` in ``sizes``, interleaved, one fresh process each."""
    ok, status = getfem_status(python) if getfem else (False, "not requested")
    load = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for ah in sizes:
            rows.append(run_brakewear(ah, Path(tmp)))
            if ok:
                rows.append(run_getfem(ah, Path(tmp), python))
    result = {"command": "python studies/hertz_getfem.py --sizes "
                         + " ".join(f"{a:g}" for a in sizes),
              "load_average_start": list(load), "load_average_end": list(os.getloadavg()),
              "getfem": status, "getfem_ran": ok, "rows": rows}
    if data:
        Path(data).mkdir(parents=True, exist_ok=True)
        (Path(data) / "hertz_getfem.json").write_text(json.dumps(result, indent=1))
    return result


def table(result: dict) -> str:
    """Markdown table of :func:`main`'s rows."""
    head = ("| code | h/a | DOFs | wall s | CPU s | solve CPU s | p0 recovered | p0 nodal "
            "| p0 L2 proj. | a, p² fit | a, area | a, outermost |\n|" + "---|" * 12)
    lines = [head]
    for r in result["rows"]:
        pct = [f"{100 * r[k]:+.2f} %" if k in r else "" for k in
               ("p0_err", "p0_nodal_err", "p0_l2_err", "a_err", "a_area_err", "a_outer_err")]
        lines.append(f"| {r['code']} | 1/{1 / r['h_over_a']:.0f} | {r['dofs']} "
                     f"| {r['wall_s']:.1f} | {r['cpu_s']:.1f} | {r['solve_cpu_s']:.1f} | "
                     + " | ".join(pct) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] in ("--getfem-child", "--brakewear-child"):
        child = getfem_child if sys.argv[1] == "--getfem-child" else brakewear_child
        sys.exit(child(sys.argv[2], sys.argv[3]))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs="+", default=list(SIZES), help="a / h")
    ap.add_argument("--getfem-python", default=GETFEM_PYTHON)
    ap.add_argument("--no-getfem", action="store_true")
    ap.add_argument("--data", help="write hertz_getfem.json here")
    args = ap.parse_args()
    res = main(args.sizes, args.getfem_python, not args.no_getfem, args.data)
    print(f"load average at start {res['load_average_start']}; {res['getfem']}")
    print(table(res))
