"""The command line of the benchmarks (``brakewear bench ...``, ``python -m brakewear.bench``)."""
from __future__ import annotations

import argparse
import json
import logging
import os
import platform
import sys
from collections.abc import Sequence

from .contact import (
    CONTACT_CASES,
    CONTACT_DIRECT_MAX,
    CONTACT_SIZES,
    CONTACT_SUPERLU_MAX,
    bench_contact,
    format_contact_table,
    run_contact_case,
)
from .elasticity import DEFAULT_SIZES, bench_elasticity, format_table, run_elasticity_case
from .rough import ROUGH_SIZES, bench_rough, format_rough_table
from .wear import INTERFACES, LAYOUTS, WEAR_SIZES, bench_wear, format_wear_table

logger = logging.getLogger(__name__)


__all__ = ['add_bench_parser', 'run_bench', 'main']

def _run_wear_bench(args: argparse.Namespace) -> int:
    if not args.json:
        print(f"brakewear bench wear: {os.cpu_count()} CPUs, {args.steps} implicit steps, "
              f"update {args.update}, sizes {' '.join(f'{s:.0f}' for s in args.sizes)}",
              flush=True)

    def progress(row):
        print(json.dumps(row) if args.json else
              f"  {row['dofs']} DOFs: {row['per_step_s']:.2f} s/step, "
              f"{row['step_over_contact']:.4f} x a contact solve ({row['interface']}, "
              f"{row['layout']} model)",
              flush=True)

    rows = bench_wear(args.sizes, args.steps, args.update, args.duration, progress,
                      interfaces=args.interfaces, layouts=args.layouts)
    if not args.json:
        print(format_wear_table(rows))
    return 0


def _add_wear_parser(subparsers) -> None:
    w = subparsers.add_parser("wear", help="wear step cost against one contact solve",
                              description="Two-surface running-in of the default brake "
                                          "(implicit scheme, fixed steps): time per step and "
                                          "its shares, against one plain contact solve.")
    w.add_argument("--json", action="store_true", help="one JSON object per size and line")
    w.add_argument("--sizes", type=float, nargs="+", default=list(WEAR_SIZES), metavar="DOFS",
                   help="target DOF counts (default: 3e4 1e5)")
    w.add_argument("--steps", type=int, default=200, help="fixed wear steps (default 200)")
    w.add_argument("--update", choices=("gap", "geometry"), default="gap",
                   help="gap offset (default) or geometry update")
    w.add_argument("--interfaces", nargs="+", choices=INTERFACES, default=["fe"],
                   help="interface models to time (default fe; condensed and winkler need "
                        "--update gap)")
    w.add_argument("--duration", type=float, default=3600.0,
                   help="simulated drag, s (default 3600)")
    w.add_argument("--layouts", nargs="+", choices=LAYOUTS, default=["half"],
                   help="half model (default) and/or the full model (both pads, whole rotor) "
                        "on the half model's mesh size")
    w.set_defaults(bench="wear", func=run_bench)


def _run_rough_bench(args: argparse.Namespace) -> int:
    if not args.json:
        print(f"brakewear bench rough: {os.cpu_count()} CPUs, tol {args.tol:g}, grids "
              f"{' '.join(f'{n}^2' for n in args.sizes)} (single-threaded FFTs)", flush=True)

    def progress(row):
        if args.json:
            print(json.dumps(row), flush=True)
        else:
            tam = (f", tamaas {row['tamaas_s']:.3f} s (area {100 * row['area_difference']:+.3f}"
                   " %)" if "tamaas_s" in row else ", tamaas not installed")
            print(f"  {row['n']}^2: half-space {row['ours_s']:.3f} s{tam}; sphere: half-space "
                  f"{row['sphere_halfspace_s']:.3f} s, foundation "
                  f"{row['sphere_foundation_s'] * 1e3:.2f} ms", flush=True)

    rows = bench_rough(args.sizes, args.tol, progress)
    if not args.json:
        print(format_rough_table(rows))
    return 0


def _add_rough_parser(subparsers) -> None:
    r = subparsers.add_parser("rough", help="half-space rough contact against tamaas and the "
                                            "foundation model",
                              description="Rough contact: the FFT half-space solve against "
                                          "tamaas (if installed: pip install brakewear"
                                          "[rough-reference]) on a periodic self-affine "
                                          "surface, and against the foundation bed on a "
                                          "sphere on a rough plane; one run, same tolerance.")
    r.add_argument("--json", action="store_true", help="one JSON object per size and line")
    r.add_argument("--sizes", type=int, nargs="+", default=list(ROUGH_SIZES), metavar="N",
                   help="grid sizes N (N x N pixels; default 256 512)")
    r.add_argument("--tol", type=float, default=1e-8,
                   help="relative pressure change at convergence, both solvers (default 1e-8)")
    r.set_defaults(bench="rough", func=run_bench)


def _add_elasticity_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true",
                   help="one JSON object per size and line instead of a table")
    p.add_argument("--sizes", type=float, nargs="+", default=list(DEFAULT_SIZES), metavar="DOFS",
                   help="target DOF counts (default: 3e4 1e5 3e5 1e6)")
    p.add_argument("--direct-max", type=int, default=100_000, dest="direct_max", metavar="DOFS",
                   help="largest system also solved by SuperLU (default 100000)")
    p.add_argument("--repeats", type=int, default=1,
                   help="fresh processes per size; timings are their medians (default 1)")
    p.set_defaults(bench="elasticity")


def add_bench_parser(subparsers) -> None:
    """Register the benchmarks as sub-commands of ``subparsers`` (the ``bench`` command's):
    ``elasticity [--json] [--sizes ...] [--direct-max N] [--repeats N]`` and
    ``contact [--json] [--sizes ...] [--cases hertz brake] [--direct-max N] [--repeats N]``,
    ``wear ...`` and ``rough [--json] [--sizes N ...] [--tol T]``.

    ``brakewear bench elasticity|contact|wear|rough`` is then run by :func:`run_bench` (also set
    as the ``func`` default of the parsed arguments).
    """
    e = subparsers.add_parser(
        "elasticity",
        help="P1 elasticity: assembly, AMG setup and solve, memory",
        description="P1 elasticity benchmark: the default rotor ring half, "
        "clamped inside, pad pressure; each size in a fresh process.",
    )
    _add_elasticity_args(e)
    e.set_defaults(func=run_bench)
    c = subparsers.add_parser("contact", help="contact solve against one elasticity solve and "
                                              "direct KKT solvers",
                              description="Contact benchmark: Hertz (rigid sphere on a quarter "
                                          "block) and the default brake (mu = 0.4, elastic "
                                          "rotor); each case and size in a fresh process.")
    c.add_argument("--json", action="store_true",
                   help="one JSON object per case, size and line instead of a table")
    c.add_argument("--sizes", type=float, nargs="+", default=list(CONTACT_SIZES), metavar="DOFS",
                   help="target DOF counts (default: 5e4 1.5e5; add 5e5 for the 500k class)")
    c.add_argument("--cases", nargs="+", default=list(CONTACT_CASES), choices=CONTACT_CASES,
                   help="cases to run (default: hertz brake)")
    c.add_argument("--direct-max", type=float, default=CONTACT_DIRECT_MAX, dest="direct_max",
                   metavar="DOFS", help="largest model whose KKT system PARDISO also "
                                        "factorises, when installed (default 200000: the "
                                        "150k-class sizes)")
    c.add_argument("--superlu-max", type=float, default=CONTACT_SUPERLU_MAX, dest="superlu_max",
                   metavar="DOFS", help="largest model for SuperLU on the KKT system (default "
                                        "60000: the 50k class; 2e5 adds the 150k class, minutes "
                                        "each)")
    c.add_argument("--repeats", type=int, default=1,
                   help="fresh processes per case and size; timings are medians (default 1)")
    c.set_defaults(bench="contact", func=run_bench)
    _add_wear_parser(subparsers)
    _add_rough_parser(subparsers)


def run_bench(args: argparse.Namespace) -> int:
    """Run the benchmark chosen by ``args`` and print a table or JSON lines; exit code."""
    which = getattr(args, "bench", "elasticity")
    if which == "contact":
        return _run_contact_bench(args)
    if which == "wear":
        return _run_wear_bench(args)
    if which == "rough":
        return _run_rough_bench(args)
    if which != "elasticity":
        print(f"unknown benchmark {args.bench!r}; available: elasticity, contact, wear, rough",
              file=sys.stderr)
        return 2
    if not args.json:
        print(
            f"brakewear bench elasticity: {os.cpu_count()} CPUs, "
            f"Python {platform.python_version()}, "
            f"sizes {' '.join(f'{s:.0f}' for s in args.sizes)}",
            flush=True,
        )

    def progress(row):
        if args.json:
            print(json.dumps(row), flush=True)
        else:
            print(f"  {row['dofs']} DOFs: total {row['total_s']:.2f} s, "
                  f"peak {row['peak_rss_mb']:.0f} MB", flush=True)

    try:
        rows = bench_elasticity(args.sizes, args.direct_max, args.repeats,
                                progress=None if args.json else progress)
    except RuntimeError as exc:
        print(f"bench elasticity failed: {exc}", file=sys.stderr)
        return 1
    if args.json:
        for row in rows:
            print(json.dumps(row), flush=True)
    else:
        print(format_table(rows))
    return 0


def _run_contact_bench(args: argparse.Namespace) -> int:
    if not args.json:
        print(
            f"brakewear bench contact: {os.cpu_count()} CPUs, Python {platform.python_version()}, "
            f"cases {' '.join(args.cases)}, sizes {' '.join(f'{s:.0f}' for s in args.sizes)}",
            flush=True,
        )

    def progress(row):
        if args.json:
            print(json.dumps(row), flush=True)
        elif "error" in row:
            print(f"  {row['case']} {row['target_dofs']}: failed", flush=True)
        else:
            print(f"  {row['case']} {row['dofs']} DOFs: contact {row['contact_solve_s']:.2f} s, "
                  f"ratio {row['ratio']:.2f}", flush=True)

    rows = bench_contact(args.sizes, args.cases, args.direct_max, args.repeats,
                         superlu_max_dofs=args.superlu_max, progress=progress)
    if not args.json:
        print(format_contact_table(rows))
    return 1 if any("error" in r for r in rows) else 0


def _contact_child(opts: dict) -> int:
    if opts.get("warmup", True):
        # imports and first calls on a tiny model, outside the timings
        if opts["case"] == "hertz":
            run_contact_case("hertz", 3000, 0)
        else:
            run_contact_case("brake", 8000, 0)
    row = run_contact_case(opts["case"], opts["target"], opts["direct_max_dofs"],
                           opts.get("superlu_max_dofs"))
    print(json.dumps(row), flush=True)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["--_child"]:
        opts = json.loads(argv[1])
        if opts.get("bench") == "contact":
            return _contact_child(opts)
        if opts.get("warmup", True):
            # first calls pay for imports and library set-up; a tiny case
            # takes them so that the timed run measures the work itself
            run_elasticity_case(1500, 0)
        row = run_elasticity_case(opts["target"], opts["direct_max_dofs"])
        print(json.dumps(row), flush=True)
        return 0
    ap = argparse.ArgumentParser(prog="python -m brakewear.bench",
                                 description="brakewear performance benchmarks")
    add_bench_parser(ap.add_subparsers(dest="bench", metavar="BENCHMARK", required=True))
    return run_bench(ap.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
