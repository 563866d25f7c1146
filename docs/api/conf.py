"""Sphinx configuration of brakewear's API reference (built by tests/test_api_docs.py).

numpydoc validates the docstring of every name of ``brakewear.__all__`` where
the reference documents it (:data:`VALIDATED`): a warning, which the test's
build (``-W``) turns into an error, for each check of :data:`CHECKS` it fails.
"""
from __future__ import annotations

import importlib
import re
from pathlib import Path

import brakewear

project = "brakewear"
extensions = ["sphinx.ext.autodoc", "numpydoc"]
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": True}
autodoc_typehints = "none"
numpydoc_show_class_members = False
exclude_patterns = ["_build"]
html_theme = "alabaster"
suppress_warnings: list[str] = []

#: the numpydoc checks the public API is held to: a docstring (GL08), sections
#: numpydoc knows in its order (GL06, GL07), a one-line summary sentence (SS01-SS03,
#: SS05, SS06), every parameter documented and described and no other (PR01, PR02,
#: PR07, PR10), a Returns section where something is returned (RT01), a Yields
#: section for a generator (YD01)
CHECKS = {"GL06", "GL07", "GL08", "SS01", "SS02", "SS03", "SS05", "SS06", "PR01", "PR02",
          "PR07", "PR10", "RT01", "YD01"}

#: a protocol is answered by classes, never made: its "parameters" are Protocol's own
OVERRIDES = {"PR01": [r"\(a protocol\)"]}


def documented_public_names(index: str | None = None) -> dict[str, str]:
    """Where the reference documents each class and function of ``brakewear.__all__``.

    Parameters
    ----------
    index
        The text of index.rst (default: this folder's).

    Returns
    -------
    dict
        Public name -> the documented name (``"Run"`` -> ``"brakewear.wear.Run"``),
        for every public name some ``automodule`` with members documents.
    """
    if index is None:
        index = (Path(__file__).parent / "index.rst").read_text()
    modules = re.findall(r"^\.\. automodule:: (\S+)\n(?!   :no-members:)", index, re.M)
    public = {n: getattr(brakewear, n) for n in brakewear.__all__
              if callable(getattr(brakewear, n))}
    out: dict[str, str] = {}
    for name in modules:
        module = importlib.import_module(name)
        for member in getattr(module, "__all__", ()):
            obj = getattr(module, member, None)
            for n, o in public.items():
                if obj is o and n not in out:
                    out[n] = f"{name}.{member}"
    return out


#: the documented names numpydoc validates: those of ``brakewear.__all__``
VALIDATED = set(documented_public_names().values())

numpydoc_validation_checks = CHECKS
# every other documented name is excluded: a pattern that matches any name but these
numpydoc_validation_exclude = {
    rf"^(?!(?:{'|'.join(re.escape(n) for n in sorted(VALIDATED))})$)"}
numpydoc_validation_overrides = OVERRIDES
