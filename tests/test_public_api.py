"""Studies and benchmarks use the package as a user would: only public names.

A name is public when it does not start with an underscore and is listed in
its module's ``__all__`` (or is a submodule of a package).  The benchmark
package may import its own modules freely, nothing private from the rest.
"""
import ast
import importlib
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _imports(path: Path, package: str):
    """(line, module, name) of every ``from ... import name`` of brakewear in ``path``."""
    for node in ast.walk(ast.parse(path.read_text())):
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            module = importlib.util.resolve_name("." * node.level + (node.module or ""), package)
        elif node.module and node.module.split(".")[0] == "brakewear":
            module = node.module
        else:
            continue
        for alias in node.names:
            yield node.lineno, module, alias.name


def _private(module: str, name: str) -> bool:
    mod = importlib.import_module(module)
    if name.startswith("_"):
        return True
    if hasattr(mod, "__path__") and importlib.util.find_spec(f"{module}.{name}") is not None:
        return False
    public = getattr(mod, "__all__", None)
    return public is not None and name not in public


STUDIES = sorted((ROOT / "studies").glob("*.py"))
BENCH = sorted((ROOT / "brakewear" / "bench").glob("*.py"))


@pytest.mark.parametrize("path", STUDIES, ids=lambda p: p.name)
def test_studies_import_only_public_names(path):
    bad = [f"{path.name}:{line}: {module}.{name}" for line, module, name in
           _imports(path, "studies") if _private(module, name)]
    assert not bad, "private names imported:\n" + "\n".join(bad)


@pytest.mark.parametrize("path", BENCH, ids=lambda p: p.name)
def test_benchmarks_import_nothing_private_from_the_package(path):
    bad = [f"{path.name}:{line}: {module}.{name}" for line, module, name in
           _imports(path, "brakewear.bench")
           if not module.startswith("brakewear.bench") and _private(module, name)]
    assert not bad, "private names imported:\n" + "\n".join(bad)


def test_the_check_sees_a_private_import(tmp_path):
    f = tmp_path / "probe.py"
    f.write_text("from brakewear.contact import elimination\n"
                 "from brakewear.figures import facets_to_pyvista, _not_public\n")
    found = [(m, n) for _, m, n in _imports(f, "studies") if _private(m, n)]
    assert found == [("brakewear.figures", "_not_public")]
