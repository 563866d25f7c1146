"""scikit-fem's private state is touched in one module, for the versions it was checked in.

A scan of the package and the studies for the underscored names of scikit-fem's
meshes, bases and mappings (attributes, and the names given to
``getattr``/``setattr``/``hasattr``) finds them in brakewear/mesh/skfem_compat.py
alone; its version guard refuses another major version naming both, and agrees
with setup.cfg's bound; its functions give what scikit-fem itself gives.
"""
from __future__ import annotations

import ast
import configparser
import re
from pathlib import Path

import numpy as np
import pytest
import skfem as fem

from brakewear.errors import DependencyError, InputError
from brakewear.mesh import skfem_compat as compat

ROOT = Path(__file__).resolve().parents[1]
COMPAT = ROOT / "brakewear" / "mesh" / "skfem_compat.py"


def _mesh() -> fem.Mesh:
    return fem.MeshTet().refined(2).with_boundaries({"left": lambda x: x[0] == 0.0}) \
        .with_subdomains({"low": lambda x: x[2] < 0.5})


def _private_names() -> tuple[set[str], set[str]]:
    """scikit-fem's underscored names: of every class the package uses, and of a
    mesh's state once its lazy tables are built (the names a string may give)."""
    m = _mesh()
    m.facets, m.f2t, m.edges, m.f2e, m.mapping(), m.dofs      # build the lazy tables
    state = {n for n in vars(m) if n.startswith("_") and not n.startswith("__")}
    classes = (fem.Mesh, fem.MeshTet1, fem.MeshTet2, fem.MeshTri1, fem.MeshQuad1,
               fem.CellBasis, fem.FacetBasis, fem.ElementTetP1, fem.ElementVector,
               fem.MappingAffine, fem.MappingIsoparametric, fem.BilinearForm)
    every = state | {n for c in classes for n in dir(c)
                     if n.startswith("_") and not n.startswith("__")}
    return every, state


def _uses(path: Path, every: set[str], state: set[str]) -> list[str]:
    """``obj._name`` (not ``self``'s) and ``getattr(obj, "_name")``-style strings."""
    found = []
    where = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path.name
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Attribute) and node.attr in every and not (
                isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
            found.append(f"{where}:{node.lineno}: {ast.unparse(node)}")
        elif isinstance(node, ast.Constant) and node.value in state:
            found.append(f"{where}:{node.lineno}: {node.value!r}")
    return found


def test_scikit_fem_private_state_is_touched_in_one_module():
    every, state = _private_names()
    assert {"_boundaries", "_facets", "_t2f", "_f2t", "_encode_cell_data"} <= every
    paths = sorted((ROOT / "brakewear").rglob("*.py")) + sorted((ROOT / "studies").glob("*.py"))
    outside = [u for p in paths if p != COMPAT for u in _uses(p, every, state)]
    assert not outside, "scikit-fem's private state outside skfem_compat.py:\n" + \
        "\n".join(outside)
    assert _uses(COMPAT, every, state), "the scan sees the compatibility module's uses"


def test_the_scan_sees_a_private_use(tmp_path):
    every, state = _private_names()
    probe = tmp_path / "probe.py"
    probe.write_text("def f(m):\n    b = m._boundaries\n    return hasattr(m, '_t2f')\n")
    found = [u.split(": ", 1)[1] for u in _uses(probe, every, state)]
    assert found == ["m._boundaries", "'_t2f'"]


def test_the_version_guard_names_the_installed_and_the_supported_versions():
    lo, hi = compat.SUPPORTED
    assert compat.check_version() == compat.check_version(None)
    for ok in (f"{lo}.0.0", f"{hi - 1}.9.1", f"{lo}.1"):
        assert compat.check_version(ok) == ok
    for bad in (f"{lo - 1}.1.1", f"{hi}.0.0", "abc", ""):
        with pytest.raises(DependencyError, match=rf"scikit-fem {re.escape(bad)} is installed; "
                                                  rf"brakewear supports scikit-fem >= {lo}, "
                                                  rf"< {hi} .*pip install \"scikit-fem>={lo},"
                                                  rf"<{hi}\""):
            compat.check_version(bad)
    assert issubclass(DependencyError, InputError)


def test_setup_cfg_bounds_scikit_fem_to_the_supported_versions():
    cfg = configparser.ConfigParser()
    cfg.read(ROOT / "setup.cfg")
    (req,) = [r.strip() for r in cfg["options"]["install_requires"].splitlines()
              if r.strip().startswith("scikit-fem")]
    lo, hi = compat.SUPPORTED
    assert req == f"scikit-fem>={lo},<{hi}"
    assert compat.check_version() is not None          # the installed one is in the range


def test_the_compatibility_functions_give_what_scikit_fem_gives():
    """A moved copy keeps the named sets and the topology; set topology tables equal
    scikit-fem's own; the named sets survive an encode-decode round trip."""
    from brakewear.mesh.topology import ensure_topology

    m = _mesh()
    fast = ensure_topology(fem.MeshTet(m.p, m.t))
    assert compat.has_topology(fast) and not compat.has_topology(fem.MeshTet(m.p, m.t))
    for name in ("facets", "t2f", "f2t"):
        assert np.array_equal(getattr(fast, name), getattr(m, name)), name
    p = m.p * 2.0
    moved = compat.moved_mesh(m, p)
    assert type(moved) is type(m) and moved.p is p and np.array_equal(moved.t, m.t)
    assert moved.boundaries.keys() == {"left"} and moved.subdomains.keys() == {"low"}
    assert compat.has_topology(moved) and moved.facets is m.facets
    decoded = compat.decode_cell_data(m, compat.encode_cell_data(m))
    assert np.array_equal(np.sort(decoded[0]["left"]), np.sort(m.boundaries["left"]))
    assert np.array_equal(np.sort(decoded[1]["low"]), np.sort(m.subdomains["low"]))
    other = compat.mesh_with_sets(fem.MeshTet, m.p, m.t, m.boundaries, None)
    assert other.boundaries is m.boundaries and other.subdomains is None
