"""The package's shape: module and function sizes, an acyclic import graph, packaging."""
import ast
import configparser
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
PKG = ROOT / "brakewear"
MAX_MODULE_LINES = 500
MAX_FUNCTION_LINES = 80
#: a function may be longer when one algorithm reads best in one piece, and says so
ONE_PIECE = "reads best in one piece"


def _modules():
    for p in sorted(PKG.rglob("*.py")):
        rel = p.relative_to(ROOT).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
        yield ".".join(parts), p


def _code_lines(lines, a, b):
    return sum(1 for s in lines[a - 1:b] if s.strip() and not s.strip().startswith("#"))


def _size_offences(name, path):
    """What in module ``name`` is longer than the rules allow."""
    src = path.read_text()
    lines = src.splitlines()
    if len(lines) > MAX_MODULE_LINES:
        yield f"{name}: {len(lines)} lines (at most {MAX_MODULE_LINES})"
    for node in ast.walk(ast.parse(src)):
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        doc = ast.get_docstring(node) or ""
        body = node.body
        start = body[0].end_lineno + 1 if doc else body[0].lineno
        n = _code_lines(lines, start, node.end_lineno)
        if n > MAX_FUNCTION_LINES and ONE_PIECE not in " ".join(doc.split()):
            yield (f"{name}.{node.name}: {n} lines of code (at most {MAX_FUNCTION_LINES}, or "
                   f"say why it {ONE_PIECE} in its docstring)")


def test_module_and_function_sizes():
    modules = list(_modules())
    bad = [s for name, path in modules for s in _size_offences(name, path)]
    assert len(modules) > 50, f"only {len(modules)} modules found"
    assert not bad, "\n".join(bad)


def test_the_size_check_sees_a_long_module_and_function(tmp_path):
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_FUNCTION_LINES + 1))
    long = tmp_path / "long.py"
    long.write_text(f"def f():\n{body}\n" + "\n" * MAX_MODULE_LINES)
    ok = tmp_path / "ok.py"
    ok.write_text(f'def f():\n    """It {ONE_PIECE}."""\n{body}\n')
    assert [s.split(":")[0] for s in _size_offences("long", long)] == ["long", "long.f"]
    assert list(_size_offences("ok", ok)) == []


def _imports(name, path):
    """Every brakewear module ``name`` imports, function-local imports included."""
    is_pkg = path.name == "__init__.py"
    base = name.split(".") if is_pkg else name.split(".")[:-1]
    known = {m for m, _ in _modules()}
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                head = base[:len(base) - node.level + 1]
                mod = ".".join(head + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            # "from pkg import submodule" imports the submodule
            targets = [mod] + [f"{mod}.{a.name}" for a in node.names]
        else:
            continue
        out |= {t for t in targets if t in known and t != name}
    return out


def test_import_graph_is_acyclic():
    graph = {name: _imports(name, path) for name, path in _modules()}
    state = {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                cycle = stack[stack.index(nxt):] + [nxt]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])


def test_setup_cfg_lists_every_subpackage():
    cfg = configparser.ConfigParser()
    cfg.read(ROOT / "setup.cfg")
    listed = set(cfg["options"]["packages"].split())
    packages = {".".join(p.parent.relative_to(ROOT).parts) for p in PKG.rglob("__init__.py")}
    assert packages <= listed, f"missing from setup.cfg: {sorted(packages - listed)}"


def test_a_source_checkout_finds_the_packaged_files(monkeypatch):
    """Without the installed ``brakewear.geometries`` (tests run from a checkout on a
    non-editable install), geometries and scenes come from the top-level geometry/."""
    import importlib.resources

    from brakewear.geometry import files
    from brakewear.scene import reader

    def missing(name):
        raise ModuleNotFoundError(name)

    monkeypatch.setattr(importlib.resources, "files", missing)
    assert (files.geometry_dir() / "default.toml").is_file()
    assert pathlib.Path(files.geometry_dir()) == ROOT / "geometry"
    assert pathlib.Path(reader.scene_dir()) == ROOT / "geometry" / "scenes"
