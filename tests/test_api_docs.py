"""The API reference (docs/api, Sphinx autodoc + numpydoc) builds without a warning:
every public docstring parses, and every public module of the package is in it."""
import importlib
import pkgutil
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
INDEX = (ROOT / "docs" / "api" / "index.rst").read_text()
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
