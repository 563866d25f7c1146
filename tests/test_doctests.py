"""The examples in the docstrings of the closed forms run, and say what they print.

The closed forms (:mod:`brakewear.analytic`, the caliper's, the wear and friction
laws, the rotor's rings) carry doctests, as scikit-fem's and pyamg's do; each
module here must hold at least its stated number of examples, and every one
passes.  ``python -m pytest --doctest-modules brakewear/analytic`` runs those of
the closed forms alone.
"""
from __future__ import annotations

import doctest
import importlib
import io

import pytest

#: module -> the fewest examples it holds
MODULES = {"brakewear.analytic.contact": 10, "brakewear.analytic.heat": 10,
           "brakewear.analytic.wear": 8, "brakewear.caliper.analytic": 8,
           "brakewear.laws.base": 10, "brakewear.mesh.rings": 8,
           "brakewear.mesh.skfem_compat": 2}


@pytest.mark.parametrize("name", sorted(MODULES))
def test_the_docstring_examples_run(name):
    module = importlib.import_module(name)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    out = io.StringIO()
    for test in doctest.DocTestFinder().find(module):
        runner.run(test, out=out.write)
    assert runner.failures == 0, out.getvalue()
    assert runner.tries >= MODULES[name], f"{name}: {runner.tries} examples"
