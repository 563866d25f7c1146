"""Every input check raises an InputError kind: a scan of the package source for builtin
exceptions, with the few sites that may keep one named and explained."""
from __future__ import annotations

import ast
import builtins
import collections
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import skfem

import brakewear
from brakewear import errors
from brakewear.analytic import inerfc
from brakewear.mesh import facet_indices, graded
from brakewear.motion.brake import check_quality
from brakewear.solvers import direct_solve

PKG = Path(__file__).resolve().parents[1] / "brakewear"

#: builtin exception classes: raised by name in the package they escape ``except
#: brakewear.InputError`` (ValueError, TypeError, KeyError) or read as a crash
#: (RuntimeError); and the input branch itself, which a check raises as one of its kinds
BUILTIN_EXCEPTIONS = {n for n in dir(builtins) if isinstance(getattr(builtins, n), type)
                      and issubclass(getattr(builtins, n), BaseException)} | {"InputError"}

#: (module, function, exception) -> (how many, why it is not an input check)
ALLOWED = {
    ("__init__.py", "__getattr__", "AttributeError"):
        (1, "the module attribute protocol: Python's import machinery expects it"),
    ("thermal/quadratic.py", "QuadraticThermal.__getattr__", "AttributeError"):
        (1, "the attribute protocol of a delegating wrapper (hasattr and getattr rely on it)"),
    ("tribology/kinds.py", "TribometerKind.__getattr__", "AttributeError"):
        (1, "the attribute protocol of a test kind's options (hasattr and getattr rely on it)"),
    ("scene/reader.py", "_convert", "AssertionError"):
        (1, "every kind of the package's own schema table is handled above it; no input "
            "reaches it"),
    ("motion/follower.py", "SurfaceFollower._weights", "RuntimeError"):
        (1, "a projection lands on a facet of the surface, whose vertices are surface nodes by "
            "construction; no input reaches it"),
    ("mesh/mirror.py", "_find", "RuntimeError"):
        (1, "the mirrored pad copies the topology exactly; no input reaches it"),
    ("solvers/patches.py", "_split_strength.aggregate_split", "RuntimeError"):
        (1, "the strength graph was split by body just before; an aggregate cannot span two"),
    ("scene/starter.py", "_replace", "RuntimeError"):
        (1, "the packaged scene files hold the lines new-scene rewrites (a test writes every "
            "start); no input reaches it"),
    ("bench/contact.py", "_run_contact_child", "RuntimeError"):
        (1, "a benchmark child process failed (not an input); the caller catches it and "
            "records the row as failed"),
    ("bench/elasticity.py", "_run_child", "RuntimeError"):
        (2, "a benchmark child process failed or printed no result (not an input); the "
            "command reports it"),
}


def _builtin_raises() -> collections.Counter:
    """(module, function, exception) -> count of ``raise <builtin exception>`` sites."""
    found: collections.Counter = collections.Counter()
    for path in sorted(PKG.rglob("*.py")):
        module = path.relative_to(PKG).as_posix()

        def visit(node, scope, module=module):
            for child in ast.iter_child_nodes(node):
                if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                    visit(child, (*scope, child.name))
                    continue
                if isinstance(child, ast.Raise) and child.exc is not None:
                    exc = child.exc.func if isinstance(child.exc, ast.Call) else child.exc
                    if isinstance(exc, ast.Name) and exc.id in BUILTIN_EXCEPTIONS:
                        found[(module, ".".join(scope), exc.id)] += 1
                visit(child, scope)

        visit(ast.parse(path.read_text()), ())
    return found


def test_no_builtin_exception_is_raised_for_input():
    """``except brakewear.InputError`` catches every bad input: no ``raise ValueError`` (or
    TypeError, KeyError, RuntimeError, Exception) in the package outside the named sites,
    and no bare ``raise InputError`` (a check raises a kind that names its part)."""
    found = _builtin_raises()
    extra = {k: n for k, n in found.items() if n > ALLOWED.get(k, (0, ""))[0]}
    assert not extra, ("builtin exceptions raised in brakewear (raise an InputError kind "
                       f"of brakewear/errors.py, naming the key and the value): {extra}")
    stale = {k: v[0] for k, v in ALLOWED.items() if found.get(k, 0) != v[0]}
    assert not stale, f"allowed sites that no longer raise as listed (update ALLOWED): {stale}"


def test_every_input_kind_is_public_and_caught_as_input():
    """Each kind of the input branch is an InputError (exit code 2, a ValueError for
    callers that catch those) and is exported at the top level."""
    kinds = [getattr(errors, n) for n in errors.__all__]
    inputs = [k for k in kinds if issubclass(k, errors.InputError)]
    assert {"MeshError", "ContactError", "MotionError", "SolverSettingsError",
            "BenchError"} <= {k.__name__ for k in inputs}
    for k in inputs:
        assert issubclass(k, ValueError) and k.exit_code == 2
        assert getattr(brakewear, k.__name__) is k


@pytest.mark.parametrize("call,kind,words", [
    (lambda: graded(0.0, 1.0, 0), "MeshError", "n = 0 cells"),
    (lambda: facet_indices(skfem.MeshTet(), "nope"), "MeshError", "no facets named 'nope'"),
    (lambda: direct_solve(sp.identity(10), np.ones(10), max_dofs=5), "SolverSettingsError",
     "exceeds max_dofs = 5"),
    (lambda: inerfc(-1, 0.0), "ThermalError", "n = -1"),
    (lambda: check_quality(skfem.MeshTet(), min_quality=1.5), "MotionError",
     "min_quality = 1.5"),
])
def test_converted_checks_raise_their_kind(call, kind, words):
    with pytest.raises(brakewear.InputError) as e:
        call()
    assert type(e.value).__name__ == kind and words in str(e.value), (type(e.value), e.value)
