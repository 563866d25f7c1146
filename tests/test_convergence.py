"""Convergence against the thick-walled cylinder (docs/references.md), 3D plane strain."""
import importlib.util
from pathlib import Path

import pytest

spec = importlib.util.spec_from_file_location(
    "cylinder_convergence", Path(__file__).parents[1] / "studies" / "cylinder_convergence.py")
cyl = importlib.util.module_from_spec(spec)
spec.loader.exec_module(cyl)


@pytest.fixture(scope="module")
def result():
    return cyl.main(ns_p1=(2, 4, 8, 16), ns_p2=(1, 2, 4, 8))


def test_p1_rates_and_finest_error(result):
    assert result["p1_l2_rate"] >= 1.8, result["p1_l2_rate"]
    assert result["p1_energy_rate"] >= 0.9, result["p1_energy_rate"]
    fin = result["p1_finest"]
    assert fin["l2"] < 1.5e-3 and fin["energy"] < 3.5e-2, fin


def test_p2_rates_and_finest_error(result):
    assert result["p2_l2_rate"] >= 2.7, result["p2_l2_rate"]
    assert result["p2_energy_rate"] >= 1.8, result["p2_energy_rate"]
    fin = result["p2_finest"]
    assert fin["l2"] < 1.5e-5 and fin["energy"] < 1.2e-3, fin


@pytest.mark.slow
def test_rates_hold_on_finer_meshes(tmp_path):
    res = cyl.main(ns_p1=(4, 8, 16, 32), ns_p2=(2, 4, 8, 16), out=tmp_path)
    assert res["p1_l2_rate"] >= 1.8 and res["p1_energy_rate"] >= 0.9, res
    assert res["p2_l2_rate"] >= 2.7 and res["p2_energy_rate"] >= 1.8, res
    assert res["p2_finest"]["l2"] < 2e-6, res["p2_finest"]
    assert (tmp_path / "cylinder_convergence.csv").exists()
    assert (tmp_path / "cylinder_convergence.png").stat().st_size > 10_000
