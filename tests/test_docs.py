"""Docs, README, package and studies speak of the software as it is, not of its development."""
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: the packaged geometry and scene files are documentation too (their comments)
FILES = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md"),
                *(ROOT / "brakewear").rglob("*.py"), *(ROOT / "studies").rglob("*.py"),
                *(ROOT / "geometry").rglob("*.toml")])

#: what tells the story of the development: work periods, issue numbers, commit
#: hashes, dates of work, other jobs on the machine
HISTORY = [
    (r"\b[Ss]ession[ -]\d+\b|\b[Ss]essions \d", "a work period"),
    (r"\bthe issue\b|\b[Ii]ssue #?\d+\b", "an issue"),
    (
        r"\bcommit\s+(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}\b|"
        r"`(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}`",
        "a commit hash",
    ),
    (
        r"\b20\d\d-\d\d-\d\d\b|"
        r"\b\d{1,2} (Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec)[a-z]* 20\d\d\b",
        "a date of work",
    ),
    (r"\bwork period\b|\bother agents\b|\bthis session\b", "the development"),
    (
        r"\b(git archive|(main|master) at) (?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}\b",
        "a commit hash",
    ),
    (r"(?i)\b(an)?other engineers?\b|\b(an)?other engineer's", "other people's jobs"),
    (
        r"(?i)\bbefore the (work|change|changes|fix|refactor)\b|\bthe old code\b|"
        r"\b(the )?old defaults?\b|\bwhat was changed\b|^(#+ |\*\*)what changed\b",
        "how the code changed",
    ),
]


def test_no_development_history():
    hits = []
    for path in FILES:
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for pattern, what in HISTORY:
                if re.search(pattern, line):
                    hits.append(f"{path.relative_to(ROOT)}:{n}: {what}: {line.strip()[:100]}")
    assert len(FILES) > 100, f"only {len(FILES)} files read"
    assert not hits, "\n".join(hits)


#: a data field that records the development (the code's commit, a work period)
HISTORY_KEY = r"(?i)commit|^git_|session|^issue"


def _keys(value):
    if isinstance(value, dict):
        for k, v in value.items():
            yield k
            yield from _keys(v)
    elif isinstance(value, list):
        for v in value:
            yield from _keys(v)


def test_data_files_carry_no_development_history():
    """docs/data's JSON (and JSON-lines) files hold the numbers, not the commit that made
    them."""
    import json

    hits, files = [], sorted([*(ROOT / "docs" / "data").glob("*.json"),
                              *(ROOT / "docs" / "data").glob("*.jsonl")])
    for path in files:
        text = path.read_text(encoding="utf-8")
        try:
            records = [json.loads(text)]
        except json.JSONDecodeError:
            records = [json.loads(s) for s in text.splitlines() if s.strip()]
        keys = {k for r in records for k in _keys(r) if re.search(HISTORY_KEY, k)}
        hits += [f"{path.relative_to(ROOT)}: {k}" for k in sorted(keys)]
    assert files, "no data files found"
    assert not hits, "fields that tell the development:\n" + "\n".join(hits)
    assert [k for k in ["code_commit", "git_sha", "session", "issue", "dofs", "mu"]
            if re.search(HISTORY_KEY, k)] == ["code_commit", "git_sha", "session", "issue"]


def test_the_history_patterns_catch_what_they_should():
    caught = ["measured in session 7", "the issue asks", "commit 5d4a881", "(`e07a9f4`)",
              "run on 2026-11-21", "21 Nov 2026", "shared with other agents",
              "Another engineer's jobs shared the machine", "while the other engineer's jobs",
              "the other engineers ran", "before the work described below",
              "took 8.1 s with the old code", "against the old defaults",
              "### What was changed", "**What changed** (`solvers.py`):",
              "git archive e3ebe84 | tar -x", "the wear loop of main at e6e354a"]
    clean = ["1e-9 relative", "`pad_wear`", "exit code 4", "the rotor issue of heat",
             "`1000000`", "the old mesh is left untouched", "is refused with what changed",
             "in other engineering tools", "before the wear step starts", "git archive HEAD",
             "the main at 20 deg", "before and after the move", "an older pad"]
    def hit(s):
        return any(re.search(p, s) for p, _ in HISTORY)
    assert [s for s in caught if not hit(s)] == []
    assert [s for s in clean if hit(s)] == []


def test_citations_point_to_the_shipped_references():
    """The closed forms and typical data are cited as docs/references.md, which ships
    (in the package's modules, the docs, the studies and tests, and the packaged
    geometry and scene files)."""
    assert (ROOT / "docs" / "references.md").is_file()
    shipped = sorted([*(ROOT / "geometry").glob("*.toml"),
                      *(ROOT / "geometry" / "scenes").glob("*.toml")])
    assert shipped, "no packaged geometry or scene files found"
    hits = [f"{p.relative_to(ROOT)}:{n}: {line.strip()[:100]}"
            for p in [*FILES, *shipped, *sorted((ROOT / "tests").glob("*.py"))]
            for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
            if re.search(r"REFERENCES\.md|shared/", line) and p.name != "test_docs.py"]
    assert not hits, "cite docs/references.md instead:\n" + "\n".join(hits)


def test_relative_links_point_to_files():
    bad, links = [], 0
    for path in [p for p in FILES if p.suffix == ".md"]:
        text = path.read_text(encoding="utf-8")
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
            if re.match(r"[a-z]+://|mailto:", target):
                continue
            links += 1
            if not (path.parent / target).exists():
                bad.append(f"{path.relative_to(ROOT)}: {target}")
    assert links > 100, f"only {links} relative links found"
    assert not bad, "broken links:\n" + "\n".join(bad)


# --- the Python snippets of README and docs use the API as it is -------------------------

import ast  # noqa: E402
import importlib  # noqa: E402

DOCS_MD = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
SNIPPETS = [(p, i, block) for p in DOCS_MD
            for i, block in enumerate(re.findall(r"```python\n(.*?)```", p.read_text(), re.S))]


def _missing_names(code: str) -> list[str]:
    """The brakewear names a snippet imports (``from brakewear.x import y``) or
    reaches through an imported module (``bw.y``, ``brakewear.x.y``) that do not exist."""
    tree = ast.parse(code)
    modules = {}            # local name -> module
    missing = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and \
                node.module.split(".")[0] == "brakewear":
            mod = importlib.import_module(node.module)
            for a in node.names:
                if not hasattr(mod, a.name):
                    try:
                        importlib.import_module(f"{node.module}.{a.name}")
                    except ImportError:
                        missing.append(f"{node.module}.{a.name}")
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "brakewear":
                    modules[a.asname or a.name.split(".")[0]] = importlib.import_module(
                        a.name if a.asname else "brakewear")
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                and node.value.id in modules and not hasattr(modules[node.value.id], node.attr):
            missing.append(f"{modules[node.value.id].__name__}.{node.attr}")
    return missing


def test_snippets_parse_and_name_what_exists():
    missing = [f"{path.relative_to(ROOT)}, python block {index}: no such name: {names}"
               for path, index, code in SNIPPETS if (names := _missing_names(code))]
    assert SNIPPETS, "no python snippets found"
    assert not missing, "\n".join(missing)


def test_the_snippet_check_sees_a_stale_name():
    assert _missing_names("import brakewear as bw\nbw.BrakeModel\nbw.NoSuchThing\n"
                          "from brakewear.scene import Scene, Interface\n") == \
        ["brakewear.scene.Interface", "brakewear.NoSuchThing"]


# --- every Python snippet of README and docs runs ---------------------------------------
#
# Each ```python block runs as written, in a fresh namespace, in a temporary working
# directory (the files it writes land there), with matplotlib on Agg and pyvista off
# screen, and with studies/ on sys.path (a snippet that imports a study says so in a
# comment). The snippets are written to be cheap -- 6-12 mm meshes, a minute of drag or a
# few steps -- so they run in the suite as a reader would run them: no settings are
# substituted behind their back. All of them together take about 15 s on 2 cores.

#: what some snippets print, checked beyond "it runs" (the numbers their comments state)
OUTPUT_CHECKS = {
    "docs/duty.md#0": lambda out: ("blended: 11.2 kJ" in out and "at most 0.89 kJ" in out
                                   and "friction only: 313.4 kJ" in out),
    "docs/duty.md#1": lambda out: len(out.strip().splitlines()) == 3
    and all("kJ dissipated" in s for s in out.strip().splitlines()),
    "docs/geometry.md#1": lambda out: "floating [0.126, 0.126]" in out
    and "push 0.0002 hat" in out and "261.5 mm^2 rim" in out,
    "docs/load_path.md#0": lambda out: out.strip().endswith("True True True"),
}


@pytest.fixture
def snippet_env(tmp_path, monkeypatch):
    """A fresh working directory, non-interactive plotting, studies/ importable."""
    import matplotlib
    import matplotlib.pyplot as plt

    matplotlib.use("Agg")
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("PYVISTA_OFF_SCREEN", "true")
    try:
        import pyvista
        monkeypatch.setattr(pyvista, "OFF_SCREEN", True)
    except ImportError:
        pass
    monkeypatch.syspath_prepend(str(ROOT / "studies"))
    monkeypatch.chdir(tmp_path)
    yield tmp_path
    plt.close("all")


@pytest.mark.parametrize("path,index,code", SNIPPETS,
                         ids=[f"{p.relative_to(ROOT)}#{i}" for p, i, _ in SNIPPETS])
def test_snippet_runs(path, index, code, snippet_env, capsys):
    key = f"{path.relative_to(ROOT)}#{index}"
    exec(compile(code, f"{key} (python block {index})", "exec"), {"__name__": "__snippet__"})
    out = capsys.readouterr().out
    check = OUTPUT_CHECKS.get(key)
    assert check is None or check(out), f"{key} printed:\n{out}"


def test_every_output_check_has_its_snippet():
    keys = {f"{p.relative_to(ROOT)}#{i}" for p, i, _ in SNIPPETS}
    assert set(OUTPUT_CHECKS) <= keys
