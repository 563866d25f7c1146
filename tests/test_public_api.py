"""Studies and benchmarks use the package as a user would: only public names.

A name is public when it does not start with an underscore and is listed in
its module's ``__all__`` (or is a submodule of a package).  The benchmark
package may import its own modules freely, nothing private from the rest.
"""
import ast
import importlib
import importlib.util
from pathlib import Path

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


def test_studies_import_only_public_names():
    bad = [f"{path.name}:{line}: {module}.{name}" for path in STUDIES
           for line, module, name in _imports(path, "studies") if _private(module, name)]
    assert STUDIES, "no studies found"
    assert not bad, "private names imported:\n" + "\n".join(bad)


def test_benchmarks_import_nothing_private_from_the_package():
    bad = [f"{path.name}:{line}: {module}.{name}" for path in BENCH
           for line, module, name in _imports(path, "brakewear.bench")
           if not module.startswith("brakewear.bench") and _private(module, name)]
    assert BENCH, "no benchmark modules found"
    assert not bad, "private names imported:\n" + "\n".join(bad)


def test_the_check_sees_a_private_import(tmp_path):
    f = tmp_path / "probe.py"
    f.write_text("from brakewear.contact import elimination\n"
                 "from brakewear.output.figures import facets_to_pyvista, _not_public\n")
    found = [(m, n) for _, m, n in _imports(f, "studies") if _private(m, n)]
    assert found == [("brakewear.output.figures", "_not_public")]


# --- no module reaches into another's private attributes ---------------------------------
#
# A unit is a subpackage of brakewear (its modules share their privates), a top-level
# module of brakewear, or one study.  ``obj._name`` in one unit, where ``_name`` is
# defined (a private function, class or name, or an attribute set on ``self``) only in
# another, reads or writes that unit's internals; so does ``from unit import _name``.

PACKAGE = ROOT / "brakewear"
UNITS = sorted(PACKAGE.rglob("*.py")) + STUDIES

#: private attributes of other libraries' objects that share a name with one of ours
#: (none: scikit-fem's are touched in brakewear/mesh/skfem_compat.py alone,
#: tests/test_skfem_compat.py)
THIRD_PARTY: set[tuple[str, str]] = set()


def _rel(path: Path) -> Path:
    return path.relative_to(ROOT) if path.is_relative_to(ROOT) else path


def _unit(path: Path) -> str:
    rel = _rel(path)
    return "/".join(rel.parts[:2]) if rel.parts[0] == "brakewear" and len(rel.parts) > 2 \
        else str(rel)


def _is_private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _defined_and_used(paths):
    """unit -> private names it defines; and (unit, path, line, text, name) of each use."""
    defined, used = {}, []
    for p in paths:
        unit, tree = _unit(p), ast.parse(p.read_text())
        own = defined.setdefault(unit, set())
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                own.add(node.name)
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                own.add(node.id)
            elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) and \
                    isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"):
                own.add(node.attr)
            if isinstance(node, ast.Attribute) and _is_private(node.attr):
                used.append((unit, p, node.lineno, ast.unparse(node)[:60], node.attr))
    return defined, used


def _cross_unit_private(paths) -> list[str]:
    defined, used = _defined_and_used(paths)
    owners = {}
    for unit, names in defined.items():
        for n in names:
            owners.setdefault(n, set()).add(unit)
    return [f"{_rel(p)}:{line}: {text} (private to {', '.join(sorted(owners[n]))})"
            for unit, p, line, text, n in used
            if n in owners and n not in defined[unit] and (unit, n) not in THIRD_PARTY]


def test_no_module_reaches_into_anothers_private_attributes():
    bad = _cross_unit_private(UNITS)
    assert not bad, "private attributes of another module:\n" + "\n".join(bad)


def test_the_package_imports_no_private_name_across_units():
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(ROOT)
        package = ".".join(rel.parts[:-1]) if path.name == "__init__.py" else \
            ".".join(rel.with_suffix("").parts[:-1])
        for line, module, name in _imports(path, package):
            parts = module.split(".")
            target = "/".join(parts[:2]) if (ROOT.joinpath(*parts[:2])).is_dir() else \
                "/".join(parts) + ".py"
            if _is_private(name) and target != _unit(path):
                bad.append(f"{rel}:{line}: {module}.{name}")
    assert not bad, "private names imported across units:\n" + "\n".join(bad)


def test_the_check_sees_a_private_attribute_of_another_module(tmp_path):
    study = tmp_path / "probe.py"
    study.write_text("def f(model, itf):\n    model._K = {}\n    return itf._base\n")
    pad = tmp_path / "pad.py"
    pad.write_text("class A:\n    def __init__(self):\n        self._base = {}\n")
    found = _cross_unit_private([study, pad, PACKAGE / "model.py"])
    assert [f.split(": ", 1)[1] for f in found] == [
        "model._K (private to brakewear/model.py)", f"itf._base (private to {pad})"]
