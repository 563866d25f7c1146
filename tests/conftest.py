"""Test-session settings: the condensed-interface cache lives in the session's
temporary directory, not in the user's home; shared fixtures."""
import pytest

from brakewear.interfaces.condensation import CACHE_ENV


@pytest.fixture(autouse=True, scope="session")
def _condensation_cache(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    mp.setenv(CACHE_ENV, str(tmp_path_factory.mktemp("condensed")))
    yield
    mp.undo()


@pytest.fixture
def no_meshing(monkeypatch):
    """Any attempt to mesh fails the test: errors must come before meshing."""
    import brakewear.model as model_mod

    def boom(*a, **k):
        raise AssertionError("a mesh was built before the scene was checked")
    for b in list(model_mod._MESHERS):
        monkeypatch.setitem(model_mod._MESHERS, b, boom)
