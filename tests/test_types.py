"""The typed modules (setup.cfg's ``[mypy] files``) pass mypy, as configured there.

``mypy`` with no arguments, from the repository's root, checks the same.
"""
from __future__ import annotations

import configparser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _typed() -> list[str]:
    cfg = configparser.ConfigParser()
    cfg.read(ROOT / "setup.cfg")
    return [f.strip() for f in cfg["mypy"]["files"].replace("\n", "").split(",") if f.strip()]


def test_the_typed_modules_pass_mypy(monkeypatch):
    api = pytest.importorskip("mypy.api")
    typed = _typed()
    assert len(typed) >= 15 and all((ROOT / f).is_file() for f in typed)
    monkeypatch.chdir(ROOT)
    out, err, status = api.run([])
    assert status == 0, out + err
    assert f"no issues found in {len(typed)} source files" in out


def test_the_configuration_sees_a_type_error(tmp_path, monkeypatch):
    api = pytest.importorskip("mypy.api")
    bad = tmp_path / "bad.py"
    bad.write_text("from brakewear.registry import OptionKey\n\n"
                   "def f(k: OptionKey) -> float:\n    return k.name\n")
    monkeypatch.chdir(ROOT)
    out, err, status = api.run(["--config-file", str(ROOT / "setup.cfg"), str(bad)])
    assert status == 1 and 'Incompatible return value type (got "str", expected "float")' \
        in out, out + err
