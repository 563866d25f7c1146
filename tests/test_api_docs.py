"""The API reference (docs/api, Sphinx autodoc + numpydoc) builds without a warning:
every public docstring parses, every public module of the package is in it, and
every class and function of ``brakewear.__all__`` has the numpydoc sections its
signature asks for (validated by numpydoc, in the build and here)."""
import importlib
import pkgutil
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
INDEX = (ROOT / "docs" / "api" / "index.rst").read_text()
CONF: dict = {"__file__": str(ROOT / "docs" / "api" / "conf.py")}
exec(compile((ROOT / "docs" / "api" / "conf.py").read_text(), CONF["__file__"], "exec"), CONF)
#: packages and modules a user reaches for; the rest are internals of these
LISTED = set(re.findall(r"^\.\. automodule:: (\S+)", INDEX, re.M))


def test_every_public_package_is_in_the_reference():
    import brakewear
    public = {f"brakewear.{m.name}" for m in pkgutil.iter_modules(brakewear.__path__)
              if not m.name.startswith("_") and m.name not in ("cli", "bench", "checks")}
    missing = sorted(public - LISTED)
    assert not missing, f"not in docs/api/index.rst: {missing}"
    for name in LISTED:
        importlib.import_module(name)


def test_the_reference_builds_without_warnings(tmp_path):
    sphinx = pytest.importorskip("sphinx.cmd.build")
    pytest.importorskip("numpydoc")
    rc = sphinx.build_main(["-W", "-q", "-b", "html", str(ROOT / "docs" / "api"),
                            str(tmp_path / "html")])
    assert rc == 0
    html = (tmp_path / "html" / "index.html").read_text()
    for name in ("wear_history", "run_schedule", "FEInterface", "TemperatureLimitError"):
        assert name in html


def _failures(name: str) -> list[str]:
    """The checks of the reference's numpydoc validation that ``name``'s docstring fails."""
    from numpydoc.validate import validate

    report = validate(name)
    return [f"{code}: {msg}" for code, msg in report["errors"] if code in CONF["CHECKS"]
            and not any(re.search(p, report["docstring"])
                        for p in CONF["OVERRIDES"].get(code, ()))]


def test_every_public_name_has_its_numpydoc_sections():
    """100 % of the classes and functions of ``brakewear.__all__`` pass the checks (the
    two data names, ``__version__`` and ``MATERIALS``, have no signature), and the
    reference documents and validates each."""
    pytest.importorskip("numpydoc")
    import brakewear

    public = [n for n in brakewear.__all__ if callable(getattr(brakewear, n))]
    assert set(brakewear.__all__) - set(public) == {"__version__", "MATERIALS"}
    assert set(CONF["documented_public_names"]()) == set(public)
    bad = {}
    for n in public:
        obj = getattr(brakewear, n)
        failed = _failures(f"{obj.__module__}.{obj.__qualname__}")
        if failed:
            bad[n] = failed
    assert not bad, f"{len(public) - len(bad)} of {len(public)} pass; the others:\n" + \
        "\n".join(f"{n}: {f}" for n, f in bad.items())


def _probe(a, b):
    """Add two numbers."""
    return a + b


def test_the_validation_sees_a_missing_section():
    pytest.importorskip("numpydoc")
    assert [f[:4] for f in _failures(f"{__name__}._probe")] == ["PR01", "RT01"]
